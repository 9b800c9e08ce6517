// A walk driven by hand (issue 33 item 1: "a run driven by hand replays exactly and can be
// re-run as a scenario"): lock-step sim_host paused from the start and stepped through its
// control channel, walk taking live commands on its socket (velocity, goal_now as the viewer's
// floor click sends it, stop) with --live-record; then the same run re-run with walk
// --live-replay of that record and no hand: the two walk logs are the same byte for byte (but
// for the last cycle's row, which walk reads or not as the producer ends).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "common/scratch.h"
#include "view/control.h"
#include "view_process.h"
#include "walk_run.h"

namespace ohrp::view::testing {
namespace {

TEST(WalkReplay, AHandDrivenWalkAndItsReplayWriteTheSameLog) {
  const fs::path dir = ohrp::testing::ScratchFolder("walk_replay");
  fs::create_directories(dir);
  const std::string sim_sock = (dir / "sim.sock").string(), walk_sock = (dir / "walk.sock").string();
  const std::string record = (dir / "walk_live.txt").string();
  // by hand: at 6 s walk forward, at 8 s a goal 0.3 m ahead and 0.2 m left turned 30 deg (from
  // the feet then), at 10 s stop; each command answered before the simulation goes on
  RunWalk(dir, "hand", {14, {"--control-socket", sim_sock}, true, true}, {"--socket", walk_sock, "--live-record", record}, [&] {
    const auto step_to = [&](const std::string& steps, const std::string& t) {
      const std::string r = SendWhenUp(sim_sock, "step " + steps);
      EXPECT_NE(r.find("t=" + t + " s"), std::string::npos) << r;
    };
    step_to("1200", "6.0000");
    std::string r = SendWhenUp(walk_sock, "velocity 0.2 0 0");
    EXPECT_EQ(r.rfind("ok: \"velocity 0.2 0 0 600\"", 0), 0u) << r;
    step_to("400", "8.0000");
    r = SendWhenUp(walk_sock, "goal_now 0.3 0.2 30");
    EXPECT_EQ(r.rfind("ok: \"goal_now 0.3 0.2 30\"", 0), 0u) << r;
    step_to("400", "10.0000");
    EXPECT_EQ(SendWhenUp(walk_sock, "stop"), "ok: stop");
    EXPECT_EQ(SendWhenUp(sim_sock, "resume").rfind("ok: resume", 0), 0u);
  });
  // the record: each command at the first cycle after it came (the cycle's time)
  const std::string rec = ReadFile(record);
  std::printf("walk --live-record:\n%s", rec.c_str());
  std::istringstream lines(rec);
  std::vector<std::string> texts;
  std::vector<double> times;
  for (std::string l; std::getline(lines, l);) {
    std::istringstream words(l);
    double t;
    std::string text;
    words >> t;
    std::getline(words >> std::ws, text);
    times.push_back(t);
    texts.push_back(text.substr(0, text.find(' ')));
  }
  EXPECT_EQ(texts, (std::vector<std::string>{"velocity", "goal_at", "stop"}));
  ASSERT_EQ(times.size(), 3u);
  // each at the cycle after it came: 2 s of simulation apart, as they were sent
  for (int i = 1; i < 3; ++i) EXPECT_NEAR(times[i] - times[i - 1], 2.0, 1e-6) << rec;
  // the re-run: no hand, the record played back
  RunWalk(dir, "replay", {14, {}, false, true}, {"--live-replay", record}, nullptr);
  const std::string hand = ReadFile(dir / "hand_walk.csv"), replay = ReadFile(dir / "replay_walk.csv");
  EXPECT_GT(std::count(hand.begin(), hand.end(), '\n'), 1000);
  // byte for byte, but for the producer's last block (t = 14 s), which walk reads or not as the
  // producer ends (a race in any run): the shorter log is the longer one's start, one row less
  const std::string& shorter = hand.size() < replay.size() ? hand : replay;
  const std::string& longer = hand.size() < replay.size() ? replay : hand;
  EXPECT_EQ(longer.compare(0, shorter.size(), shorter), 0)
      << "the walk logs differ (" << hand.size() << " and " << replay.size() << " bytes)";
  EXPECT_LE(std::count(longer.begin() + shorter.size(), longer.end(), '\n'), 1);
  const std::string out = ReadFile(dir / "replay_walk.txt");
  EXPECT_NE(out.find("walk: done, standing on both feet; 2 commands (--live-replay: 3 recorded)"),
            std::string::npos) << out;
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace ohrp::view::testing
