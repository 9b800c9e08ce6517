// The implicit soft-foot force (implicit.cc: the law averaged along the step's path) against
// the converged law, at the default 1 ms step and the default sole:
//  - impacts: a free block of 10-100 kg hitting the floor at 0.05-1 m/s, with the contact
//    starting anywhere within a step (ten phases), leaves with the restitution of the
//    Hunt-Crossley ODE integrated at a 1e-6 s step: within 2 %, or 0.005 where it is below
//    0.25, for every mass, speed and phase (the bound); the same for a Hertz-like sole
//    (exponent 1.5);
//  - no damping: 20 bounces under gravity keep the energy within 2 % for every mass.
// Before the path average (the law at the step's start, linearised), the 10 kg block at
// 0.05 m/s left 5.2 % too fast and 20 bounces of 30 kg gained 9.8 %: a contact that starts
// within a step was only seen from the next step on. Each case also prints what the explicit
// force held over the step gives (the scheme before both).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::BlockModel;
using testing::DataPtr;
using testing::LoadString;
using testing::ModelPtr;

constexpr double kDt = 1e-3;
constexpr double kRobotHalfMass = 60.0;  // mass_scale: what rides on one sole of the robot

// how an impact is run: the step, sim_host's split of the step around the contact (mj_step1,
// ApplyAfterStep1, mj_step2) or ApplyBeforeStep and mj_step, and whether the accelerations in
// mjData are stale (left by an mj_forward in another state: falling under gravity)
struct Run {
  double dt = kDt;
  bool split = false;
  bool stale = false;
};

// restitution of one impact at `speed`, the contact starting at `phase` (0-1) of a step
double Restitution(double mass, double speed, double phase, bool implicit, std::string* error,
                   const SoftContactParams& params = SoftContactParams{}, const Run& run = Run{}) {
  ModelPtr m = LoadString(BlockModel(run.dt, mass, testing::kPlaneFloor, "0 0 0"), error);
  if (!m) return -1;
  DataPtr d(mj_makeData(m.get()));
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {}, params, kRobotHalfMass, error);
  if (!contact) return -1;
  contact->SetImplicit(implicit);
  d->qpos[2] = testing::kSoleHalf[2] + phase * speed * run.dt + 1e-12;
  d->qvel[2] = -speed;
  if (run.stale) d->qacc[2] = -9.81;
  for (int i = 0; i < 20000; ++i) {
    if (run.split) {
      mj_step1(m.get(), d.get());
      contact->ApplyAfterStep1(m.get(), d.get());
      mj_step2(m.get(), d.get());
    } else {
      contact->ApplyBeforeStep(m.get(), d.get());
      mj_step(m.get(), d.get());
    }
    contact->Commit();
    if (i > 0 && d->qpos[2] > testing::kSoleHalf[2] && d->qvel[2] > 0) return d->qvel[2] / speed;
  }
  *error = "the block never left the floor";
  return -1;
}

TEST(ContactImplicit, ImpactRestitutionIsTheConvergedOneAtAnyPhase) {
  const SoftContactParams p;
  int failures = 0;
  std::printf("mass  speed  reference  implicit(worst phase)  explicit(worst phase)\n");
  for (double mass : {10.0, 30.0, 60.0, 100.0}) {
    for (double speed : {0.05, 0.1, 0.2, 0.5, 1.0}) {
      const double ref =
          HuntCrossleyRestitution(p.stiffness, p.exponent, p.damping, mass, speed, 1e-6);
      const double tol = ref < 0.25 ? 0.005 : 0.02 * ref;
      double worst_imp = ref, worst_exp = ref;
      for (double phase = 0; phase < 0.99; phase += 0.1) {
        std::string error;
        const double ei = Restitution(mass, speed, phase, true, &error);
        ASSERT_GE(ei, 0) << error;
        const double ee = Restitution(mass, speed, phase, false, &error);
        ASSERT_GE(ee, 0) << error;
        if (std::abs(ei - ref) > std::abs(worst_imp - ref)) worst_imp = ei;
        if (std::abs(ee - ref) > std::abs(worst_exp - ref)) worst_exp = ee;
        if (std::abs(ei - ref) > tol) ++failures;
        EXPECT_NEAR(ei, ref, tol) << mass << " kg at " << speed << " m/s, phase " << phase;
      }
      std::printf("%5.0f  %5.2f  %9.4f  %9.4f (%+6.1f %%)  %9.4f (%+6.1f %%)\n", mass, speed, ref,
                  worst_imp, 100 * (worst_imp - ref) / ref, worst_exp,
                  100 * (worst_exp - ref) / ref);
    }
  }
  EXPECT_EQ(failures, 0);
}

TEST(ContactImplicit, HertzSoleRestitutionIsTheConvergedOne) {
  SoftContactParams p;
  p.exponent = 1.5;
  p.stiffness = 3e8;  // N/m^1.5: about the default sole's force at its standing depth
  for (double mass : {10.0, 60.0}) {
    for (double speed : {0.05, 0.2, 1.0}) {
      const double ref =
          HuntCrossleyRestitution(p.stiffness, p.exponent, p.damping, mass, speed, 1e-6);
      const double tol = ref < 0.25 ? 0.005 : 0.02 * ref;
      for (double phase = 0; phase < 0.99; phase += 0.25) {
        std::string error;
        const double e = Restitution(mass, speed, phase, true, &error, p);
        ASSERT_GE(e, 0) << error;
        EXPECT_NEAR(e, ref, tol) << mass << " kg at " << speed << " m/s, phase " << phase;
      }
    }
  }
}

// energy of a block on a vertical slide after `bounces` undamped bounces, relative to the
// start (a free block's flat bounce lets its rocking grow, in both schemes, and the tumbling
// that follows is a different test: this one is the normal law's energy balance)
double EnergyDrift(double mass, int bounces, bool implicit, std::string* error) {
  std::string xml = BlockModel(kDt, mass, testing::kPlaneFloor);
  xml.replace(xml.find("<freejoint name=\"free\"/>"), 24,
              "<joint name=\"z\" type=\"slide\" axis=\"0 0 1\"/>");
  ModelPtr m = LoadString(xml, error);
  if (!m) return -100;
  DataPtr d(mj_makeData(m.get()));
  SoftContactParams p;
  p.damping = 0;
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {}, p, kRobotHalfMass, error);
  if (!contact) return -100;
  contact->SetImplicit(implicit);
  const double g = 9.81, body_z = 0.5;  // the slide's zero is the body's position
  auto gap = [&] { return body_z + d->qpos[0] - testing::kSoleHalf[2]; };
  auto energy = [&] { return mass * g * gap() + 0.5 * mass * d->qvel[0] * d->qvel[0]; };
  d->qpos[0] = 0.02 - body_z + testing::kSoleHalf[2];  // 2 cm above the floor
  const double e0 = energy();
  int count = 0;
  bool touching = false;
  for (int i = 0; i < 200000 && count < bounces; ++i) {
    contact->ApplyBeforeStep(m.get(), d.get());
    mj_step(m.get(), d.get());
    contact->Commit();
    const bool now = gap() < 0;
    if (touching && !now) ++count;
    touching = now;
  }
  if (count < bounces) {
    *error = "the block stopped bouncing";
    return -100;
  }
  return energy() / e0 - 1;  // in flight: the energy is the spring-free one
}

TEST(ContactImplicit, UndampedBouncesKeepTheirEnergy) {
  for (double mass : {10.0, 30.0, 60.0, 100.0}) {
    std::string error;
    const double imp = EnergyDrift(mass, 20, true, &error);
    ASSERT_GT(imp, -99) << error;
    const double exp = EnergyDrift(mass, 20, false, &error);
    std::printf("%.0f kg, 20 undamped bounces at 1 ms: energy %+.2f %% implicit, %+.2f %% "
                "explicit\n", mass, 100 * imp, 100 * exp);
    EXPECT_LT(std::abs(imp), 0.02) << mass << " kg";
  }
}

// At large steps the whole impact (14 ms at 0.1 m/s) falls within one or two steps, and the
// step's force rests on the free motion predicted from the accelerations in mjData. A state set
// from outside leaves them stale: they must be computed for it, not trusted (with stale ones
// the 60 kg block left at 0.070 instead of 0.307 at 8 ms and at 1.007 at 16 ms). Bounds: the
// restitution the same as from a consistent state (1e-9), and within 2 % of the converged one
// at 4 ms, 10 % at 8 and 16 ms (measured: +0.7 %, +4 %, +6.5 % at the worst phase).
TEST(ContactImplicit, LargeStepImpactsDoNotTrustStaleAccelerations) {
  const SoftContactParams p;
  const double mass = 60, speed = 0.1;
  const double ref = HuntCrossleyRestitution(p.stiffness, p.exponent, p.damping, mass, speed, 1e-6);
  for (double dt : {0.004, 0.008, 0.016}) {
    const double tol = (dt < 0.005 ? 0.02 : 0.10) * ref;
    double worst = ref;
    for (bool split : {false, true}) {
      for (double phase = 0; phase < 0.99; phase += 0.2) {
        std::string error;
        const double fresh = Restitution(mass, speed, phase, true, &error, p, {dt, split, false});
        ASSERT_GE(fresh, 0) << error;
        const double stale = Restitution(mass, speed, phase, true, &error, p, {dt, split, true});
        ASSERT_GE(stale, 0) << error;
        EXPECT_NEAR(stale, fresh, 1e-9) << dt << " s, split " << split << ", phase " << phase;
        EXPECT_NEAR(fresh, ref, tol) << dt << " s, split " << split << ", phase " << phase;
        if (std::abs(fresh - ref) > std::abs(worst - ref)) worst = fresh;
      }
    }
    std::printf("%g ms: restitution %.4f at the worst phase, converged %.4f (%+.1f %%)\n",
                dt * 1e3, worst, ref, 100 * (worst - ref) / ref);
  }
}

}  // namespace
}  // namespace ohrp::contact
