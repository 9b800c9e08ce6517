// A lock-step run driven by hand through sim_host's control channel (pause before the controller,
// step 100 periods, push the base, step, resume) and the same run re-run from its actions.jsonl
// (the push as the --push it records) write the same data log, byte for byte from the second
// row on (the first's status races with the controller's attach): pauses and steps
// do not change a lock-step trajectory, and the recorded push window is the one that acted.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/process.h"
#include "common/scratch.h"

namespace {

namespace fs = std::filesystem;
const std::string kBin = OHRP_BIN_DIR;
const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// one line to the control socket, its one reply line
std::string Send(const std::string& path, const std::string& line) {
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::strncpy(a.sun_path, path.c_str(), sizeof a.sun_path - 1);
  if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    close(fd);
    return "no connection";
  }
  const std::string out = line + "\n";
  (void)!write(fd, out.data(), out.size());
  std::string reply;
  char c;
  while (read(fd, &c, 1) == 1 && c != '\n') reply += c;
  close(fd);
  return reply;
}

// sim_host lock-step for 1.5 s with posture; `extra` its options; true when both end with 0
pid_t StartSim(const fs::path& dir, const std::string& segment, const std::vector<std::string>& extra) {
  std::vector<std::string> args{kBin + "/sim_host", kScene, "--segment", segment, "--duration", "1.5",
                                "--wait-controller", "20", "--progress", "0",
                                "--log", (dir / "log.csv").string(),
                                "--summary", (dir / "sim_summary.json").string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return ohrp::testing::Spawn(args, ohrp::testing::ToFile((dir / "sim_host.txt").string()));
}
pid_t StartPosture(const fs::path& dir, const std::string& segment) {
  return ohrp::testing::Spawn({kBin + "/posture", "--segment", segment, "--attach-timeout", "20"},
                              ohrp::testing::ToFile((dir / "posture.txt").string()));
}

TEST(ControlReplay, HandDrivenRunReRunsFromItsActions) {
  const fs::path root = ohrp::testing::ScratchFolder("control_replay");
  const fs::path a = root / "hand", b = root / "rerun";
  fs::create_directories(a);
  fs::create_directories(b);
  const std::string seg = "ctlrep" + std::to_string(getpid());
  const std::string sock = (root / "sim.sock").string();
  pid_t sim = StartSim(a, seg + "a", {"--control-socket", sock});
  for (int i = 0; i < 200 && !fs::exists(sock); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
  // paused before the controller attaches: the first cycle waits for the hand
  EXPECT_EQ(Send(sock, "pause"), "ok: pause: t=0.0000 s cycle 0 paused");
  pid_t posture = StartPosture(a, seg + "a");
  EXPECT_EQ(Send(sock, "step 100"), "ok: step 100: t=0.5000 s cycle 100 paused");
  EXPECT_EQ(Send(sock, "push WAIST 150 0 0 0.1"), "ok: push WAIST 150 0 0 0.1: t=0.5000 s cycle 100 paused");
  EXPECT_EQ(Send(sock, "step 3"), "ok: step 3: t=0.5150 s cycle 103 paused");
  EXPECT_EQ(Send(sock, "resume"), "ok: resume: t=0.5150 s cycle 103 running");
  ASSERT_EQ(ohrp::testing::WaitExit(sim, 60), 0) << Read(a / "sim_host.txt");
  ASSERT_EQ(ohrp::testing::WaitExit(posture, 20), 0) << Read(a / "posture.txt");

  // the record: each action with its time and cycle; the push as sim_host --push
  std::string push;
  int actions = 0;
  std::istringstream lines(Read(a / "actions.jsonl"));
  for (std::string line; std::getline(lines, line); ++actions) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("sim_host_push")) push = j["sim_host_push"];
  }
  EXPECT_EQ(actions, 5);
  EXPECT_EQ(push, "0.500000,0.600000,150,0,0,0,0,0");

  sim = StartSim(b, seg + "b", {"--push", push});
  posture = StartPosture(b, seg + "b");
  ASSERT_EQ(ohrp::testing::WaitExit(sim, 60), 0) << Read(b / "sim_host.txt");
  ASSERT_EQ(ohrp::testing::WaitExit(posture, 20), 0) << Read(b / "posture.txt");
  // the logs but their header and first row (t = 0: published before the controller attached
  // or after, its status's no-controller bit races with the attach in any run)
  auto after_first = [](const std::string& log) {
    const size_t header = log.find('\n');
    return header == std::string::npos ? "" : log.substr(log.find('\n', header + 1) + 1);
  };
  const std::string hand = after_first(Read(a / "log.csv")), rerun = after_first(Read(b / "log.csv"));
  EXPECT_GT(hand.size(), 10000u);
  EXPECT_TRUE(hand == rerun) << "the re-run's log differs from the hand-driven run's";
  // and the push acted: without it the log is another
  const fs::path c = root / "still";
  fs::create_directories(c);
  sim = StartSim(c, seg + "c", {});
  posture = StartPosture(c, seg + "c");
  ASSERT_EQ(ohrp::testing::WaitExit(sim, 60), 0) << Read(c / "sim_host.txt");
  ASSERT_EQ(ohrp::testing::WaitExit(posture, 20), 0);
  EXPECT_FALSE(after_first(Read(c / "log.csv")) == hand);
  if (!::testing::Test::HasFailure()) fs::remove_all(root);
}

// the log's column `name` at the first row at or after time `t`
double Logged(const std::string& log, const std::string& name, double t) {
  std::istringstream in(log);
  std::string line, cell;
  std::getline(in, line);
  int col = -1, i = 0;
  for (std::istringstream h(line); std::getline(h, cell, ','); ++i)
    if (cell == name) col = i;
  while (std::getline(in, line)) {
    std::vector<double> v;
    for (std::istringstream r(line); std::getline(r, cell, ',');) v.push_back(std::atof(cell.c_str()));
    if (col >= 0 && col < static_cast<int>(v.size()) && v[0] >= t - 1e-9) return v[col];
  }
  return NAN;
}

// reset: a push (60 N s) rocks the robot; "reset" puts the robot back in the run's start state (at
// the same simulated time): a period later the base is back within a tenth of how far it was
TEST(ControlReplay, ResetPutsTheRobotBackInItsStartState) {
  const fs::path root = ohrp::testing::ScratchFolder("control_reset");
  fs::create_directories(root);
  const std::string seg = "ctlrst" + std::to_string(getpid());
  const std::string sock = (root / "sim.sock").string();
  const pid_t sim = StartSim(root, seg, {"--control-socket", sock});
  for (int i = 0; i < 200 && !fs::exists(sock); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
  EXPECT_EQ(Send(sock, "pause").rfind("ok: pause", 0), 0u);
  const pid_t posture = StartPosture(root, seg);
  EXPECT_EQ(Send(sock, "push WAIST 300 0 0 0.2").rfind("ok: push", 0), 0u);
  EXPECT_EQ(Send(sock, "step 100"), "ok: step 100: t=0.5000 s cycle 100 paused");
  EXPECT_EQ(Send(sock, "reset"), "ok: reset: t=0.5000 s cycle 100 paused");
  EXPECT_EQ(Send(sock, "resume").rfind("ok: resume", 0), 0u);
  ASSERT_EQ(ohrp::testing::WaitExit(sim, 60), 0) << Read(root / "sim_host.txt");
  ASSERT_EQ(ohrp::testing::WaitExit(posture, 20), 0) << Read(root / "posture.txt");
  const std::string log = Read(root / "log.csv");
  const double x0 = Logged(log, "base_x", 0), moved = Logged(log, "base_x", 0.5) - x0,
               back = Logged(log, "base_x", 0.505) - x0;
  std::printf("base x: %+.4f m at 0.5 s, %+.5f m a period after the reset\n", moved, back);
  EXPECT_GT(std::fabs(moved), 0.002);  // the robot rocks: forward, then back past its start
  EXPECT_LT(std::fabs(back), 0.1 * std::fabs(moved));
  const std::string actions = Read(root / "actions.jsonl");
  EXPECT_NE(actions.find("\"action\": \"reset\""), std::string::npos) << actions;
  if (!::testing::Test::HasFailure()) fs::remove_all(root);
}

}  // namespace
