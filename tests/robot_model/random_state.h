// Test helper: random states of the floating HRP-1S for the kinematics tests (base pose and
// joint positions within 80 % of their ranges), applied to a Kinematics object, and moved
// along one generalised velocity column.
#pragma once

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "robot_model/kinematics.h"

namespace ohrp::model::testing {

// a state of the floating robot: base pose and joint positions
struct State {
  Eigen::Vector3d p_WB;
  Eigen::Quaterniond quat_WB;
  std::vector<double> q;
};

inline void Apply(Kinematics& kin, const State& s) {
  kin.SetBasePose(s.p_WB, s.quat_WB);
  kin.SetJointPositions(s.q.data());
  kin.Update();
}

// moves `s` by h along generalised velocity column c (base rotation with w in W)
inline State Perturb(const State& s, int c, double h) {
  State out = s;
  if (c < 3) {
    out.p_WB[c] += h;
  } else if (c < 6) {
    out.quat_WB = Eigen::Quaterniond(Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(c - 3))) * s.quat_WB;
  } else {
    out.q[c - 6] += h;
  }
  return out;
}

inline State RandomState(const Kinematics& kin, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  State s;
  s.p_WB = Eigen::Vector3d(0.1 * u(*rng), 0.1 * u(*rng), 0.7 + 0.1 * u(*rng));
  s.quat_WB = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d(u(*rng), u(*rng), u(*rng)).normalized()));
  for (const JointMap& j : kin.robot().joints) {
    const double mid = 0.5 * (j.q_min + j.q_max), half = 0.5 * (j.q_max - j.q_min);
    s.q.push_back(mid + 0.8 * half * u(*rng));
  }
  return s;
}

}  // namespace ohrp::model::testing
