// Programs of the viewer's tests as child processes: sim_host, posture and ohrp_view started
// with their arguments (output to files in the test's folder), the viewer's URL read from its
// first line, and the exit codes (common/process.h's WaitExit).
#pragma once

#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../shm_bridge/test_util.h"
#include "common/scratch.h"

namespace ohrp::view::testing {

namespace fs = std::filesystem;

inline const std::string kBin = OHRP_BIN_DIR;
inline const std::string kSource = OHRP_SOURCE_DIR;
inline const std::string kScene = kSource + "/mjcf/hrp1s/scene_flat.xml";

// Starts bin/`program` with `args`, its stdout and stderr into `out_file`.
inline pid_t Start(const std::string& program, const std::vector<std::string>& args,
                   const std::string& out_file) {
  std::vector<std::string> all{kBin + "/" + program};
  all.insert(all.end(), args.begin(), args.end());
  return ohrp::testing::Spawn(all, ohrp::testing::ToFile(out_file));
}

using ohrp::testing::ReadFile;

// A viewer started on `target`: its pid and the URL it printed ("" when it printed none within
// `timeout` [s], e.g. because it exited).
struct Viewer {
  pid_t pid = -1;
  std::string url, out_file;
  ~Viewer() { ohrp::testing::Terminate(pid, 5.0); }
};
inline void StartViewer(Viewer* v, const std::vector<std::string>& args, const std::string& out_file,
                        double timeout = 20.0) {
  v->out_file = out_file;
  v->pid = Start("ohrp_view", args, out_file);
  shm::testing::WaitFor([&] { return ReadFile(out_file).find("http://") != std::string::npos; }, timeout);
  const std::string out = ReadFile(out_file);
  const size_t at = out.find("http://");
  if (at != std::string::npos) v->url = out.substr(at, out.find(' ', at) - at);
}

// the test's output folder (screenshots): build/tests/view_output/<test name>
inline std::string OutputDir(const std::string& test) {
  const fs::path dir = fs::path(OHRP_VIEW_TEST_OUT) / test;
  fs::create_directories(dir);
  return dir.string();
}

// the robot's colours (HRP-1S's light greens, shaded) and not the floor, sky or plots
inline bool RobotGreen(int r, int g, int b) { return g > r + 25 && g > b + 25 && g > 90; }

}  // namespace ohrp::view::testing
