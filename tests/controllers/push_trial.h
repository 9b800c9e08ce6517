// Test helper: one push trial of a controller closed-loop on an in-process HRP-1S (sim_host's
// stepping, soft soles, 1 ms physics, 5 ms control, sim_host::InProcessRobot), judged on the
// simulation's truth: still standing, how long the base and the ankle torques take to settle.
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

constexpr double kPushAt = 2.5;        // [s] stance reached (ramp 0.5 s + settle 0.5 s) well before
constexpr double kPushDuration = 0.1;  // [s] the push window
constexpr double kObserve = 3.0;       // [s] after the push's end

struct PushTrial {
  bool balance = true;        // balance, else posture
  double direction = 0;       // [deg] in the horizontal plane, 0 = +x (forward), 90 = +y (left)
  double impulse = 0;         // [N s] over kPushDuration
  BalanceOptions options;     // for balance
  std::string scene = "mjcf/hrp1s/scene_flat.xml";
};

struct PushOutcome {
  bool standing = false;       // base above 80 % of its stance height and tilted < 30 deg at the end
  double max_tilt = 0;         // largest base tilt after the push [rad]
  double base_settle = -1;     // time after the push's end until the base stays within 1 cm of
                               // its stance (horizontal) [s]; -1: never within the run
  double torque_settle = -1;   // time after the push's end until the ankle torque oscillation
                               // (deviation from its mean over the run's last 0.5 s, where it
                               // has come to rest) stays below 10 % of its first peak [s]
  double torque_peak = 0;      // that first peak [N m]
  uint64_t nonfinite_commands = 0;
};

inline double Tilt(const double* q) {  // angle of the base's z axis from the vertical
  const double zz = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
  return std::acos(std::clamp(zz, -1.0, 1.0));
}

inline PushOutcome RunPushTrial(const PushTrial& t) {
  PushOutcome out;
  sim::InProcessOptions io;
  io.scene = std::string(OHRP_SOURCE_DIR) + "/" + t.scene;
  io.keyframe = "halfsit";
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
  auto robot = sim::InProcessRobot::Create(io, &error);
  EXPECT_TRUE(robot) << error;
  if (!robot) return out;
  ConfigStatus status;
  std::unique_ptr<Controller> c;
  if (t.balance) {
    BalanceOptions o = t.options;
    o.ramp = 0.5;
    c = BalanceController::Create(o, &status);
  } else {
    PostureOptions o;
    o.ramp = 0.5;
    c = PostureController::Create(o, &status);
  }
  EXPECT_TRUE(c) << status.message;
  if (!c) return out;
  status = c->configure(robot->header());
  EXPECT_TRUE(status.ok()) << status.message;
  if (!status.ok()) return out;
  c->activate(robot->sensors());

  // the stance before the push, then the record after it
  shm::CommandBlock cmd{};
  double stance[2] = {0, 0}, stance_z = 0;
  int n0 = 0;
  std::vector<double> t_after, dev_base, dev_torque;
  std::vector<std::array<double, 4>> taus;
  const double t_end = kPushAt + kPushDuration + kObserve;
  while (robot->sensors().time < t_end) {
    c->update(robot->sensors(), &cmd);
    robot->Cycle(cmd);
    const shm::SensorBlock& s = robot->sensors();
    const double* p = s.sim_truth.p_WB;
    const double tau[4] = {s.force[0].torque[0], s.force[0].torque[1], s.force[1].torque[0],
                           s.force[1].torque[1]};
    if (s.time > kPushAt - 0.5 && s.time <= kPushAt) {
      stance[0] += p[0];
      stance[1] += p[1];
      stance_z += p[2];
      ++n0;
    } else if (s.time > kPushAt) {
      if (n0 > 0) {  // the stance: the mean over the half second before the push
        stance[0] /= n0, stance[1] /= n0, stance_z /= n0;
        n0 = 0;
      }
      out.max_tilt = std::max(out.max_tilt, Tilt(s.sim_truth.quat_WB));
      if (s.time >= kPushAt + kPushDuration) {
        taus.push_back({tau[0], tau[1], tau[2], tau[3]});
        t_after.push_back(s.time - kPushAt - kPushDuration);
        dev_base.push_back(std::hypot(p[0] - stance[0], p[1] - stance[1]));
      }
    }
  }
  out.nonfinite_commands = c->counters().non_finite_fixed;
  const shm::SensorBlock& s = robot->sensors();
  out.standing = s.sim_truth.p_WB[2] > 0.8 * stance_z && Tilt(s.sim_truth.quat_WB) < 30 * M_PI / 180;
  if (!out.standing || t_after.empty()) return out;
  // settling: the last time the deviation was above its bound
  auto settle = [&](const std::vector<double>& dev, double bound) {
    for (size_t i = dev.size(); i-- > 0;)
      if (dev[i] > bound) return i + 1 < dev.size() ? t_after[i + 1] : -1.0;
    return 0.0;
  };
  out.base_settle = settle(dev_base, 0.01);
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
  out.torque_settle = settle(dev_torque, 0.1 * peak);
  return out;
}

struct OneLegOutcome {
  bool standing = false;        // at the end, base above 80 % of its start height, tilt < 30 deg
  double min_cop_margin = 1e9;  // while on one foot (lift complete): the stance sole's CoP
                                // distance to its nearest edge, smallest [m]
  double max_swing_fz = 0;      // the swing foot's largest normal force then [N]
  double min_lift = 1e9;        // the swing sole's smallest height above where it was [m]
  int holds = 0;                // sides held
  double hold_time = 0;         // time spent on one foot with the foot fully lifted [s]
};

// balance standing on each foot in turn (options.one_leg.sides), judged on the truth
inline OneLegOutcome RunOneLegTrial(const PushTrial& t, const std::string& keyframe = "halfsit") {
  OneLegOutcome out;
  sim::InProcessOptions io;
  io.scene = std::string(OHRP_SOURCE_DIR) + "/" + t.scene;
  io.keyframe = keyframe;
  std::string error;
  auto robot = sim::InProcessRobot::Create(io, &error);
  EXPECT_TRUE(robot) << error;
  if (!robot) return out;
  ConfigStatus status;
  BalanceOptions o = t.options;
  o.ramp = 0.5;
  auto c = BalanceController::Create(o, &status);
  EXPECT_TRUE(c) << status.message;
  if (!c) return out;
  status = c->configure(robot->header());
  EXPECT_TRUE(status.ok()) << status.message;
  if (!status.ok()) return out;
  c->activate(robot->sensors());
  // the soles' rectangles in their sensors' frames, from the model at the start
  const mjModel* m = robot->m();
  const mjData* d = robot->d();
  int geom[2], site[2], ft[2] = {-1, -1};
  for (int i = 0; i < 2; ++i) {
    const char* sensor = i == 0 ? "lfsensor" : "rfsensor";
    geom[i] = mj_name2id(m, mjOBJ_GEOM, i == 0 ? "LLEG_SOLE" : "RLEG_SOLE");
    site[i] = mj_name2id(m, mjOBJ_SITE, sensor);
    for (int k = 0; k < robot->header().nforce; ++k)
      if (std::string(robot->header().force_names[k]) == sensor) ft[i] = k;
    EXPECT_GE(ft[i], 0);
    EXPECT_GE(geom[i], 0);
    EXPECT_GE(site[i], 0);
    if (geom[i] < 0 || site[i] < 0 || ft[i] < 0) return out;
  }
  const double z0 = robot->sensors().sim_truth.p_WB[2];
  shm::CommandBlock cmd{};
  double sole_z0[2] = {0, 0};
  const double t_end = 1.0 + 1.0 + o.one_leg.sides.size() * (2 * o.one_leg.shift_time +
                       2 * o.one_leg.lift_time + o.one_leg.hold + o.one_leg.pause) + 1.0;
  int last_side = -1;
  while (robot->sensors().time < t_end) {
    c->update(robot->sensors(), &cmd);
    robot->Cycle(cmd);
    const shm::SensorBlock& s = robot->sensors();
    const StanceTargets& tg = c->targets();
    if (tg.standing_on < 0) {
      for (int i = 0; i < 2; ++i) sole_z0[i] = d->geom_xpos[3 * geom[i] + 2];
      continue;
    }
    const int st = tg.standing_on, sw = 1 - st;
    if (tg.lift[sw] < 0.999 * o.one_leg.lift) continue;
    if (st != last_side) ++out.holds, last_side = st;
    out.hold_time += 0.005;
    // the stance sole's CoP in its sensor's frame (the sensor on the sole's bottom plane),
    // against the sole's rectangle there
    const shm::ForceTorque& f = s.force[ft[st]];
    const double fz = f.force[2];
    if (fz > 50) {
      const double cx = -f.torque[1] / fz, cy = f.torque[0] / fz;
      // sole rectangle in the sensor frame: geom centre relative to the site, in the site frame
      double rel_W[3], rel_S[3];
      for (int k = 0; k < 3; ++k) rel_W[k] = d->geom_xpos[3 * geom[st] + k] - d->site_xpos[3 * site[st] + k];
      mju_rotVecMatT(rel_S, rel_W, d->site_xmat + 9 * site[st]);
      const double hx = m->geom_size[3 * geom[st]], hy = m->geom_size[3 * geom[st] + 1];
      const double margin = std::min({hx - std::abs(cx - rel_S[0]), hy - std::abs(cy - rel_S[1])});
      out.min_cop_margin = std::min(out.min_cop_margin, margin);
    }
    const shm::ForceTorque& fs = s.force[ft[sw]];
    out.max_swing_fz = std::max(out.max_swing_fz, fs.force[2]);
    out.min_lift = std::min(out.min_lift, d->geom_xpos[3 * geom[sw] + 2] - sole_z0[sw]);
  }
  const shm::SensorBlock& s = robot->sensors();
  out.standing = s.sim_truth.p_WB[2] > 0.8 * z0 && Tilt(s.sim_truth.quat_WB) < 30 * M_PI / 180;
  return out;
}

}  // namespace ohrp::controllers::testing
