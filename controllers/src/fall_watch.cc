// The fall watch (see fall_watch.h).
#include "controllers/fall_watch.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ohrp::controllers {
namespace {

constexpr double kG = 9.81;           // [m/s^2]
constexpr double kDeg = M_PI / 180;

std::string Fixed(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// a sustained condition: the time it began, -1 when it does not hold
bool Sustained(bool holds, double now, double needed, double* since) {
  if (!holds) {
    *since = -1;
    return false;
  }
  if (*since < 0) *since = now;
  return now - *since >= needed;
}

}  // namespace

const char* FallCauseName(FallCause c) {
  switch (c) {
    case FallCause::kNone: return "none";
    case FallCause::kTilt: return "tilt";
    case FallCause::kUnloaded: return "feet unloaded";
    case FallCause::kCollapsed: return "collapsed";
  }
  return "?";
}

FallLimits DefaultFallLimits() {
  FallLimits l;
  l.max_tilt = 45 * kDeg;
  l.tilt_time = 0.2;
  l.unloaded_fraction = 0.2;
  l.unloaded_time = 0.5;
  l.armed_fraction = 0.5;
  l.basis = "defaults for any humanoid (no model)";
  return l;
}

FallLimits FallLimitsFor(double com_height, double support_reach, double upper_body_tilt) {
  FallLimits l = DefaultFallLimits();
  if (!(com_height > 0) || !(support_reach > 0) || !std::isfinite(com_height) ||
      !std::isfinite(support_reach) || !(upper_body_tilt >= 0))
    return l;
  const double tip = std::atan2(support_reach, com_height);
  const double tau = std::sqrt(com_height / kG);
  l.max_tilt = std::min(2 * tip + upper_body_tilt, 0.5 * M_PI);
  l.tilt_time = tau;
  l.unloaded_time = 2 * tau;
  l.min_com_height = 0.5 * com_height;
  l.basis = "the model: CoM " + Fixed("%.3f", com_height) + " m over soles reaching " +
            Fixed("%.3f", support_reach) + " m (tipping at " + Fixed("%.1f", tip / kDeg) +
            " deg), pendulum time " + Fixed("%.2f", tau) + " s";
  return l;
}

std::string FallWatch::Configure(const shm::SegmentHeader& header, const FallLimits& limits) {
  limits_ = limits;
  event_ = FallEvent{};
  armed_ = false;
  tilt_since_ = unloaded_since_ = low_since_ = -1;
  nforce_ = std::clamp(header.nforce, 0, shm::kMaxForceSensors);
  weight_ = header.total_mass * kG;
  std::string off;
  const bool limits_ok = std::isfinite(limits.max_tilt) && limits.max_tilt > 0 &&
                         std::isfinite(limits.tilt_time) && limits.tilt_time >= 0 &&
                         std::isfinite(limits.unloaded_time) && limits.unloaded_time >= 0 &&
                         limits.unloaded_fraction >= 0 && limits.unloaded_fraction < 1 &&
                         limits.armed_fraction > limits.unloaded_fraction &&
                         limits.armed_fraction <= 1;
  tilt_on_ = limits_ok && header.nimu > 0 && limits.imu >= 0 && limits.imu < header.nimu;
  if (!tilt_on_) off += limits_ok ? "tilt check off: the robot has no IMU; " : "";
  bool feet_ok = nforce_ > 0;
  for (int f : limits.feet) feet_ok = feet_ok && f < nforce_;
  load_on_ = limits_ok && feet_ok && std::isfinite(weight_) && weight_ > 0;
  if (!load_on_ && limits_ok) {
    off += !feet_ok ? "unloading check off: the robot has no force/torque sensor at its feet; "
                    : "unloading check off: the segment header gives no mass; ";
  }
  if (!limits_ok) off = "fall watch off: its limits are not usable; ";
  if (!off.empty()) off.resize(off.size() - 2);
  return off;
}

double FallWatch::Tilt(const shm::SensorBlock& s, double base_tilt) const noexcept {
  if (std::isfinite(base_tilt)) return base_tilt;
  const double* q = s.imu[limits_.imu].quat_WI;  // w, x, y, z
  const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  if (!(std::abs(n2 - 1.0) < 0.1)) return std::nan("");  // no orientation (e.g. not filled)
  // z component of R(q) e_z, normalised
  const double up = (q[0] * q[0] - q[1] * q[1] - q[2] * q[2] + q[3] * q[3]) / n2;
  return std::acos(std::clamp(up, -1.0, 1.0));
}

double FallWatch::FeetLoad(const shm::SensorBlock& s) const noexcept {
  double load = 0;
  auto add = [&](int f) {
    const double* F = s.force[f].force;
    load += std::sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
  };
  if (limits_.feet[0] < 0 && limits_.feet[1] < 0) {
    for (int f = 0; f < nforce_; ++f) add(f);
  } else {
    for (int f : limits_.feet)
      if (f >= 0) add(f);
  }
  return load;
}

bool FallWatch::Update(const shm::SensorBlock& s, double base_tilt, double com_height) noexcept {
  if (fallen()) return true;
  if (limits_.min_com_height > 0 &&
      Sustained(com_height < limits_.min_com_height, s.time, limits_.tilt_time, &low_since_)) {
    event_ = {FallCause::kCollapsed, s.time, s.cycle, low_since_, com_height,
              limits_.min_com_height};
    return true;
  }
  if (tilt_on_) {
    const double tilt = Tilt(s, base_tilt);
    // a non-finite tilt is no evidence either way
    if (Sustained(tilt > limits_.max_tilt, s.time, limits_.tilt_time, &tilt_since_)) {
      event_ = {FallCause::kTilt, s.time, s.cycle, tilt_since_, tilt, limits_.max_tilt};
      return true;
    }
  }
  if (load_on_) {
    const double load = FeetLoad(s);
    if (std::isfinite(load) && load >= limits_.armed_fraction * weight_) armed_ = true;
    const double below = limits_.unloaded_fraction * weight_;
    if (armed_ && Sustained(std::isfinite(load) && load < below, s.time, limits_.unloaded_time,
                            &unloaded_since_)) {
      event_ = {FallCause::kUnloaded, s.time, s.cycle, unloaded_since_, load, below};
      return true;
    }
  }
  return false;
}

std::string FallWatch::Describe(const char* tilt_from) const {
  const FallEvent& e = event_;
  char buf[400];
  if (e.cause == FallCause::kTilt) {
    std::snprintf(buf, sizeof buf,
                  "the robot fell at t = %.3f s (cycle %llu): its base tilted %.1f deg from "
                  "%s, beyond the limit %.1f deg, since t = %.3f s",
                  e.time, static_cast<unsigned long long>(e.cycle), e.value / kDeg, tilt_from,
                  e.limit / kDeg, e.since);
  } else if (e.cause == FallCause::kUnloaded) {
    std::snprintf(buf, sizeof buf,
                  "the robot fell at t = %.3f s (cycle %llu): its feet carry %.0f N, less than "
                  "%.0f N (%.0f %% of its weight %.0f N), since t = %.3f s",
                  e.time, static_cast<unsigned long long>(e.cycle), e.value, e.limit,
                  limits_.unloaded_fraction * 100, weight_, e.since);
  } else if (e.cause == FallCause::kCollapsed) {
    std::snprintf(buf, sizeof buf,
                  "the robot fell at t = %.3f s (cycle %llu): its CoM is %.3f m over its lower "
                  "sole (the estimator), below the limit %.3f m (half its stance height), since "
                  "t = %.3f s",
                  e.time, static_cast<unsigned long long>(e.cycle), e.value, e.limit, e.since);
  } else {
    return "the robot did not fall";
  }
  return buf;
}

std::string FallWatch::Summary() const {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "fall watch: base tilt > %.1f deg for %.2f s%s; feet below %.0f %% of the weight "
                "(%.0f N) for %.2f s%s%s (%s)",
                limits_.max_tilt / kDeg, limits_.tilt_time, tilt_on_ ? "" : " (off)",
                limits_.unloaded_fraction * 100, weight_, limits_.unloaded_time,
                load_on_ ? "" : " (off)",
                limits_.min_com_height > 0
                    ? ("; CoM below " + Fixed("%.3f", limits_.min_com_height) + " m").c_str()
                    : "",
                limits_.basis.c_str());
  return buf;
}

}  // namespace ohrp::controllers
