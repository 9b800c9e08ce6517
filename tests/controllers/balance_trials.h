// Test helper: trials of a controller closed-loop on an in-process HRP-1S (sim_host's stepping,
// soft soles, 1 ms physics, 5 ms control: sim_host::InProcessRobot), judged on the simulation's
// truth: a push (still standing, settling of the base and of the ankle torques, the base
// estimator's errors), standing on one leg in turn, and standing on uneven ground (the soles'
// centres of pressure against their edges).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "controllers/balance.h"
#include "controllers/posture.h"
#include "sim_host/in_process.h"

namespace ohrp::controllers::testing {

constexpr double kPushAt = 3.0;        // [s] after the stance (ramp 0.5, settle 0.5, centring 1)
constexpr double kPushDuration = 0.1;  // [s] the push window
constexpr double kObserve = 3.0;       // [s] after the push's end
constexpr double kCycle = 0.005;       // [s] control period
constexpr double kLoaded = 50.0;       // [N] a sole carrying less is not judged (lifted)

struct Trial {
  bool balance = true;        // balance, else posture
  BalanceOptions options;     // for balance (its ramp is set to 0.5 s)
  std::string scene = "mjcf/hrp1s/scene_flat.xml";
  std::string keyframe = "halfsit";
  double direction = 0;       // push direction [deg], 0 = +x (forward), 90 = +y (left)
  double impulse = 0;         // push impulse [N s] over kPushDuration at kPushAt; 0: none
};

inline double Tilt(const double* q) {  // angle of a frame's z axis from the vertical (w,x,y,z)
  const double zz = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
  return std::acos(std::clamp(zz, -1.0, 1.0));
}

// the robot, the controller and the soles' geometry, ready to cycle
class ClosedLoop {
 public:
  explicit ClosedLoop(const Trial& t) {
    sim::InProcessOptions io;
    io.scene = std::string(OHRP_SOURCE_DIR) + "/" + t.scene;
    io.keyframe = t.keyframe;
    if (t.impulse > 0) {
      sim::Perturbation p;
      p.t0 = kPushAt;
      p.t1 = kPushAt + kPushDuration;
      const double f = t.impulse / kPushDuration, a = t.direction * M_PI / 180;
      p.force[0] = f * std::cos(a);
      p.force[1] = f * std::sin(a);
      io.pushes.push_back(p);
    }
    std::string error;
    robot_ = sim::InProcessRobot::Create(io, &error);
    EXPECT_TRUE(robot_) << error;
    if (!robot_) return;
    ConfigStatus status;
    if (t.balance) {
      BalanceOptions o = t.options;
      o.ramp = 0.5;
      auto b = BalanceController::Create(o, &status);
      balance_ = b.get();
      controller_ = std::move(b);
    } else {
      PostureOptions o;
      o.ramp = 0.5;
      controller_ = PostureController::Create(o, &status);
    }
    EXPECT_TRUE(controller_) << status.message;
    if (!controller_) return;
    status = controller_->configure(robot_->header());
    EXPECT_TRUE(status.ok()) << status.message;
    if (!status.ok()) return;
    const mjModel* m = robot_->m();
    for (int i = 0; i < 2; ++i) {
      const char* sensor = i == 0 ? "lfsensor" : "rfsensor";
      geom_[i] = mj_name2id(m, mjOBJ_GEOM, i == 0 ? "LLEG_SOLE" : "RLEG_SOLE");
      site_[i] = mj_name2id(m, mjOBJ_SITE, sensor);
      for (int k = 0; k < robot_->header().nforce; ++k)
        if (std::string(robot_->header().force_names[k]) == sensor) ft_[i] = k;
      EXPECT_TRUE(geom_[i] >= 0 && site_[i] >= 0 && ft_[i] >= 0) << "HRP-1S soles and sensors";
      if (geom_[i] < 0 || site_[i] < 0 || ft_[i] < 0) return;
    }
    controller_->activate(robot_->sensors());
    ok_ = true;
  }

  bool ok() const { return ok_; }
  // one control cycle: update, then the physics of the period
  void Cycle() {
    controller_->update(robot_->sensors(), &commands_);
    robot_->Cycle(commands_);
  }
  const shm::SensorBlock& s() const { return robot_->sensors(); }
  const mjData* d() const { return robot_->d(); }
  BalanceController* balance() const { return balance_; }
  const Controller& controller() const { return *controller_; }
  double time() const { return robot_->sensors().time; }

  // normal force on sole i [N]
  double Fz(int i) const { return s().force[ft_[i]].force[2]; }
  // sole i's centre of pressure against its edges: the distance to the nearest edge [m]
  // (negative: outside); +inf while the sole carries less than kLoaded
  double CopMargin(int i) const {
    const shm::ForceTorque& f = s().force[ft_[i]];
    const double fz = f.force[2];
    if (!(fz > kLoaded)) return INFINITY;
    // the sensor lies on the sole's bottom plane (HRP-1S): CoP = (-t_y, t_x) / f_z there
    const double cx = -f.torque[1] / fz, cy = f.torque[0] / fz;
    const mjData* dd = d();
    double rel_W[3], rel_S[3];
    for (int k = 0; k < 3; ++k) rel_W[k] = dd->geom_xpos[3 * geom_[i] + k] - dd->site_xpos[3 * site_[i] + k];
    mju_rotVecMatT(rel_S, rel_W, dd->site_xmat + 9 * site_[i]);
    const double hx = robot_->m()->geom_size[3 * geom_[i]], hy = robot_->m()->geom_size[3 * geom_[i] + 1];
    return std::min(hx - std::abs(cx - rel_S[0]), hy - std::abs(cy - rel_S[1]));
  }
  // height of sole i's centre [m]
  double SoleZ(int i) const { return d()->geom_xpos[3 * geom_[i] + 2]; }

 private:
  std::unique_ptr<sim::InProcessRobot> robot_;
  std::unique_ptr<Controller> controller_;
  BalanceController* balance_ = nullptr;
  shm::CommandBlock commands_{};
  int geom_[2] = {-1, -1}, site_[2] = {-1, -1}, ft_[2] = {-1, -1};
  bool ok_ = false;
};

//---------------- a push ----------------

struct PushOutcome {
  bool standing = false;       // base above 80 % of its stance height and tilted < 30 deg at the end
  double max_tilt = 0;         // largest base tilt after the push [rad]
  double base_settle = -1;     // time after the push's end until the base stays within 1 cm of
                               // its stance (horizontal) [s]; -1: never within the run
  double torque_settle = -1;   // time after the push's end until the ankle torque oscillation
                               // (deviation from its mean over the run's last 0.5 s, where it
                               // has come to rest) stays below 10 % of its first peak [s]
  double torque_peak = 0;      // that first peak [N m]
  // balance's base estimator against the truth from the push on: tilt [rad], height [m]
  double estimator_tilt_error = 0, estimator_height_error = 0;
  uint64_t nonfinite_commands = 0;
};

// the time after which `dev` (sampled at `t`) stays at or below `bound`; -1 if it ends above
inline double SettleTime(const std::vector<double>& t, const std::vector<double>& dev, double bound) {
  for (size_t i = dev.size(); i-- > 0;)
    if (dev[i] > bound) return i + 1 < dev.size() ? t[i + 1] : -1.0;
  return 0.0;
}

inline PushOutcome RunPushTrial(const Trial& trial) {
  PushOutcome out;
  ClosedLoop loop(trial);
  if (!loop.ok()) return out;
  double stance[3] = {0, 0, 0}, z_offset = 0;
  int n0 = 0;
  std::vector<double> t_after, dev_base, dev_torque;
  std::vector<std::array<double, 4>> taus;
  const double t_end = kPushAt + kPushDuration + kObserve;
  while (loop.time() < t_end) {
    loop.Cycle();
    const shm::SensorBlock& s = loop.s();
    const double* p = s.sim_truth.p_WB;
    const double tau[4] = {s.force[0].torque[0], s.force[0].torque[1], s.force[1].torque[0],
                           s.force[1].torque[1]};
    if (s.time > kPushAt - 0.5 && s.time <= kPushAt) {  // the stance: the last half second
      for (int k = 0; k < 3; ++k) stance[k] += p[k];
      if (loop.balance()) z_offset += loop.balance()->estimate().p_WB.z() - p[2];
      ++n0;
      continue;
    }
    if (s.time <= kPushAt) continue;
    if (n0 > 0) {
      for (double& v : stance) v /= n0;
      z_offset /= n0;
      n0 = 0;
    }
    out.max_tilt = std::max(out.max_tilt, Tilt(s.sim_truth.quat_WB));
    if (BalanceController* b = loop.balance()) {
      // the estimate's height is relative to its own origin: compare changes since the stance
      const model::BaseEstimate& e = b->estimate();
      const Eigen::Quaterniond q_true(s.sim_truth.quat_WB[0], s.sim_truth.quat_WB[1],
                                      s.sim_truth.quat_WB[2], s.sim_truth.quat_WB[3]);
      const Eigen::Vector3d z_est = e.quat_WB * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d z_true = q_true * Eigen::Vector3d::UnitZ();
      out.estimator_tilt_error = std::max(out.estimator_tilt_error,
                                          std::acos(std::clamp(z_est.dot(z_true), -1.0, 1.0)));
      out.estimator_height_error =
          std::max(out.estimator_height_error, std::abs(e.p_WB.z() - p[2] - z_offset));
    }
    if (s.time >= kPushAt + kPushDuration) {
      taus.push_back({tau[0], tau[1], tau[2], tau[3]});
      t_after.push_back(s.time - kPushAt - kPushDuration);
      dev_base.push_back(std::hypot(p[0] - stance[0], p[1] - stance[1]));
    }
  }
  out.nonfinite_commands = loop.controller().counters().non_finite_fixed;
  const shm::SensorBlock& s = loop.s();
  out.standing = s.sim_truth.p_WB[2] > 0.8 * stance[2] && Tilt(s.sim_truth.quat_WB) < 30 * M_PI / 180;
  if (!out.standing || t_after.empty()) return out;
  out.base_settle = SettleTime(t_after, dev_base, 0.01);
  // the torques' rest: their mean over the last 0.5 s
  double rest[4] = {0, 0, 0, 0};
  int nrest = 0;
  for (size_t i = 0; i < taus.size(); ++i) {
    if (t_after[i] < kObserve - 0.5) continue;
    for (int k = 0; k < 4; ++k) rest[k] += taus[i][k];
    ++nrest;
  }
  for (double& v : rest) v /= std::max(nrest, 1);
  for (const auto& tau : taus) {
    double d2 = 0;
    for (int k = 0; k < 4; ++k) d2 += (tau[k] - rest[k]) * (tau[k] - rest[k]);
    dev_torque.push_back(std::sqrt(d2));
  }
  // the first peak: the largest deviation before it first falls to half of it
  double peak = 0;
  for (double v : dev_torque) {
    if (v > peak) peak = v;
    else if (v < 0.5 * peak) break;
  }
  out.torque_peak = peak;
  out.torque_settle = SettleTime(t_after, dev_torque, 0.1 * peak);
  return out;
}

//---------------- standing on one leg ----------------

struct OneLegOutcome {
  bool standing = false;        // at the end, base above 80 % of its start height, tilt < 30 deg
  double min_cop_margin = 1e9;  // while on one foot (lift complete): the stance sole's CoP
                                // distance to its nearest edge, smallest [m]
  double max_swing_fz = 0;      // the swing foot's largest normal force then [N]
  double min_lift = 1e9;        // the swing sole's smallest height above where it was [m]
  int holds = 0;                // sides held
  double hold_time = 0;         // time spent on one foot with the foot fully lifted [s]
};

// balance standing on each foot in turn (trial.options.one_leg.sides), judged on the truth
inline OneLegOutcome RunOneLegTrial(const Trial& trial) {
  OneLegOutcome out;
  ClosedLoop loop(trial);
  if (!loop.ok() || !loop.balance()) return out;
  const OneLegOptions& o = trial.options.one_leg;
  const double z0 = loop.s().sim_truth.p_WB[2];
  double sole_z0[2] = {0, 0};
  const double t_end = 1.0 + trial.options.centre_time +
                       o.sides.size() * (2 * o.shift_time + 2 * o.lift_time + o.hold + o.pause) + 1.0;
  int last_side = -1;
  while (loop.time() < t_end) {
    loop.Cycle();
    const StanceTargets& tg = loop.balance()->targets();
    if (tg.standing_on < 0) {
      for (int i = 0; i < 2; ++i) sole_z0[i] = loop.SoleZ(i);
      continue;
    }
    const int st = tg.standing_on, sw = 1 - st;
    if (tg.lift[sw] < 0.999 * o.lift) continue;
    if (st != last_side) ++out.holds, last_side = st;
    out.hold_time += kCycle;
    out.min_cop_margin = std::min(out.min_cop_margin, loop.CopMargin(st));
    out.max_swing_fz = std::max(out.max_swing_fz, loop.Fz(sw));
    out.min_lift = std::min(out.min_lift, loop.SoleZ(sw) - sole_z0[sw]);
  }
  const shm::SensorBlock& s = loop.s();
  out.standing = s.sim_truth.p_WB[2] > 0.8 * z0 && Tilt(s.sim_truth.quat_WB) < 30 * M_PI / 180;
  return out;
}

//---------------- standing on uneven ground ----------------

struct StandOutcome {
  bool standing = false;
  double min_cop_margin[2] = {1e9, 1e9};  // left, right sole, from `after` on [m]
  double min_fz[2] = {1e9, 1e9};          // their smallest normal forces then [N]
};

inline StandOutcome RunStandTrial(const Trial& trial, double after, double until) {
  StandOutcome out;
  ClosedLoop loop(trial);
  if (!loop.ok()) return out;
  const double z0 = loop.s().sim_truth.p_WB[2];
  while (loop.time() < until) {
    loop.Cycle();
    if (loop.time() < after) continue;
    for (int i = 0; i < 2; ++i) {
      out.min_cop_margin[i] = std::min(out.min_cop_margin[i], loop.CopMargin(i));
      out.min_fz[i] = std::min(out.min_fz[i], loop.Fz(i));
    }
  }
  const shm::SensorBlock& s = loop.s();
  out.standing = s.sim_truth.p_WB[2] > 0.8 * z0 && Tilt(s.sim_truth.quat_WB) < 30 * M_PI / 180;
  return out;
}

}  // namespace ohrp::controllers::testing
