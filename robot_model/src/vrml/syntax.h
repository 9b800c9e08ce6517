// The VRML97 syntax tree of an OpenHRP model file: tokens with their line and column, field
// values, nodes (DEF/USE share one node), PROTO declarations with their field defaults.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ohrp::vrml {

// a position in a file, for messages
struct Where {
  int line = 1;
  int column = 1;
};

struct Token {
  enum Kind { kWord, kNumber, kString, kOpenBracket, kCloseBracket, kOpenBrace, kCloseBrace, kEnd };
  Kind kind = kEnd;
  std::string text;   // the word, or the string without its quotes
  double number = 0;  // kNumber
  Where at;
};

// Splits `text` into tokens (commas are white space, `#` starts a comment). Returns false with
// `*error` = "line:column: ..." at a character that starts no token or an unterminated string.
bool Tokenize(const std::string& text, std::vector<Token>* tokens, std::string* error);

struct Node;
using NodePtr = std::shared_ptr<const Node>;

// one field value: numbers (SF/MF Float, Int32, Vec3f, Rotation, Color), strings, a boolean or
// nodes (SFNode/MFNode; NULL is no node)
struct Value {
  enum Kind { kNumbers, kStrings, kBool, kNodes };
  Kind kind = kNumbers;
  std::vector<double> numbers;
  std::vector<std::string> strings;
  bool boolean = false;
  std::vector<NodePtr> nodes;
  Where at;
};

struct Node {
  std::string type;      // Transform, Joint, ...
  std::string def_name;  // DEF name, empty if none
  std::map<std::string, Value> fields;  // defaults of the type, then what the file sets
  Where at;

  // the field or null
  const Value* Field(const std::string& name) const;
  // the first number of a field, or `fallback` when absent or empty
  double Number(const std::string& name, double fallback) const;
  // the first string of a field, or `fallback`
  std::string String(const std::string& name, const std::string& fallback) const;
  // the nodes of an SFNode/MFNode field (empty when absent)
  const std::vector<NodePtr>& Nodes(const std::string& name) const;
};

// a top-level Inline { url "..." }: another file of the scene
struct InlineRef {
  std::string url;
  Where at;
};

struct Document {
  std::vector<NodePtr> roots;     // top-level nodes, in file order
  std::vector<InlineRef> inlines; // top-level Inline urls, in file order
};

// Parses the tokens. Returns false with `*error` = "line:column: ..." on a syntax error, a USE
// of an undefined name, a field the node's PROTO (or the standard node) does not have, or
// nesting deeper than the parser allows.
bool Parse(const std::vector<Token>& tokens, Document* doc, std::string* error);

// "line:column: "
std::string At(const Where& w);

}  // namespace ohrp::vrml
