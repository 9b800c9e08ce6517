// Typed reads of scenario values (see yaml_read.h).
#include "yaml_read.h"

#include <cmath>

namespace ohrp::runner {
namespace {

// a scalar's text for a message, or what the node is instead
std::string Shown(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  return "nothing";
}

}  // namespace

std::string At(const std::string& path, const YAML::Node& node, const char* kind) {
  return std::string(kind) + " '" + path + "': line " + std::to_string(node.Mark().line + 1) + ": ";
}

std::string AtKey(const std::string& path, const YAML::Node& map, const std::string& key,
                  const char* kind) {
  if (map.IsMap())
    for (const auto& kv : map)
      if (kv.first.IsScalar() && kv.first.Scalar() == key) return At(path, kv.first, kind);
  return At(path, map, kind);
}

bool ReadNumber(const YAML::Node& n, double* out, std::string* why) {
  try {
    if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "not a scalar");
    *out = n.as<double>();
  } catch (const YAML::Exception&) {
    *why = "must be a number, not " + Shown(n);
    return false;
  }
  if (!std::isfinite(*out)) {
    *why = "must be finite, not " + Shown(n);
    return false;
  }
  return true;
}

bool ReadInteger(const YAML::Node& n, long long* out, std::string* why) {
  try {
    if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "not a scalar");
    *out = n.as<long long>();
    return true;
  } catch (const YAML::Exception&) {
    *why = "must be a whole number, not " + Shown(n);
    return false;
  }
}

bool ReadText(const YAML::Node& n, std::string* out, std::string* why) {
  if (!n.IsScalar()) {
    *why = "must be a single value, not " + Shown(n);
    return false;
  }
  *out = n.Scalar();
  return true;
}

bool ReadBool(const YAML::Node& n, bool* out, std::string* why) {
  try {
    if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "not a scalar");
    *out = n.as<bool>();
    return true;
  } catch (const YAML::Exception&) {
    *why = "must be true or false, not " + Shown(n);
    return false;
  }
}

bool ReadTextList(const YAML::Node& n, std::vector<std::string>* out, std::string* why) {
  if (!n.IsSequence()) {
    *why = "must be a list, e.g. [a, b], not " + Shown(n);
    return false;
  }
  out->clear();
  for (const auto& item : n) {
    if (!item.IsScalar()) {
      *why = "must be a list of single values, not of " + Shown(item) + "s";
      return false;
    }
    out->push_back(item.Scalar());
  }
  return true;
}

bool ReadChoice(const YAML::Node& n, const std::vector<std::string>& choices, std::string* out,
                std::string* why) {
  std::string v;
  if (ReadText(n, &v, why)) {
    for (const auto& c : choices)
      if (v == c) {
        *out = v;
        return true;
      }
  }
  std::string list;
  for (size_t i = 0; i < choices.size(); ++i)
    list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  *why = "must be " + list + ", not " + Shown(n);
  return false;
}

bool KnownKeysOnly(const YAML::Node& map, const std::set<std::string>& known,
                   const std::string& path, const std::string& where, std::string* error,
                   const char* kind) {
  std::set<std::string> seen;
  for (const auto& kv : map) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    if (!known.count(key)) {
      *error = At(path, kv.first, kind) + where + "unknown key '" + key + "' (known: " +
               JoinNames(known) + ")";
      return false;
    }
    if (!seen.insert(key).second) {
      *error = At(path, kv.first, kind) + where + "'" + key + "' is given twice";
      return false;
    }
  }
  return true;
}

std::string JoinNames(const std::set<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace ohrp::runner
