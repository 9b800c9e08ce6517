// ohrp_push: how hard a push a standing controller survives, and how fast it settles.
//
// Each trial is one headless run through the runner library (runner/runner.h): sim_host on
// the scene (scene_flat.xml by default) starting in the half-sitting keyframe, soft soles,
// 1 ms physics, 5 ms control, lock-step, and one controller command (e.g. `posture` or
// `balance`); at `push_at` a horizontal push of a given impulse over `push_duration` (force =
// impulse / duration, at the base's centre of mass) in a given direction (0 deg = +x forward,
// 90 deg = +y left); the run lasts until `observe` + `window` seconds after the push's end.
//
// "Still standing" (runner/recovery.h, StandingSpec): over the last `window` seconds of the
// run (from `observe` s after the push's end) the base stays above 80 % of its height just
// before the push, the base is tilted less than 30 deg, the ankle F/T sensors carry the
// robot's weight above them within 10 % (so the soles, not a knee or a hand, hold it up), and
// sim_host ended normally (no divergence).
//
// Largest impulse (bisection): per controller and direction, the impulse `max_impulse` is
// tried first (standing there: reported as ">= max"); then [lo, hi] = [0, max_impulse] is
// halved until hi - lo <= tolerance, keeping lo standing and hi fallen. The figure reported
// is lo, the largest impulse tried that the robot survived. It assumes survival is monotonic
// in the impulse (one threshold), which holds for a standing robot in practice but is not
// checked.
//
// Settling (settle mode): one trial per controller and direction with a fixed impulse; the
// base's and the ankle torques' settling times as defined in runner/recovery.h (SettleSpec:
// 1 cm, 10 % of the first peak).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace ohrp::push {

struct PushOptions {
  std::vector<std::string> controllers = {"posture"};  // commands: program [args...]
  std::vector<double> directions = {0, 45, 90, 135, 180, 225, 270, 315};  // [deg]
  std::string scene = "mjcf/hrp1s/scene_flat.xml";
  std::string keyframe = "halfsit";
  double push_at = 3.0;        // [s] simulated (the stance settles from the keyframe first)
  double push_duration = 0.1;  // [s]
  double observe = 3.0;        // [s] after the push's end, before the standing window
  double window = 0.5;         // [s] the standing window
  double max_impulse = 200;    // [N s] upper end of the bisection
  double tolerance = 2;        // [N s] bisection stops when hi - lo <= tolerance
  double settle_impulse = 0;   // [N s] > 0: settle mode instead of bisection
  double settle_tolerance = 0.01;  // [m]
  double settle_fraction = 0.1;
  double settle_within = 1.0;  // [s]
  int jobs = 0;                // parallel trials; 0: the number of cores
  std::string out_dir;         // output folder
  std::string source_dir;      // data folder, cli::DataDir() (scene paths)
  std::string bin_dir;         // sim_host and the controllers
  bool plot = true;
  // the soles' force/torque sensors, whose log columns NAME_fz say the feet carry the weight;
  // empty: FootSensorsOf the scene's robot
  std::vector<std::string> foot_sensors;
};

// The F/T sensors of the soles of the robot in `scene` (a path), left then right as the model
// lists its soles (robot_model/kinematics.h FindSoles). False with `*error` when the model does
// not load or no sole has a sensor.
bool FootSensorsOf(const std::string& scene, std::vector<std::string>* names, std::string* error);

// Checks the options. Returns false with `*error` saying what is wrong.
bool ValidateOptions(const PushOptions& o, std::string* error);

// What one trial measured.
struct Trial {
  std::string controller;
  double direction = 0;  // [deg]
  double impulse = 0;    // [N s]
  bool ok = false;       // the trial ran (sim_host and the controller did their part)
  bool standing = false;
  std::string detail;    // why not standing, or why the trial did not run
  double lowest_height = 0, stance_height = 0, largest_tilt = 0;  // [m], [m], [deg]
  double base_time = 0, torque_time = 0, first_peak = 0;         // settle mode: [s], [s], [N m]
  double base_excursion = 0;  // settle mode: largest horizontal distance to the stance [m]
  bool settled = false;
  std::string dir;       // its run folder
};

// Runs one trial (blocking). `index` makes its segment and folder unique.
Trial RunTrial(const PushOptions& o, const std::string& controller, double direction,
               double impulse, int index);

// The result for one controller and direction.
struct Limit {
  std::string controller;
  double direction = 0;    // [deg]
  double largest = 0;      // [N s] the largest impulse survived (lo)
  double smallest_fall = 0;  // [N s] hi
  bool above_max = false;  // survived max_impulse
  bool failed = false;     // a trial did not run; see detail
  std::string detail;
  int trials = 0;
  Trial settle;            // settle mode: its one trial
};

// The bisection alone, on any trial: `trial(impulse)` says whether the robot stood. Fills
// largest, smallest_fall, above_max, failed and trials of the result (see the file comment).
enum class Outcome { kStanding, kFell, kFailed };
Limit BisectLargest(double max_impulse, double tolerance, const std::function<Outcome(double)>& trial);

// Runs every controller x direction (bisection or settle mode) with up to `jobs` trials at once,
// printing progress to stderr. Returns the results in controller-major order.
std::vector<Limit> RunAll(const PushOptions& o);

// Writes table.md, push.csv, push.json (and push.png) into o.out_dir and returns the markdown
// table. Returns false with `*error` when a file cannot be written.
bool WriteReport(const PushOptions& o, const std::vector<Limit>& results, std::string* markdown,
                 std::string* error);

// With several push times (--phases): phases.md (also printed) and phases.csv in o.out_dir, every
// controller x time x direction; `results[t]` is RunAll's for times[t]. False with `*error` when
// a file cannot be written.
bool WritePhases(const PushOptions& o, const std::vector<double>& times,
                 const std::vector<std::vector<Limit>>& results, std::string* error);
}  // namespace ohrp::push
