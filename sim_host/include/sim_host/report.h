// What a sim_host run did: the end-of-run report on stderr and the JSON summary that
// ohrp_run and the benchmarks read.
#pragma once

#include <cstdint>
#include <string>

#include "sim_host/divergence.h"
#include "sim_host/effects.h"
#include "sim_host/host.h"
#include "sim_host/model.h"

namespace ohrp::sim {

// what happened during the run, for the report and the summary
struct RunStats {
  uint64_t steps = 0;
  uint64_t cycles = 0;
  uint64_t commands = 0;
  uint64_t late = 0;
  uint64_t controller_losses = 0;
  uint64_t controllers_seen = 0;
  double wall_start = 0;
  double wall_end = 0;
  double wall_first_command = 0;  // wall time of the first accepted command
  uint64_t cycles_at_first_command = 0;
  double sim_time = 0;
  std::string outcome = "completed";
  std::string detail;
  uint64_t rejected = 0;     // joint commands rejected by the servos
  long warnings = 0;         // MuJoCo warnings during the run
  uint64_t log_rows = 0;     // rows written to the data log
  uint64_t log_dropped = 0;  // rows the log ring could not take
  std::string contact;                  // contact model under the soles (resolved)
  long long fcl_queries = 0;            // soft-foot contact: FCL distance queries
  long long contact_pairs = 0;          // (sole, object) pairs looked at
  long long contact_pairs_bounded = 0;  // of those, rejected by the cheap bound (no FCL)
  Diagnosis divergence;                 // the divergence watch's diagnostic (kind none: none)
};

const char* IntegratorName(int integrator);

// One line: outcome, simulated and wall time, real-time factor, counts.
void PrintReport(const RunStats& st);

// The JSON summary (outcome, timing, counts, the robot's mass and the mass below each force
// sensor, which the sensor does not carry).
// `effects` (may be null) adds each effect, on or off, and why.
void WriteSummary(const std::string& path, const HostOptions& o, const RobotMap& robot,
                  const mjModel* m, const RunStats& st, int exit_code,
                  const EffectsPlan* effects = nullptr);

}  // namespace ohrp::sim
