// posture: attach to a robot segment, ramp to a pose, hold it. See controllers/posture.h.
#include <iostream>

#include "controllers/posture.h"
#include "controllers/cli.h"
#include "controllers/runner.h"

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  PostureOptions options;
  RunOptions run;
  run.program = "posture";

  CLI::App app{
      "posture: attach to a robot segment (sim_host or hw_driver), read the current joint\n"
      "positions, ramp smoothly (minimum jerk) to a pose over --ramp seconds of the producer's\n"
      "time, then hold it until the producer stops or SIGINT/SIGTERM. Position mode, gains =\n"
      "the producer's default gains times --kp-scale / --kd-scale.",
      "posture"};
  app.add_option("--pose", options.pose_file,
                 "YAML pose by joint name [rad] (joints not named: 0)")
      ->default_val(DefaultPoseFile())->check(CLI::ExistingFile);
  app.add_option("--ramp", options.ramp, "ramp duration [s of producer time], 0 = jump")
      ->default_val(2.0);
  app.add_option("--kp-scale", options.kp_scale, "factor on the producer's default kp")
      ->default_val(1.0);
  app.add_option("--kd-scale", options.kd_scale, "factor on the producer's default kd")
      ->default_val(1.0);
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;

  ConfigStatus status;
  auto controller = PostureController::Create(options, &status);
  if (!controller) {
    std::cerr << "posture: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
