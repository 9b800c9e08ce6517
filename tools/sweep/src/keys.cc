// Scenario keys by path (see sweep.h: SetKey, NumberText; keys.h).
#include "keys.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace ohrp::sweep {
namespace {

// sets tokens[k..] under `node` (a handle: assignments reach the document)
bool SetIn(YAML::Node node, const std::vector<Token>& tokens, size_t k, const Value& value,
           std::string* why) {
  const Token& t = tokens[k];
  const bool last = k + 1 == tokens.size();
  if (t.index >= 0) {
    if (!node.IsSequence() || t.index >= static_cast<long>(node.size())) {
      *why = "no item [" + std::to_string(t.index) + "] there (" +
             (node.IsSequence() ? "the list has " + std::to_string(node.size()) : std::string("not a list")) + ")";
      return false;
    }
    if (last) {
      node[t.index] = value.text;
      return true;
    }
    return SetIn(node[t.index], tokens, k + 1, value, why);
  }
  if (node.IsDefined() && !node.IsNull() && !node.IsMap()) {
    *why = "'" + t.name + "' is under a value that is not a mapping";
    return false;
  }
  if (last) {
    node[t.name] = value.text;
    return true;
  }
  return SetIn(node[t.name], tokens, k + 1, value, why);
}

}  // namespace

bool SplitKey(const std::string& key, std::vector<Token>* out, std::string* why) {
  out->clear();
  size_t i = 0;
  while (i < key.size()) {
    if (key[i] == '[') {
      const size_t close = key.find(']', i);
      const std::string digits = close == std::string::npos ? "" : key.substr(i + 1, close - i - 1);
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) {
        *why = "'" + key + "': '[' must hold a list index, e.g. pushes[0].impulse";
        return false;
      }
      out->push_back({"", std::stol(digits)});
      i = close + 1;
      if (i < key.size() && key[i] == '.') ++i;
      continue;
    }
    const size_t end = key.find_first_of(".[", i);
    const std::string name = key.substr(i, end == std::string::npos ? std::string::npos : end - i);
    if (name.empty()) {
      *why = "'" + key + "' has an empty part (write keys joined by '.', e.g. contact_params.stiffness)";
      return false;
    }
    out->push_back({name, -1});
    if (end == std::string::npos) break;
    i = key[end] == '.' ? end + 1 : end;
    if (key[end] == '.' && i == key.size()) {
      *why = "'" + key + "' ends with '.'";
      return false;
    }
  }
  if (out->empty()) *why = "the key is empty";
  return !out->empty();
}

std::string NumberText(double v) {
  // not a number: said as such (inf, -inf, nan), as strtod reads them back
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf";
  char b[40];
  // whole numbers in full (3000000, 30), others in the fewest significant digits that read back
  if (std::fabs(v) < 1e15 && v == std::round(v)) {
    std::snprintf(b, sizeof(b), "%.0f", v);
    return b;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(b, sizeof(b), "%.*g", digits, v);
    if (std::strtod(b, nullptr) == v) break;
  }
  return b;
}

bool SetKey(const std::string& yaml, const std::string& key, const Value& value,
            std::string* out_yaml, std::string* why) {
  std::vector<Token> tokens;
  if (!SplitKey(key, &tokens, why)) return false;
  try {
    YAML::Node root = YAML::Load(yaml);
    if (!root.IsMap()) {
      *why = "the scenario is not a YAML mapping";
      return false;
    }
    if (!SetIn(root, tokens, 0, value, why)) return false;
    YAML::Emitter e;
    e << root;
    *out_yaml = std::string(e.c_str()) + "\n";
    return true;
  } catch (const YAML::Exception& ex) {
    *why = std::string("cannot set it: ") + ex.what();
    return false;
  }
}

}  // namespace ohrp::sweep
