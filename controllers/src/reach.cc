// Reach: balance's stance, a planning thread, the timed path on the group's joints.
#include "controllers/reach.h"
#include "controllers/reach_live.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "controllers/runner.h"
#include "robot_model/output_file.h"

namespace ohrp::controllers {
namespace {

constexpr double kLogSeconds = 120;  // the motion and hold recorded, at most this long

std::string Fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c, d);
  return text;
}

// the options' own ranges (the goals are checked against the file)
ConfigStatus CheckReachOptions(const ReachOptions& o) {
  auto bad = [](const std::string& what) { return ConfigStatus::Fail(ConfigError::kOption, what); };
  const int given = !o.goal_joints.empty() + !o.hands.empty() + !o.goals.goals.empty();
  if (given > 1 || (given == 0 && !o.live()))
    return bad("give one goal: --goal-joints NAME=VALUE,... [rad], or --group and --goal-pose, "
               "or --goals FILE (or goals while it runs: --group with --listen or --socket)");
  if (given == 0 && o.group.empty())
    return bad("live goals (--listen, --socket) without a goal given need --group (the joints they move)");
  if (!o.hands.empty() && o.group.empty()) return bad("--goal-pose needs --group (the joints it moves)");
  if (!(o.clearance >= 0 && o.clearance <= 0.2)) return bad("--clearance must be in [0, 0.2] m");
  if (!(o.start >= 0 && o.start <= 3600)) return bad("--start must be in [0, 3600] s");
  if (!(o.hold >= 0 && o.hold <= 3600)) return bad("--hold must be in [0, 3600] s");
  if (!(o.max_speed > 0 && o.max_speed <= 20)) return bad("--max-speed must be in (0, 20] rad/s");
  if (!(o.max_accel > 0 && o.max_accel <= 200)) return bad("--max-accel must be in (0, 200] rad/s^2");
  if (!(o.tolerance > 0 && o.tolerance <= 1)) return bad("--tolerance must be in (0, 1] rad");
  if (!(o.plan.time_limit > 0 && o.plan.time_limit <= 600))
    return bad("--plan-time must be in (0, 600] s");
  return ConfigStatus::Ok();
}

}  // namespace

std::unique_ptr<ReachController> ReachController::Create(const ReachOptions& options,
                                                         ConfigStatus* status) {
  ReachOptions o = options;
  if (o.collision_file.empty()) o.collision_file = DefaultSelfCollisionFile();
  *status = CheckReachOptions(o);
  if (!status->ok()) return nullptr;
  BalanceOptions filled;
  Pose pose;
  std::unique_ptr<model::Kinematics> kin_est, kin_ik;
  o.balance.program = "reach";
  o.balance.one_leg.sides.clear();
  *status = LoadParts(o.balance, "reach", &filled, &pose, &kin_est, &kin_ik);
  if (!status->ok()) return nullptr;
  std::string error;
  if (!o.plan_log.empty() && !model::PrepareOutputFile(o.plan_log, "# reach: the run is under way\n", &error)) {
    *status = ConfigStatus::Fail(ConfigError::kFile, "--plan-log: " + error);
    return nullptr;
  }
  std::unique_ptr<ReachController> r(
      new ReachController(o, filled, std::move(pose), std::move(kin_est), std::move(kin_ik)));
  if (!r->reach_.scene.empty()) {
    *status = EstimatorFrameInScene(*r->kin_ik_, o.scene_keyframe, &r->X_WE_);
    if (!status->ok()) return nullptr;
  }
  if (!collision::ReadSelfCollisionFile(o.collision_file, &r->file_, &error)) {
    *status = ConfigStatus::Fail(ConfigError::kFile, error);
    return nullptr;
  }
  // the stance pose (the group's goals are checked with its other joints)
  std::vector<double> stance;
  if (ConfigStatus s = ResolvePose(r->pose_, r->file_.robot.joint_names, &stance); !s.ok()) {
    *status = s;
    return nullptr;
  }
  stance.resize(collision::NumJoints(r->file_.robot), 0.0);
  if (r->kin_ik_->robot().joints.size() != r->file_.robot.joint_names.size()) {
    *status = ConfigStatus::Fail(ConfigError::kMismatch, "--model and --collision-file are not the same robot");
    return nullptr;
  }
  *status = r->ResolveGoals(stance);
  if (!status->ok()) return nullptr;
  return r;
}

ReachController::ReachController(const ReachOptions& options, const BalanceOptions& filled,
                                 Pose pose, std::unique_ptr<model::Kinematics> kin_est,
                                 std::unique_ptr<model::Kinematics> kin_ik)
    : BalanceController(filled, std::move(pose), std::move(kin_est), std::move(kin_ik)),
      reach_(options) {}

ReachController::~ReachController() { on_close(); }

ConfigStatus ReachController::on_configure(const shm::SegmentHeader& header) {
  if (ConfigStatus s = BalanceController::on_configure(header); !s.ok()) return s;
  if (file_.robot.model_hash != header.model_hash || file_.robot.joint_names != joint_names())
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              reach_.collision_file + " is not the segment's robot's "
                              "self-collision file (another model hash or other joints)");
  // each joint's limits: the asked speed (the file's where lower and known) and acceleration
  // (half of what the torque leaves over the gravity load, on the largest inertia, where lower)
  const int n = group_.size();
  for (int i = 0; i < n; ++i) {
    const int j = group_.ids[i];
    double v = reach_.max_speed, a = reach_.max_accel;
    if (j < static_cast<int>(file_.dynamics.size())) {
      const collision::JointDynamics& d = file_.dynamics[j];
      if (d.velocity_max > 0) v = std::min(v, d.velocity_max);
      if (d.inertia_max > 0 && header.tau_max[j] > 0)
        a = std::min(a, 0.5 * std::max(0.1 * header.tau_max[j], header.tau_max[j] - d.gravity_max) /
                            d.inertia_max);
    }
    v_max_.push_back(v);
    a_max_.push_back(a);
  }
  const int nq = collision::NumJoints(file_.robot);
  request_.assign(nq, 0.0);
  sample_q_.assign(n, 0.0);
  sample_dq_.assign(n, 0.0);
  final_error_.assign(n, NAN);
  hold_q_.assign(n, 0.0);
  reports_.assign(goals_.size(), GoalReport());
  for (GoalReport& g : reports_) g.final_error.assign(n, NAN);
  final_q_.assign(header.njoint, 0.0);
  period_ = header.control_period;
  log_capacity_ = static_cast<size_t>(kLogSeconds / header.control_period) + 1;
  log_.assign(log_capacity_ * nq, 0.0);
  thread_ = std::thread(&ReachController::PlannerThread, this);
  if (reach_.live()) return OpenChannel();
  return ConfigStatus::Ok();
}

void ReachController::on_close() {
  if (channel_) channel_->Close();
  if (thread_.joinable()) {
    quit_.store(true);
    thread_.join();
    if (!reach_.plan_log.empty()) model::WriteWholeFile(reach_.plan_log, PlanLog(), &log_error_);
  }
}

std::string ReachController::PlanLog() const {
  // goal,kind,t,JOINT...: per goal (1, 2, ... in --goals order), the waypoints at their times,
  // the timed path every 10 ms and the measured group joints every control cycle of its motion
  // and hold (t from that goal's motion start [s])
  std::string text = "# reach plan";
  for (size_t k = 0; k < ngoals_; ++k) {
    const GoalReport& g = reports_[k];
    text += Fmt(k ? "; goal %.0f: " : ": goal %.0f: ", k + 1.0) +
            (!g.planned ? std::string("not planned") : g.solved ? std::string("solved") : "not solved: " + g.reason);
  }
  text += "\ngoal,kind,t";
  for (const auto& n : group_.names) text += "," + n;
  text += "\n";
  auto row = [&](size_t goal, const char* kind, double t, const double* v) {
    text += Fmt("%.0f,", goal + 1.0) + kind + Fmt(",%.4f", t);
    for (int i = 0; i < group_.size(); ++i) text += Fmt(",%.6f", v[i]);
    text += "\n";
  };
  const size_t nq = request_.size();
  std::vector<double> q(group_.size());
  for (size_t k = 0; k < ngoals_; ++k) {
    const GoalReport& g = reports_[k];
    if (g.solved) {
      for (size_t w = 0; w < g.plan_waypoints.size(); ++w)
        row(k, "waypoint", g.plan_path.WaypointTime(static_cast<int>(w)), g.plan_waypoints[w].data());
      for (double s = 0; s <= g.plan_path.duration() + 1e-9; s += 0.01) {
        g.plan_path.Sample(s, q.data(), nullptr, nullptr);
        row(k, "planned", s, q.data());
      }
    }
    if (g.motion_start < 0) continue;
    const size_t end = g.done ? g.row_end : log_rows_;
    for (size_t r = g.row_begin; r < end && r < log_rows_; ++r) {
      for (int i = 0; i < group_.size(); ++i) q[i] = log_[r * nq + group_.ids[i]];
      row(k, "measured", (r - g.row_begin) * period_, q.data());
    }
  }
  return text;
}

void ReachController::PlannerThread() {
  for (;;) {
    if (quit_.load()) return;
    if (plan_state_.load(std::memory_order_acquire) != kRequested) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    if (!reach_.scene.empty() && !PlaceScene()) {
      reports_[current_].planned = true;
      reports_[current_].reason = result_.reason;
      plan_state_.store(kUnsolved, std::memory_order_release);
      continue;
    }
    result_ = planning::PlanJoints(*check_, request_, goal_, reach_.plan);
    // the straight joint-space line, for comparison (what the plan avoided)
    std::vector<double> start(goal_.size());
    planning::GroupValues(group_, request_, start);
    straight_ = planning::ClosestAlong(*check_, request_, {start, goal_}, reach_.plan.resolution);
    GoalReport& g = reports_[current_];  // current_ does not change while a plan is asked
    if (result_.solved) TimeThePath();
    g.planned = true;
    g.solved = result_.solved;
    g.reason = result_.reason;
    g.plan_time = result_.plan_time;
    g.simplify_time = result_.simplify_time;
    g.length = result_.length;
    g.raw_length = result_.raw_length;
    g.waypoints = result_.waypoints.size();
    g.duration = result_.solved ? path_.duration() : 0;
    g.closest = result_.closest;
    g.straight = straight_;
    if (result_.solved && !reach_.plan_log.empty()) {
      g.plan_waypoints = result_.waypoints;
      g.plan_path = path_;
    }
    int expected = kRequested;
    plan_state_.compare_exchange_strong(expected, result_.solved ? kSolved : kUnsolved,
                                        std::memory_order_acq_rel);
  }
}

void ReachController::RequestPlan(const shm::SensorBlock& s) noexcept {
  const int na = njoint();
  for (size_t j = 0; j < request_.size(); ++j)
    request_[j] = static_cast<int>(j) < na ? s.q[j] : s.passive_q[j - na];
  request_p_WB_ = estimate().p_WB;
  request_quat_WB_ = estimate().quat_WB;
  reports_[current_].request_time = s.time;
  plan_state_.store(kRequested, std::memory_order_release);
  phase_reach_ = Phase::kPlanning;
  request_time_ = s.time;
}

void ReachController::HoldGroup(const shm::SensorBlock& s) noexcept {
  for (int i = 0; i < group_.size(); ++i) {
    const int j = group_.ids[i];
    if (j >= njoint()) continue;
    q_ref_[j] = q_ik_[j] = hold_q_[i];
    dq_ref_[j] = 0;
  }
  Record(s);
}

void ReachController::Record(const shm::SensorBlock& s) noexcept {
  if (log_rows_ >= log_capacity_) {
    ++log_dropped_;
    return;
  }
  const int na = njoint(), nq = static_cast<int>(request_.size());
  double* row = log_.data() + log_rows_ * nq;
  for (int j = 0; j < nq; ++j) row[j] = j < na ? s.q[j] : s.passive_q[j - na];
  ++log_rows_;
}

void ReachController::StartNextGoal(const shm::SensorBlock& s) noexcept {
  std::copy(goal_.begin(), goal_.end(), hold_q_.begin());
  ++current_;
  std::copy(goals_[current_].begin(), goals_[current_].end(), goal_.begin());
  RequestPlan(s);
  HoldGroup(s);
}

void ReachController::Stand(const shm::SensorBlock& s, double dt) noexcept {
  BalanceController::Stand(s, dt);
  const int n = group_.size();
  // a live goal resolved on the channel's thread: into the preallocated room
  if (channel_ && ngoals_ < goals_.size() && channel_->Poll(&goals_[ngoals_])) ++ngoals_;
  switch (phase_reach_) {
    case Phase::kWait:
      if (ngoals_ > 0 && s.time - stand_time_ >= reach_.start) {
        std::copy(goals_[0].begin(), goals_[0].end(), goal_.begin());
        RequestPlan(s);
      }
      return;
    case Phase::kPlanning: {
      const int state = plan_state_.load(std::memory_order_acquire);
      if (state == kUnsolved) phase_reach_ = Phase::kFailed;
      if (state != kSolved) {
        if (current_ > 0) HoldGroup(s);  // the previous goal, while the next one is planned
        return;
      }
      phase_reach_ = Phase::kMoving;
      motion_start_ = s.time;
      reports_[current_].motion_start = s.time;
      reports_[current_].row_begin = log_rows_;
      break;
    }
    case Phase::kMoving:
      if (s.time - motion_start_ >= path_.duration()) {
        phase_reach_ = Phase::kHolding;
        hold_start_ = s.time;
      }
      break;
    case Phase::kHolding:
      if (s.time - hold_start_ >= holds_[current_]) {
        GoalReport& g = reports_[current_];
        for (int i = 0; i < n; ++i) g.final_error[i] = final_error_[i] = s.q[group_.ids[i]] - goal_[i];
        for (int j = 0; j < njoint(); ++j) final_q_[j] = s.q[j];
        g.row_end = log_rows_;
        g.done = true;
        if (current_ + 1 < ngoals_) return StartNextGoal(s);  // the next goal, from here
        motion_end_ = s.time;
        phase_reach_ = Phase::kDone;
      }
      break;
    case Phase::kDone:
      if (current_ + 1 < ngoals_) return StartNextGoal(s);  // a live goal came
      break;
    case Phase::kFailed:
      break;
  }
  if (phase_reach_ == Phase::kFailed || phase_reach_ == Phase::kWait) return;
  // the group's references: the timed path (its end while holding)
  path_.Sample(s.time - motion_start_, sample_q_.data(), sample_dq_.data(), nullptr);
  for (int i = 0; i < n; ++i) {
    const int j = group_.ids[i];
    if (j >= njoint()) continue;  // a passive joint moves with the others
    q_ref_[j] = q_ik_[j] = sample_q_[i];
    dq_ref_[j] = sample_dq_[i];
  }
  if (phase_reach_ != Phase::kDone) Record(s);
}

}  // namespace ohrp::controllers
