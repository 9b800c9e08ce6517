// Slope: a block on an incline of angle theta sticks below the friction angle atan(mu) (creep
// under 1 mm in 5 s, after the tangential spring's elastic offset m g sin(theta) / k_t) and,
// above it, slides with the Coulomb acceleration g (sin(theta) - mu cos(theta)) within 2 %.
// The incline is a plane geom rotated about y, the block starts at rest at its static sink
// with its tangential spring unloaded.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::BlockModel;
using testing::DataPtr;
using testing::LoadString;
using testing::ModelPtr;

constexpr double kG = 9.81;
constexpr double kMass = 60.0;
constexpr double kDt = 0.001;

struct Slope {
  ModelPtr m;
  DataPtr d;
  std::unique_ptr<SoftFootContact> contact;
  Eigen::Vector3d down;  // unit vector down the slope
  double theta;
};

Slope Make(double theta_deg, double mu, std::string* error) {
  Slope s;
  s.theta = theta_deg * M_PI / 180;
  const std::string plane = "<geom name=\"incline\" type=\"plane\" size=\"10 10 0.1\" euler=\"0 " +
                            std::to_string(theta_deg) + " 0\"/>";
  s.m = LoadString(BlockModel(kDt, kMass, plane), error);
  if (!s.m) return s;
  s.d.reset(mj_makeData(s.m.get()));
  SoftContactParams p;
  p.friction = mu;
  s.contact = SoftFootContact::Create(s.m.get(), {"sole"}, {}, p, kMass, error);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(s.theta, Eigen::Vector3d::UnitY()));
  const double sink = kMass * kG * std::cos(s.theta) / p.stiffness;
  const Eigen::Vector3d pos = q * Eigen::Vector3d(0, 0, testing::kSoleHalf[2] - sink);
  for (int k = 0; k < 3; ++k) s.d->qpos[k] = pos[k];
  s.d->qpos[3] = q.w();
  s.d->qpos[4] = q.x();
  s.d->qpos[5] = q.y();
  s.d->qpos[6] = q.z();
  s.down = q * Eigen::Vector3d::UnitX();
  return s;
}

void Simulate(Slope* s, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int i = 0; i < steps; ++i) {
    s->contact->ApplyBeforeStep(s->m.get(), s->d.get());
    mj_step(s->m.get(), s->d.get());
    s->contact->Commit();
  }
}

double Along(const Slope& s) { return s.down.dot(Eigen::Vector3d(s.d->qpos)); }
double SpeedAlong(const Slope& s) { return s.down.dot(Eigen::Vector3d(s.d->qvel)); }

TEST(ContactSlope, SticksBelowTheFrictionAngle) {
  for (const auto& [theta, mu] : {std::pair{20.0, 1.0}, std::pair{24.0, 0.5}}) {
    std::string error;
    Slope s = Make(theta, mu, &error);
    ASSERT_TRUE(s.contact) << error;
    const double x0 = Along(s);
    Simulate(&s, 0.5);
    const double x1 = Along(s);
    Simulate(&s, 4.5);
    const double x2 = Along(s);
    const double offset = kMass * kG * std::sin(s.theta) / s.contact->params().tangential_stiffness;
    const SoleWrench& w = s.contact->wrenches()[0];
    std::printf("[stick %.0f deg, mu %.2f (friction angle %.1f deg)] elastic offset %.4f mm "
                "(m g sin/k_t = %.4f mm), creep from 0.5 s to 5 s %.2e mm, slipping points %d\n",
                theta, mu, std::atan(mu) * 180 / M_PI, (x1 - x0) * 1e3, offset * 1e3,
                (x2 - x1) * 1e3, w.slipping);
    EXPECT_LT(std::abs(x2 - x1), 1e-3);                     // creep under 1 mm
    // The load arrives at once at t = 0 and the stick spring overshoots (damping ratio ~0.3):
    // far below the friction angle the block moves by the spring's offset only; near it
    // (24 deg for 26.6) it slips a couple of mm during that transient, then sticks.
    if (std::tan(s.theta) < 0.5 * mu) {
      EXPECT_NEAR(x1 - x0, offset, 0.1 * offset);
    } else {
      EXPECT_LT(std::abs(x1 - x0), 5e-3);
    }
    EXPECT_EQ(w.slipping, 0);
    EXPECT_LT(std::abs(SpeedAlong(s)), 1e-5);
  }
}

TEST(ContactSlope, SlidesAboveTheFrictionAngleWithCoulombAcceleration) {
  for (const auto& [theta, mu] : {std::pair{35.0, 0.5}, std::pair{30.0, 0.3}}) {
    std::string error;
    Slope s = Make(theta, mu, &error);
    ASSERT_TRUE(s.contact) << error;
    Simulate(&s, 0.3);
    const double v1 = SpeedAlong(s);
    Simulate(&s, 0.5);
    const double v2 = SpeedAlong(s);
    const double a_sim = (v2 - v1) / 0.5;
    const double a_ref = kG * (std::sin(s.theta) - mu * std::cos(s.theta));
    const SoleWrench& w = s.contact->wrenches()[0];
    std::printf("[slide %.0f deg, mu %.2f] acceleration %.4f m/s^2, Coulomb %.4f m/s^2 "
                "(error %.3f %%), slipping points %d of %d\n",
                theta, mu, a_sim, a_ref, 100 * (a_sim - a_ref) / a_ref, w.slipping, w.points);
    EXPECT_NEAR(a_sim, a_ref, 0.02 * a_ref);
    EXPECT_EQ(w.slipping, w.points);
  }
}

}  // namespace
}  // namespace ohrp::contact

namespace ohrp::contact {
namespace {

// The friction state only advances in Commit(), from the first evaluation since the previous
// Commit: extra evaluations at another state (an RK4 stage, an mj_forward for a viewer) leave
// the trajectory unchanged.
TEST(ContactSlope, ExtraEvaluationsDoNotAdvanceTheFrictionState) {
  std::string error;
  Slope a = Make(24.0, 0.5, &error);  // slips ~2 mm (anchors dragged), then sticks
  ASSERT_TRUE(a.contact) << error;
  Slope b = Make(24.0, 0.5, &error);
  ASSERT_TRUE(b.contact) << error;
  for (int i = 0; i < 600; ++i) {
    a.contact->ApplyBeforeStep(a.m.get(), a.d.get());
    mj_step(a.m.get(), a.d.get());
    a.contact->Commit();

    b.contact->ApplyBeforeStep(b.m.get(), b.d.get());
    mj_step(b.m.get(), b.d.get());
    SoftFootContact::UpdateKinematics(b.m.get(), b.d.get());  // the state after the step
    b.contact->Evaluate(b.m.get(), b.d.get());
    b.contact->Evaluate(b.m.get(), b.d.get());
    b.contact->Commit();
  }
  // Equal to rounding (mj_kinematics in between perturbs the last bits); anchors taken from the
  // post-step state instead would move the block by micrometres.
  for (int k = 0; k < a.m->nq; ++k) EXPECT_NEAR(a.d->qpos[k], b.d->qpos[k], 1e-12) << k;
  // And a state evaluated many times without Commit gives the same force each time.
  const Eigen::Vector3d f0 = a.contact->Evaluate(a.m.get(), a.d.get())[0].force;
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(a.contact->Evaluate(a.m.get(), a.d.get())[0].force, f0);
  }
}

}  // namespace
}  // namespace ohrp::contact
