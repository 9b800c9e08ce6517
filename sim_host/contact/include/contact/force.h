// The force step of the soft-foot contact (OpenHRP, IJRR 2004, section 3.3.2), for one sole:
//  1. least-squares penetration: per (sole, object) pair, the plane delta(u, v) = a + b u + c v
//     fitted (area-weighted) to the depths of the penetrating points, in the sole frame: the
//     sole's infinitesimal penetration, depth a at the sole centre and tilt (b, c);
//  2. spring: at each penetrating point i, k * w_i * max(delta_i, 0)^n along its normal n_i,
//     where w_i is the point's area fraction (a bed of springs: the sum of the point forces and
//     moments is the sole's spring force and moment);
//  3. penetration velocity from the contact constraint: ddelta_i = -(v_sole(p_i) . n_i) (the
//     environment is static);
//  4. Hunt-Crossley damper: the spring force times (1 + c ddelta_i), clamped >= 0, so it never
//     pulls and vanishes with the penetration;
//  5. sum, plus friction: a tangential spring k_t w_i from an anchor (the point where p_i stuck)
//     and a damper b_t w_i on the tangential velocity, saturated at mu f_n,i (slip). While
//     slipping, the anchor is dragged so that the spring alone gives the saturated force.
// Anchors are state: Compute() reads the committed anchors and proposes new ones; they only
// become the state when the caller commits (after mj_step), never inside force evaluation.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "contact/geometry.h"
#include "contact/params.h"

namespace ohrp::contact {

// Anchor of one sample point's tangential spring (world), valid while the point touches.
struct Anchor {
  bool active = false;
  int object = -1;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
};

struct PointForce {
  int index = -1;
  int object = -1;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // normal + tangential [N], on the sole
  double depth = 0;      // raw depth from the geometry [m]
  double depth_fit = 0;  // least-squares depth used by the law [m], >= 0
  // the signed depth the implicit step integrates [m]: the fitted one (may be < 0 where the
  // fitted plane leaves the point outside), or the point's own depth < 0 for a point outside
  // within the search's reach (fn 0, no friction: it may only enter during the step)
  double depth_signed = 0;
  double pen_vel = 0;    // penetration velocity [m/s], > 0 going in
  double fn = 0;         // normal force [N]
  // the friction spring and damper before Coulomb's limit [N] (for a point outside: the damper
  // alone, as if it stuck where it is): the implicit step limits it by its own normal force
  Eigen::Vector3d ft_trial = Eigen::Vector3d::Zero();
  bool slipping = false;
};

// The contact's result for one sole, everything in world coordinates.
struct SoleWrench {
  bool in_contact = false;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // [N], exerted on the sole
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // [N m], about `point`
  // Application point: the centre of pressure of the normal forces (the centroid of the
  // touching points when they carry no normal force).
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // normal-force weighted mean normal
  double normal_force = 0;                            // sum of f_n [N]
  // Least-squares penetration of the pair carrying the most points: depth at the sole centre
  // [m] and tilt d(delta)/du, d(delta)/dv [m/m] in the sole frame.
  double depth = 0;
  double tilt_u = 0;
  double tilt_v = 0;
  double penetration_velocity = 0;  // normal-force weighted mean [m/s]
  int points = 0;
  int slipping = 0;
  std::vector<PointForce> per_point;
};

// Velocity of the sole: linear velocity of the sole frame's origin and angular velocity (world).
struct SoleTwist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

// Computes the wrench from the penetrating points (depth > 0); points outside within the
// search's reach (depth <= 0) are listed in per_point with fn 0 and no force, and count nowhere
// else (not in_contact, not in points). `anchors` (committed, one per sample point)
// is read; `proposed` (resized to the grid) receives the anchors this evaluation would leave.
void ComputeWrench(const SoftContactParams& p, const SoleBox& sole, const SoleTwist& twist,
                   const std::vector<SamplePoint>& grid, const std::vector<PointContact>& points,
                   const std::vector<Anchor>& anchors, std::vector<Anchor>* proposed,
                   SoleWrench* out);

}  // namespace ohrp::contact
