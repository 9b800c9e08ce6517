// Scenario files: one headless scripted run (scene, controllers, duration, pass criteria).
// The format is documented with an example in docs/scenarios.md; scenarios/ holds the shipped
// ones. Paths inside a scenario are relative to the repository root (or absolute).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace ohrp::runner {

struct ControllerSpec {
  std::string program;            // a program in build/bin (e.g. posture) or a path
  std::vector<std::string> args;  // extra arguments; --segment and --attach-timeout are added;
                                  // `{out}` becomes the output folder (runner/commands.h)
  int line = 0;                   // where the scenario file gives it (0: not from a file)
};

// One pass criterion, evaluated on the data log after the run (see checks.h for the types and
// check_keys.h for the keys each one takes).
struct CheckSpec {
  std::string type;
  std::map<std::string, std::string> params;  // the check's own keys (numbers as "%.17g", lists
                                              // joined with ',', booleans true/false)
  double Number(const std::string& key, double fallback) const;
  // the key's value, or its default in the table of check keys (check_keys.h; NaN: none)
  double Number(const std::string& key) const;
  bool Has(const std::string& key) const { return params.count(key) > 0; }
  int line = 0;  // where the scenario file gives it (0: not from a file)
};

// An external push on the robot's base (scenario key `pushes`), applied by sim_host --push
// at the base's centre of mass, world frame. Either a horizontal direction and an impulse
// (force = impulse / duration along the direction) or an explicit force.
struct PushSpec {
  double at = 0;              // [s] simulated start
  double duration = 0.1;      // [s]
  double direction_deg = 0;   // [deg] horizontal, 0 = +x (forward), 90 = +y (left)
  double impulse = 0;         // [N s]
  bool explicit_force = false;
  double force[3] = {0, 0, 0};  // [N] world frame, when explicit_force
  // the force it applies [N], world frame
  void Force(double f_W[3]) const;
};

// sim_host's --push value for a push: "t0,t1,fx,fy,fz,0,0,0".
std::string PushArgument(const PushSpec& push);

struct Scenario {
  std::string name;
  std::string description;
  std::string file;              // where it was read from
  std::string scene;             // MJCF path
  int scene_line = 0;            // where the file gives it (0: not from a file)
  std::string keyframe;
  double duration = 10;          // [s] simulated
  double physics_dt = 0;         // [s], 0: the scene's
  double control_period = 0;     // [s], 0: sim_host's default (the multiple of the step nearest 5 ms)
  double camera_rate = 0;        // [frames per simulated s] of the cameras asked for; 0: sim_host's (30)
  std::string integrator;        // empty: the scene's
  bool realtime = false;
  std::string on_controller_loss = "end";
  double controller_timeout = 1.0;  // [s]
  double wall_timeout = 0;       // [s] wall time before the run is stopped; 0: derived
  int log_every = 1;
  std::string contact;           // soft | native | rigid | auto; empty: sim_host's default (auto)
  std::map<std::string, double> contact_params;  // soft-foot parameters, e.g. stiffness
  // per joint: armature, damping, frictionloss (written to the run folder for sim_host's
  // --joint-file: robot_model/joint_params.h)
  std::map<std::string, std::map<std::string, double>> joint_params;
  // the values of the keys of sim_host's option table (cli/host_options.h) that have no field
  // here, as sim_host's option takes them (e.g. effects: "gravity=off,noise=on" in the file's
  // order); SimHostCommand passes them on
  std::map<std::string, std::string> host_options;
  std::vector<std::string> sim_args;  // extra sim_host arguments (`{out}` as in controllers)
  std::vector<PushSpec> pushes;       // RunScenario passes each as sim_host --push
  std::vector<ControllerSpec> controllers;
  std::vector<CheckSpec> checks;
  std::vector<std::string> plot_joints;  // joints drawn in the plot (default: a few legs)
  std::vector<std::string> plot_torques; // joints whose torque gets a panel of the plot
  // falls (sim_host/fall.h): every run fails on a fall unless it expects one, and then it fails
  // without one
  bool expect_fall = false;
  std::string on_fall = "end";           // sim_host --on-fall: end | continue
  std::vector<std::string> fall_allow_contact;  // sim_host --fall-allow-contact: bodies
  std::map<std::string, int> lines;      // top-level key -> its line in the file
};

// Reads and validates a scenario: unknown or repeated keys at every level, values of the wrong
// type or out of range (the keys that are sim_host options against their type and range in the
// one table of them, cli/host_options.h; control_period a whole multiple of physics_dt,
// duration at least one control period, effects as sim_host's parser takes them), placeholders other than `{out}` in controller args and sim_args, unknown check types
// and check keys, check times outside the run, a missing `checks`
// (or an empty list) and a missing `controllers` (write `controllers: []` to run without one)
// are refused. Returns false with `*error` naming the file, the line, the key and what would do.
// Whether the scene and the controller programs exist is checked by RunScenario (runner.h),
// which knows the repository and the programs' folder.
bool LoadScenario(const std::string& path, Scenario* out, std::string* error);

// The same checks on scenario text already in memory; `path` names it in messages and gives
// the default name (the fuzzer and tests use it; no file is read).
bool ParseScenario(const std::string& text, const std::string& path, Scenario* out,
                   std::string* error);

}  // namespace ohrp::runner
