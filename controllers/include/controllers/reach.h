// Reach: stand as balance does and move a joint group (an arm, both arms) to goal joint values
// along a collision-free path planned on the robot's self-collision geometry (the paper's
// section 4.3, application 3; robot_model/planning, docs/planning.md).
//
//   set-up    the self-collision file (--collision-file: the online guard's pairs, margin and
//             safe ranges, the links' geometry) gives the group's joints and limits; goals (joint
//             values, or a hand pose turned into joint values by the shared limb IK) are
//             checked against them and, with the stance pose's other joints, against the
//             checker before anything attaches (bad input: exit 2).
//   stand     balance's stance (BalanceController: ramp, centre the CoM, stabilizer); the
//             group's joints follow the stance pose until `start` seconds after the stance.
//   plan      the measured posture is handed to a planning thread (OMPL's RRTConnect, path
//             simplification, rest-to-rest synchronised trapezoids within the speed and
//             acceleration limits); the control loop keeps standing and never waits for it.
//   move      the group's references follow the timed path (position and velocity), the rest of
//             the robot balance's; then the goal is held.
//   report    planning time, path length, the smallest clearance of the motion computed from
//             the MEASURED joint angles (recorded every cycle of the motion and hold, checked
//             after the run through the same checker) and the tracking error at the end of the
//             hold. failure(): no path (the reason), the run ended before the hold did, or a
//             final tracking error above the tolerance.
//   scene     --box obstacles in the base frame; --scene FILE: a scene's static geoms
//             (model::ReadSceneObstacles), placed in the base frame at each plan's request from
//             the estimated base pose and the estimator's frame in the scene (reach_scene.cc).
//   goals     --goals FILE (reach_goals.h): several goals in sequence, each planned from where
//             the previous left the arm (held meanwhile), reported per goal (reach_report.cc).
//   live      --listen / --socket PATH (reach_live.h): goals sent while it stands, resolved on
//             the channel's thread, taken by the cycle in order after the ones before them.
// The per-cycle path allocates nothing, throws nothing and logs nothing.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "collision/pair_file.h"
#include "controllers/balance.h"
#include "robot_model/scene_obstacles.h"
#include "planning/arm_planner.h"
#include "planning/timed_path.h"

namespace ohrp::controllers {

// a goal for a hand: a site of the robot at a position (and, if given, an orientation) in the
// base frame
struct HandGoal {
  std::string site;
  Eigen::Vector3d p_B = Eigen::Vector3d::Zero();  // [m]
  bool orientation = false;                       // false: the position only
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();  // roll, pitch, yaw about the base's x, y, z [rad]
};

// one goal of a goals file (reach --goals, controllers/reach_goals.h)
struct GoalSpec {
  std::vector<std::pair<std::string, double>> joints;  // a joints goal (by name) [rad], or
  std::vector<HandGoal> hands;                         // or a hand pose goal (one per limb)
  double hold = -1;  // [s]; < 0: the command line's --hold
  int line = 0;      // the goal's line in the file (for messages)
};

struct GoalsFile {
  std::string path;
  std::vector<std::string> group;  // empty: the first goal's joints
  std::vector<GoalSpec> goals;
};

// The group's goal for hand poses: per hand, the shared limb IK (robot_model/ik.h) of the chain
// from the group's joint nearest the base on the hand's way up to the hand, started from
// `stance` (joint-id order). Each chain's joints must all be in the group and no two hands may
// share a joint (two hands: both arms in one group); the group's other joints keep their stance
// values. kOption with the reason: an unknown site, a chain that is not the group's, chains that
// share a joint, a pose out of reach (by how far the closest pose found stays from it).
ConfigStatus GoalFromHandPose(model::Kinematics& kin, const planning::JointGroup& group,
                              const std::vector<HandGoal>& hands, const std::vector<double>& stance,
                              std::vector<double>* goal);

// The estimator's world frame in the scene's world (reach --scene): the soles' midpoint on the
// floor, the base's yaw, as the scene's keyframe `key` stands the robot (reach_scene.cc).
// kOption when the robot has no floating base or the keyframe does not exist.
ConfigStatus EstimatorFrameInScene(model::Kinematics& kin, const std::string& key,
                                   Eigen::Isometry3d* X_WE);

struct ReachOptions {
  BalanceOptions balance;
  std::string collision_file;  // the self-collision file; empty: DefaultSelfCollisionFile()
  std::vector<std::pair<std::string, double>> goal_joints;  // the group and its goal [rad]
  // or: the group by name and hand poses (one per limb), the goal by IK (hands not empty)
  std::vector<std::string> group;
  // or: a goals file's goals in sequence (goals.goals not empty; its group, or the first goal's
  // joints, is the group)
  GoalsFile goals;
  std::vector<HandGoal> hands;
  // static boxes to keep clear of, in the base frame (the waist, as the robot stands)
  std::vector<planning::SceneBox> boxes;
  // a scene's static obstacles (--scene FILE, model::ReadSceneObstacles) in the world; placed in
  // the base frame from the estimated base pose when the plan is asked
  std::string scene_file;
  std::vector<model::SceneObstacle> scene;
  // the keyframe the scene starts the robot in: where its soles stand in the scene's world, the
  // estimator's origin (midway between the soles, yaw of the base, on z = 0)
  std::string scene_keyframe = "halfsit";
  double clearance = 0.01;     // [m] kept beyond the file's margin
  double start = 1.5;          // [s] after the stance begins (the CoM centred first)
  double hold = 1.5;           // [s] at the goal before the tracking error is taken
  double max_speed = 0.8;      // [rad/s] per joint (the file's speed limit where lower)
  double max_accel = 2.0;      // [rad/s^2] per joint (half what the torque allows where lower)
  double tolerance = 0.1;      // [rad] largest final tracking error accepted
  bool stop_at_waypoints = false;  // rest to rest at every waypoint (else blended where clear)
  std::string plan_log;        // CSV of the plan (waypoints, timed samples) and the measured
                               // motion, written after the run; "" none
  planning::PlanOptions plan;
  bool listen = false;         // live goals on stdin (reach_live.h)
  std::string socket;          // live goals on this local socket ("" none)
  bool live() const { return listen || !socket.empty(); }
};

class ReachChannel;

class ReachController : public BalanceController {
 public:
  // Checks the options, loads the model, the pose and the self-collision file; checks the goals
  // (known joints, within limits, clear of the body in the stance pose). Null with `*status`
  // (kOption: bad goals; kFile: a file) on failure.
  static std::unique_ptr<ReachController> Create(const ReachOptions& options, ConfigStatus* status);
  ~ReachController() override;

  void report(std::ostream& out) const override;
  std::string failure() const override;

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void on_close() override;
  void Stand(const shm::SensorBlock& s, double dt) noexcept override;

 private:
  ReachController(const ReachOptions& options, const BalanceOptions& filled, Pose pose,
                  std::unique_ptr<model::Kinematics> kin_est,
                  std::unique_ptr<model::Kinematics> kin_ik);
  // the group, the goals (the command line's one or the goals file's), each checked against the
  // limits and, with `stance`'s other joints, the checker; fills group_, check_, goals_
  // (reach_sequence.cc)
  ConfigStatus ResolveGoals(const std::vector<double>& stance);
  // one goal's group values (the previous goal's in `*values` on entry) by `kin`'s IK and
  // `check` in the stance pose; false with the key ("joints", "pose") and what is wrong (an IK
  // refusal's text without its option) in `*key` and `*what`, `*ik` when the IK refused
  bool ResolveGoal(model::Kinematics& kin, planning::PostureCheck& check, const GoalSpec& g,
                   std::vector<double>* values, std::string* key, std::string* what, bool* ik) const;
  // the live channel (reach_live.h) on its own copies of the IK model and the checker
  ConfigStatus OpenChannel();
  // the next goal, from the one held (control thread)
  void StartNextGoal(const shm::SensorBlock& s) noexcept;
  // goal k's label: "FILE:LINE", "the goal", or the live command's text
  std::string Label(size_t k) const;
  // hands the measured posture and goal `current_` to the planner (control thread, no allocation)
  void RequestPlan(const shm::SensorBlock& s) noexcept;
  // the group's references at hold_q_ (between two goals), the posture recorded
  void HoldGroup(const shm::SensorBlock& s) noexcept;
  void PlannerThread();
  // the solved plan's timing into path_ and goal current_'s report (planner thread,
  // reach_timing.cc): blended at the waypoints when that path, checked again, keeps the
  // planner's clearance; else rest to rest
  void TimeThePath();
  // the largest corner cut of path_'s inner waypoints [rad] (0 rest to rest)
  double MaxCornerCut() const;
  // the check with the scene placed from the base pose at the request (planner thread); false
  // with result_.reason when the checker refuses it
  bool PlaceScene();
  void Record(const shm::SensorBlock& s) noexcept;
  // the plan log's text (ReachOptions::plan_log)
  std::string PlanLog() const;
  // a hand goal: the site's distance from its target at the final measured posture [m]
  double HandError(const HandGoal& hand) const;
  std::vector<HandGoal> last_hands_;  // the last goal's hand poses (none: a joints goal)
  // the smallest clearance of the recorded motion (computed once, after the run)
  const planning::Verdict& MeasuredClearance() const;
  // the smallest clearances of the recorded rows [begin, end), the robot's own pairs and the
  // pairs with an obstacle apart (reach_report.cc), and their text
  struct Clearances {
    planning::Verdict self, scene;
  };
  Clearances ClearanceOfRows(size_t begin, size_t end) const;
  std::string Describe(const Clearances& c) const;
  bool has_scene_pairs_ = false;  // --box or --scene obstacles
  // one line per goal of a goals file
  void ReportGoals(std::ostream& out) const;

  enum class Phase { kWait, kPlanning, kMoving, kHolding, kDone, kFailed };
  enum PlanState : int { kIdle, kRequested, kSolved, kUnsolved };
  ReachOptions reach_;
  collision::SelfCollisionFile file_;
  planning::JointGroup group_;
  std::unique_ptr<planning::PostureCheck> check_;
  std::vector<double> goal_;            // group values: the goal being planned or reached
  // the goals in sequence (one without a goals file), their holds [s] and labels ("FILE:LINE")
  // (live goals: room for kMaxLiveGoals more, preallocated; ngoals_ of them are goals)
  std::vector<std::vector<double>> goals_;
  std::vector<double> holds_;
  std::vector<std::string> labels_;
  size_t ngoals_ = 0, nfixed_ = 0;      // goals so far, and those given before the run
  static constexpr size_t kMaxLiveGoals = 64;
  std::vector<double> stance_;          // the stance pose (goals are checked in it)
  std::unique_ptr<ReachChannel> channel_;
  std::unique_ptr<model::Kinematics> live_kin_;
  std::unique_ptr<planning::PostureCheck> live_check_;
  size_t current_ = 0;                  // the goal under way
  std::vector<double> hold_q_;          // group: the previous goal held while the next is planned
  // per goal, what was planned (planner thread) and measured (control thread); preallocated
  struct GoalReport {
    bool planned = false, solved = false;
    std::string reason;
    double plan_time = 0, simplify_time = 0, length = 0, raw_length = 0, duration = 0;
    size_t waypoints = 0;
    planning::Verdict closest, straight;
    // the timing: blended at the waypoints, and the blended path's closest pair; or why it
    // stops at them ("" blended)
    bool blended = false;
    planning::Verdict blended_closest;
    std::string stops;
    double request_time = 0, motion_start = -1;
    size_t row_begin = 0, row_end = 0;  // its measured rows in log_ (motion and hold)
    bool done = false;
    std::vector<double> final_error;   // group
    // the plan for the plan log (planner thread, before kSolved): its waypoints and timing
    std::vector<std::vector<double>> plan_waypoints;
    planning::TimedPath plan_path;
  };
  std::vector<GoalReport> reports_;
  std::vector<double> v_max_, a_max_;   // per group joint
  std::vector<double> request_;         // the measured posture handed to the planner
  planning::PlanResult result_;         // written by the planner thread before kSolved/kUnsolved
  planning::TimedPath path_;
  planning::Verdict straight_;          // the straight line's closest pair (planner thread)
  std::atomic<int> plan_state_{kIdle};
  std::atomic<bool> quit_{false};      // the planning thread ends
  std::thread thread_;
  Phase phase_reach_ = Phase::kWait;
  // the estimated base pose when the plan was asked (the scene's boxes placed from it)
  Eigen::Vector3d request_p_WB_ = Eigen::Vector3d::Zero();
  Eigen::Isometry3d X_WE_ = Eigen::Isometry3d::Identity();  // the estimator's frame in the scene
  Eigen::Quaterniond request_quat_WB_ = Eigen::Quaterniond::Identity();
  double request_time_ = 0, motion_start_ = 0, hold_start_ = 0, motion_end_ = -1;  // [s]
  std::vector<double> sample_q_, sample_dq_;  // group
  std::vector<double> final_error_;           // group: measured - goal at the end of the hold
  std::vector<double> final_q_;               // njoint: the measured posture then
  // measured postures of the motion and the hold, one per cycle (preallocated)
  std::vector<double> log_;
  size_t log_rows_ = 0, log_capacity_ = 0;
  long log_dropped_ = 0;
  std::string log_error_;  // the plan log could not be written: why
  double period_ = 0;      // [s] the producer's control period
  mutable bool clearance_done_ = false;
  mutable planning::Verdict clearance_;
};

}  // namespace ohrp::controllers
