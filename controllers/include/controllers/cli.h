// The command-line options every controller program shares (segment, attach and read
// timeouts, the exit codes in the help), so that each main adds only its own. Header-only:
// CLI11 is a header library and the controllers library itself does not depend on it.
#pragma once

#include "cli/command_line.h"
#include "controllers/runner.h"

namespace ohrp::controllers {

// Adds --segment, --attach-timeout and --read-timeout (into `run`) and the exit-code footer.
inline void AddRunOptions(CLI::App* app, RunOptions* run) {
  app->add_option("--segment", run->segment, "robot segment name, as given to the producer")
      ->required();
  app->add_option("--attach-timeout", run->attach_timeout,
                  "[s] wait this long for the segment to appear (0 = fail at once)")
      ->default_val(0.0)->check(cli::InRange(0.0, 3600.0));
  app->add_option("--read-timeout", run->read_timeout,
                  "[s] longest wait for one sensor block before giving up")
      ->default_val(2.0)->check(cli::Plausible("timeout"));
  run->self_collision = DefaultSelfCollisionFile();
  run->self_collision_is_default = true;
  app->add_option_function<std::string>(
         "--self-collision",
         [run](const std::string& path) {
           run->self_collision = path;
           run->self_collision_is_default = false;
         },
         "self-collision file (ohrp_selfcollision, with the joints' dynamics): a command whose "
         "motion, with a brake after it, could bring a pair of links closer than its margin is "
         "replaced by that brake, then a hold (default: HRP-1S's file; for another robot: no "
         "check, said on stderr; a file for this robot's name but another model: exit 3)")
      ->check(CLI::ExistingFile);
  app->add_flag_callback(
      "--no-self-collision", [run] { run->self_collision.clear(); },
      "turn the online self-collision check off");
  app->add_flag_callback(
      "--no-fall-watch", [run] { run->fall_watch = false; },
      "do not end the run when the robot falls (exit 8): for experiments that expect a fall");
  app->add_option("--rt-priority", run->rt_priority,
                  "SCHED_FIFO priority of the cycle loop, with memory locked, where the system "
                  "permits (root, CAP_SYS_NICE or ulimit -r; refused: said, and the loop runs "
                  "without); 0: the normal scheduler. For the hardware chain (hw_driver/README.md): "
                  "below the driver's 80, e.g. 70")
      ->default_val(0)->check(cli::Plausible("priority"));
  app->footer(ExitCodeHelp());
}

// Adds --load-feedforward and --no-load-feedforward (balance and walk: BalanceOptions::
// load_feedforward, 1 and 0; neither leaves the robot profile's choice, -1).
inline void AddLoadFeedforwardFlags(CLI::App* app, int* load_feedforward) {
  auto* on = app->add_flag_callback(
      "--load-feedforward", [load_feedforward] { *load_feedforward = 1; },
      "send the joints a feed-forward torque for the robot's weight (gravity at the measured "
      "posture, the weight on the soles in the stabilizer's shares), so that a servo soft against "
      "the weight does not sag under it (G1: docs/robots.md); default: the robot profile's "
      "servo.load_feedforward, else off");
  app->add_flag_callback(
         "--no-load-feedforward", [load_feedforward] { *load_feedforward = 0; },
         "no such feed-forward, whatever the robot profile says")
      ->excludes(on);
}

// The command line is parsed as every program's is (cli/command_line.h): help 0, usage error 2.
using cli::ParseCommandLine;

}  // namespace ohrp::controllers
