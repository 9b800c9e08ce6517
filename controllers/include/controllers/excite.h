// Excite: drives chosen joints about the posture they have at activation with a documented
// signal, for the identification of joints and actuators (issue 35, docs/identify.md); every
// other joint holds where it was (position mode, the producer's default gains). Works on any
// producer (sim_host, hw_driver).
//
// For each excited joint j, q0_j its position at activation, t the producer's time since
// activation minus `start` (a hold to settle first):
//   target_j(t) = q0_j + amplitude * u(t)      (u below; 0 before and after the signal)
//   kept `margin` inside the joint's limits, then rate-limited: the reference moves at most
//   max_velocity * dt a cycle (dq_ref is that rate). After the signal it returns to q0_j the same way.
// The signals u(t) in [-1, 1], over t in [0, duration]:
//   chirp  sin(2 pi (f_min t + (f_max - f_min) t^2 / (2 duration))): a linear sweep from f_min
//          to f_max [Hz], faded in and out by a raised cosine over kChirpTaper s at both ends
//   steps  +1 and -1 in turn, each held 1 / (2 f_min) s (f_max unused)
//   prbs   a maximal-length 9-bit shift register (x^9 + x^5 + 1, 511 bits, start state `seed`),
//          +1 or -1 per bit, each bit held 0.44 / f_max s (the spectrum is 3 dB down at f_max)
// Safety: an excited joint measured outside its limits or farther than amplitude + band from
// q0_j fails the run (failure(): the runner exits kExitFailed naming the joint, its value and
// the time); the excitation stops there and every joint returns to q0. A fall is the runner's
// (fall_watch.h, exit kExitFell).
// Log (--log): one CSV row per cycle: time, then per excited joint its reference, measured
// position, velocity and torque; kept in memory (preallocated at configure for
// start + duration + kLogTail seconds) and written after the run.
// on_update does not allocate, throw or log.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "controllers/controller.h"

namespace ohrp::controllers {

inline constexpr double kChirpTaper = 0.5;  // [s] raised-cosine fade of the chirp
inline constexpr double kPrbsBitFactor = 0.44;  // bit time = this / f_max
inline constexpr double kLogTail = 2.0;     // [s] logged after the signal

enum class ExciteSignal { kChirp, kSteps, kPrbs };
// "chirp", "steps", "prbs"; false for anything else
bool ParseExciteSignal(const std::string& name, ExciteSignal* signal);

struct ExciteOptions {
  std::vector<std::string> joints;  // names of the joints to excite
  std::string signal = "chirp";
  double amplitude = 0.1;           // [rad]
  double f_min = 0.2, f_max = 2.0;  // [Hz]
  double duration = 10.0;           // [s] of the signal
  double start = 1.0;               // [s] held after activation before the signal
  double max_velocity = 1.0;        // [rad/s] bound on the references' rate
  double margin = 0.02;             // [rad] references kept this far inside the limits
  double band = 0.05;               // [rad] allowed beyond the amplitude (measured)
  uint32_t seed = 1;                // prbs start state (1..511)
  double kp_scale = 1.0, kd_scale = 1.0;
  std::string log_file;
};

// The normalised signal u(t) of the options (0 outside [0, duration]); `prbs` the register's
// bits (PrbsBits), unused by the other signals. Does not allocate.
double ExciteSignalValue(ExciteSignal s, const ExciteOptions& o, const std::vector<int8_t>& prbs,
                         double t) noexcept;
// One period of the 9-bit maximal-length sequence from start state `seed` (511 values, +-1).
std::vector<int8_t> PrbsBits(uint32_t seed);

// The options' values checked: "" when they are fine, else what is wrong (for exit 2).
std::string CheckExciteOptions(const ExciteOptions& o);

class ExciteController : public Controller {
 public:
  explicit ExciteController(const ExciteOptions& options);
  void report(std::ostream& out) const override;
  std::string failure() const override;

  // (tests) the excited joints' ids, and what happened
  const std::vector<int>& excited() const { return ids_; }
  uint64_t limited_cycles() const { return limited_; }

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void on_activate(const shm::SensorBlock& sensors) noexcept override;
  void on_update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept override;

 private:
  void Watch(const shm::SensorBlock& s) noexcept;
  void Log(const shm::SensorBlock& s) noexcept;

  ExciteOptions o_;
  ExciteSignal signal_ = ExciteSignal::kChirp;
  std::vector<int8_t> prbs_;
  std::vector<int> ids_;
  std::array<double, shm::kMaxJoints> q0_{}, ref_{};
  std::array<double, shm::kMaxJoints> excursion_{};  // largest measured |q - q0| [rad]
  double t0_ = 0, last_time_ = 0;
  bool first_ = true;
  uint64_t limited_ = 0;  // cycles in which a target was kept inside the limits or rate-limited
  // the first breach of the band (latched)
  bool failed_ = false;
  int failed_joint_ = -1;
  double failed_q_ = 0, failed_time_ = 0;
  // the log, preallocated
  std::vector<double> log_;
  size_t log_rows_ = 0, log_capacity_ = 0;
  mutable std::string log_error_;  // report() could not write the log: why (failure())
};

}  // namespace ohrp::controllers
