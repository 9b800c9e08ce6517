// Files and folders a test writes, in one place: a folder of the test process's own, made
// unique by mkdtemp (never a name a previous run, or another process with a reused pid, left
// behind) and removed with everything in it when the process that made it exits, unless one of
// its tests failed: then it is kept for a look, and its path printed. A test that crashes
// leaves its folder too; the next run cannot collide with it.
#pragma once

#include <string>

namespace ohrp::testing {

// The test process's scratch folder, $TMPDIR/ohrp_test_<program>_XXXXXX, made at the first
// call. Removed at the exit of the process that made it when its tests passed (a forked child's
// exit leaves it).
// Throws std::runtime_error when it cannot be made.
const std::string& ScratchDir();

// A fresh path in the scratch folder: "<tag>_<n><suffix>" with n counting up in this process.
// Nothing is created.
std::string ScratchPath(const std::string& tag, const std::string& suffix = "");

// A fresh path in the scratch folder with `text` written to it.
std::string ScratchFile(const std::string& tag, const std::string& text,
                        const std::string& suffix = "");

// A fresh, empty folder in the scratch folder.
std::string ScratchFolder(const std::string& tag);

// A small disk that fills up: a tmpfs of `size` ("64k") mounted on a fresh scratch folder,
// unmounted when this goes. Mounting needs root: when it fails, dir() is "" and why() says why
// (the caller skips). For the "disk full" cases of the logs and outputs.
class ScratchTmpfs {
 public:
  explicit ScratchTmpfs(const std::string& size);
  ~ScratchTmpfs();
  ScratchTmpfs(const ScratchTmpfs&) = delete;
  ScratchTmpfs& operator=(const ScratchTmpfs&) = delete;
  const std::string& dir() const { return dir_; }
  const std::string& why() const { return why_; }

 private:
  std::string dir_, why_;
};

// The whole text of the file at `path` (a program's output, a log, a report); "" when it cannot
// be read.
std::string ReadFile(const std::string& path);

}  // namespace ohrp::testing
