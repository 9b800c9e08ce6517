// Checks on the soles' contact, measured from the ankle F/T sensors in sim_host's data log and
// the soles' rectangles in its JSON summary ("soles", see sim_host/report.h):
//   cop_inside   each loaded sole's centre of pressure stays `margin` inside the sole's edges
//                (both soles flat on the ground, no standing on an edge)
//   foot_lifted  a sensor's vertical force stays below `max_fz` (the foot is in the air)
// The scenario keys are listed in checks.h. SI units: metres, newtons, newton metres, seconds.
#pragma once

#include <nlohmann/json.hpp>

#include "runner/checks.h"

namespace ohrp::runner {

// A sole's bottom face in its F/T sensor's frame: x, y ranges and the height z of the face.
struct SoleRect {
  double x[2] = {0, 0};  // [m] min, max
  double y[2] = {0, 0};  // [m] min, max
  double z = 0;          // [m]
  double foot_mass = 0;  // [kg] below the sensor (0: the foot's weight is not corrected for)
  double foot_com[3] = {0, 0, 0};  // [m] its centre of mass, sensor frame
};

// The ground's force f_g and its moment n_g about the sensor origin from the logged f, n, for a
// foot at rest of mass m with its centre of mass at c (sensor frame) whose weight acts along the
// sensor's -z (a sole lying about level: on a 5 deg ramp the error is m g sin 5 deg along x, a
// tenth of a millimetre of CoP for HRP-1S): the foot's balance f_g + W = f and
// n_g + c x W = n with W = (0, 0, -m g) gives
//   f_g = f + (0, 0, m g),   n_g = n + (c_y m g, -c_x m g, 0).
// Without the correction the CoP is off by m g (p_x - c_x) / (f_z + m g) along x: about 5 mm
// at HRP-1S's heel edge (1.9 kg at 8 cm in front of the ankle, 600 N on the sole).
void GroundWrench(const double f[3], const double n[3], double mass, const double com[3],
                  double g, double f_g[3], double n_g[3]);

// The centre of pressure (px, py) on the plane z = `z` of the sensor frame from the ground's
// force f [N] on the sole and its moment n [N m] about the sensor origin (GroundWrench; the
// logged values themselves are what the foot exerts on the leg, shm_bridge/layout.h, equal to
// the ground's for a massless foot at rest). From n = p x f with p = (px, py, z):
//   px = (z f_x - n_y) / f_z,   py = (n_x + z f_y) / f_z.
// Returns false (p untouched) when f_z <= 0 (no pressure).
bool CentreOfPressure(const double f[3], const double n[3], double z, double* px, double* py);

// Distance of (px, py) inside the rectangle's nearest edge: min(px - xmin, xmax - px,
// py - ymin, ymax - py) [m]; negative outside (then the distance beyond the farthest-crossed
// edge line, not the Euclidean distance to a corner).
double InsideDistance(const SoleRect& r, double px, double py);

// The sole rectangles of sim_host's summary (key "soles"); false with `*error` when `sensor`
// has none.
bool SoleFromSummary(const nlohmann::json& sim, const std::string& sensor, SoleRect* out,
                     std::string* error);

// The checks (keys in checks.h). cop_inside corrects for the foot's weight when the summary
// gives it (foot_mass, foot_com) unless the key `foot_weight` is false.
CheckResult CopInside(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim);
CheckResult FootLifted(const CheckSpec& spec, const datalog::Table& log);

}  // namespace ohrp::runner
