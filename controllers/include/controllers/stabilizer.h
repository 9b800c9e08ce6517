// The standing stabilizer: a lower-layer law, no process and no segment in it, shared by the
// `balance` controller (and later by walking). It follows the stabilizers of position-controlled
// HRP robots (Kajita et al. 2010, "Biped walking stabilization based on linear inverted
// pendulum tracking"; hrpsys-base's Stabilizer), for a robot on two feet:
//
//   1. measured ZMP       from the two ankle force/torque sensors (MeasureZmp).
//   2. desired ZMP        from the divergent component of motion (DCM, capture point)
//                         xi = c + dc/omega, omega = sqrt(g / h), tracking the reference's
//                         xi_r = c_r + dc_r/omega with the reference's ZMP p_r = c_r - ddc_r/omega^2:
//                           p_d = p_r + (1 + k_dcm / omega) (xi - xi_r)
//                         so that xi - xi_r decays at the rate k_dcm [1/s] (for a still
//                         reference: p_d = xi + (k_dcm / omega)(xi - c_r)); p_d is then clamped
//                         to the support (the supporting soles' rectangle less a margin).
//   3. ankle strategy     the ZMP is distributed to the feet (normal force shares from p_d's
//                         lateral position, each sole's centre of pressure at p_d as far as the
//                         sole allows); each foot's rotation offset follows the damping
//                         control d(theta)/dt = (tau_measured - tau_desired) / D - theta / T,
//                         and the difference of the soles' heights follows
//                         d(dz)/dt = (fz_diff_measured - fz_diff_desired) / D_z - dz / T_z.
//                         On the soft soles this is the compliance the issue asks for: the foot
//                         yields until it carries the moment the balance needs. The offsets
//                         return (time constant T) to a rest orientation that follows the
//                         sole's measured tilt while its own CoP stays well inside it (it
//                         stands flat, so its tilt is the ground's): on a slope or a wave the
//                         feet keep the ground's tilt instead of being pulled back onto an
//                         edge, and on flat ground the rest stays flat (ground adaptation).
//   4. CoM correction    what the (leaky) damping control leaves of the CoM error is integrated
//                         slowly into a shift of the hips: d(offset)/dt = k_i (c_ref - c),
//                         only while the DCM is near c_ref (no wind-up during a push).
//   5. hip strategy       what the clamp cut off (the ZMP the soles cannot carry) is asked of
//                         the upper body instead: a torso rotation whose angular-momentum rate
//                         m g (p_d_raw - p_d) supplies the missing moment about the CoM,
//                         returned to upright by a critically damped spring once it is not
//                         needed.
// Frames: W (world, z up). Everything is in SI units. Update never allocates or throws.
#pragma once

#include <Eigen/Core>

namespace ohrp::controllers {

// The wrench measured at one ankle sensor, expressed in W: what the foot exerts on the leg
// (the ground reaction carried by the sensor) and its moment about the sensor origin p_WS.
struct FootWrench {
  Eigen::Vector3d p_WS = Eigen::Vector3d::Zero();  // sensor origin [m]
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();   // force [N]
  Eigen::Vector3d n_W = Eigen::Vector3d::Zero();   // moment about p_WS [N m]
};

// The ZMP of the wrenches on the horizontal plane z = ground_z. Returns false (and leaves p
// untouched) when the total normal force is below `min_fz` [N].
bool MeasureZmp(const FootWrench* feet, int n, double ground_z, double min_fz,
                Eigen::Vector2d* p_W);

struct StabilizerGains {
  double k_dcm = 3.0;            // DCM convergence rate [1/s]
  double support_margin = 0.015; // keep the desired ZMP this far inside the soles [m]
  double ankle_damping = 300.0;  // D of the foot rotation damping control [N m s/rad]
  double ankle_recovery = 2.0;   // T: foot rotation offsets decay with this time constant [s]
  double max_foot_rotation = 0.15;  // clamp of the foot rotation offsets about the rest [rad]
  // clamp of the rest orientation itself: the ground's tilt the soles follow (a slope, learnt or
  // from a known terrain) [rad]
  double max_ground_tilt = 0.35;
  double ground_adaptation = 1.0;   // time constant with which the feet's rest orientation
                                    // follows the measured tilt of the sole while it stands
                                    // flat [s] (0: off; the offsets then return to zero)
  double flat_margin = 0.02;        // a sole stands flat while its CoP is this far inside [m]
  double z_damping = 2.0e4;      // D_z of the sole height difference control [N s/m]
  double z_recovery = 0.5;       // T_z [s]
  double max_dz = 0.03;          // clamp of the sole height difference [m]
  double k_com_integral = 1.0;   // rate of the slow CoM position correction [1/s]
  double max_com_offset = 0.03;  // clamp of that correction [m]
  double com_integral_band = 0.01;  // integrate only while |DCM - c_ref| is below this [m]
  double hip_gain = 1.0;         // share of the cut-off moment asked of the torso [-]
  double hip_return = 4.0;       // natural frequency of the torso's return to upright [rad/s]
  // per torso axis (pitch, roll), set from the model by balance and walk (hip_strategy.h): the
  // upper body's inertia about the waist joint [kg m^2] (balance and walk give both axes the
  // pitch joint's), the share of hip_gain this axis takes [-] and the clamp of its offset [rad]
  double torso_inertia[2] = {6.0, 6.0};
  double torso_share[2] = {1.0, 1.0};
  double torso_limit[2] = {0.35, 0.35};
  bool ankle_strategy = true;    // foot damping control on (off: feet held as commanded)
  bool hip_strategy = true;      // torso rotation on
};

// The support: the two soles as rectangles in W (centres, half sizes along the sole's own x
// and y, yaw about W's z), and where the CoM should stand. The desired ZMP is clamped into the
// supporting sole (one foot) or into the bounding box of both soles' corners (two feet); the
// normal force is shared along the line between the soles' centres and each sole's CoP is
// placed, in the sole's own frame, as near the desired ZMP as the sole allows.
struct Support {
  Eigen::Vector2d centre[2];      // left, right sole centres [m]
  Eigen::Vector2d half_size[2];   // their half lengths along the sole's x and y [m]
  double yaw[2] = {0, 0};         // the soles' yaw in W [rad] (0: aligned with W's axes)
  double ground_z = 0;            // height of the soles' bottoms [m]
  bool supporting[2] = {true, true};  // which soles carry the robot (false: a swing foot,
                                      // given no load, no damping control, no height control)
};

struct StabilizerInput {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();   // centre of mass (estimated) [m]
  Eigen::Vector3d dc = Eigen::Vector3d::Zero();  // its velocity [m/s]
  Eigen::Vector2d c_ref = Eigen::Vector2d::Zero();  // where the CoM should be [m]
  Eigen::Vector2d dc_ref = Eigen::Vector2d::Zero();   // its velocity [m/s]
  Eigen::Vector2d ddc_ref = Eigen::Vector2d::Zero();  // its acceleration [m/s^2]
  // what the reference's ZMP has beyond the cart-table's c_ref - ddc_ref / omega^2 (a walk's
  // swinging legs: walking::WalkSample::zmp_swing) [m]
  Eigen::Vector2d zmp_ref_offset = Eigen::Vector2d::Zero();
  FootWrench feet[2];                            // left, right ankle wrenches
  // the soles' measured tilt in W (estimated base orientation and joint angles): roll about
  // x and pitch about y such that the sole's normal is Rx(roll) Ry(pitch) e_z [rad]
  Eigen::Vector2d sole_tilt[2] = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  Support support;
  double mass = 0;                               // robot mass [kg]
  // the torso's heading in W (yaw) [rad]: the hip strategy's torso pitch and roll are joint
  // offsets about the torso's own axes, so a ZMP excess along W is turned into them
  double heading = 0;
};

struct StabilizerOutput {
  Eigen::Vector2d zmp_measured = Eigen::Vector2d::Zero();  // [m] (last valid)
  Eigen::Vector2d zmp_desired_raw = Eigen::Vector2d::Zero();  // before the clamp [m]
  Eigen::Vector2d zmp_desired = Eigen::Vector2d::Zero();   // clamped to the support [m]
  Eigen::Vector2d dcm = Eigen::Vector2d::Zero();           // xi [m]
  double fz_share[2] = {0.5, 0.5};                         // desired normal force shares
  // commands: foot rotation offsets about W's x and y (left, right) [rad], sole height
  // difference left minus right [m] (applied +dz/2 on the left, -dz/2 on the right), and the
  // torso's pitch (about y) and roll (about x) offsets [rad]
  double foot_roll[2] = {0, 0}, foot_pitch[2] = {0, 0};
  // the orientation the offsets return to: learnt while the sole stands flat on the ground,
  // so that a foot on a slope stays parallel to it (ground adaptation) [rad]
  double rest_roll[2] = {0, 0}, rest_pitch[2] = {0, 0};
  double dz = 0;
  double torso_pitch = 0, torso_roll = 0;
  // the slow correction of the CoM's stance: move the base (hips) by this in W's x and y, so
  // that what the leaky ankle control leaves of a CoM error goes to zero [m]
  Eigen::Vector2d com_offset = Eigen::Vector2d::Zero();
  bool zmp_valid = false;
};

class Stabilizer {
 public:
  explicit Stabilizer(StabilizerGains gains = {});
  // forgets the offsets (foot, height, torso): the robot stands as commanded
  void Reset();
  // the same, with the feet starting at (and resting on) the given tilts [rad]: the ground's
  // under each sole, when the robot starts on uneven ground
  void Reset(const Eigen::Vector2d ground_tilt[2]);
  // sets foot i's rotation offsets and the orientation they return to (a swing foot that will
  // land on a surface of this tilt) [rad]
  void SetFootTilt(int i, double roll, double pitch);
  // one control cycle of `dt` [s]
  const StabilizerOutput& Update(const StabilizerInput& in, double dt) noexcept;

  const StabilizerGains& gains() const { return gains_; }
  StabilizerGains& gains() { return gains_; }
  const StabilizerOutput& output() const { return out_; }

 private:
  // Update's stages, in order (stabilizer.cc)
  void MeasureZmpAtFeet(const StabilizerInput& in) noexcept;
  void DesireZmpFromDcm(const StabilizerInput& in) noexcept;
  void HoldZmpInsideSupport(const Support& s, const Eigen::Vector2d& c) noexcept;
  Eigen::Vector2d ShareLoadBetweenFeet(const Support& s) noexcept;
  void DampFoot(const StabilizerInput& in, int i, double fz_d, const Eigen::Vector2d& residual,
                double dt) noexcept;
  void AdaptRestToGround(const StabilizerInput& in, int i, double dt) noexcept;
  void DampSoleHeights(const StabilizerInput& in, double fz_total, double dt) noexcept;
  void CorrectComSlowly(const StabilizerInput& in, const Eigen::Vector2d& c, double dt) noexcept;
  void SwayTorso(const StabilizerInput& in, const Eigen::Vector2d& excess, double dt) noexcept;

  StabilizerGains gains_;
  StabilizerOutput out_;
  double torso_rate_[2] = {0, 0};  // pitch, roll angular velocities of the torso offsets [rad/s]
};

}  // namespace ohrp::controllers
