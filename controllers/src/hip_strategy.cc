// The hip strategy's gain and clamp from the robot (see hip_strategy.h).
#include "controllers/hip_strategy.h"

#include <algorithm>
#include <cmath>

namespace ohrp::controllers {

HipAxisLimits DeriveHipAxis(const TorsoAxis& a, double mass, double sole_half) {
  constexpr double kGravity = 9.81;
  constexpr double kTravelShare = 2.0 / 3.0;
  constexpr double kSoleShare = 0.5;
  HipAxisLimits out;
  // the clamp: two thirds of the joint's travel (a third left for the servo's lag and its
  // braking), and a lean that moves the CoM by at most half the sole's half size
  const double lever = a.moment / std::max(mass, 1e-9);  // CoM shift per unit sin(lean) [m]
  double clamp = kTravelShare * a.travel;
  if (lever > kSoleShare * sole_half) clamp = std::min(clamp, std::asin(kSoleShare * sole_half / lever));
  out.max_angle = std::max(clamp, 0.0);
  // the share: the moment asked for an excess of the sole's half size must be within the
  // torque the joint has left at the clamp (after holding the leaning upper body)
  double share = 1.0;
  const double tau_free = a.tau_max - kGravity * a.moment * std::sin(out.max_angle);
  const double tau_ask = mass * kGravity * sole_half;
  if (tau_ask > 0) share = std::min(share, tau_free / tau_ask);
  out.gain = std::max(share, 0.0);
  return out;
}

}  // namespace ohrp::controllers
