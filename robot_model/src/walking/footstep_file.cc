// Footstep files: the written steps placed in W and checked against the limits (see
// walking/footstep_file.h; the readers are footstep_yaml.cc and footstep_csv.cc).
#include "walking/footstep_file.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <sstream>

#include "footstep_rows.h"
#include "step_geometry.h"

namespace ohrp::walking {
namespace {

// the key of a step that a refused limit is about
const char* KeyOf(Limit which) {
  switch (which) {
    case Limit::kForward:
    case Limit::kBackward:
      return "x";
    case Limit::kTurn:
    case Limit::kTurnIn:
      return "yaw_deg";
    case Limit::kClearance:
      return "x, y, yaw_deg";
    case Limit::kRise:
      return "z";
    case Limit::kApex:
      return "height";
    case Limit::kDuration:
      return "duration";
    default:
      return "y";
  }
}

// a written step in W: relative to the start's mid frame unless the file says world
Footstep Place(const Written& w, const Header& h, const Frame2& mid) {
  Footstep s;
  s.foot = w.foot;
  const double yaw = w.yaw_deg * M_PI / 180;
  if (h.world) {
    s.p = Eigen::Vector3d(w.x, w.y, w.has_z ? w.z : mid.p.z());
    s.yaw = yaw;
  } else {
    const Eigen::Vector2d xy =
        mid.p.head<2>() + Eigen::Rotation2Dd(mid.yaw) * Eigen::Vector2d(w.x, w.y);
    s.p = Eigen::Vector3d(xy.x(), xy.y(), mid.p.z() + (w.has_z ? w.z : 0));
    s.yaw = mid.yaw + yaw;
  }
  s.height = w.height >= 0 ? w.height : h.height;
  s.duration = w.duration > 0 ? w.duration : h.duration;
  return s;
}

// the written steps in W from `start`, each checked from the stance the steps before leave
bool Finish(const std::vector<Written>& rows, const Header& h, const std::string& name,
            const FeetPose& start, const StepLimits& limits, std::vector<Footstep>* steps,
            std::string* error) {
  if (rows.empty())
    return Fail(error, At(name, 1),
                "steps: the file holds no step (write at least one; docs/footsteps.md)");
  const Frame2 mid = MidFrame(start);
  FeetPose feet = start;
  int previous = -1;
  for (size_t k = 0; k < rows.size(); ++k) {
    const Written& w = rows[k];
    const std::string step = "step " + std::to_string(k + 1) + " (" + SideName(w.foot) + "): ";
    // the feet alternate unless the step says otherwise
    if (w.foot == previous && !w.same_foot)
      return Fail(error, At(name, w.foot_line),
                  std::string("foot: ") + SideName(w.foot) + " again after a " + SideName(w.foot) +
                      " step (step " + std::to_string(k + 1) +
                      "): the feet alternate (write same_foot: true on this step to step twice "
                      "with one foot)");
    if (w.same_foot && w.foot != previous)
      return Fail(error, At(name, w.line),
                  "same_foot: true on " + step + "but the step before was " +
                      (previous < 0 ? std::string("none")
                                    : std::string("by the ") + SideName(previous) + " foot") +
                      " (remove it)");
    // the limits
    const Footstep s = Place(w, h, mid);
    Limit which;
    const std::string why = CheckStepLimit(feet, s, limits, &which);
    if (!why.empty()) return Fail(error, At(name, w.line), KeyOf(which) + (": " + step) + why);
    steps->push_back(s);
    feet = After(feet, s);
    previous = w.foot;
  }
  return true;
}

}  // namespace

bool FootstepFormatOf(const std::string& path, FootstepFormat* format) {
  auto ends = [&](const std::string& s) {
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".yaml") || ends(".yml")) {
    *format = FootstepFormat::kYaml;
    return true;
  }
  if (ends(".csv")) {
    *format = FootstepFormat::kCsv;
    return true;
  }
  return false;
}

bool ParseFootstepText(const std::string& text, FootstepFormat format, const std::string& name,
                       const FeetPose& start, const StepLimits& limits,
                       std::vector<Footstep>* steps, std::string* error) {
  steps->clear();
  const std::string bad = CheckLimits(limits);
  if (!bad.empty()) return Fail(error, name + ": ", bad);
  Header h;
  std::vector<Written> rows;
  bool ok = false;
  try {
    ok = format == FootstepFormat::kYaml ? ParseYamlSteps(text, name, &h, &rows, error)
                                         : ParseCsvSteps(text, name, &rows, error);
  } catch (const YAML::Exception& e) {  // a node yaml-cpp could not read after loading
    ok = Fail(error, At(name, e.mark.line + 1), "cannot read the YAML: " + e.msg);
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
    return Fail(error, path + ": ",
                "not a footstep file: the name must end in .yaml, .yml or .csv");
  std::ifstream in(path);
  if (!in) return Fail(error, path + ": ", "cannot be read (does it exist?)");
  std::stringstream text;
  text << in.rdbuf();
  return ParseFootstepText(text.str(), format, path, start, limits, steps, error);
}

}  // namespace ohrp::walking
