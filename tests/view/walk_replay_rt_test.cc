// A walk driven by hand in REAL TIME (sim_host --realtime, walk taking live commands on its
// socket with --live-record) and its lock-step re-run with walk --live-replay: what is the same
// is the commands and the cycles that took them (the re-run's --live-record, each replayed line
// at the cycle that took it, is the hand run's record byte for byte); the logs are not (the
// real-time run's physics went on at late cycles with the previous command, a lock-step run
// has none late), so they are not compared.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <sstream>
#include <thread>

#include "common/scratch.h"
#include "view/control.h"
#include "view_process.h"
#include "walk_run.h"

namespace ohrp::view::testing {
namespace {

// the record's lines: (T, the command's first word)
std::vector<std::pair<double, std::string>> Lines(const std::string& rec) {
  std::vector<std::pair<double, std::string>> out;
  std::istringstream lines(rec);
  for (std::string l; std::getline(lines, l);) {
    std::istringstream words(l);
    double t = -1;
    std::string word;
    words >> t >> word;
    out.emplace_back(t, word);
  }
  return out;
}

TEST(WalkReplayRealTime, TheReplayTakesTheCommandsAtTheSameCycles) {
  const fs::path dir = ohrp::testing::ScratchFolder("walk_replay_rt");
  fs::create_directories(dir);
  const std::string walk_sock = (dir / "walk.sock").string();
  const std::string record = (dir / "hand_live.txt").string(), replayed = (dir / "replay_live.txt").string();
  // by hand, in real time: forward as soon as walk answers, stop 2 s later (wall clock)
  RunWalk(dir, "hand", {12, {"--realtime"}, false, false}, {"--socket", walk_sock, "--live-record", record}, [&] {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    const std::string r = SendWhenUp(walk_sock, "velocity 0.2 0 0");
    EXPECT_EQ(r.rfind("ok: \"velocity 0.2 0 0", 0), 0u) << r;
    std::this_thread::sleep_for(std::chrono::seconds(2));
    EXPECT_EQ(SendWhenUp(walk_sock, "stop"), "ok: stop");
  });
  const std::string rec = ReadFile(record);
  std::printf("the real-time run's --live-record:\n%s", rec.c_str());
  const auto lines = Lines(rec);
  ASSERT_EQ(lines.size(), 2u) << rec;
  EXPECT_EQ(lines[0].second, "velocity");
  EXPECT_EQ(lines[1].second, "stop");
  // taken at cycles: multiples of the control period (5 ms), about 2 s apart (the wall clock)
  for (const auto& [t, word] : lines) EXPECT_NEAR(t / 0.005, std::round(t / 0.005), 1e-6) << rec;
  EXPECT_NEAR(lines[1].first - lines[0].first, 2.0, 0.5) << rec;
  EXPECT_LT(lines[1].first, 11.0) << "the stop came near the run's end: a slow start? " << rec;
  // the lock-step re-run: the record played back, and what it took recorded
  RunWalk(dir, "replay", {12, {}, false, false}, {"--live-replay", record, "--live-record", replayed}, nullptr);
  EXPECT_EQ(ReadFile(replayed), rec) << "the re-run took the commands at other cycles";
  const std::string out = ReadFile(dir / "replay_walk.txt");
  EXPECT_NE(out.find("(--live-replay: 2 recorded)"), std::string::npos) << out;
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace ohrp::view::testing
