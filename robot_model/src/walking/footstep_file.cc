// Footstep files, YAML and CSV (see walking/footstep_file.h and docs/footsteps.md).
#include "walking/footstep_file.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "step_geometry.h"

namespace ohrp::walking {
namespace {

constexpr double kMaxHeight = 0.5;     // [m] swing apex a file may ask for
constexpr double kMaxDuration = 10.0;  // [s] step time a file may ask for
const char* const kStepKeys = "foot, x, y, yaw_deg (required); z, height, duration, same_foot";

// one step as written, with the line of each part for messages
struct Written {
  int line = 0;       // the step's first line (1-based)
  int foot_line = 0;  // the line of its foot
  int foot = -1;
  double x = 0, y = 0, z = 0, yaw_deg = 0, height = -1, duration = -1;
  bool has_z = false, same_foot = false;
};

// what the file says besides its steps
struct Header {
  bool world = false;                   // frame: world
  double height = -1, duration = -1;    // defaults; <0: the generator's
};

// "NAME:LINE: "
std::string At(const std::string& name, int line) {
  return name + ":" + std::to_string(line) + ": ";
}

// a finite number from text (the whole text), or false
bool Number(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  *out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*out);
}

// range checks of the optional per-step values; "" or why
std::string CheckHeight(double h) {
  if (h < 0 || h > kMaxHeight)
    return "height: " + std::to_string(h) + " m is out of range (0 .. 0.5 m above the higher sole)";
  return "";
}
std::string CheckDuration(double d) {
  if (d <= 0 || d > kMaxDuration)
    return "duration: " + std::to_string(d) + " s is out of range (above 0 .. 10 s)";
  return "";
}

// sets one value of a step from its key and text; "" or why (the key first)
std::string SetValue(const std::string& key, const std::string& text, Written* w) {
  if (key == "foot") {
    if (text == "left") w->foot = kLeft;
    else if (text == "right") w->foot = kRight;
    else return "foot: must be left or right, not '" + text + "'";
    return "";
  }
  if (key == "same_foot") {
    if (text == "true") w->same_foot = true;
    else if (text == "false") w->same_foot = false;
    else return "same_foot: must be true or false, not '" + text + "'";
    return "";
  }
  double v;
  if (!Number(text, &v))
    return key + ": must be a finite number (" + (key == "yaw_deg" ? "deg" : key == "duration" ? "s" : "m") +
           "), not '" + text + "'";
  if (key == "x") w->x = v;
  else if (key == "y") w->y = v;
  else if (key == "z") w->z = v, w->has_z = true;
  else if (key == "yaw_deg") w->yaw_deg = v;
  else if (key == "height") w->height = v;
  else if (key == "duration") w->duration = v;
  if (key == "height") return CheckHeight(v);
  if (key == "duration") return CheckDuration(v);
  return "";
}

const std::set<std::string>& StepKeys() {
  static const std::set<std::string> keys = {"foot", "x",      "y",        "z",
                                             "yaw_deg", "height", "duration", "same_foot"};
  return keys;
}

// the required keys all seen; "" or the first missing
std::string Missing(const std::set<std::string>& seen) {
  for (const char* k : {"foot", "x", "y", "yaw_deg"})
    if (!seen.count(k)) return std::string("missing key '") + k + "' (every step has " + kStepKeys + ")";
  return "";
}

// the written steps in W from `start`, checked against the limits one after the other
bool Finish(const std::vector<Written>& rows, const Header& h, const std::string& name,
            const FeetPose& start, const StepLimits& limits, std::vector<Footstep>* steps,
            std::string* error) {
  if (rows.empty()) {
    *error = At(name, 1) + "steps: the file holds no step (write at least one; docs/footsteps.md)";
    return false;
  }
  const Frame2 mid = MidFrame(start);
  FeetPose feet = start;
  int previous = -1;
  for (size_t k = 0; k < rows.size(); ++k) {
    const Written& w = rows[k];
    const std::string step = "step " + std::to_string(k + 1) + " (" + SideName(w.foot) + "): ";
    // the feet alternate unless the step says otherwise
    if (w.foot == previous && !w.same_foot) {
      *error = At(name, w.foot_line) + "foot: " + step + SideName(w.foot) + " again after a " +
               SideName(w.foot) + " step: the feet alternate (write same_foot: true on this step "
               "to step twice with one foot)";
      return false;
    }
    if (w.same_foot && w.foot != previous) {
      *error = At(name, w.line) + "same_foot: " + step + "says true but the step before was " +
               (previous < 0 ? std::string("none") : std::string("by the ") + SideName(previous) +
                                                          " foot") + " (remove it)";
      return false;
    }
    // the pose in W
    Footstep s;
    s.foot = w.foot;
    const double yaw = w.yaw_deg * M_PI / 180;
    if (h.world) {
      s.p = Eigen::Vector3d(w.x, w.y, w.has_z ? w.z : mid.p.z());
      s.yaw = yaw;
    } else {
      const Eigen::Vector2d xy = mid.p.head<2>() + Eigen::Rotation2Dd(mid.yaw) * Eigen::Vector2d(w.x, w.y);
      s.p = Eigen::Vector3d(xy.x(), xy.y(), mid.p.z() + (w.has_z ? w.z : 0));
      s.yaw = mid.yaw + yaw;
    }
    s.height = w.height >= 0 ? w.height : h.height;
    s.duration = w.duration > 0 ? w.duration : h.duration;
    // the limits from the stance the steps before leave
    const std::string why = CheckStep(feet, s, limits);
    if (!why.empty()) {
      *error = At(name, w.line) + step + why;
      return false;
    }
    steps->push_back(s);
    feet = After(feet, s);
    previous = w.foot;
  }
  return true;
}

//---------------- YAML ----------------

// a YAML scalar's text, or why it is not one
bool Scalar(const YAML::Node& n, const std::string& key, std::string* out, std::string* why) {
  if (n.IsScalar()) {
    *out = n.Scalar();
    return true;
  }
  *why = key + ": must be a single value, not " + (n.IsSequence() ? "a list" : n.IsMap() ? "a mapping" : "empty");
  return false;
}

bool ParseYaml(const std::string& text, const std::string& name, Header* h,
               std::vector<Written>* rows, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    *error = At(name, e.mark.line + 1) + "not valid YAML: " + e.msg;
    return false;
  }
  if (!root.IsMap()) {
    *error = At(name, 1) + "steps: the file must be a mapping with a list `steps:` (docs/footsteps.md)";
    return false;
  }
  std::string why, v;
  // the top level: frame, defaults, steps, description
  std::set<std::string> seen;
  YAML::Node steps;
  int steps_line = 1;
  for (const auto& kv : root) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    const int line = kv.first.Mark().line + 1;
    if (!seen.insert(key).second) return *error = At(name, line) + key + ": given twice", false;
    if (key == "frame") {
      if (!Scalar(kv.second, key, &v, &why)) return *error = At(name, line) + why, false;
      if (v != "start" && v != "world")
        return *error = At(name, line) + "frame: must be start or world, not '" + v + "'", false;
      h->world = v == "world";
    } else if (key == "defaults") {
      if (!kv.second.IsMap())
        return *error = At(name, line) + "defaults: must be a mapping of height and duration", false;
      for (const auto& d : kv.second) {
        const std::string dk = d.first.IsScalar() ? d.first.Scalar() : "?";
        const int dl = d.first.Mark().line + 1;
        if (dk != "height" && dk != "duration")
          return *error = At(name, dl) + "defaults: unknown key '" + dk + "' (known: duration, height)", false;
        double x;
        if (!Scalar(d.second, dk, &v, &why)) return *error = At(name, dl) + why, false;
        if (!Number(v, &x)) return *error = At(name, dl) + dk + ": must be a finite number, not '" + v + "'", false;
        why = dk == "height" ? CheckHeight(x) : CheckDuration(x);
        if (!why.empty()) return *error = At(name, dl) + why, false;
        (dk == "height" ? h->height : h->duration) = x;
      }
    } else if (key == "steps") {
      steps = kv.second;
      steps_line = line;
    } else if (key == "description") {
      if (!Scalar(kv.second, key, &v, &why)) return *error = At(name, line) + why, false;
    } else {
      *error = At(name, line) + "unknown key '" + key + "' (known: defaults, description, frame, steps)";
      return false;
    }
  }
  if (!steps.IsDefined())
    return *error = At(name, 1) + "steps: missing: the file needs a list `steps:` (docs/footsteps.md)", false;
  if (!steps.IsSequence())
    return *error = At(name, steps_line) + "steps: must be a list of steps, e.g. - {foot: left, x: 0.2, y: 0.09, yaw_deg: 0}", false;
  // the steps
  for (const auto& item : steps) {
    Written w;
    w.line = item.Mark().line + 1;
    if (!item.IsMap())
      return *error = At(name, w.line) + "steps: each step must be a mapping, e.g. {foot: left, x: 0.2, y: 0.09, yaw_deg: 0}", false;
    std::set<std::string> keys;
    for (const auto& kv : item) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
      const int line = kv.first.Mark().line + 1;
      if (!StepKeys().count(key))
        return *error = At(name, line) + "unknown key '" + key + "' (known: " + kStepKeys + ")", false;
      if (!keys.insert(key).second) return *error = At(name, line) + key + ": given twice", false;
      if (!Scalar(kv.second, key, &v, &why)) return *error = At(name, line) + why, false;
      why = SetValue(key, v, &w);
      if (!why.empty()) return *error = At(name, line) + why, false;
      if (key == "foot") w.foot_line = line;
    }
    why = Missing(keys);
    if (!why.empty()) return *error = At(name, w.line) + why, false;
    rows->push_back(w);
  }
  return true;
}

//---------------- CSV ----------------

// the comma-separated cells of a line, trimmed
std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string c;
  while (std::getline(in, c, ',')) {
    const size_t a = c.find_first_not_of(" \t"), b = c.find_last_not_of(" \t");
    out.push_back(a == std::string::npos ? "" : c.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

bool ParseCsv(const std::string& text, const std::string& name, std::vector<Written>* rows,
              std::string* error) {
  std::stringstream in(text);
  std::string line;
  std::vector<std::string> columns;
  for (int n = 1; std::getline(in, line); ++n) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#')
      continue;
    const std::vector<std::string> cells = Cells(line);
    // the header names the columns
    if (columns.empty()) {
      std::set<std::string> seen;
      for (const auto& c : cells) {
        if (!StepKeys().count(c))
          return *error = At(name, n) + "unknown column '" + c + "' (known: " + kStepKeys + ")", false;
        if (!seen.insert(c).second) return *error = At(name, n) + c + ": column given twice", false;
      }
      const std::string why = Missing(seen);
      if (!why.empty()) return *error = At(name, n) + "header: " + why, false;
      columns = cells;
      continue;
    }
    // a step; an empty cell of an optional column is the default
    if (cells.size() != columns.size())
      return *error = At(name, n) + "row: " + std::to_string(cells.size()) + " cells, the header has " +
                      std::to_string(columns.size()) + " (" + line + ")", false;
    Written w;
    w.line = w.foot_line = n;
    for (size_t i = 0; i < cells.size(); ++i) {
      const std::string& key = columns[i];
      if (cells[i].empty()) {
        if (key == "foot" || key == "x" || key == "y" || key == "yaw_deg")
          return *error = At(name, n) + key + ": empty (every step has " + kStepKeys + ")", false;
        continue;
      }
      const std::string why = SetValue(key, cells[i], &w);
      if (!why.empty()) return *error = At(name, n) + why, false;
    }
    rows->push_back(w);
  }
  if (columns.empty())
    return *error = At(name, 1) + "header: missing: the first line names the columns, e.g. foot,x,y,yaw_deg", false;
  return true;
}

}  // namespace

bool FootstepFormatOf(const std::string& path, FootstepFormat* format) {
  auto ends = [&](const std::string& s) {
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".yaml") || ends(".yml")) return *format = FootstepFormat::kYaml, true;
  if (ends(".csv")) return *format = FootstepFormat::kCsv, true;
  return false;
}

bool ParseFootstepText(const std::string& text, FootstepFormat format, const std::string& name,
                       const FeetPose& start, const StepLimits& limits,
                       std::vector<Footstep>* steps, std::string* error) {
  steps->clear();
  const std::string bad = CheckLimits(limits);
  if (!bad.empty()) return *error = name + ": " + bad, false;
  Header h;
  std::vector<Written> rows;
  bool ok = false;
  try {
    ok = format == FootstepFormat::kYaml ? ParseYaml(text, name, &h, &rows, error)
                                         : ParseCsv(text, name, &rows, error);
  } catch (const YAML::Exception& e) {  // a node yaml-cpp could not read after loading
    *error = At(name, e.mark.line + 1) + "cannot read the YAML: " + e.msg;
    ok = false;
  }
  ok = ok && Finish(rows, h, name, start, limits, steps, error);
  if (!ok) steps->clear();
  return ok;
}

bool ReadFootstepFile(const std::string& path, const FeetPose& start, const StepLimits& limits,
                      std::vector<Footstep>* steps, std::string* error) {
  steps->clear();
  FootstepFormat format;
  if (!FootstepFormatOf(path, &format))
    return *error = path + ": not a footstep file: the name must end in .yaml, .yml or .csv", false;
  std::ifstream in(path);
  if (!in) return *error = path + ": cannot be read (does it exist?)", false;
  std::stringstream text;
  text << in.rdbuf();
  return ParseFootstepText(text.str(), format, path, start, limits, steps, error);
}

}  // namespace ohrp::walking
