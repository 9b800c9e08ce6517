// excite: attach to a robot segment, drive chosen joints with a chirp, steps or a PRBS about the
// posture they have, the rest held, and log reference and measurement (controllers/excite.h).
#include <iostream>

#include "controllers/cli.h"
#include "controllers/excite.h"
#include "controllers/runner.h"
#include "robot_model/output_file.h"

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  ExciteOptions o;
  RunOptions run;
  run.program = "excite";
  CLI::App app{
      "excite: attach to a robot segment (sim_host or hw_driver) and drive the joints of --joints\n"
      "about the positions they have at activation with a documented signal, for the\n"
      "identification of joints and actuators; every other joint holds where it was (position\n"
      "mode, the producer's default gains). After --start s of hold, for --duration s:\n"
      "  chirp  a linear sweep f_min -> f_max, faded in and out over 0.5 s\n"
      "  steps  +amplitude and -amplitude in turn, each held 1/(2 f_min)\n"
      "  prbs   a 9-bit maximal-length sequence (511 bits) of +-amplitude, bits of 0.44/f_max\n"
      "The references stay --margin inside the joint limits and move at most --max-velocity;\n"
      "an excited joint measured outside its limits or beyond amplitude + --band from its start\n"
      "stops the excitation and fails the run (exit 9); a fall is exit 8. Then it holds until\n"
      "the producer stops.",
      "excite"};
  app.add_option("--joints", o.joints, "joints to excite, by name, e.g. LARM_SHOULDER_P,LARM_ELBOW")
      ->required()->delimiter(',');
  app.add_option("--signal", o.signal, "chirp, steps or prbs")->capture_default_str()
      ->check(CLI::IsMember({"chirp", "steps", "prbs"}));
  app.add_option("--amplitude", o.amplitude, "[rad] about the start position")->capture_default_str()
      ->check(ohrp::cli::InRange(1e-6, 1.0));
  app.add_option("--f-min", o.f_min, "[Hz] lowest frequency (chirp start, steps' rate)")
      ->capture_default_str()->check(ohrp::cli::InRange(1e-3, 50.0));
  app.add_option("--f-max", o.f_max, "[Hz] highest frequency (chirp end, prbs bandwidth)")
      ->capture_default_str()->check(ohrp::cli::InRange(1e-3, 50.0));
  app.add_option("--duration", o.duration, "[s] of signal")->capture_default_str()
      ->check(ohrp::cli::InRange(1e-3, 3600.0));
  app.add_option("--start", o.start, "[s] of hold after activation before the signal")
      ->capture_default_str()->check(ohrp::cli::InRange(0.0, 3600.0));
  app.add_option("--max-velocity", o.max_velocity, "[rad/s] bound on the references' rate")
      ->capture_default_str()->check(ohrp::cli::InRange(1e-3, 100.0));
  app.add_option("--margin", o.margin, "[rad] references kept this far inside the joint limits")
      ->capture_default_str()->check(ohrp::cli::InRange(0.0, 1.0));
  app.add_option("--band", o.band, "[rad] a joint measured farther than amplitude + band from its "
                 "start fails the run")->capture_default_str()->check(ohrp::cli::InRange(1e-6, 3.0));
  app.add_option("--seed", o.seed, "prbs: the register's start state, 1..511")->capture_default_str()
      ->check(ohrp::cli::InRange(1, 511));
  app.add_option("--kp-scale", o.kp_scale, "factor on the producer's default kp")
      ->capture_default_str()->check(ohrp::cli::Plausible("gain_scale"));
  app.add_option("--kd-scale", o.kd_scale, "factor on the producer's default kd")
      ->capture_default_str()->check(ohrp::cli::Plausible("gain_scale"));
  app.add_option("--log", o.log_file, "CSV: time, then per joint reference, q, dq, tau, per cycle "
                 "(written at the end)");
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;
  if (const std::string e = CheckExciteOptions(o); !e.empty()) {
    std::cerr << "excite: " << e << "\n";
    return kExitUsage;
  }
  // the log is written at the end: a path it cannot be written to is refused before attaching
  if (std::string error; !o.log_file.empty() &&
      !ohrp::model::PrepareOutputFile(o.log_file, "# excite: the run is under way\n", &error)) {
    std::cerr << "excite: --log: " << error << "\n";
    return kExitConfig;
  }
  ExciteController controller(o);
  InstallStopSignalHandlers();
  return RunController(controller, run, std::cout, std::cerr);
}
