// A test's walk run: sim_host and walk started and waited for, and lines to their local control
// sockets once the programs are up (walk_replay_test.cc, walk_replay_rt_test.cc).
#pragma once

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "view/control.h"
#include "view_process.h"

namespace ohrp::view::testing {

// `line` to the program listening on local socket `path`, retried while the socket is not up yet
// (10 s at most); the program's reply, or SendLine's error
inline std::string SendWhenUp(const std::string& path, const std::string& line) {
  std::string reply;
  for (int i = 0; i < 200; ++i) {
    if (SendLine(path, line, 60.0, &reply) || reply.rfind("cannot connect", 0) != 0) return reply;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return reply;
}

struct WalkRun {
  double seconds = 14;                 // sim_host's --duration [s]
  std::vector<std::string> sim_extra;  // sim_host's other options (--realtime, --control-socket)
  bool pause_first = false;            // pause sim_host (its control socket dir/sim.sock) before
                                       // walk attaches: its first cycle waits for the hand
  bool walk_must_succeed = true;       // walk's exit 0 expected (else only that it ran to the end)
};

// sim_host with `run` and walk with `walk_args` (logging to dir/NAME_walk.csv), `hand` run
// meanwhile; both waited for, sim_host's exit 0 expected
inline void RunWalk(const fs::path& dir, const std::string& name, const WalkRun& run,
                    const std::vector<std::string>& walk_args, const std::function<void()>& hand) {
  const std::string segment = shm::testing::UniqueSegment("vwr");
  shm::testing::RemoveSegment(segment);
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%g", run.seconds);
  std::vector<std::string> sim = {kScene, "--segment", segment, "--duration", seconds, "--progress", "0",
                                  "--wait-controller", "20", "--summary", (dir / (name + "_summary.json")).string()};
  sim.insert(sim.end(), run.sim_extra.begin(), run.sim_extra.end());
  const pid_t host = Start("sim_host", sim, (dir / (name + "_sim_host.txt")).string());
  if (run.pause_first) {
    const std::string paused = SendWhenUp((dir / "sim.sock").string(), "pause");
    EXPECT_EQ(paused.rfind("ok: pause: t=0.0000 s", 0), 0u) << paused;
  }
  std::vector<std::string> w = {"--segment", segment, "--attach-timeout", "20",
                                "--log", (dir / (name + "_walk.csv")).string()};
  w.insert(w.end(), walk_args.begin(), walk_args.end());
  const pid_t walk = Start("walk", w, (dir / (name + "_walk.txt")).string());
  if (hand) hand();
  int status = 0;
  EXPECT_EQ(waitpid(host, &status, 0), host);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << ReadFile(dir / (name + "_sim_host.txt"));
  EXPECT_EQ(waitpid(walk, &status, 0), walk);
  EXPECT_TRUE(WIFEXITED(status) && (!run.walk_must_succeed || WEXITSTATUS(status) == 0))
      << ReadFile(dir / (name + "_walk.txt"));
  shm::testing::RemoveSegment(segment);
}

}  // namespace ohrp::view::testing
