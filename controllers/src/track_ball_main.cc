// track_ball: a vision example. See controllers/track_ball.h.
#include <iostream>

#include "controllers/cli.h"
#include "controllers/runner.h"
#include "controllers/track_ball.h"

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  TrackBallOptions options;
  RunOptions run;
  run.program = "track_ball";

  CLI::App app{
      "track_ball: a vision example. Attaches to a robot segment (sim_host, or hw_driver with\n"
      "the replay plugin), stands the robot as posture does, asks the producer for one camera's\n"
      "images, finds the red ball in each frame (red pixels, their centroid) and turns one yaw\n"
      "joint with a PI law on the ball's bearing to keep it in the middle of the image.",
      "track_ball"};
  app.add_option("--pose", options.posture.pose_file,
                 "YAML pose held by the other joints, by joint name [rad]")
      ->default_val(DefaultPoseFile())->check(CLI::ExistingFile);
  app.add_option("--ramp", options.posture.ramp,
                 "ramp to the pose [s of producer time]; the tracking starts after it")
      ->default_val(2.0)->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--camera", options.camera, "the camera (a name of the segment header)")
      ->capture_default_str();
  app.add_option("--joint", options.joint, "the yaw joint that turns the camera")
      ->capture_default_str();
  app.add_option("--kp", options.kp, "joint rate per radian of bearing [1/s]")
      ->capture_default_str()->check(ohrp::cli::Plausible("rate"));
  app.add_option("--ki", options.ki, "integral gain [1/s^2]")
      ->capture_default_str()->check(ohrp::cli::Plausible("rate2"));
  app.add_option("--max-rate", options.max_rate, "largest joint rate [rad/s]")
      ->capture_default_str()->check(ohrp::cli::Positive())
      ->check(ohrp::cli::Plausible("joint_speed"));
  app.add_option("--min-red", options.min_red, "a ball pixel's least red value [0, 255]")
      ->capture_default_str()->check(CLI::Range(0, 255));
  app.add_option("--red-ratio", options.red_ratio,
                 "a ball pixel's red exceeds this many times its green and its blue")
      ->capture_default_str()->check(ohrp::cli::InRange(1.0, 100.0));
  app.add_option("--min-pixels", options.min_pixels, "fewer red pixels: no ball in the frame")
      ->capture_default_str()->check(CLI::Range(1, 1 << 20));
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;

  ConfigStatus status;
  auto controller = TrackBallController::Create(options, &status);
  if (!controller) {
    std::cerr << "track_ball: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
