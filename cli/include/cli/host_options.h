// The one table of the sim_host options a scenario can set (issue 32, item 5). For each key: the
// scenario key, sim_host's option, the value's type and range, and the help. Three readers use it:
// - the runner reads and validates a scenario's keys with it (tools/runner/src/host_keys.cc: a
//   bad value is refused with the file, the line, the key and the range, exit 2);
// - the runner builds sim_host's command line from it (runner/commands.h, SimHostCommand);
// - sim_host registers these CLI11 options from it (AddTableOption below, sim_host's
//   command_line.cc), with the same name, range and help.
// Adding a key is one line here; sim_host binds the option to its field of HostOptions, and the
// runner passes the value on (a key with no field in runner::Scenario is kept as text in
// Scenario::host_options).
//
// Header-only on CLI11 (as command_line.h).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "cli/command_line.h"
#include "cli/plausible.h"

namespace ohrp::cli {

enum class OptionType {
  kNumber,   // a finite number in the plausible range of `range` (plausible.h), or in [lo, hi]
  kChoice,   // one of the words of `range` ("a|b|c")
  kFlag,     // true | false in a scenario; the bare option when true
  kText,     // a non-empty word (a keyframe's name)
  kList,     // a list of words in a scenario; comma-joined for the option
  kEffects,  // a mapping NAME: on|off|number in a scenario; "NAME=VALUE,..." (sim_host/effects.h)
  kPushes,   // a list of pushes in a scenario; one option "t0,t1,fx,fy,fz,tx,ty,tz" per push
};

struct HostOption {
  const char* key;       // the scenario key
  const char* option;    // sim_host's option
  OptionType type;
  const char* range;     // kNumber: a quantity of plausible.h ("" : [lo, hi]); kChoice: "a|b|c"
  double lo, hi;         // kNumber with range "": the bounds (inclusive)
  const char* unit;      // kNumber with range "": the unit, for messages
  bool host_zero;        // kNumber: sim_host also takes 0 (what 0 means is in the help)
  const char* left_out;  // a value the runner does not pass (sim_host's default; "": none)
  const char* help;      // sim_host's help of the option
};

// clang-format off
// The order is the order of the runner's arguments (after --scene, --segment, the log and the
// summary; runner/commands.h).
inline constexpr HostOption kHostOptions[] = {
  {"duration", "--duration", OptionType::kNumber, "duration", 0, 0, "", true, "",
   "simulated time to run [s]; 0 runs until Ctrl-C"},
  {"on_controller_loss", "--on-controller-loss", OptionType::kChoice, "end|wait|continue", 0, 0, "", false, "",
   "when the controller dies, hangs or detaches: end the run, wait for a new one, or continue "
   "holding (a hung controller is dropped: resumed, it exits 7)"},
  {"controller_timeout", "--controller-timeout", OptionType::kNumber, "timeout", 0, 0, "", false, "",
   "wall time a lock-step controller may take to answer a cycle [s]"},
  {"log_every", "--log-every", OptionType::kNumber, "cycles", 0, 0, "", false, "",
   "record one row every N control cycles"},
  {"control_period", "--control-period", OptionType::kNumber, "control_period", 0, 0, "", false, "0",
   "sensor/command cycle [s], a whole multiple of the physics step (default: the multiple "
   "nearest 5 ms, e.g. 4 ms on a 2 ms step)"},
  {"physics_dt", "--physics-dt", OptionType::kNumber, "physics_dt", 0, 0, "", false, "0",
   "physics step [s] (default: the scene's timestep)"},
  {"integrator", "--integrator", OptionType::kChoice, "euler|rk4|implicit", 0, 0, "", false, "",
   "euler | rk4 | implicit (default: the scene's)"},
  {"camera_rate", "--camera-rate", OptionType::kNumber, "", 0.1, 1000, "frames per simulated s", false, "0",
   "frames per second of simulated time of each camera an attached program asks for (rendered "
   "offscreen only while asked)"},
  {"keyframe", "--keyframe", OptionType::kText, "", 0, 0, "", false, "",
   "initial state: a keyframe of the scene (default: the model's pose)"},
  {"realtime", "--realtime", OptionType::kFlag, "", 0, 0, "", false, "false",
   "pace cycles to the wall clock instead of lock-step"},
  {"contact", "--contact", OptionType::kChoice, "soft|native|rigid|auto", 0, 0, "", false, "",
   "contact under the soles: soft (the paper's spring-damper on FCL), native (MuJoCo's), rigid "
   "(MuJoCo's, near-rigid), auto (soft when the model has *_SOLE geoms, else native)"},
  {"on_fall", "--on-fall", OptionType::kChoice, "end|continue", 0, 0, "", false, "end",
   "when the robot falls (a body other than the feet touches the ground, the base sinks below "
   "half its start height over the soles or tilts past 60 deg; docs/architecture.md): end the "
   "run at once, or continue simulating; either way the fall is an event of the summary and the "
   "exit code is 6"},
  {"fall_allow_contact", "--fall-allow-contact", OptionType::kList, "", 0, 0, "", false, "",
   "bodies of the robot (with the bodies below them) allowed to touch the ground without it "
   "being a fall, e.g. the hands: BODY,BODY"},
  {"pushes", "--push", OptionType::kPushes, "", 0, 0, "", false, "",
   "external push on the base: t0,t1,fx,fy,fz,tx,ty,tz (simulated s; world-frame N and N m at "
   "the base's centre of mass); may be given several times, overlapping pushes add"},
  {"effects", "--effects", OptionType::kEffects, "", 0, 0, "", false, "",
   "switch effects on or off: NAME=on|off, contact:BODY1/BODY2=on|off, noise.KIND=STD (q dq tau "
   "force torque gyro accel orientation, SI units), noise.seed=N; comma-separated, repeatable "
   "(e.g. gravity=off,noise=on). Effects: gravity joint_limits passive native_contact "
   "self_contact self_collision soft_contact encoders joint_velocities joint_torques "
   "force_torque gyro accelerometer orientation rne_post other_sensors noise cameras log "
   "log_base log_joints log_force_torque log_imu (docs/effects.md)"},
};
// clang-format on

// The entry of scenario key `key`, or nullptr.
inline const HostOption* FindHostOption(std::string_view key) {
  for (const HostOption& o : kHostOptions)
    if (key == o.key) return &o;
  return nullptr;
}

// The words of a kChoice entry's range.
inline std::vector<std::string> HostOptionChoices(const HostOption& o) {
  std::vector<std::string> words;
  std::string_view r = o.range;
  while (!r.empty()) {
    const size_t bar = r.find('|');
    words.emplace_back(r.substr(0, bar));
    r = bar == std::string_view::npos ? std::string_view() : r.substr(bar + 1);
  }
  return words;
}

// "" when `value` is a valid number for kNumber entry `o` (a scenario's value: 0 only where the
// range holds it); otherwise why not, with the range.
inline std::string CheckHostNumber(const HostOption& o, double value, const std::string& text) {
  if (o.range[0] != '\0') {
    const PlausibleRange* r = FindPlausible(o.range);
    if (r && IsPlausible(*r, value)) return std::string();
    return text + " is outside " + (r ? PlausibleRangeText(*r) : std::string("?"));
  }
  if (std::isfinite(value) && value >= o.lo && value <= o.hi) return std::string();
  return "must be in [" + detail::Short(o.lo) + ", " + detail::Short(o.hi) + "] " + o.unit +
         ", not " + text;
}

// Registers table entry `key` as a CLI11 option of `app` bound to `target`: the option's name,
// help and check from the table (a flag for kFlag; a comma delimiter for kList). A key not in
// the table is a programming error (the tests register every entry).
template <typename T>
CLI::Option* AddTableOption(CLI::App* app, std::string_view key, T* target) {
  const HostOption* o = FindHostOption(key);
  if (o == nullptr) throw std::logic_error("no sim_host option for key " + std::string(key));
  if constexpr (std::is_same_v<T, bool>) {
    return app->add_flag(o->option, *target, o->help);
  } else {
    CLI::Option* opt = app->add_option(o->option, *target, o->help);
    switch (o->type) {
      case OptionType::kNumber: {
        CLI::Validator v = o->range[0] ? Plausible(o->range) : InRange(o->lo, o->hi);
        opt->check(o->host_zero ? InRange(0, 0) | v : v);
        break;
      }
      case OptionType::kChoice: opt->check(CLI::IsMember(HostOptionChoices(*o))); break;
      case OptionType::kList: opt->delimiter(','); break;
      default: break;
    }
    // the default shown in the help, unless it is "nothing" (0 or empty)
    opt->capture_default_str();
    const std::string shown = opt->get_default_str();
    if (shown.empty() || shown == "0" || shown == "[]") opt->default_str("");
    return opt;
  }
}

}  // namespace ohrp::cli
