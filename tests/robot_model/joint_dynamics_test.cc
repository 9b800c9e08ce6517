// The joints' dynamics bounds (collision/joint_dynamics.h) against MuJoCo at random postures
// of HRP-1S and of MuJoCo's humanoid: qM's diagonal (the links beyond each joint, the robot
// floating) lies within [inertia_min, inertia_max]; the inertia of the rest of the robot about
// the joint's axis (what the joint drives when the links beyond stand on the ground), computed
// here from MuJoCo's body poses, is within inertia_max - armature; qfrc_bias at zero velocity
// (gravity of the links beyond) and the gravity torque of the rest are within gravity_max.
#include "collision/joint_dynamics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "robot_model/model_hash.h"

namespace ohrp::collision {
namespace {

struct Worst {
  double inertia = 0, gravity = 0;  // the largest observed over the bound (<= 1 passes)
};

// `n` random postures within the joint limits, the base as the model has it
Worst CheckModel(const std::string& path, int n) {
  char err[512] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  EXPECT_NE(m, nullptr) << err;
  if (!m) return {};
  mjData* d = mj_makeData(m);
  model::RobotMap robot;
  std::string error;
  EXPECT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  const std::vector<JointDynamics> dyn = JointDynamicsFromModel(m, robot);
  EXPECT_EQ(dyn.size(), robot.joints.size());
  const std::vector<int> bodies = model::RobotBodies(m, robot);
  const std::vector<char> support = SupportBodies(m, robot);
  std::mt19937 rng(7);
  Worst w;
  for (int s = 0; s < n; ++s) {
    mj_resetData(m, d);
    // a random base orientation too: the bounds hold in any posture
    if (robot.base_qpos >= 0) {
      std::normal_distribution<double> g;
      double* quat = d->qpos + robot.base_qpos + 3;
      for (int k = 0; k < 4; ++k) quat[k] = g(rng);
      mju_normalize4(quat);
    }
    for (const auto& j : robot.joints) {
      const double lo = j.q_min > -1e8 ? j.q_min : -M_PI, hi = j.q_max < 1e8 ? j.q_max : M_PI;
      d->qpos[j.qpos_adr] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    mj_forward(m, d);
    for (size_t k = 0; k < robot.joints.size(); ++k) {
      const auto& j = robot.joints[k];
      const JointDynamics& b = dyn[k];
      const double qm = d->qM[m->dof_Madr[j.dof_adr]];
      EXPECT_GE(qm, b.inertia_min * (1 - 1e-9)) << j.name;
      EXPECT_LE(qm, b.inertia_max * (1 + 1e-9)) << j.name;
      EXPECT_LE(std::abs(d->qfrc_bias[j.dof_adr]), b.gravity_max * (1 + 1e-9) + 1e-9) << j.name;
      // tightness without the armature (which both hold exactly)
      const double arm = m->dof_armature[j.dof_adr];
      if (b.inertia_max - arm > 1e-3) w.inertia = std::max(w.inertia, (qm - arm) / (b.inertia_max - arm));
      w.gravity = std::max(w.gravity, std::abs(d->qfrc_bias[j.dof_adr]) / b.gravity_max);
      // the rest of the robot about the same axis, from the bodies' poses
      const int jb = m->jnt_bodyid[j.joint_id];
      const double* axis = d->xaxis + 3 * j.joint_id;
      const double* anchor = d->xanchor + 3 * j.joint_id;
      double inertia = 0, torque = 0;
      bool carries = false;  // a foot beyond the joint: the rest is what it drives, standing
      for (int body : bodies) {
        int up = body;
        while (up > 0 && up != jb) up = m->body_parentid[up];
        carries = carries || (up == jb && support[body]);
      }
      for (int body : bodies) {
        if (!carries) break;
        int up = body;
        while (up > 0 && up != jb) up = m->body_parentid[up];
        if (up == jb) continue;  // beyond the joint
        double r[3], rxa[3], perp2;
        for (int i = 0; i < 3; ++i) r[i] = d->xipos[3 * body + i] - anchor[i];
        mju_cross(rxa, r, axis);
        perp2 = mju_dot3(rxa, rxa);
        // axis^T R I R^T axis
        double a_local[3];
        mju_mulMatTVec(a_local, d->ximat + 9 * body, axis, 3, 3);
        double own = 0;
        for (int i = 0; i < 3; ++i) own += m->body_inertia[3 * body + i] * a_local[i] * a_local[i];
        inertia += m->body_mass[body] * perp2 + own;
        double f[3], rxf[3];
        for (int i = 0; i < 3; ++i) f[i] = m->body_mass[body] * m->opt.gravity[i];
        mju_cross(rxf, r, f);
        torque += mju_dot3(rxf, axis);
      }
      const double armature = m->dof_armature[j.dof_adr];
      EXPECT_LE(inertia + armature, b.inertia_max * (1 + 1e-9)) << j.name << " (the rest)";
      EXPECT_LE(std::abs(torque), b.gravity_max * (1 + 1e-9) + 1e-9) << j.name << " (the rest)";
      if (b.inertia_max - armature > 1e-3) w.inertia = std::max(w.inertia, inertia / (b.inertia_max - armature));
      w.gravity = std::max(w.gravity, std::abs(torque) / b.gravity_max);
    }
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return w;
}

TEST(JointDynamics, Hrp1sBoundsHoldAtRandomPostures) {
  const Worst w = CheckModel(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml", 2000);
  std::printf("HRP-1S: largest observed / bound: inertia less armature %.3f, gravity %.3f\n", w.inertia, w.gravity);
  EXPECT_GT(w.inertia, 0.2);  // not absurdly loose either
}

// the supports are the feet: HRP-1S's soles, not its hands
TEST(JointDynamics, SupportsAreTheFeet) {
  char err[512] = "";
  mjModel* m = mj_loadXML((std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml").c_str(), nullptr, err, sizeof(err));
  ASSERT_NE(m, nullptr) << err;
  model::RobotMap robot;
  std::string error;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  const std::vector<char> support = SupportBodies(m, robot);
  std::string names;
  for (int b = 0; b < m->nbody; ++b)
    if (support[b]) names += std::string(mj_id2name(m, mjOBJ_BODY, b)) + " ";
  EXPECT_EQ(names, "LLEG_ANKLE_P LLEG_ANKLE_R RLEG_ANKLE_P RLEG_ANKLE_R ");
  mj_deleteModel(m);
}

TEST(JointDynamics, MujocosHumanoidBoundsHoldAtRandomPostures) {
  const std::string path = std::string(OHRP_SOURCE_DIR) +
                           "/../shared/external/mujoco-2.2.2-models/humanoid/humanoid.xml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
  const Worst w = CheckModel(path, 2000);
  std::printf("humanoid: largest observed / bound: inertia less armature %.3f, gravity %.3f\n", w.inertia, w.gravity);
  EXPECT_GT(w.inertia, 0.2);
}

}  // namespace
}  // namespace ohrp::collision
