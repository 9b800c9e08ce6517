// The runner: the stop signals, the exit codes, and a run as its stages in order
// (controller_run.h).
#include "controllers/runner.h"

#include <csignal>

#include "cli/data_dir.h"
#include "controller_run.h"

namespace ohrp::controllers {
namespace {

volatile std::sig_atomic_t g_stop = 0;

void OnStopSignal(int) { g_stop = 1; }

}  // namespace

const char* ExitCodeHelp() {
  return "Exit codes:\n"
         "  0  the producer (sim_host / hw_driver) ended its run normally, or SIGINT/SIGTERM\n"
         "  2  bad command line (an unknown option, a bad value, a file that does not exist)\n"
         "  3  a file is malformed or does not fit the robot (joint names/count, limits)\n"
         "  4  could not attach to the segment (not there within --attach-timeout, built\n"
         "     against another layout, another controller attached, ...)\n"
         "  5  the producer's process is gone, or sent no sensors within --read-timeout, or\n"
         "     the segment was corrupted under the run (truncated, overwritten)\n"
         "  6  the producer ended reporting a failure (e.g. the simulation diverged)\n"
         "  7  the producer dropped this controller: it did not answer within the producer's\n"
         "     timeout (e.g. it was stopped, then resumed)\n"
         "  8  the robot fell: its base tilted beyond the limit, its feet stopped carrying its\n"
         "     weight, or its CoM sank below half its stance height (the message says when and\n"
         "     why; the limits come from the robot; --no-fall-watch turns this off)\n"
         "  9  the controller could not do what it was asked, by its own measurements (e.g.\n"
         "     walk: a step that did not land; balance: leg IK failing persistently)\n";
}

std::string DefaultSelfCollisionFile() { return cli::DataPath("mjcf/hrp1s/selfcollision.yaml"); }

void InstallStopSignalHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: blocking waits return with EINTR
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void RequestStop() noexcept { g_stop = 1; }
void ClearStopRequest() noexcept { g_stop = 0; }

bool StopRequested() noexcept { return g_stop != 0; }

int RunController(Controller& controller, const RunOptions& options, std::ostream& out,
                  std::ostream& err, RunReport* report) {
  ControllerRun run(controller, options, out, err, report);
  if (!run.Attach() || !run.Configure()) return run.exit_code();
  run.Loop();
  run.End();
  return run.exit_code();
}

}  // namespace ohrp::controllers
