// The walking controller's plan for the viewer's plan overlays (docs/view.md, "The walk's plan
// in 3D"): a run folder's walk.csv (controllers/src/walk_report.cc, one row per control cycle,
// everything in the walk's plan frame, t on simulated time like log.csv's) read back as
// - the desired ZMP (the stabilizer's, zmp_des_x/y),
// - the DCM: the stabilizer's (dcm_x/y, from the estimated CoM and its velocity) and the plan's
//   capture point, computed here from the CoM reference and its velocity (CapturePoint),
// - the footstep plan: each sole where it stands at the first row and wherever its support
//   column turns to 1 (a landing), as the model's sole rectangle,
// all in the world. Plan to world: the plan frame's columns (frame_x, frame_y, frame_yaw:
// p_plan = Rz(yaw) p_est + (x, y)) take a point to the estimator's frame, and that frame is
// placed in the world once, where the log shows the soles at walk.csv's first row (Register).
// Units: SI (m, s, rad).
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "datalog/table.h"

namespace ohrp::view {

constexpr double kPlanGravity = 9.81;  // [m/s^2], as the stabilizer's

// The capture point (instantaneous DCM) of a CoM at `c` [m] moving at `v` [m/s] (horizontal)
// over the ground at height `ground_z` [m]: c + v / omega, omega = sqrt(g / (c_z - ground_z))
// (the height kept at least 1 cm). A CoM at rest: its ground projection.
std::array<double, 2> CapturePoint(const double c[3], const double v[2], double ground_z);

// A planar rigid map (x, y, yaw): p -> Rz(yaw) p + (x, y); z moves by dz.
struct Planar {
  double x = 0, y = 0, yaw = 0, dz = 0;
  std::array<double, 3> Apply(const double p[3]) const;
  double Yaw(double yaw_in) const { return yaw_in + yaw; }
};

// The map that takes two points a, b (e.g. the left and right soles) onto A, B: the yaw of
// b - a onto B - A, their middle onto the middle (z: the mean heights' difference).
Planar FitTwoPoints(const double a[3], const double b[3], const double A[3], const double B[3]);

// The model's two soles (robot_model's FindSoles: *_SOLE boxes), left first (larger y in the base
// frame at the model's initial configuration): geom ids, -1 when the model has not two.
std::array<int, 2> LeftRightSoles(const mjModel* m);

class WalkPlan {
 public:
  // Reads `path` (walk.csv). Null with `*error` when it cannot be read or has no 't' column or
  // no rows. Columns an overlay needs and the file lacks are listed by Missing().
  static std::unique_ptr<WalkPlan> Load(const std::string& path, std::string* error);

  // {"desired_zmp": [missing columns], "dcm": [...], "footsteps": [...]} ([] when drawable)
  nlohmann::json Missing() const;
  double t0() const;  // the first row's time [s]

  // Places the estimator's frame in the world from where the soles stand (the centres of their
  // bottom faces, world [m]) at the first row: the plan's left and right soles at that row go
  // onto them. Without it the estimator's frame is the world.
  void Register(const double left_W[3], const double right_W[3]);
  const Planar& registration() const { return world_from_est_; }

  // The footstep plan in the world: [{"side": "left"|"right", "t" (landing time, or the first
  // row's for the starting stance) [s], "center": [x, y, z], "yaw", "corners": [[x, y, z] x 4]}],
  // in time order; each rectangle is 2 `half[side][0]` long and 2 `half[side][1]` wide
  // (the model's sole box). [] when the footstep columns are missing.
  nlohmann::json Footsteps(const double half[2][2]) const;

  // The plan at time t (linear interpolation between rows; before the first row null):
  // {"t", "zmp_des": [x, y, z] | null, "dcm": [x, y, z] | null (the stabilizer's),
  //  "cp": [x, y, z] | null (the plan's capture point), "support": [left, right] | null},
  // z the mean height of the supporting soles in the plan.
  nlohmann::json At(double t) const;

 private:
  WalkPlan() = default;
  double Value(int c, size_t lo, size_t hi, double s) const;
  Planar WorldFromPlan(size_t row) const;  // registration after the row's plan frame
  std::array<double, 2> PlanCapturePoint(size_t row) const;  // plan frame
  double GroundZ(size_t row) const;                           // plan frame

  datalog::Table table_;
  int t_ = -1;
  std::vector<int> zmp_des_, dcm_, com_ref_, left_, right_, support_, frame_;  // column ids
  Planar world_from_est_;
};

}  // namespace ohrp::view
