// Balance: a standing stabilizer that keeps the robot up against pushes with the robot's own
// sensors only (ankle force/torque sensors, the IMU, the joint encoders; never sim_truth).
//
//   configure  loads its own copy of the robot's MJCF (--model) and refuses a producer whose
//              robot differs (the model hash in the segment header, robot_model/model_hash.h);
//              refuses a robot without a floating base, two soles each with a force/torque
//              sensor, or an IMU, saying what is missing.
//   ramp       once both soles are on the ground and the estimator has run 0.3 s (at most 1 s
//              after the first sensors, holding the measured pose until then), from the
//              measured pose to the stance pose
//              (half-sitting by default) over `ramp`
//              seconds of the producer's time, the soles kept at the tilt the estimator measures
//              at the start (on a ramp or a wave the ankles keep the ground's slope instead of
//              putting the soles on an edge), then `settle` seconds of quiet standing; the
//              centre of mass measured at the end is the stance reference c_ref. Then
//              (centre_com) the hips move so that the CoM comes over the middle of the soles,
//              where the soles leave the same margin to the toes and to the heels: the shift
//              is computed on the model (the CoM of the stance pose against the soles' centres)
//              and made over `centre_time` seconds, c_ref moving with it. Then, if asked,
//              standing on one leg in turn (stance_plan.h): the CoM over one sole, the other
//              lifted, held, put down, back to the middle.
//   stand      every cycle: the base estimator (robot_model/estimator.h) gives the CoM and its
//              velocity; the stabilizer (stabilizer.h) turns the DCM error into a desired ZMP,
//              foot rotation and height offsets (ankle strategy, damping control against the
//              ankle sensors) and torso offsets (hip strategy); leg inverse kinematics
//              (robot_model/ik.h) turns the sole targets into joint references.
//   hold       sensors that go non-finite or stale (their time stops advancing), or a board
//              fault reported by the producer, latch a
//              hold of the last commanded posture (never NaN); the reason and the time are
//              reported at the end of the run.
// The per-cycle path allocates nothing, throws nothing and logs nothing.
#pragma once

#include <array>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "controllers/controller.h"
#include "controllers/load_feedforward.h"
#include "controllers/pose.h"
#include "controllers/stabilizer.h"
#include "controllers/stance_plan.h"
#include "robot_model/estimator.h"
#include "robot_model/ik.h"
#include "robot_model/kinematics.h"

namespace ohrp::controllers {

// mjcf/hrp1s/hrp1s.xml of the data folder (cli/data_dir.h: <bin>/../share/ohrp)
std::string DefaultModelFile();

struct BalanceOptions {
  std::string model;        // MJCF of the robot; empty: DefaultModelFile()
  std::string pose_file;    // stance pose (pose.h); empty: half-sitting
  std::string keyframe;     // the stance pose from this keyframe of the --model MJCF instead
                            // of a pose file (e.g. G1's "stand"); empty: pose_file
  double ramp = 2.0;        // [s] from the measured pose to the stance pose
  double settle = 0.5;      // [s] of quiet standing before c_ref is taken
  bool centre_com = true;   // move the CoM over the middle of the soles once standing
  std::string program = "balance";  // the program the options came from (its messages' remedies)
  double centre_time = 1.0; // [s] that move takes (minimum jerk)
  OneLegOptions one_leg;    // standing on one foot in turn after that (stance_plan.h)
  StabilizerGains gains;
  model::EstimatorOptions estimator;
  // the joints' servo: the producer's suggested gains (a critically damped servo at 6 Hz on
  // each joint's own inertia) scaled to this closing frequency [Hz]: kp * (f / 6)^2,
  // kd * (f / 6); 0: the suggested gains as they are
  double servo_frequency = 0;
  // the joints' feed-forward carries the robot's weight on the soles in the stabilizer's
  // shares (load_feedforward.h), so the servo does not sag under it: 1 on (--load-feedforward),
  // 0 off (--no-load-feedforward), -1 the robot profile's servo.load_feedforward (else off)
  int load_feedforward = -1;
  // set by the set-up (not an option): the stance leg's largest sag under the whole weight
  // without the feed-forward (derived_gait.h, LargestSag) [rad]; 0 when not known
  double stance_sag = 0;
};

// why the controller went to its hold (BalanceController::hold_reason)
enum class HoldReason { kNone, kNonFiniteSensors, kBoardFault, kEstimatorFailed, kStaleSensors };
const char* HoldReasonName(HoldReason r);

// what happened during the run, for the report and for tests
struct BalanceStats {
  uint64_t stand_cycles = 0;
  uint64_t ik_failures = 0;          // leg IK results not converged (the leg kept its last refs)
  uint64_t ik_failed_cycles = 0;     // stance cycles in which a leg's IK did not converge
  double longest_ik_failure = 0;     // longest run of such cycles in a row [s]
  uint64_t hold_cycles = 0;
  double max_zmp_error = 0;          // max |zmp_measured - zmp_desired| while standing [m]
  double max_torso_angle = 0;        // largest torso offset used [rad]
  double max_foot_rotation = 0;      // largest foot rotation offset used [rad]
  double max_dcm_error = 0;          // max |xi - c_ref| [m]
  double hold_time = -1;             // producer time of the hold (-1: never) [s]
  HoldReason hold_reason = HoldReason::kNone;
};

class BalanceController : public Controller {
 public:
  // Checks the options, loads the pose and the model, checks the robot has what balance needs.
  // Null with `*status` set on failure (kOption: a bad value; kFile: a file; kMismatch: the
  // robot lacks a sensor balance needs).
  static std::unique_ptr<BalanceController> Create(const BalanceOptions& options,
                                                   ConfigStatus* status);

  const BalanceStats& stats() const { return stats_; }
  // a leg that leaves the ground is part of the balance (a step): the guard does not brake it
  bool guard_may_brake_legs() const override { return false; }
  const StabilizerOutput& stabilizer_output() const { return stabilizer_.output(); }
  const model::BaseEstimate& estimate() const { return estimator_->estimate(); }
  bool standing() const { return phase_ == Phase::kStand; }
  // the stance reference of the CoM (valid once standing) [m]
  const Eigen::Vector2d& c_ref() const { return c_ref_; }
  // the stance plan's targets of the last cycle (while standing)
  const StanceTargets& targets() const { return targets_; }
  void report(std::ostream& out) const override;
  // the fall watch from the model: the stance CoM's height over the soles, the soles' reach
  void fall_limits(FallLimits* limits) const override;
  // the estimator's base tilt (NaN before it runs and while held)
  double base_tilt() const noexcept override;
  // the estimator's CoM over the lower sole (NaN before it runs and while held)
  double com_height() const noexcept override;
  // persistent leg IK failures: the stance was not what was commanded (balance.cc)
  std::string failure() const override;

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void on_activate(const shm::SensorBlock& sensors) noexcept override;
  void on_update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept override;

 protected:
  // what a balance-based controller (e.g. walk.h) needs of it; its per-cycle stages are
  // protected so that a subclass can run them in its own Stand
  enum class Phase { kRamp, kStand, kHold };
  BalanceController(const BalanceOptions& options, Pose pose,
                    std::unique_ptr<model::Kinematics> kin_est,
                    std::unique_ptr<model::Kinematics> kin_ik);
  // Create's checks and loads: the options with the defaults filled in, the stance pose and
  // two copies of the model (estimator, IK); `program` names the caller in messages
  static ConfigStatus LoadParts(const BalanceOptions& options, const char* program,
                                BalanceOptions* filled, Pose* pose,
                                std::unique_ptr<model::Kinematics>* kin_est,
                                std::unique_ptr<model::Kinematics>* kin_ik);
  bool SensorsUsable(const shm::SensorBlock& s, HoldReason* why) const noexcept;
  void EnterStand(const shm::SensorBlock& s) noexcept;
  // the ramp to the stance pose, the legs fitted to the ground under the loaded soles
  void StartRamp(double time) noexcept;
  // sole i's tilt in W as the estimator sees it (roll, pitch; stabilizer.h), base yaw removed
  Eigen::Vector2d SoleTilt(int i) const;
  // the hip shift (base frame) that puts the model's CoM over `p_B` (base frame) with the soles
  // held, and how far the CoM moves; false when the legs cannot reach
  bool SolveShiftOver(const Eigen::Vector2d& p_B, StanceShift* shift);
  // the hip strategy's per-axis inertia, share and clamp from the model (hip_strategy.h)
  void DeriveHipStrategy(StabilizerGains* g);
  // the foot rotation damping D from the ankles' servo stiffness (balance_derive.cc)
  void DeriveAnkleDamping(StabilizerGains* g);
  // one stance cycle, in stages:
  virtual void Stand(const shm::SensorBlock& s, double dt) noexcept;
  void FillStabilizerInput(const shm::SensorBlock& s, double t,
                           const Eigen::Rotation2Dd& R_yaw) noexcept;
  void SwingLift(double dt, double lift[2]) noexcept;
  void CountStand(const StabilizerOutput& out) noexcept;
  // tau_ff_: the load's feed-forward for the measured state and the stabilizer's force shares
  // (zeros without it)
  void CarryLoad(const StabilizerOutput& out) noexcept;
  void SolveJoints(const StabilizerOutput& out, const Eigen::Vector2d& offset_B,
                   const double lift[2]) noexcept;
  void Write(shm::CommandBlock* commands, double dt) noexcept;
  // counts a stance cycle whose IK failed (`failed`) or not, and the longest run of them
  void CountIk(bool failed) noexcept;
  // the report's figures of the stance: "1.23 s (246 cycles); max |ZMP error| ..."
  std::string StanceFigures() const;

  BalanceOptions options_;
  Pose pose_;
  std::unique_ptr<model::Kinematics> kin_est_;  // the estimator's (estimated state)
  std::unique_ptr<model::Kinematics> kin_ik_;   // the legs' IK (base frame, upright)
  std::unique_ptr<model::BaseEstimator> estimator_;
  std::unique_ptr<model::LimbIk> leg_ik_[2];    // left, right
  std::unique_ptr<LoadFeedforward> load_ff_;     // null without --load-feedforward
  Stabilizer stabilizer_;
  StabilizerInput input_;
  int sole_[2] = {-1, -1};
  int sensor_site_[2] = {-1, -1};
  int force_[2] = {-1, -1};
  int imu_ = 0;
  int torso_pitch_joint_ = -1, torso_roll_joint_ = -1;
  Eigen::Vector3d p_BS_nominal_[2];
  Eigen::Matrix3d R_BS_nominal_[2];
  Eigen::Vector2d c_ref_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d c_ref_start_ = Eigen::Vector2d::Zero();  // measured at the stance [m]
  StancePlan plan_;                                         // hips, CoM, support over time
  StanceTargets targets_;                                   // its targets of the last cycle
  double lift_extra_ = 0;    // closes the swing foot's measured lift onto the plan's [m]
  double sole_z0_[2] = {0, 0};  // the soles' estimated heights while both stand [m]
  int last_swing_ = 0;          // the sole lifted last
  bool lifted_ = false;         // the swing foot has reached its full lift
  double stand_time_ = 0;                                  // producer time of the stance [s]
  double com_height_ = 0;    // the stance CoM's height over the soles (model) [m]
  double sole_reach_ = 0;    // the soles' half length (model) [m]
  uint64_t ik_fail_run_ = 0; // stance cycles in a row whose IK failed

  Phase phase_ = Phase::kRamp;
  std::vector<double> target_;                   // stance pose (njoint)
  std::array<double, shm::kMaxJoints> ramp_target_{};  // the same, legs fitted to the ground
  std::array<double, shm::kMaxJoints> start_{};  // measured pose at activation
  std::array<double, shm::kMaxJoints> q_ref_{};
  std::array<double, shm::kMaxJoints> q_prev_{};
  std::array<double, shm::kMaxJoints> dq_ref_{};
  std::array<double, shm::kMaxJoints> q_ik_{};
  std::array<double, shm::kMaxJoints> tau_ff_{};  // feed-forward torques sent (the load's)
  double start_time_ = 0, last_time_ = 0, activate_time_ = 0;
  bool ramp_started_ = false;
  int stale_blocks_ = 0;     // sensor blocks in a row whose time did not advance
  BalanceStats stats_;
};

}  // namespace ohrp::controllers
