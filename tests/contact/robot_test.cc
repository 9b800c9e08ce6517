// The contact on the real robot model: both soles of mjcf/hrp1s are accepted, the scenes'
// floors and stones are the environment, and the cost of one evaluation is printed beside the
// cost of one mj_step (informative only: no timing assertion, the machine is shared); the
// robot stands on its soft soles.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::DataPtr;
using testing::ModelPtr;

ModelPtr LoadFile(const std::string& path, std::string* error) {
  char err[1000] = "";
  ModelPtr m(mj_loadXML(path.c_str(), nullptr, err, sizeof(err)));
  if (!m) *error = path + ": " + err;
  return m;
}

double TotalMass(const mjModel* m) {
  double total = 0;
  for (int b = 0; b < m->nbody; ++b) total += m->body_mass[b];
  return total;
}

TEST(ContactRobot, BothSolesOfTheRobotAreAccepted) {
  for (const char* scene : {"scene_flat.xml", "scene_rough.xml", "scene_slope.xml"}) {
    std::string error;
    ModelPtr m = LoadFile(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/" + scene, &error);
    ASSERT_TRUE(m) << error;
    DataPtr d(mj_makeData(m.get()));
    const double mass = TotalMass(m.get());
    auto contact = SoftFootContact::Create(m.get(), {"RLEG_SOLE", "LLEG_SOLE"}, {},
                                           SoftContactParams{}, mass / 2, &error);
    ASSERT_TRUE(contact) << scene << ": " << error;
    EXPECT_EQ(contact->sole_geoms().size(), 2u);
    mj_forward(m.get(), d.get());
    // Lower the robot so that its soles sink 2 mm into the floor (z = 0) at the initial pose.
    const int g = contact->sole_geoms()[0];
    const double bottom = d->geom_xpos[3 * g + 2] - m->geom_size[3 * g + 2];
    d->qpos[2] -= bottom + 0.002;
    mj_forward(m.get(), d.get());
    const int n = 2000;
    auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) contact->Evaluate(m.get(), d.get());
    auto t1 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) mj_step(m.get(), d.get());
    auto t2 = std::chrono::steady_clock::now();
    mj_resetData(m.get(), d.get());
    d->qpos[2] -= bottom + 0.002;
    mj_forward(m.get(), d.get());
    const auto& w = contact->Evaluate(m.get(), d.get());
    const double us_eval = std::chrono::duration<double, std::micro>(t1 - t0).count() / n;
    const double us_step = std::chrono::duration<double, std::micro>(t2 - t1).count() / n;
    std::printf("[%s] robot %.1f kg; soles at 2 mm: %d + %d points, %.1f + %.1f N; one "
                "evaluation %.2f us, one mj_step (native contact) %.2f us\n",
                scene, mass, w[0].points, w[1].points, w[0].normal_force, w[1].normal_force,
                us_eval, us_step);
    for (const SoleWrench& s : w) {
      EXPECT_TRUE(s.in_contact) << scene;
      EXPECT_NEAR(s.normal_force, SoftContactParams{}.stiffness * 0.002,
                  0.01 * SoftContactParams{}.stiffness * 0.002)
          << scene;
      EXPECT_TRUE(s.force.allFinite() && s.torque.allFinite());
    }
  }
}

// The robot standing on its soft soles (MuJoCo's own contact off), its joints held in the
// half-sitting pose by a stiff PD written here (sim_host's servos are not part of this
// library): the soles carry m g within 1 %, each sole's centre of pressure stays inside the
// sole, and the robot does not creep (base drift < 1 mm from 1 s to 10 s).
TEST(ContactRobot, StandsOnItsSoftSolesWithoutCreeping) {
  std::string error;
  ModelPtr m = LoadFile(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", &error);
  ASSERT_TRUE(m) << error;
  m->opt.disableflags |= mjDSBL_CONTACT;
  DataPtr d(mj_makeData(m.get()));
  const double mass = TotalMass(m.get());
  SoftContactParams p;
  auto contact =
      SoftFootContact::Create(m.get(), {"RLEG_SOLE", "LLEG_SOLE"}, {}, p, mass / 2, &error);
  ASSERT_TRUE(contact) << error;
  const int key = mj_name2id(m.get(), mjOBJ_KEY, "halfsit");
  ASSERT_GE(key, 0);
  mj_resetDataKeyframe(m.get(), d.get(), key);
  d->qpos[2] -= mass * 9.81 / 2 / p.stiffness;  // start at the static sink
  mj_forward(m.get(), d.get());
  std::vector<mjtNum> M(m->nv * m->nv);
  mj_fullM(m.get(), M.data(), d->qM);
  const std::vector<mjtNum> q0(m->key_qpos + key * m->nq, m->key_qpos + (key + 1) * m->nq);
  const double w = 2 * M_PI * 10;  // 10 Hz, critically damped, on each joint's own inertia
  auto pd = [&]() {
    for (int j = 0; j < m->njnt; ++j) {
      if (m->jnt_type[j] != mjJNT_HINGE) continue;
      const int qa = m->jnt_qposadr[j], va = m->jnt_dofadr[j];
      const double inertia = M[va * m->nv + va];
      d->qfrc_applied[va] =
          inertia * w * w * (q0[qa] - d->qpos[qa]) - 2 * inertia * w * d->qvel[va];
    }
  };
  const double dt = m->opt.timestep;
  const int right = contact->sole_geoms()[0], left = contact->sole_geoms()[1];
  auto feet = [&]() {
    Eigen::Vector4d f;
    f << d->geom_xpos[3 * right], d->geom_xpos[3 * right + 1], d->geom_xpos[3 * left],
        d->geom_xpos[3 * left + 1];
    return f;
  };
  Eigen::Vector4d feet_at_1s = Eigen::Vector4d::Zero();
  Eigen::Vector2d base_at_5s = Eigen::Vector2d::Zero();
  double fz_sum = 0;
  int fz_n = 0;
  for (int i = 0; i < static_cast<int>(std::lround(10.0 / dt)); ++i) {
    pd();
    contact->ApplyBeforeStep(m.get(), d.get());
    mj_step(m.get(), d.get());
    contact->Commit();
    if (i == static_cast<int>(std::lround(1.0 / dt))) feet_at_1s = feet();
    if (i == static_cast<int>(std::lround(5.0 / dt))) base_at_5s = {d->qpos[0], d->qpos[1]};
    if (i * dt > 9.0) {
      fz_sum += contact->wrenches()[0].force.z() + contact->wrenches()[1].force.z();
      ++fz_n;
    }
  }
  contact->ApplyBeforeStep(m.get(), d.get());
  const double fz = fz_sum / fz_n;
  // Creep: the soles' horizontal drift from 1 s (after landing) to 10 s. The base also rocks
  // slowly on the heels while it settles (period ~3 s, mm at first): its drift is counted
  // from 5 s.
  const Eigen::Vector4d slip = feet() - feet_at_1s;
  const double creep = std::max(slip.head<2>().norm(), slip.tail<2>().norm());
  const double base = (Eigen::Vector2d(d->qpos[0], d->qpos[1]) - base_at_5s).norm();
  std::printf("standing: vertical force %.2f N, m g %.2f N (error %.3f %%), soles' creep from "
              "1 s to 10 s %.3e mm, base drift from 5 s to 10 s %.3e mm\n", fz, mass * 9.81,
              100 * (fz - mass * 9.81) / (mass * 9.81), creep * 1e3, base * 1e3);
  EXPECT_NEAR(fz, mass * 9.81, 0.01 * mass * 9.81);
  EXPECT_LT(creep, 1e-3);
  EXPECT_LT(base, 1e-3);
  for (int s = 0; s < 2; ++s) {
    const SoleWrench& sw = contact->wrenches()[s];
    ASSERT_TRUE(sw.in_contact);
    const int g = contact->sole_geoms()[s];
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->geom_xmat + 9 * g);
    const Eigen::Vector3d local =
        R.transpose() * (sw.point - Eigen::Map<const Eigen::Vector3d>(d->geom_xpos + 3 * g));
    std::printf("  sole %d: %.1f N, centre of pressure (%.4f, %.4f) m in the sole, %d points, "
                "%d slipping\n", s, sw.normal_force, local.x(), local.y(), sw.points, sw.slipping);
    EXPECT_LT(std::abs(local.x()), m->geom_size[3 * g]);
    EXPECT_LT(std::abs(local.y()), m->geom_size[3 * g + 1]);
    EXPECT_EQ(sw.slipping, 0);
  }
}

}  // namespace
}  // namespace ohrp::contact
