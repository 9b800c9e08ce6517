// The values of a written step: keys, types and ranges (see footstep_rows.h).
#include "footstep_rows.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "walking/footsteps.h"

namespace ohrp::walking {
namespace {

constexpr double kMaxHeight = 0.5;     // [m] swing apex a file may ask for
constexpr double kMaxDuration = 10.0;  // [s] step time a file may ask for

// a number as a person would write it
std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%g", v);
  return b;
}

// the unit of a numeric key, for messages
const char* Unit(const std::string& key) {
  if (key == "yaw_deg") return "deg";
  if (key == "duration") return "s";
  return "m";
}

}  // namespace

const char* const kStepKeys = "foot, x, y, yaw_deg (required); z, height, duration, same_foot";

const std::set<std::string>& StepKeys() {
  static const std::set<std::string> keys = {"foot",    "x",      "y",        "z",
                                             "yaw_deg", "height", "duration", "same_foot"};
  return keys;
}

std::string At(const std::string& name, int line) {
  return name + ":" + std::to_string(line) + ": ";
}

bool Fail(std::string* error, const std::string& at, const std::string& why) {
  *error = at + why;
  return false;
}

bool Number(const std::string& text, double* out) {
  if (text.empty()) return false;
  char* end = nullptr;
  *out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*out);
}

std::string CheckHeight(double h) {
  if (h < 0 || h > kMaxHeight)
    return "height: " + Num(h) + " m is out of range (0 .. 0.5 m above the higher sole)";
  return "";
}

std::string CheckDuration(double d) {
  if (d <= 0 || d > kMaxDuration)
    return "duration: " + Num(d) + " s is out of range (above 0 .. 10 s)";
  return "";
}

std::string SetValue(const std::string& key, const std::string& text, Written* w) {
  // the words
  if (key == "foot") {
    if (text != "left" && text != "right") return "foot: must be left or right, not '" + text + "'";
    w->foot = text == "left" ? kLeft : kRight;
    return "";
  }
  if (key == "same_foot") {
    if (text != "true" && text != "false")
      return "same_foot: must be true or false, not '" + text + "'";
    w->same_foot = text == "true";
    return "";
  }
  // the numbers
  double v;
  if (!Number(text, &v))
    return key + ": must be a finite number [" + Unit(key) + "], not '" + text + "'";
  if (key == "x") w->x = v;
  if (key == "y") w->y = v;
  if (key == "z") {
    w->z = v;
    w->has_z = true;
  }
  if (key == "yaw_deg") w->yaw_deg = v;
  if (key == "height") w->height = v;
  if (key == "duration") w->duration = v;
  if (key == "height") return CheckHeight(v);
  if (key == "duration") return CheckDuration(v);
  return "";
}

std::string Missing(const std::set<std::string>& seen) {
  for (const char* k : {"foot", "x", "y", "yaw_deg"})
    if (!seen.count(k))
      return std::string("missing key '") + k + "' (every step has " + kStepKeys + ")";
  return "";
}

}  // namespace ohrp::walking
