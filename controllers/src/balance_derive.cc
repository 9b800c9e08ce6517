// The stabilizer's gains derived from the robot's servos (docs/robots.md, "Derived from the
// robot"): the foot rotation damping D from the ankles' stiffness.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "controllers/balance.h"
#include "controllers/derived_gait.h"

namespace ohrp::controllers {

void BalanceController::DeriveAnkleDamping(StabilizerGains* g) {
  // only when not set (a program or --ankle-damping giving another value than the default)
  if (g->ankle_damping != StabilizerGains{}.ankle_damping) return;
  const model::Kinematics& k = *kin_ik_;  // at the stance (on_configure set it)
  const mjModel* m = k.m();
  const double scale = options_.servo_frequency > 0 ? options_.servo_frequency / 6.0 : 1.0;
  AnkleStiffness a;
  for (int side = 0; side < 2; ++side) {
    const std::vector<int> chain = k.Chain(k.robot().base_body, k.soles()[sole_[side]].body_id);
    // from the sole up: the first joint turning about the base's x (roll), and about its y (pitch)
    bool found[2] = {false, false};
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const model::JointMap& jm = k.robot().joints[*it];
      const int jid = jm.joint_id;
      const Eigen::Vector3d axis =
          k.R_WBody(m->jnt_bodyid[jid]) *
          Eigen::Vector3d(m->jnt_axis[3 * jid], m->jnt_axis[3 * jid + 1], m->jnt_axis[3 * jid + 2]);
      for (int a_i = 0; a_i < 2; ++a_i) {
        if (found[a_i] || std::abs(axis[a_i]) < kAnkleAxisAlignment) continue;
        found[a_i] = true;
        const double kp = jm.default_kp * scale * scale;
        if (kp > 0 && kp < a.kp) {
          a.kp = kp;
          a.joint = *it;
        }
      }
    }
  }
  if (a.joint < 0) return;  // no ankle joint with a stiffness: the default stays
  // the pendulum's time constant at the stance CoM height over the soles
  const double z = k.p_WCoM().z() - 0.5 * (k.p_WSole(sole_[0]).z() + k.p_WSole(sole_[1]).z());
  const double tc = std::sqrt(std::max(z, 1e-3) / 9.81);
  const double share = kAnkleTorqueShare;
  const double d = AnkleDamping(a.kp, g->ankle_damping, share * tc);
  std::fprintf(stderr,
               "%s: foot rotation damping D %.1f N m s/rad (derived: the ankles' least servo "
               "stiffness %.0f N m/rad at %s times %.2f x the pendulum's time constant %.3f s "
               "(CoM %.3f m over the soles), at most HRP-1S's %.0f; --ankle-damping sets it)\n",
               options_.program.c_str(), d, a.kp, k.robot().joints[a.joint].name.c_str(), share,
               tc, z, g->ankle_damping);
  g->ankle_damping = d;
}

}  // namespace ohrp::controllers
