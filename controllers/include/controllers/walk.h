// Walk: the balance controller's stance (balance.h) plus the walking pattern generator
// (robot_model/include/walking/): the robot stands up, then walks the commands it is given and
// stops on both feet. Its own sensors only (never sim_truth), so the same binary runs against
// sim_host and against hw_driver.
//
//   stand up   balance's ramp to the stance pose, settle and CoM centring (balance.h).
//   start      the plan frame is put where the estimator sees the feet (the commanded stance,
//              placed on the estimated soles' middle and heading); the generator starts at
//              rest there, the CoM lowered by `com_lower` over `lower_time` (the legs' reach
//              when a foot goes up a step), and the commands are taken in turn.
//   commands   planned at set-up (footsteps.h), each from the stance the previous one ends in:
//              `goal X Y YAW_DEG` (relative to the stance, the fewest steps within the step
//              limits), `velocity VX VY WZ_DEG SECONDS`, `steps FILE` (footstep_file.h),
//              `wait SECONDS`. SIGUSR1 stops the walk under way: the step in the air lands,
//              the next foot closes beside it, and the remaining commands are dropped.
//   each cycle the generator gives the CoM (with its velocity and acceleration), the ZMP
//              reference and the feet; the estimate is mapped into the plan frame through the
//              supporting feet (the planned and the estimated soles, low-passed over 0.1 s, so
//              the plan does not drift with the estimate's slow errors); the stabilizer
//              (stabilizer.h) turns the DCM error into a desired ZMP, foot rotations, the soles'
//              height difference and a slow CoM correction; the legs and the base follow by
//              WalkIk (CoM and soles), the torso by the hip strategy. The legs' velocity
//              references are the rates of the plan's own IK (without the stabilizer's
//              corrections); the swing leg also gets its joints' own inertia times the plan's
//              acceleration as feed-forward torque.
//   hold       as balance: non-finite or stale sensors, a board fault or a failed estimate
//              latch a hold of the last commanded posture.
// Per-cycle code allocates nothing, throws nothing and logs nothing; the optional CSV log
// (`log_file`) is kept in memory (`log_seconds` at most) and written when the controller closes.
#pragma once

#include <array>
#include <atomic>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "controllers/balance.h"
#include "controllers/walk_channel.h"
#include "walking/footsteps.h"
#include "walking/pattern_generator.h"
#include "walking/terrain.h"
#include "walking/walk_ik.h"

namespace ohrp::controllers {

struct WalkCommand {
  enum class Kind { kGoal, kVelocity, kSteps, kWait, kRandom };
  Kind kind = Kind::kGoal;
  double x = 0, y = 0, yaw = 0;  // goal [m, m, rad] or velocity [m/s, m/s, rad/s]
  double time = 0;               // velocity's duration or wait [s]
  int count = 0;                 // random: steps
  unsigned seed = 0;             // random: the generator's seed
  std::string file;              // steps
  std::string text;              // as given
};
// "goal 1 0 0", "velocity 0.2 0 0 10", "steps FILE", "wait 2", "random 20 7" (angles in
// degrees); false with
// `*error` saying what would work
bool ParseWalkCommand(const std::string& text, WalkCommand* command, std::string* error);
// the command lines' help
const char* WalkCommandHelp();
// the steps of command `c` from the stance `feet` (goal, velocity, steps, random; wait: none),
// checked against the limits; false with `*error` naming the command, the step and the limit. A
// velocity reduced to the limits says so in `*note`. Planning code: allocates.
bool PlanWalkCommand(const WalkCommand& c, const walking::FeetPose& feet,
                     const walking::StepLimits& limits, double step_time,
                     std::vector<walking::Footstep>* steps, std::string* note, std::string* error);

struct WalkOptions {
  BalanceOptions balance;        // stand-up, stabilizer gains, estimator
  walking::GaitOptions gait;
  walking::PreviewOptions preview;  // dt and zc come from the robot (period, stance CoM)
  walking::StepLimits limits;    // `width` from the stance
  double com_lower = 0.02;       // [m] walk with the CoM this much lower than the stance's
  double lower_time = 1.0;       // [s] to lower it
  bool touchdown = false;        // experimental: a swing foot that meets the ground early is
                                 // held there, one that has not met it at its landing goes on
                                 // down, the landing held (walk_touchdown.cc; --touchdown)
  bool stepping = false;         // the stepping strategy (AdjustStep, experimental: in the
                                 // push tables better in some cells, worse in others): a swing
                                 // foot lands where the measured DCM needs it
  bool stepping_timing = true;   // and sooner when that place is out of reach (a swing shortened)
  double stepping_time_cost = 0.05;  // [m/s] a shorter swing's cost against the landing's shortfall
  double stepping_reach = 0.6;       // share of the leg's reach a recovery step may use [-]
                                     // (0.6 measured better than 0.8 and 1 in the push tables)
  double stepping_gain = 1.0;        // share of the DCM's landing change applied [-]
  bool stepping_rebase = false;  // and the plan's CoM re-based on the measured state
  bool stepping_deadband = false;  // the landing moved only beyond what its own ankle takes back
  double swing_tilt_compensation = 1.0;  // share of the base's measured tilt taken out of the
                                         // swing foot's target (about the stance sole) [-]
  double inertia_feedforward = 1.0;  // share of each joint's own inertia times the references'
                                     // acceleration sent as feed-forward torque [-]
  double swing_zmp = 1.0;  // share of the swinging legs' ZMP shift (walking::SwingZmpGain, from
                           // the model) the preview plans the CoM against [-]
  // the gait's keys (those of a --params file) set by the command line, the robot profile's
  // walking: or a --params file; max_forward, step_height and step_time not among them and still
  // at their defaults (a program building WalkOptions may set them) are
  // derived from the leg's length (derived_gait.h); those the command line set before Create
  // keep their values over the profile's and the --params file's
  std::vector<std::string> given;
  std::vector<WalkCommand> commands;
  std::string params_file;       // YAML: gait, preview and limit parameters (walk_commands.cc)
  std::string terrain;           // MJCF scene whose static geometry the steps are put on
                                 // (walking/terrain.h); empty: flat ground at the start's height
  std::string keyframe;          // the scene's keyframe the robot starts from (terrain only)
  double step_search = 0.05;     // [m] a step across an edge of the terrain moves this far at
                                 // most to rest on one plane (walking/terrain.h)
  bool listen = false;           // live commands on stdin (walk_channel.h)
  std::string socket;            // live commands on this local socket ("": none)
  std::string live_record;       // each live command as applied, "T LINE" a line ("": none)
  std::string live_replay;       // a live record played back at its cycles ("": none)
  std::string log_file;          // CSV log of the walk (plan frame), empty: none
  double log_seconds = 900;      // [s] of log kept in memory at most
};

// the YAML parameter file into `o` (strict keys; errors name the file, line and key); a key in
// `keep` (set on the command line) is checked but keeps `o`'s value
ConfigStatus LoadWalkParams(const std::string& path, WalkOptions* o,
                            const std::vector<std::string>& keep = {});
// a robot profile's walking: map (robot_model/profile.h) into `o`, the same keys as a parameter
// file; nothing when the profile has none
ConfigStatus LoadProfileWalkParams(const std::string& profile, WalkOptions* o,
                                   const std::vector<std::string>& keep = {});

struct WalkStats {
  uint64_t walk_cycles = 0;     // cycles under the generator
  int steps_planned = 0;
  int steps_done = 0;           // landed, by measurement: the landing foot's force/torque
                                // sensor carried load within a tolerance of the planned time
  int steps_missed = 0;         // steps whose foot carried no load within that tolerance
  int first_missed_step = -1;   // the first of them (gait index, 0-based)
  int first_missed_foot = -1;   // its foot (walking::kLeft, kRight)
  double first_missed_due = -1; // its planned landing time (generator time) [s]
  double first_missed_load = 0; // the most its foot carried in the window [N]
  int commands_done = 0;
  uint64_t ik_failures = 0;     // cycles whose leg/CoM IK did not converge (last joints kept)
  double first_ik_failure = -1; // producer time of the first [s]
  int first_ik_failure_what = 0;  // 0 left leg, 1 right leg, 2 the CoM
  double max_com_error = 0;     // max |CoM estimated - planned| (plan frame, horizontal) [m]
  double max_zmp_error = 0;     // max |ZMP measured - desired| while walking [m]
  double max_frame_drift = 0;   // largest correction of the plan frame [m]
  int steps_fitted = 0;         // steps that the frame's correction had moved out of the step
                                // limits, set back within them before they began
                                // (walking::FitStep; the next step of each remap)
  double max_fit = 0;           // the most such a step's sole was moved back [m]
  double max_fit_yaw = 0;       // and turned back [rad]
  int steps_adjusted = 0;       // steps the stepping strategy moved (the DCM beyond the ankle)
  double max_adjust = 0;        // the most a landing was moved [m]
  int steps_shortened = 0;      // swings the stepping strategy shortened (landed sooner)
  double max_shorten = 0;       // by up to [s]
  int early_touchdowns = 0;     // swing feet that met the ground before their planned landing
                                // (walk_touchdown.cc) and were held there
  double max_touch_height = 0;  // the highest of them above the planned landing [m]
  int step_ups = 0;             // of them, more than 5 mm above the ground looked for (torso limited)
  int late_touchdowns = 0;      // swing feet that had not met the ground at their planned
                                // landing, went on down and met it (walk_touchdown.cc)
  int late_missed = 0;          // of those, feet that reached the leg's reach without contact
  double max_late_depth = 0;    // the deepest below the planned landing they met it [m]
  int late_dcm_cut = 0;         // late landings taken before contact: the DCM at the stance
                                // sole's edge (the foot searched on in support)
  bool stopped = false;         // SIGUSR1 stopped a walk
  double walk_start = -1;       // producer time the generator started [s]
};

class WalkController : public BalanceController {
 public:
  static std::unique_ptr<WalkController> Create(const WalkOptions& options, ConfigStatus* status);
  // the options as set up (the robot's figures derived, docs/robots.md "Derived from the robot")
  const WalkOptions& walk_options() const { return walk_options_; }
  // SIGUSR1's handler calls this (async-signal-safe): stop the walk under way
  static void RequestWalkStop() noexcept;

  const WalkStats& walk_stats() const { return walk_stats_; }
  const walking::PatternGenerator& generator() const { return gen_; }
  bool walking() const { return started_ && gen_.walking(); }
  // all commands walked and the ZMP back between the feet
  bool done() const;
  // the base's tilt from the orientation the legs' solution gives it (upright, or rolled on
  // purpose by legs without an ankle roll), for the fall watch
  double base_tilt() const noexcept override;
  // from the commanded orientation while the pelvis rolls (base_tilt), else upright
  const char* tilt_reference() const noexcept override;
  // done(), and verified from the measurements at the end: every step landed (measured), both
  // feet carrying load and the base upright; "" then, else what is missing
  std::string Unverified() const;
  // the plan's total steps (all commands) and the commands' final stance in the plan frame
  const std::vector<std::vector<walking::Footstep>>& chunks() const { return chunks_; }
  void report(std::ostream& out) const override;
  // balance's verdict, then the walk's: not Unverified()
  std::string failure() const override;
  // a planning note (a capped speed...) said on stderr once, at set-up
  const std::vector<std::string>& notes() const { return notes_; }

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void Stand(const shm::SensorBlock& s, double dt) noexcept override;
  void on_close() override;

 private:
  WalkController(const WalkOptions& options, const BalanceOptions& filled, Pose pose,
                 std::unique_ptr<model::Kinematics> kin_est,
                 std::unique_ptr<model::Kinematics> kin_ik);
  // set-up: the commands planned into chunks of footsteps from the nominal stance (its mid
  // frame at the origin), checked against the limits (walk_setup.cc)
  ConfigStatus PlanCommands();
  // before attaching (Create): the stance pose on the model's joints, the limits, the terrain and
  // the commands planned, so that a file or an option that does not fit is refused at once
  ConfigStatus Preflight();
  // the stance's nominal feet, the walking CoM height and the step limits from the model at
  // joint positions `q` (base upright at the origin); then the limits of the robot's physics
  ConfigStatus FitStance(const double* q);
  // the swinging legs' ZMP share (walking::SwingZmpGain) from the model, to the generator
  void SetSwingZmp(double hip_stance, double sole_z);
  // refuses a max_forward and step timing whose swing needs more than the hip can accelerate
  ConfigStatus FitSwing();
  ConfigStatus FitPhysics(double leg_length);
  // stride, swing height and step time from the leg's length where not given (derived_gait.h)
  void DeriveGait(double leg_length);
  ConfigStatus LoadTerrain();
  // hip joint to sole along the left leg (the model) [m]; 0 when no chain is found; `*hip`:
  // the hip joint (the chain's first anchor) in the model's current pose
  double LegLength(Eigen::Vector3d* hip = nullptr) const;
  // the switch from standing to walking: the plan frame, the generator's start
  void StartWalking(const shm::SensorBlock& s) noexcept;
  void WalkCycle(const shm::SensorBlock& s, double dt) noexcept;
  void NextCommand(double now) noexcept;
  // the command's steps not yet begun, corrected by the plan frame's drift since the start and
  // kept within the step limits against the feet each steps from (walking::FitStep)
  void Remap() noexcept;
  void Stop() noexcept;
  // the stepping strategy (walk_step_adjust.cc): in a single support, the DCM error the stance
  // ankle cannot take back, predicted to the landing, moves the swing foot's landing by as much
  // (within the recovery limits against the stance sole), and lands it sooner when that place
  // is out of reach; the later steps go on from the new foothold
  void AdjustStep() noexcept;
  // its stages: the measured DCM's error beyond what the stance ankle takes back (false: none);
  // the landing (place and rest) the DCM asks for, the least shortfall plus time taken off among
  // the landing times tried; the landing moved, the later steps and the statistics after it
  struct DcmExcess {
    double omega = 0;                                  // [1/s] the LIPM's at the CoM's height
    Eigen::Vector2d d_plan = Eigen::Vector2d::Zero();  // [m] the plan's DCM from the stance point
    Eigen::Vector2d beyond = Eigen::Vector2d::Zero();  // [m] the error beyond the ankle, in W
  };
  bool DcmBeyondAnkle(const walking::WalkSample& w, int stance, DcmExcess* x) const noexcept;
  void ChooseLanding(int k, double remaining, const DcmExcess& x, walking::Footstep* best,
                     double* best_rest) const noexcept;
  void MoveLanding(int k, double remaining, const walking::Footstep& best, double best_rest) noexcept;
  // live commands (walk_live.cc): the stance a new command starts from published to the
  // channel, a plan made from it taken and walked (what was planned after the step under way
  // replaced), or a stop
  void LiveCycle() noexcept;
  ConfigStatus OpenChannel();
  // the estimate's frame onto the plan's, from the supporting feet
  void UpdateFrame(double dt, bool first) noexcept;
  Eigen::Vector3d ToPlan(const Eigen::Vector3d& p_est) const;
  void FillWalkInput(const shm::SensorBlock& s, const walking::WalkSample& w) noexcept;
  // how much each sole must come out flat and the CoM's sideways place count (WalkIk)
  static void SoleWeights(const walking::GaitState& g, double weights[3]) noexcept;
  void SolveWalkJoints(const StabilizerOutput& out, const walking::WalkSample& w,
                       double z_offset) noexcept;
  void LogRow(const walking::WalkSample& w, const StabilizerOutput& out) noexcept;
  // touchdown (walk_touchdown.cc): a swing foot whose sensor carries load in the last part of
  // its descent has met ground higher than the plan's: it is held where it touched (and lands
  // at once when it is over its landing). One without contact at its planned landing goes on
  // down (its target at most 1 cm below the measured sole), the landing held
  // (Gait::DelayLanding) while the measured DCM stays on the stance sole, then taken, the foot
  // searching on down in support. The touched ground, measured, re-bases the later steps and
  // the CoM
  void Touchdown(const shm::SensorBlock& s, const walking::WalkSample& w, double dt) noexcept;
  // the steps whose landing window has come: landed when the foot's sensor carries load
  void CountLandings(const shm::SensorBlock& s, double t) noexcept;
  double FootLoad(const shm::SensorBlock& s, int foot) const noexcept;

  WalkOptions walk_options_;
  walking::PatternGenerator gen_;
  std::unique_ptr<walking::WalkIk> walk_ik_;
  // commands: steps per command in the nominal stance's mid frame, and in the plan frame
  std::vector<std::vector<walking::Footstep>> chunks_;
  std::vector<std::vector<walking::Footstep>> chunks_plan_;
  std::vector<walking::Footstep> stop_steps_;  // one closing step (preallocated)
  std::vector<walking::Footstep> remap_;       // the corrected steps (preallocated)
  int chunk_ = -1;                             // the command whose steps are walked
  int chunk_first_ = 0;                        // the gait's index of its first step
  int last_started_ = -2;                      // the gait's step under way at the last remap
  double frame0_yaw_ = 0;                      // the plan frame at the start
  Eigen::Vector3d frame0_p_ = Eigen::Vector3d::Zero();
  walking::FeetPose nominal_;                  // the stance's soles, mid frame at the origin
  Eigen::Matrix3d R0_[2];                      // the soles' orientation at yaw 0 (W)
  double sole_yaw_B_[2] = {0, 0};              // the soles' yaw against the base's
  double z_lower_ = 0;                         // [m] lowering still to do at the start
  double zc_ = 0;                              // [m] walking CoM height over the soles
  double swing_zmp_gain_ = 0;                  // [s^2] walking::SwingZmpGain of a leg
  double leg_mass_ = 0, leg_depth_ = 0;        // [kg], [m] a leg's mass, its CoM below the hip
  bool started_ = false;
  int next_command_ = 0;
  double ready_time_ = 0;                      // a wait ends [s]
  double walk_t0_ = 0;
  Eigen::Vector3d p_WB_ = Eigen::Vector3d::Zero();  // IK base position (plan frame)
  // estimate -> plan: p_plan = R(frame_yaw_) p_est + frame_p_
  double frame_yaw_ = 0;
  Eigen::Vector3d frame_p_ = Eigen::Vector3d::Zero();
  // the plan's own joints (no stabilizer correction), for the velocity references
  std::array<double, shm::kMaxJoints> q_plan_{}, q_plan_prev_{};
  std::array<double, shm::kMaxJoints> rate_{};     // their rate [rad/s]
  Eigen::Vector3d p_WB_plan_ = Eigen::Vector3d::Zero();
  // the base's roll in the legs' solutions (WalkIk::rolls_base: legs without an ankle roll)
  double roll_ = 0, roll_plan_ = 0;
  bool plan_valid_ = false;                        // q_plan_prev_ holds a solution
  std::vector<std::array<double, 33>> log_;
  std::string log_error_;                      // the log could not be written: why
  std::vector<std::string> notes_;             // what planning changed (reported)
  std::unique_ptr<walking::TerrainMap> terrain_;
  WalkStats walk_stats_;
  int next_to_land_ = 0;       // the gait's first step whose landing is not yet measured
  double window_load_ = 0;     // the most its foot carried in its window so far [N]
  double land_load_ = 0;       // a foot carrying this much is on the ground [N] (a tenth of
                               // the robot's weight)
  double end_load_[2] = {0, 0};  // both feet's loads at the last walk cycle [N]
  double end_tilt_ = -1;       // the base's tilt then [rad] (-1: never walked)
  // touchdown, per foot: the offset of the sole's height from the plan's [m], its value when
  // the swing began, the height where an early touchdown holds the sole (plan frame) [m], the
  // gait step of its swing, and whether it touched early in it
  double foot_dz_[2] = {0, 0}, lift_dz_[2] = {0, 0}, touch_z_[2] = {0, 0};
  int swing_step_[2] = {-1, -1};
  bool touched_[2] = {false, false};
  // a late touchdown, per foot: whether its landing is held for it in this swing, how far below
  // the planned landing the foot has gone on [m] (<= 0) and the most it may (the leg's reach) [m]
  bool late_[2] = {false, false};
  double late_dz_[2] = {0, 0}, late_depth_[2] = {0, 0};
  double com_dz_ = 0;  // the CoM's height off the plan's with the ground found [m]
  // the ground's height off the plan's where a foot last touched [m]: the later steps land there
  double floor_dz_ = 0;
  // the foot whose early touch found a step up (-1: none) until the other foot, trailing on the
  // lower ground, is half way through its swing: the torso's pitch is limited meanwhile
  int rise_foot_ = -1;
  // that limit [rad] (measured, docs/walking.md "Touchdown": at the hip strategy's 0.35 rad the
  // torso leaning back moved the pelvis 33-45 mm forward and the trailing knee went straight)
  static constexpr double kStepUpTorsoPitch = 0.1;
  // a late foot's landing taken (the DCM at its support's edge, or its hold over): it searches on
  // down in support
  bool late_landed_[2] = {false, false};
  double late_com0_[2] = {0, 0};  // com_dz_ when its search began [m]
  // touchdown stages (walk_touchdown.cc)
  double SoleLag(int i, const walking::GaitState& g) const noexcept;
  double MeasuredGround(int i, const walking::GaitState& g) noexcept;
  double ground_dz_[2] = {0, 0};  // the ground under each foot off the plan's, measured [m]
  void LateDescent(int i, const walking::GaitState& g, double dt) noexcept;
  bool DcmPastStance(const walking::GaitState& g) const noexcept;
  // the swing foot's sensor in the air (the mean of its vertical force over the first half of
  // the swing after lift-off) [N], the cycles it has read a touch in a row
  double air_fz_[2] = {0, 0}, air_sum_[2] = {0, 0};
  int air_n_[2] = {0, 0}, touch_cycles_[2] = {0, 0};
  double touch_load_ = 0;      // a swing foot carrying this much has touched [N] (a twentieth
                               // of the robot's weight)
  std::unique_ptr<WalkChannel> channel_;       // live commands (null: none)
  std::vector<walking::Footstep> live_steps_;  // swapped with the channel's plans
  uint64_t live_version_ = 0;                  // of the stance a live command starts from
  int live_started_ = -2;                      // the gait's step under way at the last publish
  struct Replayed {
    double t;
    std::string text;
  };
  std::vector<Replayed> replay_;  // --live-replay: the recorded commands, in time order
  size_t replay_next_ = 0;        // the next one due
  std::vector<std::pair<double, size_t>> replay_taken_;  // (the cycle's time, which), reserved
  LivePlanning replay_planning_;
  void ReplayCycle() noexcept;
  void WriteLiveRecord();
  void TakeLive(bool stop) noexcept;
  walking::StepLimits recovery_limits_;  // the stepping strategy's: as far as a leg reaches
  int adjust_step_ = -1;       // the step whose landing the stepping strategy may move
  walking::Footstep adjust_planned_;  // its landing as planned
  double adjust_planned_land_ = 0;    // and its landing time [s]
  // what the hip lets a swinging foot accelerate [m/s^2] (FitSwing: the hip pitch joint's torque
  // less the leg's gravity load, over its inertia; infinite when not known): a landing moved or
  // brought forward must stay within the travel this allows over the rest of the swing
  double swing_accel_limit_ = std::numeric_limits<double>::infinity();
  bool gait_derived_ = false;  // DeriveGait has run (and said what it derived)
  // how far the stepping strategy has moved the footholds (plan frame [m]): the command's later
  // steps go on from there (Remap), not back onto the plan the robot was pushed off
  Eigen::Vector2d recovery_shift_ = Eigen::Vector2d::Zero();
};

}  // namespace ohrp::controllers
