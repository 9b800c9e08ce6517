// The contact on the real robot model: both soles of mjcf/hrp1s are accepted, the scenes'
// floors and stones are the environment, and the cost of one evaluation is printed beside the
// cost of one mj_step (informative only: no timing assertion, the machine is shared).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

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

}  // namespace
}  // namespace ohrp::contact
