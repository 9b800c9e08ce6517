// The hip strategy's gain and clamp from the robot (issue 31): what the stabilizer's torso
// offsets (stabilizer.h, step 5) may ask of a torso joint, derived from the model instead of
// HRP-1S's numbers. For each torso axis (pitch, roll):
//
//   I        the upper body's inertia about the joint (the link's, not the rotor's: the rotor's
//            reaction goes to the base), the mass matrix's diagonal at the stance;
//   m_u h_u  the upper body's mass times its centre of mass's height above the joint: leaning
//            the torso by theta moves the robot's CoM by (m_u h_u / m) sin(theta);
//   the joint's travel from the stance angle to its nearer limit, and its torque limit.
//
//   clamp    theta_max = min(travel / 2,  asin(half the sole's half width / ((m_u h_u) / m))):
//            half the joint's travel is left for the servo's overshoot and for braking, and a
//            torso leaning at its clamp moves the CoM by at most half the sole's half size
//            across it (the lean's weight is a ZMP shift the soles must then carry);
//   gain     the share of the cut-off moment asked of the torso, min(1, tau_free / (I a_ask)):
//            tau_free = tau_max - m_u g h_u sin(theta_max) is the torque the joint has left at
//            the clamp, a_ask the acceleration that reaches the clamp from rest within
//            the return's time scale 1/w0 (2 theta_max w0^2) --- the joint must be able to
//            stop what it was asked to start.
//
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
// half length for the pitch, half width for the roll) [m], `hip_return` w0 [rad/s]
HipAxisLimits DeriveHipAxis(const TorsoAxis& a, double mass, double sole_half, double hip_return);

}  // namespace ohrp::controllers
