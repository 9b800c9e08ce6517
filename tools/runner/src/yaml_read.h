// Typed reads of scenario values (internal to the runner library). Each read refuses what is not
// of its type; the caller prefixes the message with At() so that every error names the file, the
// line and the key: "scenario 'FILE': line N: KEY: must be a number, not 'low'".
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

namespace ohrp::runner {

// "scenario 'FILE': line N: " for the node (its first line, 1-based). `kind` names what the
// file is: a scenario, or a file of another format read with these functions ("sweep").
std::string At(const std::string& path, const YAML::Node& node, const char* kind = "scenario");

// At() of the key `key` of mapping `map` (the line of the key: a value left empty has no line
// of its own); At(map) when the key is absent.
std::string AtKey(const std::string& path, const YAML::Node& map, const std::string& key,
                  const char* kind = "scenario");

// A finite number. False with `*why` ("must be a number, not 'low'" or "must be finite").
bool ReadNumber(const YAML::Node& n, double* out, std::string* why);
// A whole number.
bool ReadInteger(const YAML::Node& n, long long* out, std::string* why);
// A scalar, as written (numbers too: `2.0` reads "2.0"); a list or a mapping is refused.
bool ReadText(const YAML::Node& n, std::string* out, std::string* why);
// true or false (also yes/no, on/off).
bool ReadBool(const YAML::Node& n, bool* out, std::string* why);
// A list of scalars (an empty list is a list).
bool ReadTextList(const YAML::Node& n, std::vector<std::string>* out, std::string* why);
// One of `choices`; `why` lists them.
bool ReadChoice(const YAML::Node& n, const std::vector<std::string>& choices, std::string* out,
                std::string* why);

// The keys of mapping `map` are all in `known` and none is repeated. False with `*error`
// (prefixed with At() of the key) naming the first key that is not, and the known ones.
bool KnownKeysOnly(const YAML::Node& map, const std::set<std::string>& known,
                   const std::string& path, const std::string& where, std::string* error,
                   const char* kind = "scenario");

// "a, b, c"
std::string JoinNames(const std::set<std::string>& names);

}  // namespace ohrp::runner
