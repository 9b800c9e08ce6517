// stand_controller: an out-of-tree controller built against an installed ohrp. It attaches to a
// robot segment (sim_host or hw_driver), ramps from wherever the robot is to a standing pose
// (HRP-1S's half-sitting from the installed data by default) and holds it until the producer
// stops. The controller is the library's PostureController; the lifecycle, the cycle loop, the
// self-collision guard and the fall watch are the library's runner, as in the in-tree programs.
#include <iostream>

#include "controllers/cli.h"
#include "controllers/posture.h"
#include "controllers/runner.h"
#include "ohrp/version.h"

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  PostureOptions options;
  RunOptions run;
  run.program = "stand_controller";

  CLI::App app{"stand_controller: ramp to a standing pose and hold it (an out-of-tree example "
               "built on ohrp " OHRP_VERSION_STRING ")",
               "stand_controller"};
  app.add_option("--pose", options.pose_file, "YAML pose by joint name [rad]")
      ->default_val(std::string(STAND_DATA_DIR) + "/controllers/poses/hrp1s_halfsit.yaml")
      ->check(CLI::ExistingFile);
  app.add_option("--ramp", options.ramp, "ramp duration [s of producer time], 0 = jump")
      ->default_val(2.0)->check(ohrp::cli::Plausible("ramp_time"));
  AddRunOptions(&app, &run);
  // the installed self-collision file (the library's default looks beside the running program)
  run.self_collision = std::string(STAND_DATA_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;

  ConfigStatus status;
  std::unique_ptr<PostureController> controller = PostureController::Create(options, &status);
  if (!controller) {
    std::cerr << "stand_controller: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  std::cout << "stand_controller: ohrp " << ohrp::kVersion << ", segment layout "
            << OHRP_LAYOUT_VERSION << "\n";
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
