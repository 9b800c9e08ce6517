// Parameters of the soft-foot contact (OpenHRP, IJRR 2004, section 3.3) and their validation.
//
// The normal law is Hunt-Crossley on a penetration delta >= 0 [m] and its rate ddelta [m/s]:
//     f_n = k * delta^n * (1 + c * ddelta),  clamped to f_n >= 0 (the contact never pulls),
// which vanishes continuously at separation (delta -> 0). The friction is a tangential spring
// with a damper, saturated by Coulomb's cone |f_t| <= mu * f_n (stick below, slip at the bound).
// All stiffnesses and dampings are PER SOLE (the whole bottom face in full contact); the
// library spreads them over the sample points of the face by area.
#pragma once

#include <string>

namespace ohrp::contact {

struct SoftContactParams {
  // k [N/m^n] (N/m for n = 1): the normal stiffness of one sole (rubber + foot mechanism).
  // Default 3e6 N/m: HRP-1S in mjcf/hrp1s (130.8 kg, 1283 N) standing sinks 0.21 mm per foot,
  // 0.43 mm on one foot. Why not "a few mm": the robot's centre of mass stands above the ankle,
  // 5.6 cm behind the sole's centre, outside the middle sixth (L/6 = 4.2 cm) where a bed of
  // springs keeps the whole sole loaded, so the toes unload and the heel rows must hold the
  // rigid robot against m g h = 975 N m/rad of toppling. Measured (tests/contact/robot_test,
  // joints held stiff) with an earlier cell-centred sample grid, whose support polygon was
  // half a cell (2.5 cm) shorter at each end than the sole: it fell over backwards at
  // k <= 1e6 N/m (2 mm sink: 3e5 N/m) and stood from 2e6 N/m; 3e6 keeps a 1.5x margin. Vertical frequency standing: sqrt(2k/m) = 214 rad/s
  // (34 Hz); explicit-step number at 1 ms: (omega dt)^2 = 0.05, far inside the stable range.
  double stiffness = 3.0e6;
  // n [-]: force ~ k * delta^n. 1 = linear mechanism spring (default, the HRP-1S foot has a
  // mechanical spring); 1.5 = Hertz-like rubber pad. Must be in [1, 3].
  double exponent = 1.0;
  // c [s/m]: Hunt-Crossley damping coefficient (the "alpha" of Hunt & Crossley 1975). For small
  // impact speeds (c v << 1) the coefficient of restitution is e ~= 1 - (2/3) c v (any n).
  // Default 30 s/m, chosen from the standing robot's modes (the foot mechanism's damper):
  //  - vertical: damping ratio c*g/(2*omega) = 0.69 (omega = sqrt(2k/m) = 214 rad/s);
  //  - rocking (figure 12, tests/sim_host/rocking_test): about 0.06. The damper force scales
  //    with the static depth (0.2 mm), so the slow rocking modes are the least damped; at
  //    c = 10 rocking was damped 2 % and the robot swayed for seconds after landing on the
  //    uneven floor (scenarios/stand_uneven.yaml), ringing 2.6 N where 30 s/m gives 0.4 N;
  //  - restitution (the law's ODE) 0.31 for a foot landing at 0.1 m/s, 0.11 at 0.3 m/s;
  //  - explicit stability at 1 ms with the peak load 3 m g (see Validate): 2 dt c 3 g = 1.8
  //    of the budget 2, so 30 s/m is close to the most a 1 ms step accepts; a smaller step
  //    accepts more (the limit is inversely proportional to dt).
  double damping = 30.0;
  // mu [-]: Coulomb friction coefficient, rubber on a floor (matches the model's friction 1).
  double friction = 1.0;
  // k_t [N/m]: tangential (shear) stiffness of one sole while it sticks. 1e6 N/m: 0.6 mm of
  // shear at the sliding limit of a standing foot (mu * 640 N).
  double tangential_stiffness = 1.0e6;
  // b_t [N s/m]: tangential damping of one sole while it sticks: damping ratio
  // b_t / (2 sqrt(k_t m)) = 0.19 for 65 kg on a sole, and still explicit-stable at 1 ms for a
  // mass of 5 kg.
  double tangential_damping = 3.0e3;
  // Sample grid on the sole's bottom face: grid_x points along the sole's x (length), grid_y
  // along y (width), the outer ones on the sole's edges so that the sampled support polygon is
  // the sole's own, weighted by the trapezoid rule (see MakeGrid).
  int grid_x = 5;
  int grid_y = 3;
  // [m]: broad-phase margin. A sole whose bounding box is farther than this from an object's
  // bounding box (or whose lowest corner is this far above a plane) costs no FCL query.
  double margin = 0.01;
  // Estimate the sole's penetration (depth + tilt) by least squares per (sole, object) pair, as
  // the paper does, instead of using each point's raw depth.
  bool least_squares = true;
};

// Peak load used by the stability check, as a multiple of mass_scale * g (impacts, walking).
inline constexpr double kPeakLoadFactor = 3.0;
// The check demands dt^2*K/m + 2*dt*beta <= kStabilityBudget; the explicit (semi-implicit
// Euler) step of a damped oscillator is stable for values < 4, half of that is kept as margin.
inline constexpr double kStabilityBudget = 2.0;

// How the step integrates the law: kImplicit is SoftFootContact's linearly implicit force (the
// spring and damper through the sole bodies' apparent inertia, implicit.cc), stable at any step
// for the linearised law, so only the ranges are checked; kExplicit is the law held over the
// step (RK4's stage evaluation, SetImplicit(false)), checked against the budget below.
enum class StepScheme { kExplicit, kImplicit };

// Checks the parameters for a physics step dt [s] and the smallest mass that rides on one sole
// mass_scale [kg] (the robot standing: its mass / 2; a single block: its mass). Returns false
// with every problem in *error (one per line), each naming the parameter, why, and what would
// work. The stability check linearises the normal law at kPeakLoadFactor * mass_scale * g:
// K = n k delta^(n-1), beta = c k delta^n / m, and the tangential law: K = k_t, beta = b_t / m
// (kExplicit only).
bool Validate(const SoftContactParams& p, double dt, double mass_scale, std::string* error,
              StepScheme scheme = StepScheme::kExplicit);

// How long an impact on the sole lasts: half a period of the law linearised at the static load
// of mass_scale, pi / sqrt(K / m), K = n k delta^(n-1), delta = (m g / k)^(1/n) [s] (14 ms for
// the default sole under 60 kg).
double ImpactDuration(const SoftContactParams& p, double mass_scale);
// Steps per impact below which a step does not resolve the force during an impact (its peak and
// shape). The restitution holds: the 60 kg block at 0.1 m/s on the default sole leaves within
// 0.7 % of the converged restitution at 4 ms, 4 % at 8 ms, 6.5 % at 16 ms, whatever the phase
// (contact_implicit_test). Standing and walking hold at 4 ms (scenarios stand_4ms,
// walk_samplepd_4ms).
inline constexpr double kImpactSteps = 4.0;
// A note for the user when dt gives fewer than kImpactSteps steps per impact ("" otherwise):
// what it means and what would resolve impacts. Not an error: the implicit step stays stable.
std::string ImpactNote(const SoftContactParams& p, double dt, double mass_scale);

// The law's coefficient of restitution for a point mass m [kg] hitting at v0 [m/s] (> 0): the
// 1-DOF oscillator m x'' = -k x^n (1 + c x')+ integrated with RK4 at step h [s] from contact to
// separation (crossing linearly interpolated). The reference for the impact tests and the
// accuracy report; NaN if it has not separated after 1e8 steps.
double HuntCrossleyRestitution(double k, double n, double c, double m, double v0, double h);

}  // namespace ohrp::contact
