// Where the soft-foot force enters each integrator. A block resting on the soft contact with no
// damper (c = 0, so the closed form is plain: x(t) = x_s + A cos(w t), w = sqrt(k/m), x_s the
// static sink m g / k) bounces vertically with every sample point in contact. Checked:
//   - Euler (semi-implicit), implicit and RK4 with the force held over the step all converge to
//     the closed form at first order; RK4 with the hold is worse than semi-implicit Euler (for
//     the contact it is an explicit Euler step: the bounce gains energy);
//   - RK4 with the force evaluated at every stage (EvaluateAtEveryStage) converges at fourth
//     order and is far more accurate at the same step;
//   - the stage mode is exclusive (mjcb_control is process-wide) and restores the previous
//     callback.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::BlockModel;
using testing::DataPtr;
using testing::kPlaneFloor;
using testing::kSoleHalf;
using testing::LoadString;
using testing::ModelPtr;

constexpr double kMass = 60, kG = 9.81, kAmplitude = 1e-4, kDuration = 0.2;

// Largest deviation of the block's height from the closed form over kDuration [m].
double MaxError(const std::string& integrator, double dt, bool every_stage) {
  std::string error;
  ModelPtr m = LoadString(BlockModel(dt, kMass, kPlaneFloor, "0 0 -9.81", "", integrator), &error);
  EXPECT_TRUE(m) << error;
  if (!m) return 1e9;
  DataPtr d(mj_makeData(m.get()));
  SoftContactParams p;
  p.damping = 0;
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {}, p, kMass, &error);
  EXPECT_TRUE(contact) << error;
  if (!contact) return 1e9;
  EXPECT_TRUE(contact->EvaluateAtEveryStage(every_stage, &error)) << error;
  const double sink = kMass * kG / p.stiffness;  // 0.196 mm: the 0.1 mm bounce keeps contact
  const double omega = std::sqrt(p.stiffness / kMass);
  const double z0 = kSoleHalf[2] - sink;  // the block's centre at the static sink
  d->qpos[2] = z0 - kAmplitude;           // pressed 0.1 mm further, at rest
  mj_forward(m.get(), d.get());
  double worst = 0;
  while (d->time < kDuration - 0.5 * dt) {
    contact->ApplyBeforeStep(m.get(), d.get());
    mj_step(m.get(), d.get());
    contact->Commit();
    const double exact = z0 - kAmplitude * std::cos(omega * d->time);
    worst = std::max(worst, std::fabs(d->qpos[2] - exact));
  }
  return worst;
}

TEST(ContactStages, HeldForceConvergesAtFirstOrderInEveryIntegrator) {
  double euler_error = 0;
  for (const char* integrator : {"Euler", "implicit", "RK4"}) {
    const double e1 = MaxError(integrator, 2e-4, false), e2 = MaxError(integrator, 1e-4, false);
    const double order = std::log2(e1 / e2);
    std::printf("%-8s held force: error %.3g m at 0.2 ms, %.3g m at 0.1 ms, order %.2f\n",
                integrator, e1, e2, order);
    EXPECT_GT(order, 0.8) << integrator;
    EXPECT_LT(order, 1.5) << integrator;  // the hold: no better than first order
    if (std::string(integrator) == "Euler") {
      euler_error = e2;
      EXPECT_LT(e2, 0.02 * kAmplitude);  // semi-implicit Euler: 2 % of the bounce at 0.1 ms
    }
    if (std::string(integrator) == "RK4") {
      // RK4 with a held force is an explicit Euler step in disguise for the contact: it gains
      // energy and is worse than semi-implicit Euler at the same step (hence the stage mode)
      EXPECT_GT(e2, 5 * euler_error);
    }
  }
}

TEST(ContactStages, ForceAtEveryStageKeepsRk4FourthOrder) {
  const double e1 = MaxError("RK4", 1e-3, true), e2 = MaxError("RK4", 5e-4, true);
  const double held = MaxError("RK4", 5e-4, false);
  const double order = std::log2(e1 / e2);
  std::printf("RK4 force at every stage: error %.3g m at 1 ms, %.3g m at 0.5 ms, order %.2f; "
              "held force at 0.5 ms: %.3g m\n", e1, e2, order, held);
  EXPECT_GT(order, 3.5);
  EXPECT_LT(e2, 1e-3 * held);  // three orders of magnitude better than the hold
}

TEST(ContactStages, OneContactAtATimeAndThePreviousCallbackIsRestored) {
  std::string error;
  ModelPtr m = LoadString(BlockModel(1e-3, kMass, kPlaneFloor), &error);
  ASSERT_TRUE(m) << error;
  auto a = SoftFootContact::Create(m.get(), {"sole"}, {}, SoftContactParams{}, kMass, &error);
  auto b = SoftFootContact::Create(m.get(), {"sole"}, {}, SoftContactParams{}, kMass, &error);
  ASSERT_TRUE(a && b) << error;
  static int calls = 0;
  mjcb_control = [](const mjModel*, mjData*) { ++calls; };
  const mjfGeneric mine = mjcb_control;
  ASSERT_TRUE(a->EvaluateAtEveryStage(true, &error)) << error;
  EXPECT_FALSE(b->EvaluateAtEveryStage(true, &error));
  EXPECT_NE(error.find("process-wide"), std::string::npos) << error;
  DataPtr d(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  EXPECT_EQ(calls, 1);  // the earlier callback still runs
  a.reset();            // destroying the contact switches it off
  EXPECT_EQ(mjcb_control, mine);
  EXPECT_TRUE(b->EvaluateAtEveryStage(true, &error)) << error;
  EXPECT_TRUE(b->EvaluateAtEveryStage(false, &error));
  EXPECT_EQ(mjcb_control, mine);
  mjcb_control = nullptr;
}

}  // namespace
}  // namespace ohrp::contact
