// The linearised rocking of the standing robot on its soft soles (the paper's figure 12): the
// rigid robot on the soles' sample points in the sagittal plane, coordinates the centre of
// mass's x and z and the pitch. Each point is a normal spring-damper (k w, the Hunt-Crossley
// damper linearised at the point's static depth: b = c k w delta, so b does not depend on k)
// and a tangential one (k_t w, b_t w); gravity's lever shortens as the body tilts (- m g h).
// The slowest oscillating mode of that 3-degree-of-freedom system is the rocking: its damped
// frequency and damping ratio in closed form (an eigenvalue problem), and back: the stiffness
// and damping that give a measured frequency and damping ratio (each monotone in its
// parameter, solved by bisection). tests/sim_host/rocking_test.cc checks the prediction against
// sim_host; ohrp identify inverts it (docs/identify.md).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "contact/params.h"

namespace ohrp::identify {

struct Mode {
  double omega_d = 0, zeta = 0;  // [rad/s], [-]; omega_d 0: no oscillating mode
};

// The rocking mode of the body of mass m [kg] and pitch inertia Iyy about its centre of mass
// [kg m^2] on the sample points `r` ((x, z) from the centre of mass [m], z up, in the soles'
// frame) of area fractions `w` (per sole), gravity g [m/s^2], soles `p`.
Mode PredictRocking(const std::vector<Eigen::Vector2d>& r, const std::vector<double>& w, double m,
                    double Iyy, double g, const contact::SoftContactParams& p);

// What the prediction needs of the robot in a posture.
struct RockingGeometry {
  std::vector<Eigen::Vector2d> points;  // (x, z) from the centre of mass, in the soles' frame
  std::vector<double> weights;
  double mass = 0, Iyy = 0, g = 9.81;
  double com_height = 0;                // above the soles [m]
  double com_ahead = 0;                 // ahead of the soles' middle [m]
};

// The geometry of the robot of `m` (a scene whose soles are the box geoms "*_SOLE") with its
// joints at `q` (by joint name; joints not given stay at qpos0), seen from its soles: the
// soles' sample points (contact::MakeGrid with p's grid) and the centre of mass and pitch
// inertia, all in the right sole's frame (the soles standing flat). False with `*error`.
bool GeometryAt(const mjModel* m, const std::vector<std::pair<std::string, double>>& q,
                const contact::SoftContactParams& p, RockingGeometry* out, std::string* error);

// The soles' stiffness and damping that give the rocking mode (omega_d, zeta) on `geometry`,
// the other parameters as in `p`: K by bisection on omega_d where it rises through the target
// on a grid over [k_lo, k_hi] (the rocking branch), then D on zeta over [0, d_hi] at that K,
// then K again at that D. False with `*error` when a target lies outside what the ranges give.
bool InvertRocking(const RockingGeometry& geometry, const contact::SoftContactParams& p,
                   double omega_d, double zeta, double* k, double* d, std::string* error,
                   double k_lo = 2e5, double k_hi = 1e8, double d_hi = 1e3);

}  // namespace ohrp::identify
