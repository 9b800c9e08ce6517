// The hip strategy's gain and clamp from the robot (issue 31): what the stabilizer's torso
// offsets (stabilizer.h, step 5) may ask of a torso joint, derived from the model instead of
// HRP-1S's numbers. For each torso axis (pitch, roll):
//
//   I        the upper body's inertia about the joint (the link's, not the rotor's: the rotor's
//            reaction goes to the base), the mass matrix's diagonal at the stance: measured and
//            reported, not used by the clamp or the share (the stabilizer takes the pitch
//            joint's on both axes, docs/robots.md);
//   m_u h_u  the upper body's mass times its centre of mass's height above the joint: leaning
//            the torso by theta moves the robot's CoM by (m_u h_u / m) sin(theta);
//   the joint's travel from the stance angle to its nearer limit, and its torque limit.
//
//   clamp    theta_max = min(2/3 travel, asin(sole_half / 2 / (m_u h_u / m))): a third of the
//            joint's travel left for the servo's lag and its braking, and a torso leaning at
//            its clamp moves the CoM by at most half the sole's half size across it (the lean's
//            weight is a ZMP shift the soles must then carry);
//   share    min(1, tau_free / (m g sole_half)): the moment asked for an excess of the sole's
//            half size must be within tau_free = tau_max - g m_u h_u sin(theta_max), the torque
//            the joint has left at the clamp after holding the leaning upper body.
//
// HRP-1S (WAIST_P / WAIST_R, travel 0.524 rad, m_u h_u 11.48 kg m of 130.8 kg, 400 N m): clamp
// 0.349 rad on both axes (was 0.35), share 1 (was 1). G1 (waist pitch / roll, travel 0.52 rad,
// m_u h_u 1.96 kg m of 33.3 kg, 50 N m, sole 0.17 x 0.06 m): pitch 0.347 rad, roll 0.258 rad
// (the lean's CoM shift across the 6 cm sole), share 1. The control period does not enter
// (docs/robots.md says what was tried).
// Configuration time only (allocates).
#pragma once

namespace ohrp::controllers {

struct TorsoAxis {
  double inertia = 0;   // upper body about the joint, without the rotor [kg m^2]
  double moment = 0;    // m_u h_u [kg m]
  double travel = 0;    // from the stance angle to the nearer joint limit [rad]
  double tau_max = 0;   // the joint's torque limit [N m]
};

struct HipAxisLimits {
  double gain = 0;       // share of the cut-off moment asked of this axis [-]
  double max_angle = 0;  // clamp of the offset [rad]
};

// `mass` the robot's [kg], `sole_half` the sole's half size across this axis's lean (the sole's
// half length for the pitch, half width for the roll) [m]
HipAxisLimits DeriveHipAxis(const TorsoAxis& a, double mass, double sole_half);

}  // namespace ohrp::controllers
