// The walking pattern generator (the paper's section 4.2): footsteps in; the CoM, the ZMP,
// the feet and, through walk_ik.h, the joint angles out, one control period at a time.
//
// The CoM's horizontal motion is the preview control of the cart-table model
// (preview_control.h) on the gait's ZMP reference (gait.h); its height is the CoM height of the
// stance (from the robot model, given at Start) above the ground under the ZMP reference, which
// moves over the double supports on stairs and slopes. Steps that have not started can be
// replaced at any time (Replace): the preview servo's state carries on, so the CoM does not
// jump; only the reference ahead changes.
// Per-cycle (Advance) work allocates nothing and throws nothing.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "walking/gait.h"
#include "walking/preview_control.h"

namespace ohrp::walking {

struct WalkSample {
  double t = 0;                                      // [s]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();     // planned CoM [m]
  Eigen::Vector3d dcom = Eigen::Vector3d::Zero();    // [m/s]
  Eigen::Vector3d ddcom = Eigen::Vector3d::Zero();   // [m/s^2]
  Eigen::Vector2d zmp = Eigen::Vector2d::Zero();     // the cart-table ZMP of the planned CoM [m]
  // the ZMP's share the swinging legs add to the cart's (SwingZmpGain times the feet's
  // horizontal acceleration): the robot's ZMP is zmp + zmp_swing, which the preview makes the
  // gait's reference [m]
  Eigen::Vector2d zmp_swing = Eigen::Vector2d::Zero();
  GaitState gait;                                    // ZMP reference, ground, feet, support
};

// A leg's body, for SwingZmpGain: its mass and its centre of mass's height above the soles in
// the walking stance.
struct LegBody {
  double mass = 0;    // [kg]
  double height = 0;  // [m]
};
// How far the ZMP moves per unit horizontal acceleration of a swinging foot [s^2] when the
// whole-body CoM follows the plan (the leg IK moves the rest of the body against the leg):
//   kappa = sum_i m_i s_i (z_r - z_i) / (M g),  s_i = clamp((hip - z_i) / (hip - sole), 0, 1)
// body i of the leg, at height z_i, moving with the share s_i of the foot's acceleration (the
// leg turning about the hip joint at height `hip_height`, the sole at 0); z_r the height of the
// rest of the robot's centre of mass (total mass M, CoM at `com_height`), whose acceleration
// cancels the leg's linear momentum rate: the ZMP moves by kappa times the foot's acceleration,
// the way it goes. 0 for no legs or no mass.
double SwingZmpGain(const std::vector<LegBody>& leg, double hip_height, double com_height,
                    double total_mass, double gravity = 9.81);

class PatternGenerator {
 public:
  // the preview gains for this period and CoM height; false with `*error` on bad options
  bool Configure(const GaitOptions& gait, const PreviewOptions& preview, std::string* error);
  // standing at `t` on `feet` with the CoM at `com` (at rest); the CoM height above the
  // feet's mean height is the preview's zc (the gains are recomputed if it differs from the
  // configured one by more than 1 mm)
  bool Start(double t, const FeetPose& feet, const Eigen::Vector3d& com, std::string* error);
  // room for `n` steps (Replace allocates nothing up to that many)
  void Reserve(int n) { gait_.Reserve(n); }
  // replaces the steps not yet started by `steps` (gait.h); returns the first new index
  int Replace(const std::vector<Footstep>& steps);
  // moves the landing of step k, under way in its single support, to `xy` (Gait::AdjustLanding
  // at the generator's time); false when it is not in single support. No allocation.
  bool AdjustLanding(int k, const Eigen::Vector2d& xy) { return gait_.AdjustLanding(k, xy, t_); }
  // and its landing time, the later steps carried with it (Gait::AdjustStep). No allocation.
  bool AdjustStep(int k, const Eigen::Vector2d& xy, double t_land, bool carry_later) {
    return gait_.AdjustStep(k, xy, t_land, carry_later, t_);
  }
  // the planned CoM moved by `dc` [m] and its velocity by `dv` [m/s] (horizontal; e.g. onto a
  // measured state after a push): the preview servo plans on from there. No allocation.
  void ShiftCoM(const Eigen::Vector2d& dc, const Eigen::Vector2d& dv);
  // the ZMP's share per unit horizontal acceleration of a swinging foot (SwingZmpGain) [s^2]:
  // the preview follows the gait's ZMP reference less that share, so that the robot's ZMP (the
  // cart's plus the legs') is on the reference. 0 (the default): the cart-table model alone
  void SetSwingZmpGain(double kappa) { swing_gain_ = kappa; }
  // one control period ahead; no allocation
  const WalkSample& Advance();

  const WalkSample& sample() const { return sample_; }
  // step k's landing `delay` [s] later, the rest after it (Gait::DelayLanding). No allocation.
  bool DelayLanding(int k, double delay) { return gait_.DelayLanding(k, delay, t_); }
  const Gait& gait() const { return gait_; }
  const PreviewGains& gains() const { return gains_; }
  double zc() const { return gains_.options().zc; }
  // true while steps remain or the ZMP reference still moves
  bool walking() const { return sample_.t < gait_.end_time(); }

 private:
  void Sample();
  void SizeHorizon();
  // the legs' share of the ZMP over the horizon taken out of the reference (swing_gain_)
  void SwingShare(double dt, int n);

  GaitOptions gait_options_;
  PreviewGains gains_;
  Gait gait_;
  PreviewAxis axis_[2];
  std::vector<double> ref_[2];  // the ZMP reference over the horizon, x and y
  // both feet's horizontal positions over the horizon, one sample before and after it too
  std::vector<Eigen::Vector2d> feet_[2];
  double swing_gain_ = 0;       // [s^2]
  double t_ = 0;
  double ground0_ = 0;          // the ground height the CoM height zc is measured from at Start
  WalkSample sample_;
};

}  // namespace ohrp::walking
