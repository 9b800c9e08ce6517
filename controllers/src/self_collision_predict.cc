// The guard's prediction (controllers/self_collision_guard.h, "predict"): what a command can do
// from the measured state, per joint: the interval it can reach, the nominal motion (the
// command's middle acceleration for two periods, then the brake) and its envelope.
#include <algorithm>
#include <cmath>

#include "controllers/self_collision_guard.h"

namespace ohrp::controllers {
namespace {

// the servo's torque for the command at (q, dq), unclamped; NaN when it cannot be told
double Servo(const shm::JointCommand& c, double q, double dq) noexcept {
  switch (c.mode) {
    case shm::JointMode::kPosition: return c.kp * (c.q_ref - q) + c.kd * (c.dq_ref - dq) + c.tau_ff;
    case shm::JointMode::kVelocity: return c.kd * (c.dq_ref - dq) + c.tau_ff;
    case shm::JointMode::kTorque: return c.tau_ff;
    default: return 0.0;
  }
}

}  // namespace

void SelfCollisionGuard::VelocityBand(const shm::JointCommand& c, double q, double v,
                                      double load_lo, double load_hi, double tau_max,
                                      double horizon, double* v_floor, double* v_ceil) {
  // A servo with damping kd > 0 drives the velocity towards v_eq = dq_ref + (kp (q_ref - q) +
  // tau_ff - L) / kd: above it, the servo's torque (clamped to tau_max, the same sign) is below
  // the load L, so the velocity falls, whatever the inertia (|L| <= tau_max). Over the horizon q
  // stays within v_floor t .. v_ceil t of the start, which bounds kp (q_ref - q); the band and
  // that range are narrowed in turn, each step from sound bounds (kp t / kd < 1 contracts).
  const bool position = c.mode == shm::JointMode::kPosition;
  if (!(c.mode == shm::JointMode::kPosition || c.mode == shm::JointMode::kVelocity)) return;
  const double kp = position ? c.kp : 0.0;
  if (!(c.kd > 0) || !(kp >= 0) || !std::isfinite(c.kd) || !std::isfinite(kp)) return;
  // the ceiling needs every load >= -tau_max (else the load can outpull any torque), the floor
  // every load <= tau_max
  const bool ceil_ok = load_lo >= -tau_max, floor_ok = load_hi <= tau_max;
  const double drive = (position ? kp * (c.q_ref - q) : 0.0) + c.tau_ff;
  if (!std::isfinite(drive) || !std::isfinite(c.dq_ref)) return;
  for (int k = 0; k < 4; ++k) {
    const double back = std::max(0.0, *v_ceil) * horizon;   // how far q can rise
    const double ahead = std::max(0.0, -*v_floor) * horizon;  // how far it can fall
    const double hi = c.dq_ref + (drive + kp * ahead - load_lo) / c.kd;
    const double lo = c.dq_ref + (drive - kp * back - load_hi) / c.kd;
    if (ceil_ok) *v_ceil = std::min(*v_ceil, std::max(v, hi));
    if (floor_ok) *v_floor = std::max(*v_floor, std::min(v, lo));
  }
}

void SelfCollisionGuard::UpdateLoads(const shm::SensorBlock& sensors, bool first) {
  // A foot carries load when its sensor's force is above the file's support_force (a tenth of
  // the robot's weight) and stops carrying it below half of that: the band between (a
  // twentieth of the weight: 64 N on HRP-1S, 17 N on G1) is the hysteresis, wide against an
  // F/T sensor's noise (a few N) so that noise cannot toggle the brake. The force's magnitude,
  // not its normal part: at least the normal force, so a stance foot is never read as unloaded.
  // Conservative where the measurement says nothing: a sensor the segment lacks or a reading
  // not finite is a loaded foot (never braked); at activation a reading within the band too.
  for (int j = 0; j < njoint_; ++j) {
    if (!CarriesFoot(j)) {
      loaded_[j] = 0;
      continue;
    }
    const int fs = support_[j];
    if (fs < 0) {
      loaded_[j] = 1;
      continue;
    }
    const double* f = sensors.force[fs].force;
    const double n = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    const double on = file_.dynamics[j].support_force, off = 0.5 * on;
    if (!std::isfinite(n)) loaded_[j] = 1;
    else if (n > on) loaded_[j] = 1;
    else if (n < off) loaded_[j] = 0;
    else if (first) loaded_[j] = 1;
  }
  standing_ = false;
  for (int j = 0; j < njoint_; ++j) standing_ = standing_ || (CarriesFoot(j) && loaded_[j]);
}

double SelfCollisionGuard::Deceleration(int j, double tau_measured) const {
  return Decelerate(j, tau_measured, file_.dynamics[j].inertia_max);
}

double SelfCollisionGuard::Decelerate(int j, double tau_measured, double inertia) const {
  // the torque left for braking: the limit less what holding needs (the gravity bound, or the
  // measured load when less), at least a tenth of the limit
  // (a joint whose holding takes all of it still brakes, slowly, on the prediction's side)
  const collision::JointDynamics& d = file_.dynamics[j];
  const double hold = std::isfinite(tau_measured) ? std::min(d.gravity_max, tau_measured)
                                                  : d.gravity_max;
  return std::max(tau_max_[j] - hold, 0.1 * tau_max_[j]) / inertia;
}

void SelfCollisionGuard::Excursion(double v, double a_lo, double a_hi, double horizon,
                                   double v_max, double decel, double* lo, double* hi) {
  const double ceil = v_max > 0 ? std::max(v, v_max) : INFINITY;
  const double floor = v_max > 0 ? std::min(v, -v_max) : -INFINITY;
  Excursion(v, a_lo, a_hi, horizon, floor, ceil, decel, lo, hi);
}

void SelfCollisionGuard::Excursion(double v, double a_lo, double a_hi, double horizon,
                                   double v_floor, double v_ceil, double decel, double* lo,
                                   double* hi) {
  const double t = horizon;
  // free motion: position extremes of v t + a t^2 / 2 over [0, t] for a in [a_lo, a_hi]
  double up = std::max(0.0, v * t + 0.5 * (v >= 0 ? std::max(a_hi, 0.0) : a_hi) * t * t);
  double down = std::min(0.0, v * t + 0.5 * (v <= 0 ? std::min(a_lo, 0.0) : a_lo) * t * t);
  double v_up = v + a_hi * t, v_down = v + a_lo * t;
  // the velocity band (the actuator's speed limit, the servo's damping): the velocity stays
  // within [min(v, v_floor), max(v, v_ceil)] over the horizon
  v_ceil = std::max(v, v_ceil);
  v_floor = std::min(v, v_floor);
  up = std::min(up, std::max(0.0, v_ceil) * t);
  down = std::max(down, std::min(0.0, v_floor) * t);
  v_up = std::min(v_up, v_ceil);
  v_down = std::max(v_down, v_floor);
  // then the brake to rest
  if (v_up > 0) up += v_up * v_up / (2 * decel);
  if (v_down < 0) down -= v_down * v_down / (2 * decel);
  *lo = down;
  *hi = up;
}

bool SelfCollisionGuard::Predict(const shm::SensorBlock& sensors, const shm::CommandBlock& c) noexcept {
  const double horizon = 2 * period_;  // this command's period and one of latency
  // the fastest joint: how much the load can change over the horizon (below)
  double speed = 0;
  for (int j = 0; j < njoint_; ++j) speed = std::max(speed, std::abs(sensors.dq[j]));
  UpdateLoads(sensors, false);  // which feet carry load: the inertia, and which legs may brake
  for (int j = 0; j < njoint_; ++j) {
    const double q = sensors.q[j], v = sensors.dq[j];
    if (!std::isfinite(q) || !std::isfinite(v)) {
      have_last_ = false;
      return false;
    }
    JointMotion m;
    if (!BoundAcceleration(j, sensors, c.joint[j], speed, horizon, &m)) return false;
    BoundVelocity(j, q, v, c.joint[j], horizon, &m);
    double lo = 0, hi = 0;
    Excursion(v, m.a_lo, m.a_hi, horizon, m.v_floor, m.v_ceil, decel_[j], &lo, &hi);
    q_[j] = q;
    meas_v_[j] = v;  // the retreat's support rate (self_collision_retreat.cc)
    meas_a_[j] = have_last_ ? (v - last_dq_[j]) / period_ : 0.0;
    box_lo_[j] = q + lo;
    box_hi_[j] = q + hi;
    PlanNominal(j, q, v, horizon, &m);
  }
  horizon_end_ = horizon + *std::max_element(stop_.begin(), stop_.end());
  if (!PredictPassive(sensors)) return false;
  for (int j = 0; j < njoint_; ++j) last_dq_[j] = sensors.dq[j];
  have_last_ = true;
  return true;
}

bool SelfCollisionGuard::BoundAcceleration(int j, const shm::SensorBlock& sensors,
                                           const shm::JointCommand& c, double speed,
                                           double horizon, JointMotion* m) noexcept {
  const double q = sensors.q[j], v = sensors.dq[j];
  const collision::JointDynamics& d = file_.dynamics[j];
  // the inertia the joint drives: the links beyond alone while their force sensor says they
  // carry no weight (UpdateLoads), else the bound under any contact
  const double inertia = CarriesFoot(j) && !loaded_[j] ? d.inertia_free : d.inertia_max;
  // the joint's acceleration over the last period and the servo's torque that made it: the
  // next acceleration is that one plus the change of torque over the (unknown, common)
  // inertia, the load changing by at most the gravity bound times the angle turned over the
  // horizon. Without a last period (a measurement was not finite): the load is anywhere
  // within the gravity bound. At activation the joints are taken as not accelerating.
  const double a_last = have_last_ ? (v - last_dq_[j]) / period_ : NAN;
  const bool observed = std::isfinite(a_last) && std::isfinite(sensors.tau[j]);
  const double slack = observed ? d.gravity_max * std::min(1.0, 3 * speed * period_) + d.damping * std::abs(v)
                                : d.gravity_max;
  const double base = observed ? sensors.tau[j] : 0.0;  // the torque the acceleration answers
  const double a0 = observed ? a_last : 0.0;
  // the servo's torque along the period (at the start and where the velocity carries the
  // joint), clamped to the limit; a command that cannot be told gives the whole range
  const double t0 = Servo(c, q, v), t1 = Servo(c, q + v * horizon, v);
  double tau_lo = -tau_max_[j], tau_hi = tau_max_[j];
  if (std::isfinite(t0) && std::isfinite(t1)) {
    tau_lo = std::clamp(std::min(t0, t1), -tau_max_[j], tau_max_[j]);
    tau_hi = std::clamp(std::max(t0, t1), -tau_max_[j], tau_max_[j]);
  }
  if (!std::isfinite(tau_lo) || !std::isfinite(tau_hi)) return false;  // no limit, no command
  const double f_lo = tau_lo - base - slack, f_hi = tau_hi - base + slack;
  m->a_lo = a0 + std::min(f_lo / d.inertia_min, f_lo / inertia);
  m->a_hi = a0 + std::max(f_hi / d.inertia_min, f_hi / inertia);
  // braking: the limit less the largest load (the torque less what accelerated the joint),
  // over the inertia
  const double load = observed ? std::max(std::abs(base - d.inertia_min * a0), std::abs(base - inertia * a0)) + slack
                               : d.gravity_max;
  decel_[j] = Decelerate(j, load, inertia);
  m->inertia = inertia;
  m->observed = observed;
  m->slack = slack;
  m->base = base;
  m->a0 = a0;
  return true;
}

void SelfCollisionGuard::BoundVelocity(int j, double q, double v, const shm::JointCommand& c,
                                       double horizon, JointMotion* m) const noexcept {
  const collision::JointDynamics& d = file_.dynamics[j];
  const double inertia = m->inertia, slack = m->slack, base = m->base, a0 = m->a0;
  const bool observed = m->observed;
  // the velocity band: the speed limit, and the servo's damping (VelocityBand)
  m->v_floor = d.velocity_max > 0 ? std::min(v, -d.velocity_max) : -INFINITY;
  m->v_ceil = d.velocity_max > 0 ? std::max(v, d.velocity_max) : INFINITY;
  // the load the joint carries: what the measured torque did not spend on the measured
  // acceleration (for any inertia within the bounds), changing by the slack; unmeasured:
  // within the gravity bound
  // (the measured acceleration of a light joint is large and its inertia uncertain: the
  // load is also kept within the gravity bound and the slack, as the brake's rate is)
  const double l_lo = observed ? std::max(std::min(base - d.inertia_min * a0, base - inertia * a0),
                                          -d.gravity_max) - slack
                               : -d.gravity_max;
  const double l_hi = observed ? std::min(std::max(base - d.inertia_min * a0, base - inertia * a0),
                                          d.gravity_max) + slack
                               : d.gravity_max;
  double band_lo = v + std::min(m->a_lo, 0.0) * horizon, band_hi = v + std::max(m->a_hi, 0.0) * horizon;
  VelocityBand(c, q, v, l_lo, l_hi, tau_max_[j], horizon, &band_lo, &band_hi);
  m->v_floor = std::max(m->v_floor, band_lo);
  m->v_ceil = std::min(m->v_ceil, band_hi);
}

void SelfCollisionGuard::PlanNominal(int j, double q, double v, double horizon,
                                     const JointMotion* m) noexcept {
  const double a_lo = m->a_lo, a_hi = m->a_hi;
  // the nominal motion (the middle acceleration, then the brake) and how far the motion
  // within the bounds can be from it at any time: the acceleration's spread over the
  // horizon, and the brake's stopping point from the extreme velocities (two brakes at one
  // rate from v and v' differ by at most their stopping points' difference at any time)
  // Within the band the velocity at time s lies in [max(v + a_lo s, v_floor), min(v + a_hi s,
  // v_ceil)] (v_floor <= v <= v_ceil); the nominal velocity v + a_mid s, a_mid in [a_lo, a_hi]
  // the middle of the band's end velocities. The position's deviation at t <= horizon is
  // at most the integral of the velocity's: both 0.5 max(a_hi - a_mid, a_mid - a_lo) t^2
  // (the accelerations) and t (max(v_ceil - v, v - v_floor) + |a_mid| t) (the band)
  const double v_ceil = std::max(v, m->v_ceil);
  const double v_floor = std::min(v, m->v_floor);
  const double v_up = std::min(v + a_hi * horizon, v_ceil);
  const double v_down = std::max(v + a_lo * horizon, v_floor);
  const double a_mid = std::clamp((0.5 * (v_up + v_down) - v) / horizon, a_lo, a_hi);
  const double v1 = v + a_mid * horizon;
  const auto stop = [&](double u) { return u * std::abs(u) / (2 * decel_[j]); };
  v0_[j] = v;
  a_mid_[j] = a_mid;
  v1_[j] = v1;
  q1_[j] = q + v * horizon + 0.5 * a_mid * horizon * horizon;
  stop_[j] = std::abs(v1) / decel_[j];
  speed_[j] = std::max(std::abs(v), std::abs(v1));  // the nominal's (the envelope the rest)
  const double spread =
      std::min(0.5 * std::max(a_hi - a_mid, a_mid - a_lo) * horizon * horizon,
               horizon * (std::max(v_ceil - v, v - v_floor) + std::abs(a_mid) * horizon));
  envelope_[j] = spread + std::max(std::abs(stop(v_up) - stop(v1)), std::abs(stop(v_down) - stop(v1)));
}

bool SelfCollisionGuard::PredictPassive(const shm::SensorBlock& sensors) noexcept {
  // passive joints: measured, never commanded nor braked; taken to keep their measured speed
  // over the whole motion (their deviation from standing still is all envelope)
  for (int k = njoint_; k < nq_; ++k) {
    const double q = sensors.passive_q[k - njoint_], v = sensors.passive_dq[k - njoint_];
    if (!std::isfinite(q) || !std::isfinite(v)) {
      have_last_ = false;
      return false;
    }
    q_[k] = q1_[k] = q;
    meas_v_[k] = v, meas_a_[k] = 0.0;
    envelope_[k] = std::abs(v) * horizon_end_;
    box_lo_[k] = q - envelope_[k];
    box_hi_[k] = q + envelope_[k];
  }
  return true;
}

void SelfCollisionGuard::Nominal(double t) {
  const double horizon = 2 * period_;
  for (int k = njoint_; k < nq_; ++k) centre_[k] = q_[k];  // passive: as measured
  for (int j = 0; j < njoint_; ++j) {
    if (t <= horizon) {
      centre_[j] = q_[j] + v0_[j] * t + 0.5 * a_mid_[j] * t * t;
    } else {
      const double u = std::min(t - horizon, stop_[j]);
      centre_[j] = q1_[j] + v1_[j] * u - 0.5 * (v1_[j] > 0 ? 1 : -1) * decel_[j] * u * u;
    }
  }
}

}  // namespace ohrp::controllers
