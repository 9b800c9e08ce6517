// Reading a YAML input file (a joint file, a contact file, a goals file, ...) with the one error
// wording every program uses: "PATH: cannot read the WHAT" when the file cannot be opened,
// "PATH:LINE: not YAML: ..." when it does not parse. The caller then checks the keys and values.
//
// Use:
//   YAML::Node root;
//   if (!ohrp::cli::LoadYamlFile(path, "joint file", &root, error)) return false;
//
// Header-only; the including library links yaml-cpp itself (ohrp::cli does not).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace ohrp::cli {

inline bool LoadYamlFile(const std::string& path, const std::string& what, YAML::Node* root,
                         std::string* error) {
  try {
    *root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    *error = path + ": cannot read the " + what;
    return false;
  } catch (const YAML::Exception& e) {
    *error = path + ":" + std::to_string(e.mark.line + 1) + ": not YAML: " + e.msg;
    return false;
  }
  return true;
}

}  // namespace ohrp::cli
