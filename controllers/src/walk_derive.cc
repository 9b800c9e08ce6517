// The walk's figures derived from the robot's leg where not given (derived_gait.h;
// docs/robots.md "Derived from the robot").
#include <algorithm>
#include <cstdio>
#include <string>

#include "controllers/derived_gait.h"
#include "controllers/walk.h"

namespace ohrp::controllers {

void WalkController::DeriveGait(double leg) {
  // once: the first fit (Preflight) derives, the values stay for on_configure's
  if (gait_derived_ || !(leg > 0)) return;
  gait_derived_ = true;
  const std::vector<std::string>& given = walk_options_.given;
  auto is_given = [&](const char* key) {
    return std::find(given.begin(), given.end(), key) != given.end();
  };
  // HRP-1S's figures: the defaults of StepLimits and GaitOptions
  const walking::StepLimits lim0;
  const walking::GaitOptions gait0;
  DerivedGait d = ScaleGait(leg, kAnchorLegLength, lim0.max_forward, gait0.step_height,
                            gait0.step_time);
  // a stance leg whose servos yield under the weight: a shorter stride
  const double scaled_stride = d.max_forward;
  d.max_forward = CompliantStride(d.max_forward, leg, walk_options_.balance.stance_sag);
  std::string derived;
  char buf[120];
  // a figure given, or set to another value than the default by a program building WalkOptions
  // itself, stays
  auto take = [&](const char* key, double* value, double v, double fallback, const char* unit) {
    if (is_given(key) || *value != fallback) return;
    *value = v;
    std::snprintf(buf, sizeof buf, "%s%s %.3f %s", derived.empty() ? "" : ", ", key, v, unit);
    derived += buf;
  };
  take("max_forward", &walk_options_.limits.max_forward, d.max_forward, lim0.max_forward, "m");
  take("step_height", &walk_options_.gait.step_height, d.step_height, gait0.step_height, "m");
  take("step_time", &walk_options_.gait.step_time, d.step_time, gait0.step_time, "s");
  if (derived.empty()) return;
  if (d.max_forward != scaled_stride && derived.find("max_forward") != std::string::npos) {
    std::snprintf(buf, sizeof buf,
                  "; the stride %.3f m less the hip's %.3f m that the stance leg's sag %.4f rad "
                  "allows",
                  scaled_stride, scaled_stride - d.max_forward, walk_options_.balance.stance_sag);
    derived += buf;
  }
  std::fprintf(stderr,
               "%s: derived from the leg (%s; the rest given): leg %.4f m = %.3f x HRP-1S's "
               "%.3f m; lengths scale with the leg (HRP-1S: stride %.2f m, swing %.3f m), times "
               "with sqrt(leg / g) (HRP-1S: %.2f s steps)\n",
               walk_options_.balance.program.c_str(), derived.c_str(), leg, d.ratio,
               kAnchorLegLength, lim0.max_forward, gait0.step_height, gait0.step_time);
}

}  // namespace ohrp::controllers
