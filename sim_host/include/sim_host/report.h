// What a sim_host run did: the end-of-run report on stderr and the JSON summary that
// ohrp_run and the benchmarks read.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sim_host/divergence.h"
#include "sim_host/effects.h"
#include "sim_host/fall.h"
#include "sim_host/host.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "datalog/recorder.h"
#include "sim_host/guard_watch.h"
#include "sim_host/self_collision_watch.h"

namespace ohrp::sim {

// One thing that happened in the run, for the summary's "events": a controller attached, lost
// (died, detached, silent past the timeout) or whose commands began to be rejected; a push
// began or ended. Recorded without allocation (RunStats::Record).
struct HostEvent {
  double time = 0;         // simulated time [s]
  uint64_t cycle = 0;
  const char* kind = "";   // controller_attached | controller_died | controller_detached |
                           // controller_silent | commands_rejected | push_start | push_end |
                           // fall | guard_hold_begin | guard_hold_end
  int64_t value = 0;       // controller_*: its pid; commands_rejected: joints rejected in that
                           // block; push_*: the push's index in the order given; fall: the body
                           // that touched the ground (-1: height or tilt; the summary's "cause");
                           // guard_hold_*: the episode's index in the summary's
                           // "self_collision_guard" "holds" (its pair and distance are added)
};

inline constexpr size_t kMaxHostEvents = 4096;  // events kept per run; more are counted

// what happened during the run, for the report and the summary
struct RunStats {
  RunStats() { events.reserve(kMaxHostEvents); }
  // appends an event (capacity reserved: no allocation), or counts it as dropped when full
  void Record(double time, const char* kind, int64_t value) {
    if (events.size() < kMaxHostEvents) {
      events.push_back(HostEvent{time, cycles, kind, value});
    } else {
      ++events_dropped;
    }
  }
  std::vector<HostEvent> events;
  uint64_t events_dropped = 0;

  uint64_t steps = 0;
  uint64_t cycles = 0;
  uint64_t commands = 0;
  uint64_t late = 0;
  uint64_t controller_losses = 0;
  uint64_t controllers_seen = 0;
  double wall_start = 0;
  double wall_end = 0;
  double wall_first_command = 0;  // wall time of the first accepted command
  double wall_waiting = 0;  // [s] wall time spent waiting for a controller (none attached, or a
                            // new one's first answer) while simulated time stood still
  uint64_t cycles_at_first_command = 0;
  double sim_time = 0;
  std::string outcome = "completed";
  std::string detail;
  uint64_t rejected = 0;     // joint commands rejected by the servos
  uint64_t clamped = 0;      // physics steps x joints whose actuator clamped the servo's torque
                             // (ctrlrange or forcerange, robot_model/actuator.h)
  std::vector<std::pair<std::string, uint64_t>> clamped_joints;  // (joint, steps) with steps > 0
  long warnings = 0;         // MuJoCo warnings during the run
  uint64_t log_rows = 0;     // rows of the data log on disk (written whole; synced at the end)
  uint64_t log_dropped = 0;  // rows the log ring could not take
  uint64_t log_lost = 0;     // rows never written because a write failed
  uint64_t log_over_limit = 0;  // rows not written past --log-max
  uint64_t log_bytes = 0;    // the log's size on disk
  std::string log_error;     // why the log is incomplete ("" when it is complete)
  std::string contact;                  // contact model under the soles (resolved)
  long long fcl_queries = 0;            // soft-foot contact: FCL distance queries
  long long contact_pairs = 0;          // (sole, object) pairs looked at
  long long contact_pairs_bounded = 0;  // of those, rejected by the cheap bound (no FCL)
  Diagnosis divergence;                 // the divergence watch's diagnostic (kind none: none)
  SelfCollisionSummary self_collision;  // the self_collision effect (on: false when off)
  FallSummary fall;                     // the fall watch and the robot's fall (sim_host/fall.h)
  GuardSummary guard;                   // the controller's self-collision guard (guard_watch.h)
  uint64_t images_recorded = 0;         // --record-images: frames written whole
  double images_waited = 0;             // [s] the loop's wait for the image writer
  std::string images_error;             // why the recorded images are incomplete ("": complete)
};

const char* IntegratorName(int integrator);

// Simulated time over the wall time spent simulating: the run's wall time less its waits for a
// controller (`wall_waiting`); 0 when nothing ran. `now` is the wall time the figure is for.
double RealTimeFactor(double sim_time, const RunStats& st, double now);

// A sole seen from the F/T sensor above it: the rectangle of the sole box's bottom face in the
// sensor's frame, at the model's reference configuration (the sole is fixed to the foot, so
// this is constant when the sensor sits on the sole's body). The scenario check `cop_inside`
// (tools/runner) judges the centre of pressure against it.
struct SoleRectangle {
  std::string sensor;           // F/T sensor (site) name, e.g. "lfsensor"
  std::string sole;             // sole geom name, e.g. "LLEG_SOLE"
  double x[2] = {0, 0};         // [m] min, max of the bottom face's corners along the sensor's x
  double y[2] = {0, 0};         // [m] the same along y
  double z = 0;                 // [m] height of the bottom face's centre along the sensor's z
  double foot_mass = 0;         // [kg] mass below the sensor (the subtree of the sensor's body)
  double foot_com[3] = {0, 0, 0};  // [m] its centre of mass in the sensor frame
};

// Every sole of `m` with an F/T sensor above it (model::FindSoles), in geom order.
std::vector<SoleRectangle> SoleRectangles(const mjModel* m, const model::RobotMap& robot);

// One line: outcome, simulated and wall time, real-time factor, counts.
void PrintReport(const RunStats& st);

// The end of the data log (sim_host/log_report.cc): closes it (everything written and synced)
// and puts what reached the disk into `st` (log_*). A failed write is an event
// "log_write_failed" (at the time and cycle of the first row not on disk; value: the rows on
// disk), the run's outcome "log_failed" and *exit_code kExitOutputFailed unless the run had
// already failed otherwise; the size bound reached is an event "log_limit_reached" (value: the
// rows not written). Either is also said on stderr, --quiet or not.
void EndLog(datalog::Recorder* log, RunStats* st, int* exit_code);

// The summary written at the start (--summary checked writable before anything runs): outcome
// "running", replaced at the end; a reader of a run killed on the way sees that.
std::string ProvisionalSummary(const HostOptions& o);

// The JSON summary (outcome, timing, counts, the events with their simulated times and cycles,
// "events": [{"time", "cycle", "event", "value"}], the robot's mass and the mass below each force
// sensor, which the sensor does not carry, and the soles' rectangles in their sensors' frames,
// "soles": {sensor: {"sole", "x": [min, max], "y": [min, max], "z", "foot_mass",
// "foot_com": [x, y, z]}}).
// The fall watch (sim_host/fall.h): "fall_watch": {"on", "text", "start_height", "min_height",
// "max_tilt_deg", "on_fall", "allow_contact"}, and "fall": null, or the first fall {"time",
// "cycle", "kind" (contact | height | tilt), "cause", "body", "geom", "ground", "depth",
// "height", "tilt_deg"}; the event "fall" carries the same "cause".
// `effects` (may be null) adds each effect, on or off, and why. With the self_collision effect
// on, "self_collision": {"source", "links", "pairs_checked", "excluded", "checks",
// "cycles_in_contact", "check_mean_s", "check_max_s", "pairs": [{"pair", "first_time",
// "first_cycle", "deepest" [m], "deepest_time", "cycles"}], "closest_mm" (the smallest signed
// distance of any checked pair over the run [mm], negative when penetrating; a lower bound when
// "closest_exact" is false: no pair came within SelfCollisionWatch::kClosestRange),
// "closest_pair", "closest_t" [s], "closest_cycle"}.
// The controller's self-collision guard (sim_host/guard_watch.h), always: "self_collision_guard":
// {"hold_episodes", "held_cycles", "controller_holds", "holding_at_end", "first" and "closest"
// (null, or {"pair", "distance_mm", "time", "cycle"}), "holds": [{"begin", "begin_cycle",
// "end" (-1: held to the end), "end_cycle", "pair", "distance_mm", "closest_mm", "cycles"}]}.
// False (and said on stderr, with the reason) when the file could not be written whole.
bool WriteSummary(const std::string& path, const HostOptions& o, const model::RobotMap& robot,
                  const mjModel* m, const RunStats& st, int exit_code,
                  const EffectsPlan* effects = nullptr);

}  // namespace ohrp::sim
