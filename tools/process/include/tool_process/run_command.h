// Running another program from a tool without a shell (issue 28 item 5: no user string ever
// reaches `sh -c`): the program and each argument are one element of an argument vector, handed
// to execvp as they are, so a joint name such as "RLEG_KNEE;touch${IFS}pwned;echo" is one
// argument of the program and nothing else.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace ohrp::tool {

// Runs argv[0] (looked up in PATH when it has no '/') with `argv`, and waits for it: stdin from
// /dev/null, stdout and stderr appended to the file `output` (empty: the caller's). Returns its
// exit code, 128 + the signal that ended it, or -1 with `*error` when it could not be started
// (no such program, the output file cannot be opened, fork failed).
int RunCommand(const std::vector<std::string>& argv, const std::string& output, std::string* error);

// A program reading what the caller writes to its standard input (e.g. ffmpeg taking frames):
// stdout and stderr as in RunCommand.
class PipeTo {
 public:
  // Null with `*error` when it could not be started.
  static std::unique_ptr<PipeTo> Start(const std::vector<std::string>& argv,
                                       const std::string& output, std::string* error);
  ~PipeTo();
  PipeTo(const PipeTo&) = delete;
  PipeTo& operator=(const PipeTo&) = delete;

  FILE* file() const { return in_; }  // the program's standard input
  // Closes its input and waits for it: its exit code, or 128 + signal.
  int Close();

 private:
  PipeTo() = default;
  FILE* in_ = nullptr;
  int pid_ = -1;
};

}  // namespace ohrp::tool
