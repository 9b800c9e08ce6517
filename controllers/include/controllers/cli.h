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
      ->default_val(0.0)->check(cli::NonNegative());
  app->add_option("--read-timeout", run->read_timeout,
                  "[s] longest wait for one sensor block before giving up")
      ->default_val(2.0)->check(cli::Positive());
  app->footer(ExitCodeHelp());
}

// The command line is parsed as every program's is (cli/command_line.h): help 0, usage error 2.
using cli::ParseCommandLine;

}  // namespace ohrp::controllers
