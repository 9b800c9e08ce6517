// A program run to its end from an argument vector, never through a shell (the log comparison's
// plot script, ohrp_identify's ohrp_compare_logs): file names and channel names are the user's.
#pragma once

#include <string>
#include <vector>

namespace ohrp::compare {

// Runs argv[0] (a path, or a name looked up in PATH) with argv[1..], its stdin /dev/null, its
// stdout and stderr into the file `output` (created or truncated), and waits for it. Returns its
// exit code, 128 + the signal that ended it, or -1 when it could not be started (the output
// file cannot be made, fork failed); a program that cannot be executed exits 127.
int RunProgram(const std::vector<std::string>& argv, const std::string& output);

}  // namespace ohrp::compare
