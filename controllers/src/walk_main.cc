// walk: attach to a robot segment, stand up, walk the commands given, stop on both feet. See
// controllers/walk.h.

#include <csignal>
#include <filesystem>
#include <iostream>

#include "cli/command_line.h"
#include "controllers/cli.h"
#include "controllers/posture.h"
#include "controllers/runner.h"
#include "controllers/walk.h"
#include "robot_model/model.h"

namespace {
[[noreturn]] void OnMujocoFatal(const char*) { std::_Exit(ohrp::controllers::kExitConfig); }
void OnUsr1(int) { ohrp::controllers::WalkController::RequestWalkStop(); }
}  // namespace

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  WalkOptions o;
  RunOptions run;
  run.program = "walk";
  BalanceOptions& b = o.balance;

  CLI::App app{
      "walk: attach to a robot segment (sim_host or hw_driver), stand up as balance does, then\n"
      "walk the commands given and stop on both feet. The walking pattern generator (preview\n"
      "control of the cart-table model, Kajita 2003) turns footsteps into the CoM, ZMP and feet;\n"
      "the stabilizer keeps the measured ZMP on the desired one (ankle force/torque sensors,\n"
      "IMU, leg kinematics; never the simulator's truth); legs and base by inverse kinematics on\n"
      "the robot's own model (--model, checked against the producer's robot).",
      "walk"};
  std::vector<std::string> commands;
  app.add_option("--command,-c", commands, "a walk command (repeatable; see below)")->take_all();
  app.add_option("--params", o.params_file,
                 "YAML file of gait, preview and step-limit parameters (docs/walking.md)")
      ->check(CLI::ExistingFile);
  app.add_option("--terrain", o.terrain,
                 "MJCF scene whose static geometry the steps are put on (height and tilt under "
                 "each sole); default: flat ground")
      ->check(CLI::ExistingFile);
  app.add_option("--keyframe", o.keyframe,
                 "the --terrain scene's keyframe the robot starts from (default: its initial state)");
  app.add_option("--log", o.log_file, "CSV log of the walk (plan frame), written at the end");
  app.add_option("--log-seconds", o.log_seconds, "[s] of walk log kept at most")
      ->default_val(o.log_seconds)->check(ohrp::cli::Plausible("duration"));
  app.add_option("--model", b.model, "MJCF, OpenHRP VRML .wrl or robot profile .yaml of the robot (must match the producer's robot)")
      ->default_val(DefaultModelFile())
      ->check(CLI::ExistingFile);
  auto* pose_option = app.add_option("--pose", b.pose_file, "stance pose, YAML by joint name [rad]")
      ->default_val(DefaultPoseFile())
      ->check(CLI::ExistingFile);
  app.add_option("--stance-keyframe", b.keyframe,
                 "take the stance pose from this keyframe of --model instead of a pose file "
                 "(balance's --keyframe; walk's --keyframe is the --terrain scene's start)")
      ->excludes(pose_option);
  app.add_option("--ramp", b.ramp, "[s] ramp from the measured pose to the stance pose")
      ->default_val(b.ramp)->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--step-time", o.gait.step_time, "[s] one step (double + single support)")
      ->default_val(o.gait.step_time)->check(ohrp::cli::Plausible("step_time"));
  app.add_option("--step-height", o.gait.step_height, "[m] swing foot apex")
      ->default_val(o.gait.step_height)->check(ohrp::cli::Plausible("swing_apex"));
  app.add_option("--double-support", o.gait.double_support_ratio, "share of a step on both feet")
      ->default_val(o.gait.double_support_ratio)->check(ohrp::cli::Plausible("fraction"));
  app.add_option("--max-stride", o.limits.max_forward, "[m] longest step forward")
      ->default_val(o.limits.max_forward)->check(ohrp::cli::Plausible("stride"));
  app.add_option("--com-lower", o.com_lower, "[m] walk with the CoM this much below the stance's")
      ->default_val(o.com_lower)->check(ohrp::cli::Plausible("height"));
  AddLoadFeedforwardFlags(&app, &b.load_feedforward);
  app.add_option("--servo-hz", b.servo_frequency,
                 "[Hz] closing frequency of the joints' servo (the producer suggests 6 Hz); 0: the "
                 "robot profile's servo.frequency, else the suggested gains")
      ->default_val(b.servo_frequency)
      ->check(ohrp::cli::InRange(0.0, 50.0));
  app.add_option("--k-dcm", b.gains.k_dcm, "[1/s] convergence rate of the capture point")
      ->default_val(b.gains.k_dcm)->check(ohrp::cli::Plausible("rate"));
  app.add_flag("--listen", o.listen,
               "take live walk commands on stdin, one a line: a --command (goal, velocity, steps, "
               "random; 'velocity VX VY WZ_DEG' without a duration walks until the next command; "
               "'goal_now X Y YAW_DEG' a goal from the feet as they are now, at most 5 m) or "
               "'stop'; each replaces what is planned after the step under way; replies on stderr "
               "(docs/walking.md)");
  app.add_option("--socket", o.socket,
                 "take the same live commands on a local stream socket at this path (one client at "
                 "a time; one reply line per command: 'ok: ...' or 'error: ...')");
  app.add_option("--live-record", o.live_record,
                 "with --socket / --listen: write each live command as the cycle took it, 'T LINE' "
                 "a line (T the cycle's time [s]; a goal_now as its goal_at in the plan frame), "
                 "when the walk ends (for --live-replay); with --live-replay: each replayed line "
                 "at the cycle that took it");
  app.add_option("--live-replay", o.live_replay,
                 "play a --live-record's commands back, each at the cycle it was taken (a "
                 "hand-driven run as a scenario; the cycle plans them itself: for lock-step runs)")
      ->check(CLI::ExistingFile);
  bool stepping = false;
  app.add_flag("--stepping", stepping,
               "experimental: move a swing foot's landing where the measured capture point needs "
               "it, and land sooner when that place is out of reach (a stepping strategy against "
               "pushes; better in some cells of the push table, worse in others: docs/walking.md)");
  bool no_timing = false, rebase = false, deadband = false;
  app.add_flag("--stepping-no-timing", no_timing,
               "with --stepping: move the landing only, never land sooner");
  app.add_flag("--stepping-deadband", deadband,
               "with --stepping: move the landing only by what the DCM needs beyond what the "
               "landed sole's ankle takes back (its half size less the stabilizer's margin)");
  app.add_flag("--stepping-rebase", rebase,
               "with --stepping: re-base the plan's CoM on the measured state at each adjustment");
  app.add_option("--stepping-time-cost", o.stepping_time_cost,
                 "with --stepping: a shorter swing's cost [m/s] against the distance its landing "
                 "falls short of the DCM's need")->capture_default_str();
  app.add_option("--stepping-reach", o.stepping_reach,
                 "with --stepping: share of the leg's reach (from the hip at the walking height) "
                 "a recovery step may use beyond the planner's step limits")->capture_default_str();
  app.add_option("--stepping-gain", o.stepping_gain,
                 "with --stepping: share of the DCM's landing change applied")->capture_default_str();
  bool touchdown = false;
  app.add_flag("--touchdown", touchdown,
               "experimental: hold a swing foot where it meets the ground before its planned "
               "landing (its force/torque sensor, in the last swing height of its descent) instead "
               "of pushing it on down to where the plan expects the ground; one that has not met "
               "it at its planned landing goes on down within the leg's reach, the landing held "
               "(docs/walking.md)");
  AddRunOptions(&app, &run);
  app.footer(std::string(WalkCommandHelp()) + "\n" + ExitCodeHelp());
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;
  o.stepping = stepping;
  o.stepping_timing = !no_timing;
  o.stepping_rebase = rebase;
  o.stepping_deadband = deadband;
  o.touchdown = touchdown;
  for (const std::string& text : commands) {
    WalkCommand c;
    std::string error;
    if (!ParseWalkCommand(text, &c, &error)) {
      std::cerr << "walk: --command " << error << "\n";
      return kExitUsage;
    }
    if (c.kind == WalkCommand::Kind::kSteps && !std::filesystem::exists(c.file)) {
      std::cerr << "walk: --command \"" << text << "\": no footstep file " << c.file << "\n";
      return kExitUsage;
    }
    o.commands.push_back(c);
  }

  // what the command line set: kept over the profile's walking: and a --params file, and not
  // derived from the robot
  for (const auto& [flag, key] : {std::pair<const char*, const char*>{"--max-stride", "max_forward"},
                                  {"--step-height", "step_height"}, {"--step-time", "step_time"},
                                  {"--double-support", "double_support_ratio"},
                                  {"--com-lower", "com_lower"}})
    if (app.count(flag) > 0) o.given.push_back(key);
  ohrp::model::InstallMujocoHandlers(OnMujocoFatal);
  ConfigStatus status;
  auto controller = WalkController::Create(o, &status);
  if (!controller) {
    std::cerr << "walk: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  // what planning changed of the commands (a capped speed...): said once now, and in the report
  for (const std::string& note : controller->notes()) std::cerr << "walk: note: " << note << "\n";
  InstallStopSignalHandlers();
  std::signal(SIGUSR1, OnUsr1);
  return RunController(*controller, run, std::cout, std::cerr);
}
