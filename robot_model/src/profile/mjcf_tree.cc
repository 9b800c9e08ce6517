// MJCF as an editable tree, includes expanded (see mjcf_tree.h).
#include "profile/mjcf_tree.h"

#include <boost/property_tree/xml_parser.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace ohrp::model::mjcf {
namespace pt = boost::property_tree;
namespace {

constexpr int kMaxFiles = 32;

bool Parse(const std::string& text, const std::string& file, Tree* doc, std::string* error) {
  std::istringstream in(text);
  try {
    pt::read_xml(in, *doc, pt::xml_parser::trim_whitespace | pt::xml_parser::no_comments);
  } catch (const pt::xml_parser_error& e) {
    *error = file + ":" + std::to_string(e.line()) + ": not valid XML: " + e.message();
    return false;
  }
  if (doc->size() != 1 || doc->begin()->first != "mujoco") {
    *error = file + ": the top element must be <mujoco> (an MJCF file)";
    return false;
  }
  return true;
}

struct Expander {
  std::filesystem::path base;  // the main file's folder
  std::set<std::string> seen;
  std::string* error;

  // replaces the <include> children of `element` (at any depth) by the included files' content
  bool Expand(Tree* element, const std::string& where) {
    for (auto it = element->begin(); it != element->end();) {
      if (it->first != "include") {
        if (it->first != "<xmlattr>" && !Expand(&it->second, where)) return false;
        ++it;
        continue;
      }
      const std::string name = it->second.get("<xmlattr>.file", "");
      if (name.empty()) {
        *error = where + ": <include> without a file attribute";
        return false;
      }
      const std::filesystem::path path = std::filesystem::path(name).is_absolute()
                                             ? std::filesystem::path(name) : base / name;
      std::error_code ec;
      const std::string key = std::filesystem::weakly_canonical(path, ec).string();
      if (!seen.insert(key).second) {
        *error = where + ": <include file=\"" + name + "\"> includes a file a second time";
        return false;
      }
      if (static_cast<int>(seen.size()) > kMaxFiles) {
        *error = where + ": more than " + std::to_string(kMaxFiles) + " included files";
        return false;
      }
      std::ifstream in(path, std::ios::binary);
      if (!in || !std::filesystem::is_regular_file(path, ec)) {
        *error = where + ": cannot read included file '" + path.string() +
                 "' (include names are relative to the main file's folder)";
        return false;
      }
      std::ostringstream s;
      s << in.rdbuf();
      Tree inner;
      if (!Parse(s.str(), path.string(), &inner, error)) return false;
      Tree& root = inner.begin()->second;
      if (!Expand(&root, path.string())) return false;
      // the included <mujoco>'s children in place of the include (its attributes dropped)
      for (auto& child : root) {
        if (child.first == "<xmlattr>") continue;
        element->insert(it, child);
      }
      it = element->erase(it);
    }
    return true;
  }
};

Tree* FindBodyIn(Tree* element, const std::string& name) {
  for (auto& child : *element) {
    if (child.first != "body") continue;
    if (child.second.get("<xmlattr>.name", "") == name) return &child.second;
    if (Tree* t = FindBodyIn(&child.second, name)) return t;
  }
  return nullptr;
}

}  // namespace

bool ReadExpanded(const std::string& text, const std::string& file, Tree* doc, std::string* error) {
  if (!Parse(text, file, doc, error)) return false;
  Expander x{std::filesystem::path(file).parent_path(), {}, error};
  std::error_code ec;
  x.seen.insert(std::filesystem::weakly_canonical(file, ec).string());
  return x.Expand(&doc->begin()->second, file);
}

std::string Write(const Tree& doc) {
  std::ostringstream out;
  pt::write_xml(out, doc, pt::xml_writer_make_settings<std::string>(' ', 1));
  return out.str();
}

Tree* FindBody(Tree* mujoco, const std::string& name) {
  for (auto& child : *mujoco) {
    if (child.first != "worldbody") continue;
    if (Tree* t = FindBodyIn(&child.second, name)) return t;
  }
  return nullptr;
}

Tree* NthChild(Tree* element, const std::string& tag, int k) {
  for (auto& child : *element) {
    if (child.first == tag && k-- == 0) return &child.second;
  }
  return nullptr;
}

Tree& Append(Tree* parent, const std::string& tag) {
  return parent->push_back({tag, Tree()})->second;
}

std::string Number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

void SetAttr(Tree* element, const std::string& name, const std::string& value) {
  element->put("<xmlattr>." + name, value);
}

void RemoveKey(Tree* mujoco, const std::string& name) {
  for (auto& section : *mujoco) {
    if (section.first != "keyframe") continue;
    Tree& keys = section.second;
    for (auto it = keys.begin(); it != keys.end();) {
      if (it->first == "key" && it->second.get("<xmlattr>.name", "") == name) {
        it = keys.erase(it);
      } else {
        ++it;
      }
    }
  }
}

}  // namespace ohrp::model::mjcf
