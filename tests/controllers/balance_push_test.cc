// Tests the balance controller closed-loop on the simulated HRP-1S (in-process, soft soles,
// 1 ms physics, 5 ms control): it stands, it survives and settles after pushes in 8 directions,
// and it does at least as well as the stiff posture controller.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "push_trial.h"

namespace ohrp::controllers::testing {
namespace {

double Env(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

// a development aid (disabled): settling and survival for the gains in OHRP_TUNE_* variables
TEST(BalancePush, DISABLED_Explore) {
  model::InstallMujocoHandlers(nullptr);
  BalanceOptions o;
  StabilizerGains& g = o.gains;
  g.k_dcm = Env("OHRP_TUNE_KDCM", g.k_dcm);
  g.ankle_damping = Env("OHRP_TUNE_D", g.ankle_damping);
  g.ankle_recovery = Env("OHRP_TUNE_T", g.ankle_recovery);
  g.z_damping = Env("OHRP_TUNE_DZ", g.z_damping);
  g.hip_gain = Env("OHRP_TUNE_HIP", g.hip_gain);
  g.hip_return = Env("OHRP_TUNE_HIPW", g.hip_return);
  g.ankle_strategy = Env("OHRP_TUNE_ANKLE", 1) > 0;
  g.support_margin = Env("OHRP_TUNE_MARGIN", g.support_margin);
  g.ground_adaptation = Env("OHRP_TUNE_GA", g.ground_adaptation);
  o.centre_com = Env("OHRP_TUNE_CENTRE", 1) > 0;
  const double impulse = Env("OHRP_TUNE_IMPULSE", 15);
  const bool posture = Env("OHRP_TUNE_POSTURE", 0) > 0;
  const bool bisect = Env("OHRP_TUNE_BISECT", 0) > 0;
  if (Env("OHRP_TUNE_ONELEG", 0) > 0) {
    o.one_leg.sides = {0, 1};
    PushTrial t;
    t.options = o;
    t.scene = std::getenv("OHRP_TUNE_SCENE") ? std::getenv("OHRP_TUNE_SCENE") : t.scene;
    const OneLegOutcome r = RunOneLegTrial(t);
    std::printf("one leg: %s, min stance CoP margin %.1f mm, max swing load %.1f N, min lift %.1f mm\n",
                r.standing ? "standing" : "FELL", r.min_cop_margin * 1e3, r.max_swing_fz, r.min_lift * 1e3);
    return;
  }
  for (int dir = 0; dir < 360; dir += 45) {
    if (bisect) {
      double lo = 0, hi = 200;
      for (int k = 0; k < 2; ++k) {
        double a = 0, b = hi;
        while (b - a > 2) {
          const double mid = 0.5 * (a + b);
          PushTrial t;
          t.balance = k == 0;
          t.direction = dir;
          t.impulse = mid;
          t.options = o;
          (RunPushTrial(t).standing ? a : b) = mid;
        }
        (k == 0 ? lo : hi) = a;
      }
      std::printf("dir %3d largest impulse: balance %6.1f N s, posture %6.1f N s\n", dir, lo, hi);
      continue;
    }
    PushTrial t;
    t.balance = !posture;
    t.direction = dir;
    t.impulse = impulse;
    t.options = o;
    const PushOutcome r = RunPushTrial(t);
    std::printf("dir %3d impulse %5.1f: %s tilt %5.2f deg, base settles %6.3f s, torque settles "
                "%6.3f s (peak %.1f N m)\n",
                dir, impulse, r.standing ? "standing" : "FELL    ", r.max_tilt * 180 / M_PI,
                r.base_settle, r.torque_settle, r.torque_peak);
  }
}

}  // namespace
}  // namespace ohrp::controllers::testing
