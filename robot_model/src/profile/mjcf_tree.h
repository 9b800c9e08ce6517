// An MJCF document as an editable tree (Boost.PropertyTree's XML reader and writer): read with
// its <include>s expanded as MuJoCo does (the included file's <mujoco> children in place of the
// include, file names relative to the main file's folder), edited, written back as text. The
// robot profile (robot_model/profile.h) augments a model this way, in memory.
#pragma once

#include <boost/property_tree/ptree.hpp>

#include <string>

namespace ohrp::model::mjcf {

using Tree = boost::property_tree::ptree;

// Parses `text` (named `file` in messages; its folder is the base of include file names) and
// expands its includes recursively (at most 32 files, a file included twice is an error, as in
// MuJoCo). `*doc` holds one child, "mujoco". False with `*error` set on malformed XML or an
// include that cannot be read.
bool ReadExpanded(const std::string& text, const std::string& file, Tree* doc, std::string* error);

// The document as XML text.
std::string Write(const Tree& doc);

// The element <body name="NAME"> anywhere under <worldbody> (nested), or null.
Tree* FindBody(Tree* mujoco, const std::string& name);

// The `k`-th child element named `tag` of `element` (0-based), or null.
Tree* NthChild(Tree* element, const std::string& tag, int k);

// Appends <tag attr.../> to `parent` and returns it.
Tree& Append(Tree* parent, const std::string& tag);

// A number as an attribute value (10 significant digits).
std::string Number(double v);

// Sets attribute `name` of `element`.
void SetAttr(Tree* element, const std::string& name, const std::string& value);

// Removes every <key name="NAME"> from the <keyframe> sections of `mujoco`.
void RemoveKey(Tree* mujoco, const std::string& name);

}  // namespace ohrp::model::mjcf
