// VRML97 tokens (see syntax.h).
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "vrml/syntax.h"

namespace ohrp::vrml {
namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ','; }

// characters that end a word (VRML97 Id rules, plus what the grammar treats as punctuation)
bool EndsWord(char c) {
  return IsSpace(c) || c == '[' || c == ']' || c == '{' || c == '}' || c == '"' || c == '#';
}

bool StartsNumber(const std::string& w) {
  const char c = w[0];
  return (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.';
}

}  // namespace

std::string At(const Where& w) {
  return std::to_string(w.line) + ":" + std::to_string(w.column) + ": ";
}

bool Tokenize(const std::string& text, std::vector<Token>* tokens, std::string* error) {
  tokens->clear();
  Where at;
  size_t i = 0;
  auto advance = [&](size_t n) {
    for (size_t k = 0; k < n && i < text.size(); ++k, ++i) {
      if (text[i] == '\n') {
        ++at.line;
        at.column = 1;
      } else {
        ++at.column;
      }
    }
  };
  while (i < text.size()) {
    const char c = text[i];
    // white space and comments
    if (IsSpace(c)) {
      advance(1);
      continue;
    }
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') advance(1);
      continue;
    }
    Token t;
    t.at = at;
    // punctuation
    if (c == '[' || c == ']' || c == '{' || c == '}') {
      t.kind = c == '[' ? Token::kOpenBracket
               : c == ']' ? Token::kCloseBracket
               : c == '{' ? Token::kOpenBrace
                          : Token::kCloseBrace;
      t.text = std::string(1, c);
      tokens->push_back(t);
      advance(1);
      continue;
    }
    // strings: backslash escapes the next character
    if (c == '"') {
      advance(1);
      while (i < text.size() && text[i] != '"') {
        if (text[i] == '\\' && i + 1 < text.size()) advance(1);
        t.text += text[i];
        advance(1);
      }
      if (i >= text.size()) {
        *error = At(t.at) + "string not terminated: a '\"' is missing";
        return false;
      }
      advance(1);
      t.kind = Token::kString;
      tokens->push_back(t);
      continue;
    }
    // control characters start nothing
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      *error = At(at) + "unexpected control character (code " +
               std::to_string(static_cast<unsigned char>(c)) + ")";
      return false;
    }
    // words: numbers or identifiers
    size_t end = i;
    while (end < text.size() && !EndsWord(text[end]) &&
           static_cast<unsigned char>(text[end]) >= 0x20)
      ++end;
    t.text = text.substr(i, end - i);
    if (StartsNumber(t.text)) {
      const bool hex = t.text.size() > 2 && t.text[0] == '0' && (t.text[1] == 'x' || t.text[1] == 'X');
      char* stop = nullptr;
      errno = 0;
      t.number = hex ? static_cast<double>(std::strtoll(t.text.c_str(), &stop, 16))
                     : std::strtod(t.text.c_str(), &stop);
      if (stop != t.text.c_str() + t.text.size() || errno == ERANGE || !std::isfinite(t.number)) {
        *error = At(t.at) + "'" + t.text + "' is not a number (numbers look like 1, -0.5, 2e-3)";
        return false;
      }
      t.kind = Token::kNumber;
    } else {
      t.kind = Token::kWord;
    }
    tokens->push_back(t);
    advance(end - i);
  }
  Token end_token;
  end_token.kind = Token::kEnd;
  end_token.at = at;
  tokens->push_back(end_token);
  return true;
}

}  // namespace ohrp::vrml
