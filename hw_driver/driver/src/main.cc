// hw_driver: the real-time robot driver (see hw_driver/driver/include/hw_driver/driver.h and
// hw_driver/README.md).

#include "cli/command_line.h"
#include "robot_model/output_file.h"
#include "hw_driver/program.h"

int main(int argc, char** argv) {
  ohrp::hw::ProgramOptions o;
  ohrp::hw::DriverOptions& d = o.driver;
  bool no_mlock = false;
  CLI::App app{
      "hw_driver: the robot's real-time driver. Reads the robot from its MJCF (or VRML) model, loads the\n"
      "boards' IO plugin, creates the segment NAME (producer kind hardware) and runs the servo\n"
      "cycle: read boards, publish sensors, wait for the controller's commands until the\n"
      "cycle's deadline, check and clamp them, write boards. Controllers attach exactly as to\n"
      "sim_host (e.g. 'posture --segment NAME'). SIGUSR1 prints the lateness histogram;\n"
      "SIGUSR2 is an emergency stop; SIGINT/SIGTERM stop cleanly (damped hold, servo-off).",
      "hw_driver"};
  app.add_option("--model", o.model, "MJCF model of the robot, OpenHRP VRML (.wrl), URDF or a robot profile (.yaml) (e.g. mjcf/hrp1s/hrp1s.xml)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--io", o.io_plugin, "IO plugin shared object (e.g. build/lib/libohrp_io_replay.so)")
      ->required();
  app.add_option("--io-arg", o.io_args, "KEY=VALUE handed to the plugin (repeat)");
  app.add_option("--segment", o.segment, "segment name the controller attaches to")
      ->capture_default_str();
  app.add_option("--period", d.period, "servo cycle = control cycle [s]")
      ->capture_default_str()->check(ohrp::cli::InRange(1e-4, 1.0));
  app.add_option("--command-margin", d.command_margin,
                 "part of the period left after the command wait for checks and the write")
      ->capture_default_str()->check(ohrp::cli::InRange(0.0, 0.9));
  app.add_option("--watchdog-cycles", d.watchdog_cycles,
                 "controller silent this many cycles after its first answer -> safe mode")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--board-timeout-cycles", d.board_timeout_cycles,
                 "a board silent this many cycles -> safe mode")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--safe-time", d.safe_time, "[s] damped hold in safe mode, then servo-off")
      ->capture_default_str()->check(ohrp::cli::NonNegative());
  app.add_option("--servo-off-time", d.servo_off_time,
                 "[s] damped hold before servo-off at a normal stop")
      ->capture_default_str()->check(ohrp::cli::NonNegative());
  app.add_option("--safe-kp-scale", d.safe_kp_scale,
                 "damped hold: kp = default kp * this (a hold: not 0; the gains must be ones the "
                 "servos accept)")
      ->capture_default_str()->check(ohrp::cli::Plausible("hold_gain_scale"));
  app.add_option("--safe-kd-scale", d.safe_kd_scale, "damped hold: kd = default kd * this")
      ->capture_default_str()->check(ohrp::cli::Plausible("gain_scale"));
  app.add_option("--tracking-time", d.tracking_time,
                 "[s] a position-mode joint may be further than tau_max / kp (at least 0.05 rad) "
                 "from its reference this long; longer: the board disobeys, safe mode (exit 8)")
      ->capture_default_str()->check(ohrp::cli::Plausible("timeout"));
  app.add_option("--reset-ramp-time", d.reset_ramp_time,
                 "[s] after a board reset, its joints ramp back from where they are to their "
                 "references in this time, the others holding theirs")
      ->capture_default_str()->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--fall-tilt", d.fall_tilt,
                 "[rad] the first IMU tilted this far from its pose at servo-on: a fall, safe mode "
                 "(exit 10); 0: no fall check")
      ->capture_default_str()->check(ohrp::cli::Plausible("tilt"));
  app.add_option("--servo-on-timeout", d.servo_on_timeout,
                 "[s] wait this long for the boards' first valid read")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--duration", d.duration, "[s] run this long, then stop; 0 runs until stopped")
      ->capture_default_str()->check(ohrp::cli::NonNegative());
  std::string loss = "end";
  app.add_option("--on-controller-loss", loss,
                 "when the controller dies, goes silent or detaches: safe mode, then end the run, "
                 "or turn the servos off and wait for a new controller (servo-on again when it "
                 "attaches)")
      ->capture_default_str()->check(CLI::IsMember({"end", "wait"}));
  app.add_option("--rt-priority", d.rt.priority, "SCHED_FIFO priority of the loop; 0: SCHED_OTHER")
      ->capture_default_str()->check(ohrp::cli::InRange(0, 99));
  app.add_flag("--no-mlock", no_mlock, "do not lock the process's memory");
  std::string wake = ohrp::hw::WakeModeName(d.wake.mode);
  app.add_option("--wake", wake,
                 "how each cycle waits for its start: spin-tail sleeps (clock_nanosleep) until a "
                 "margin before it, learned from the sleeps' lateness (bounded by 200 us and a "
                 "quarter of the period), then spins on the monotonic clock: within a few us, "
                 "at the CPU cost of the spin; sleep sleeps to the start itself: no spin, tens "
                 "of us late")
      ->capture_default_str()->check(CLI::IsMember({"spin-tail", "sleep"}));
  app.add_option("--log", o.log_path,
                 "CSV data log in sim_host's format (same column names, no ground-truth base_* "
                 "columns): time, q_/qref_/tau_<joint>, F/T, IMU, status, rejected, guard_holding; written by a "
                 "thread off the servo loop, flushed at the end (also after SIGINT/SIGTERM)");
  app.add_option("--log-every", d.log_every, "cycles between rows of --log")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_flag("--log-dq", o.log_dq, "--log also records each joint's velocity (dq_<joint>)");
  std::string log_time = "driver";
  app.add_option("--log-time", log_time,
                 "--log's time: driver (the servo cycle's) or board (the boards' timestamp of the "
                 "data, the robot's time; a cycle without new board data is not logged)")
      ->capture_default_str()->check(CLI::IsMember({"driver", "board"}));
  std::string log_max;
  app.add_option("--log-max", log_max,
                 "bound on --log's size: bytes, or with k, M, G (e.g. 50M); rows past it are not "
                 "written, and the report says how many");
  app.add_option("--summary", o.summary_path, "JSON summary written at the end");
  app.add_option("--stats", o.stats_path, "JSON stats file rewritten while running");
  app.add_option("--stats-interval", o.stats_interval, "[s] between rewrites of --stats")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_flag("--quiet,-q", o.quiet,
               "errors and warnings only: no report after a normal end or SIGINT/SIGTERM, and "
               "after a failure its outcome and events without the lateness table");
  app.footer(
      "Exit codes: 0 duration reached or replay ended, 2 bad option, model, plugin file or\n"
      "segment, 3 the boards failed (open, or no valid read), 5 controller lost (safe mode),\n"
      "6 board silent, NaN or implausible values (safe mode), 7 emergency stop, 8 a board\n"
      "disobeyed (servo state, acknowledgements, tracking, refused or foreign commands, a reset\n"
      "not re-armed, a refused safe-mode hold), 9 the data log or the summary could not be\n"
      "written completely (file and error named), 10 the robot fell (IMU tilt), 130 interrupted\n"
      "(SIGINT/SIGTERM). A board reset is held through: its joints re-armed and ramped back, the\n"
      "others holding; a lost controller with --on-controller-loss wait is recovered from:\n"
      "servo-off, then servo-on when a new one attaches; the run's end then decides the exit code.\n"
      "Details: hw_driver/README.md.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  if (std::string error; !log_max.empty() && !ohrp::model::ParseByteSize(log_max, &o.log_max, &error)) {
    std::fprintf(stderr, "hw_driver: --log-max: %s\n", error.c_str());
    return ohrp::hw::kExitUsage;
  }
  d.rt.lock_memory = !no_mlock;
  d.log_board_time = log_time == "board";
  ohrp::hw::ParseWakeMode(wake, &d.wake.mode);  // one of the choices above
  ohrp::shm::ParseControllerLoss(loss, &d.on_controller_loss);  // one of the choices above
  return ohrp::hw::RunProgram(o);
}
