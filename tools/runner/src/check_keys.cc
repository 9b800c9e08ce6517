// The check types and their keys, and the reading of one check entry (see runner/check_keys.h).
#include "runner/check_keys.h"

#include <cstdio>
#include <limits>
#include <set>

#include "check_parse.h"
#include "yaml_read.h"

namespace ohrp::runner {
namespace {

constexpr double kBig = 1e300;

// the table's rows, short: a time, a number in a range, a list, a flag
CheckKey Time(const char* name, bool required = false, const char* doc = nullptr) {
  return {name, KeyKind::kTime, required, doc ? doc : required ? "s, required" : "s"};
}
CheckKey Num(const char* name, const char* doc, double lo, double hi, bool lo_open,
             bool required = false, double fallback = std::numeric_limits<double>::quiet_NaN()) {
  return {name, KeyKind::kNumber, required, doc, lo, hi, lo_open, fallback};
}
CheckKey Positive(const char* name, const char* doc, double fallback) {
  return Num(name, doc, 0, kBig, true, false, fallback);
}
CheckKey List(const char* name, const char* doc, bool required = false) {
  return {name, KeyKind::kList, required, doc};
}
CheckKey Flag(const char* name, const char* doc) { return {name, KeyKind::kBool, false, doc}; }

std::string Fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}

std::string Short(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%g", v);
  return b;
}

// "must be > 0", "must be in [0, 180]"
std::string RangeText(const CheckKey& k) {
  if (k.hi >= kBig) return std::string("must be ") + (k.lo_open ? "> " : ">= ") + Short(k.lo);
  return std::string("must be in ") + (k.lo_open ? "(" : "[") + Short(k.lo) + ", " + Short(k.hi) + "]";
}

}  // namespace

//---------------- the table ----------------

const std::vector<CheckType>& CheckTypes() {
  static const std::vector<CheckType> types = {
      {"base_height",
       {Time("after"), Time("until"), Positive("tolerance", "m, 0.02", 0.02),
        Num("reference", "m, default: the window's mean", -kBig, kBig, false)},
       "the base height stays within `tolerance` of `reference` in the window"},
      {"not_fallen",
       {Num("min_height", "m, 0.4", -kBig, kBig, false, false, 0.4),
        Num("max_tilt_deg", "deg, 45", 0, 180, true, false, 45)},
       "over the whole run, the base stays above `min_height` and its z axis within "
       "`max_tilt_deg` of vertical (its roll and pitch together; the heading does not count)"},
      {"feet_carry_weight",
       {Time("after"), Time("until"), List("sensors", "list, required", true),
        Positive("tolerance", "relative, 0.03", 0.03)},
       "the mean of the sensors' summed vertical force equals the weight they carry: the robot's "
       "mass less the mass below each sensor, times g"},
      {"base_displacement",
       {{"axis", KeyKind::kAxis, false, "x, y or z; x"}, Num("min", "m", -kBig, kBig, false),
        Num("max", "m", -kBig, kBig, false), Time("from", false, "s, 0")},
       "the base's displacement from `from` to the end lies in [min, max] (at least one of "
       "the two)"},
      {"goal_reached",
       {Num("x", "m, 0", -kBig, kBig, false, false, 0), Num("y", "m, 0", -kBig, kBig, false, false, 0),
        Num("yaw_deg", "deg, 0", -kBig, kBig, false, false, 0), Positive("tolerance", "m, 0.2", 0.2),
        Positive("tolerance_deg", "deg, 5", 5), Time("from", false, "s, 0")},
       "the base's final pose relative to its pose at `from` (the start), in that heading's frame (x "
       "forward, y left, yaw unwrapped over the run: 360 is a full turn), lies within "
       "`tolerance` of (x, y) and `tolerance_deg` of `yaw_deg` (below); the value is the "
       "distance to (x, y)"},
      {"average_speed",
       {Num("min", "m/s, required", 0, kBig, true, true), Positive("threshold", "m, 0.02", 0.02)},
       "the base's horizontal distance from its start to its end over the time it moved, from "
       "the first time it is `threshold` from its start to the first time after that it is "
       "within `threshold` of its final position, is at least `min` (below)"},
      {"force_ringing",
       {Time("after"), Time("until"), List("sensors", "list, required", true),
        Positive("window", "s, 0.02", 0.02), Num("max", "N, required", 0, kBig, false, true)},
       "the RMS of each sensor's vertical force less its moving average over `window` (the "
       "high-frequency ringing of a stiff contact) stays below `max`"},
      {"standing",
       {Time("stance_at", true), Time("after", true),
        Num("min_height_fraction", "0.8", 0, 1, true, false, 0.8), Num("max_tilt_deg", "deg, 30", 0, 180, true, false, 30),
        List("sensors", "list, optional"), Positive("load_tolerance", "relative, 0.1", 0.1)},
       "still standing after a push (below)"},
      {"settles",
       {Time("at", true), Positive("duration", "s, 0.1", 0.1), Positive("tolerance", "m, 0.01", 0.01),
        Num("fraction", "0.1", 0, 1, true, false, 0.1), Positive("within", "s, 1", 1.0),
        Positive("baseline", "s, 0.5", 0.5), List("sensors", "list; rfsensor, lfsensor")},
       "after the push on [at, at + duration] the base and the ankle torques settle within "
       "`within` (below); the value is the later of the two times"},
      {"cop_inside",
       {Time("after"), Time("until"), List("sensors", "list; default: every sensor with a sole"),
        Num("margin", "m, 0.01", -kBig, kBig, false, false, 0.01), Num("min_fz", "N, 50", 0, kBig, false, false, 50),
        Flag("require_loaded", "false"), Flag("foot_weight", "true")},
       "at every row each sole carrying at least `min_fz` has its centre of pressure at least "
       "`margin` inside its edges (below); the value is the smallest distance inside "
       "(negative: outside)"},
      {"foot_lifted",
       {{"sensor", KeyKind::kText, true, "required"}, Time("after", true), Time("until", true),
        Positive("max_fz", "N, 10", 10)},
       "the sensor's vertical force stays below `max_fz` over [after, until] (the foot is in "
       "the air); a log ending before `until` fails"},
      {"ball_centred",
       {{"geom", KeyKind::kText, true, "required"}, {"camera", KeyKind::kText, true, "required"},
        Num("width", "pixel, 640", 1, 640, false, false, 640),
        Num("height", "pixel, 480", 1, 480, false, false, 480),
        Positive("tolerance", "pixel, 10", 10), Time("at", false, "s, the end of the log")},
       "at `at` the centre of geom `geom`, projected by a pinhole camera at camera `camera`'s "
       "pose (the logged base pose and joint angles through the scene's kinematics, the "
       "camera's fovy, a `width` x `height` image), lies within `tolerance` pixels of the "
       "image centre (runner/vision_checks.h)"},
      {"obstacle_contacts",
       {Num("max", "cycles, 0", 0, kBig, false, false, 0)},
       "the robot's contacts with the scene's static obstacles (geoms welded to the world, not "
       "the floor), measured on the logged motion (the simulated base pose and joint angles "
       "through the scene's model and MuJoCo's collision functions; runner/obstacle_checks.h): "
       "the logged cycles in which a robot geom penetrates one are at most `max`; the detail "
       "names the first contact and the deepest"},
      {"obstacle_clearance",
       {Num("min", "m, 0", -1, 1, false, false, 0)},
       "the robot's clearance from the scene's static obstacles on the logged motion (as "
       "obstacle_contacts, with the self-collision checker's certified distances; "
       "runner/obstacle_checks.h): the smallest distance of a robot geom to one is at least `min` "
       "[m]; the detail names the closest pair, when, and the cycles below `min`"},
      {"max_rejected",
       {Num("max", "0", 0, kBig, false, false, 0)},
       "joint commands rejected by the servos (NaN, out of range) are at most `max`"},
      {"real_time_factor",
       {Num("min", "required", 0, kBig, true, true)},
       "sim_host's simulated time over its wall time while simulating (waits for a controller left out) is at least `min`"},
      {"self_collisions",
       {Num("max", "cycles, 0", 0, kBig, false, false, 0),
        {"pair", KeyKind::kText, false, "LINK_A/LINK_B, optional"},
        Num("min_distance_mm", "mm, optional; 0", -kBig, kBig, false, false, 0)},
       "sim_host's `self_collision` effect (switched on by this check; docs/selfcollision.md): "
       "the control cycles in which two of the robot's links penetrate are at most `max`; with "
       "`pair`, instead, that pair of links (either order) was in contact; with "
       "`min_distance_mm`, instead, the closest approach of any checked pair over the run (its "
       "smallest signed distance, negative when penetrating) is at least that; the detail names "
       "each pair with its first time and deepest penetration, and the closest approach"},
      {"self_collision_holds",
       {Num("max", "holds, 0", 0, kBig, false, false, 0)},
       "the controller's self-collision guard began at most `max` hold episodes (sim_host's "
       "summary \"self_collision_guard\", from the segment's guard record); the detail names "
       "the first and the closest pair with the guard's predicted distance"},
  };
  return types;
}

const CheckType* FindCheckType(const std::string& type) {
  for (const auto& t : CheckTypes())
    if (type == t.type) return &t;
  return nullptr;
}

double CheckDefault(const std::string& type, const std::string& key) {
  if (const CheckType* t = FindCheckType(type))
    for (const auto& k : t->keys)
      if (key == k.name) return k.fallback;
  return std::numeric_limits<double>::quiet_NaN();
}

std::string CheckTypeNames() {
  std::string s;
  for (const auto& t : CheckTypes()) s += (s.empty() ? "" : ", ") + std::string(t.type);
  return s;
}

//---------------- one entry ----------------

bool ParseCheck(const YAML::Node& entry, size_t index, double duration, const std::string& path,
                CheckSpec* out, std::string* error) {
  std::string where = "checks[" + std::to_string(index) + "]: ";
  if (!entry.IsMap()) {
    *error = At(path, entry) + where + "each check must be a mapping with a 'type', e.g. "
             "{type: not_fallen, min_height: 0.5}";
    return false;
  }
  // the type first: it says which keys are known
  std::string why;
  if (!entry["type"]) {
    *error = At(path, entry) + where + "'type' is required (one of " + CheckTypeNames() + ")";
    return false;
  }
  if (!ReadText(entry["type"], &out->type, &why)) {
    *error = AtKey(path, entry, "type") + where + "type: " + why;
    return false;
  }
  const CheckType* type = FindCheckType(out->type);
  if (!type) {
    *error = AtKey(path, entry, "type") + where + "unknown check type '" + out->type +
             "' (known: " + CheckTypeNames() + ")";
    return false;
  }
  where = "checks[" + std::to_string(index) + "] (" + out->type + "): ";
  std::set<std::string> known = {"type"};
  for (const auto& k : type->keys) known.insert(k.name);
  if (!KnownKeysOnly(entry, known, path, where, error)) return false;

  // each key: present when required, of its kind, in its range
  out->params.clear();
  for (const auto& k : type->keys) {
    const YAML::Node n = entry[k.name];
    if (!n) {
      if (k.required) {
        *error = At(path, entry) + where + "'" + k.name + "' is required";
        return false;
      }
      continue;
    }
    const std::string at = AtKey(path, entry, k.name) + where + k.name + ": ";
    std::string value;
    bool ok = true;
    switch (k.kind) {
      case KeyKind::kNumber:
      case KeyKind::kTime: {
        double v = 0;
        ok = ReadNumber(n, &v, &why);
        if (ok && k.kind == KeyKind::kTime && (v < 0 || v > duration)) {
          why = "must be a time within the run, [0, " + Short(duration) + "] s, not " + Short(v);
          ok = false;
        }
        if (ok && k.kind == KeyKind::kNumber && (v < k.lo || (k.lo_open && v == k.lo) || v > k.hi)) {
          why = RangeText(k) + ", not " + Short(v);
          ok = false;
        }
        value = Fmt(v);
        break;
      }
      case KeyKind::kText:
        ok = ReadText(n, &value, &why) && !value.empty();
        if (ok && value.find(',') != std::string::npos) {
          why = "must be one name, not '" + value + "'";
          ok = false;
        }
        break;
      case KeyKind::kList: {
        std::vector<std::string> items;
        ok = ReadTextList(n, &items, &why);
        if (ok && items.empty()) {
          why = "must name at least one, e.g. [rfsensor, lfsensor]";
          ok = false;
        }
        for (const auto& item : items) value += (value.empty() ? "" : ",") + item;
        break;
      }
      case KeyKind::kBool: {
        bool b = false;
        ok = ReadBool(n, &b, &why);
        value = b ? "true" : "false";
        break;
      }
      case KeyKind::kAxis:
        ok = ReadChoice(n, {"x", "y", "z"}, &value, &why);
        break;
    }
    if (!ok) {
      *error = at + (why.empty() ? "must not be empty" : why);
      return false;
    }
    out->params[k.name] = value;
  }

  // rules between keys
  const auto has = [&](const char* key) { return out->Has(key); };
  const auto num = [&](const char* key) { return out->Number(key, 0); };
  std::string rule;
  if (has("after") && has("until") && !(num("after") < num("until")))
    rule = "'after' must come before 'until'";
  else if (out->type == "base_displacement" && !has("min") && !has("max"))
    rule = "give 'min', 'max' or both (without them it cannot fail)";
  else if (has("min") && has("max") && num("min") > num("max"))
    rule = "'min' must not exceed 'max'";
  else if (out->type == "standing" && num("after") < num("stance_at"))
    rule = "'after' must not come before 'stance_at'";
  else if (out->type == "settles" && num("at") + out->Number("duration", 0.1) > duration)
    rule = "the push [at, at + duration] must end within the run (" + Short(duration) + " s)";
  if (!rule.empty()) {
    *error = At(path, entry) + where + rule;
    return false;
  }
  return true;
}

//---------------- the docs ----------------

std::string CheckTableMarkdown() {
  std::string md = "| type | keys | passes when |\n|---|---|---|\n";
  for (const auto& t : CheckTypes()) {
    std::string keys;
    for (const auto& k : t.keys) {
      keys += (keys.empty() ? "" : ", ") + std::string("`") + k.name + "`";
      if (*k.doc) keys += std::string(" (") + k.doc + ")";
    }
    md += std::string("| `") + t.type + "` | " + keys + " | " + t.passes_when + " |\n";
  }
  return md;
}

}  // namespace ohrp::runner
