// playback: attach to a robot segment and play an OpenHRP joint trajectory. See
// controllers/playback.h.
#include <iostream>

#include "controllers/playback.h"
#include "controllers/cli.h"
#include "controllers/runner.h"

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  PlaybackOptions options;
  RunOptions run;
  run.program = "playback";

  CLI::App app{
      "playback: attach to a robot segment and play a joint trajectory like hrpsys's sequence\n"
      "player: ramp (minimum jerk) from the current pose to the first row over --ramp seconds,\n"
      "then play the rows against the producer's time (linear interpolation), then hold the\n"
      "last row until the producer stops or SIGINT/SIGTERM.\n"
      "Files are OpenHRP's format (SamplePD angle.dat, vel.dat, PDgain.dat): each row is the\n"
      "time [s] then one value per joint in joint-id order; the gain file has 'P D' per joint.\n"
      "Without --velocities, dq_ref is the slope between neighbouring rows. Without --gains,\n"
      "the producer's default gains are used.",
      "playback"};
  app.add_option("--angles", options.angles_file, "joint positions: time q0 q1 ... [s, rad]")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--velocities", options.velocities_file,
                 "joint velocities, same rows as --angles [rad/s]")
      ->check(CLI::ExistingFile);
  app.add_option("--gains", options.gains_file, "PD gains, one 'P D' row per joint")
      ->check(CLI::ExistingFile);
  app.add_option("--ramp", options.ramp,
                 "[s of producer time] ramp from the current pose to the first row")
      ->default_val(2.0)->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--time-scale", options.time_scale,
                 "trajectory seconds per producer second (2 = twice as fast)")
      ->default_val(1.0)->check(ohrp::cli::Plausible("speed_factor"));
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;

  ConfigStatus status;
  auto controller = PlaybackController::Create(options, &status);
  if (!controller) {
    std::cerr << "playback: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  std::cout << "playback: " << options.angles_file << ": " << controller->angles().rows()
            << " rows, " << controller->angles().njoint << " joints, "
            << controller->angles().duration() << " s\n";
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
