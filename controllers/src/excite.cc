// The excite controller (see controllers/excite.h).
#include "controllers/excite.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <sstream>

namespace ohrp::controllers {

bool ParseExciteSignal(const std::string& name, ExciteSignal* signal) {
  if (name == "chirp") *signal = ExciteSignal::kChirp;
  else if (name == "steps") *signal = ExciteSignal::kSteps;
  else if (name == "prbs") *signal = ExciteSignal::kPrbs;
  else return false;
  return true;
}

std::vector<int8_t> PrbsBits(uint32_t seed) {
  std::vector<int8_t> bits(511);
  uint32_t r = seed & 0x1ff;
  if (r == 0) r = 1;
  for (int8_t& b : bits) {
    b = (r & 1) ? 1 : -1;
    const uint32_t fb = ((r >> 0) ^ (r >> 4)) & 1;  // taps 9 and 5 (x^9 + x^5 + 1)
    r = (r >> 1) | (fb << 8);
  }
  return bits;
}

double ExciteSignalValue(ExciteSignal s, const ExciteOptions& o, const std::vector<int8_t>& prbs,
                         double t) noexcept {
  if (!(t >= 0 && t <= o.duration)) return 0;
  switch (s) {
    case ExciteSignal::kChirp: {
      const double phase =
          2 * M_PI * (o.f_min * t + (o.f_max - o.f_min) * t * t / (2 * o.duration));
      const double edge = std::fmin(t, o.duration - t);
      const double taper =
          edge >= kChirpTaper ? 1.0 : 0.5 * (1 - std::cos(M_PI * edge / kChirpTaper));
      return taper * std::sin(phase);
    }
    case ExciteSignal::kSteps: {
      const long k = static_cast<long>(std::floor(t * 2 * o.f_min));
      return k % 2 == 0 ? 1.0 : -1.0;
    }
    case ExciteSignal::kPrbs: {
      if (prbs.empty()) return 0;
      const long k = static_cast<long>(std::floor(t * o.f_max / kPrbsBitFactor));
      return prbs[static_cast<size_t>(k) % prbs.size()];
    }
  }
  return 0;
}

std::string CheckExciteOptions(const ExciteOptions& o) {
  ExciteSignal s;
  auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (o.joints.empty()) return "--joints: name at least one joint to excite";
  if (!ParseExciteSignal(o.signal, &s)) return "--signal " + o.signal + ": want chirp, steps or prbs";
  if (!positive(o.amplitude) || o.amplitude > 1.0) return "--amplitude must be in (0, 1] rad";
  if (!positive(o.f_min) || !positive(o.f_max) || o.f_min >= o.f_max || o.f_max > 50)
    return "--f-min/--f-max: want 0 < f_min < f_max <= 50 Hz";
  if (!positive(o.duration) || o.duration > 3600) return "--duration must be in (0, 3600] s";
  if (s == ExciteSignal::kChirp && o.duration < 2 * kChirpTaper)
    return "--duration: a chirp needs at least 1 s (its fades)";
  if (!(std::isfinite(o.start) && o.start >= 0)) return "--start must be a time >= 0 s";
  if (!positive(o.max_velocity)) return "--max-velocity must be > 0 rad/s";
  if (!(std::isfinite(o.margin) && o.margin >= 0)) return "--margin must be >= 0 rad";
  if (!positive(o.band)) return "--band must be > 0 rad";
  if (o.seed < 1 || o.seed > 511) return "--seed must be 1..511 (the 9-bit register's state)";
  if (!(std::isfinite(o.kp_scale) && o.kp_scale >= 0 && std::isfinite(o.kd_scale) &&
        o.kd_scale >= 0))
    return "--kp-scale/--kd-scale must be finite and >= 0";
  return "";
}

ExciteController::ExciteController(const ExciteOptions& options) : o_(options) {}

ConfigStatus ExciteController::on_configure(const shm::SegmentHeader& header) {
  if (const std::string e = CheckExciteOptions(o_); !e.empty())
    return ConfigStatus::Fail(ConfigError::kOption, e);
  ParseExciteSignal(o_.signal, &signal_);
  prbs_ = PrbsBits(o_.seed);
  ids_.clear();
  const std::vector<std::string>& names = joint_names();
  for (const std::string& name : o_.joints) {
    int id = -1;
    for (int j = 0; j < static_cast<int>(names.size()); ++j)
      if (names[j] == name) id = j;
    if (id < 0) {
      std::string all;
      for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
      return ConfigStatus::Fail(ConfigError::kUnknownJoint,
                                "--joints: the robot has no joint '" + name + "' (it has " + all + ")");
    }
    for (int other : ids_)
      if (other == id) return ConfigStatus::Fail(ConfigError::kOption, "--joints: '" + name + "' twice");
    if (HasLimits(header, id) &&
        header.q_max[id] - header.q_min[id] < 2 * o_.margin + 1e-6)
      return ConfigStatus::Fail(ConfigError::kLimits, "--margin leaves joint '" + name + "' no range");
    ids_.push_back(id);
  }
  const double period = header.control_period > 0 ? header.control_period : 0.001;
  log_capacity_ = o_.log_file.empty()
                      ? 0
                      : static_cast<size_t>((o_.start + o_.duration + kLogTail) / period) + 16;
  log_.assign(log_capacity_ * (1 + 4 * ids_.size()), 0.0);
  log_rows_ = 0;
  return ConfigStatus::Ok();
}

void ExciteController::on_activate(const shm::SensorBlock& sensors) noexcept {
  for (int j = 0; j < njoint(); ++j) {
    q0_[j] = ref_[j] = sensors.q[j];
    excursion_[j] = 0;
  }
  t0_ = last_time_ = sensors.time;
  first_ = true;
}

void ExciteController::on_update(const shm::SensorBlock& sensors,
                                 shm::CommandBlock* commands) noexcept {
  const shm::SegmentHeader& h = header();
  const double dt = first_ ? (h.control_period > 0 ? h.control_period : 0.001)
                           : std::fmax(0.0, sensors.time - last_time_);
  first_ = false;
  last_time_ = sensors.time;
  Watch(sensors);
  const double u = failed_ ? 0.0
                           : ExciteSignalValue(signal_, o_, prbs_, sensors.time - t0_ - o_.start);
  for (int j = 0; j < njoint(); ++j) {
    shm::JointCommand& c = commands->joint[j];
    c.mode = shm::JointMode::kPosition;
    c.q_ref = q0_[j];
    c.dq_ref = 0;
    c.tau_ff = 0;
    c.kp = h.default_kp[j] * o_.kp_scale;
    c.kd = h.default_kd[j] * o_.kd_scale;
  }
  bool limited = false;
  for (int j : ids_) {
    double target = q0_[j] + o_.amplitude * u;
    if (HasLimits(h, j)) {
      const double lo = h.q_min[j] + o_.margin, hi = h.q_max[j] - o_.margin;
      const double kept = std::fmin(hi, std::fmax(lo, target));
      limited |= kept != target;
      target = kept;
    }
    const double step = o_.max_velocity * dt;
    const double move = std::fmin(step, std::fmax(-step, target - ref_[j]));
    limited |= move != target - ref_[j];
    ref_[j] += move;
    commands->joint[j].q_ref = ref_[j];
    commands->joint[j].dq_ref = dt > 0 ? move / dt : 0;
  }
  limited_ += limited ? 1 : 0;
  Log(sensors);
}

// an excited joint outside its limits, or beyond amplitude + band from where it started
void ExciteController::Watch(const shm::SensorBlock& s) noexcept {
  if (failed_) return;
  const shm::SegmentHeader& h = header();
  for (int j : ids_) {
    const double q = s.q[j];
    excursion_[j] = std::fmax(excursion_[j], std::fabs(q - q0_[j]));
    const bool outside = HasLimits(h, j) && (q < h.q_min[j] || q > h.q_max[j]);
    if (outside || !std::isfinite(q) || std::fabs(q - q0_[j]) > o_.amplitude + o_.band) {
      failed_ = true;
      failed_joint_ = j;
      failed_q_ = q;
      failed_time_ = s.time;
      return;
    }
  }
}

void ExciteController::Log(const shm::SensorBlock& s) noexcept {
  if (log_rows_ >= log_capacity_) return;
  double* row = log_.data() + log_rows_ * (1 + 4 * ids_.size());
  *row++ = s.time;
  for (int j : ids_) {
    *row++ = ref_[j];
    *row++ = s.q[j];
    *row++ = s.dq[j];
    *row++ = s.tau[j];
  }
  ++log_rows_;
}

std::string ExciteController::failure() const {
  if (!log_error_.empty()) return "--log: " + log_error_;  // (report() wrote it, before this)
  if (!failed_) return "";
  const shm::SegmentHeader& h = header();
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "joint %s left its band at t = %.3f s: q = %.4f rad, started at %.4f, amplitude "
                "%.3f + band %.3f, limits [%.4f, %.4f]; the excitation stopped there",
                joint_names()[failed_joint_].c_str(), failed_time_, failed_q_, q0_[failed_joint_],
                o_.amplitude, o_.band, h.q_min[failed_joint_], h.q_max[failed_joint_]);
  return buf;
}

void ExciteController::report(std::ostream& out) const {
  out << "excite: " << o_.signal << " on " << ids_.size() << " joints, amplitude " << o_.amplitude
      << " rad, " << o_.f_min << "-" << o_.f_max << " Hz over " << o_.duration << " s; "
      << limited_ << " cycles with a reference kept inside the limits or the rate bound; "
      << "largest excursion from the start:";
  for (int j : ids_) out << " " << joint_names()[j] << " " << excursion_[j] << " rad";
  out << "\n";
  if (o_.log_file.empty()) return;
  // the whole text, then one write, every result checked (a full disk fails the run: failure())
  std::string text = "time";
  for (int j : ids_) {
    const std::string& n = joint_names()[j];
    text += "," + n + "_ref," + n + "_q," + n + "_dq," + n + "_tau";
  }
  text += "\n";
  const size_t width = 1 + 4 * ids_.size();
  char value[32];
  for (size_t r = 0; r < log_rows_; ++r) {
    const double* row = log_.data() + r * width;
    for (size_t k = 0; k < width; ++k) {
      std::snprintf(value, sizeof value, k ? ",%.9g" : "%.6f", row[k]);
      text += value;
    }
    text += "\n";
  }
  FILE* f = std::fopen(o_.log_file.c_str(), "w");
  const bool written = f && std::fwrite(text.data(), 1, text.size(), f) == text.size() &&
                       std::fflush(f) == 0 && !std::ferror(f);
  const int saved = errno;
  const bool closed = f && std::fclose(f) == 0;
  if (!written || !closed) {
    log_error_ = "cannot write '" + o_.log_file + "': " + std::strerror(written ? errno : saved);
    out << "excite: log NOT written: " << log_error_ << "\n";
    return;
  }
  out << "excite: log " << o_.log_file << " (" << log_rows_ << " rows)\n";
}

}  // namespace ohrp::controllers
