// Soak test of sim_host (ctest label `soak`): HRP-1S in real time with no end and
// --on-controller-loss wait, a controller killed and restarted every few seconds (posture ended by
// SIGKILL, posture ended by SIGTERM, and a controller that sends NaN and runaway velocity
// references, ended by SIGKILL), pushes on the base. Checked at the end: sim_host's resident
// memory stayed within kRssBound of its value after the warm-up, the data log lost no row (one
// row per control cycle, times one period apart, none dropped), and the summary lists every
// event the test caused, in order: each controller attached and lost as it was ended, the
// rejections, each push's start and end.
//
// Duration: OHRP_SOAK_SECONDS (default 60, what CI runs); by hand, 5 minutes:
//   OHRP_SOAK_SECONDS=300 ./ohrp test -L soak
#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../controllers/fake_robot.h"  // Spawn, WaitExit, Program, TempPath, ReadFile
#include "shm_bridge/bridge.h"

namespace ohrp::sim {
namespace {

namespace ct = ohrp::controllers::testing;
using Clock = std::chrono::steady_clock;

constexpr double kControllerLife = 3.0;  // [s] wall time each controller runs
constexpr double kPushEvery = 8.0;       // [s] of simulated time between pushes
constexpr double kControlPeriod = 0.005;  // [s] sim_host's default
constexpr long kRssBound = 1024;         // [kB] allowed RSS growth after the warm-up

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double SoakSeconds() {
  const char* env = std::getenv("OHRP_SOAK_SECONDS");
  const double s = env != nullptr ? std::atof(env) : 60.0;
  return s >= 10.0 ? s : 60.0;
}

// resident memory of `pid` [kB], or -1
long RssKb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
  }
  return -1;
}

size_t Count(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// a controller that holds the measured pose but sends a NaN position for joint 0 and a
// runaway velocity reference for joint 1 in every block, until killed
pid_t BadController(const std::string& segment) {
  return ohrp::testing::Spawn([&]() -> int {
    shm::RobotAdaptor a;
    for (int i = 0; i < 400 && !a.open(segment).ok(); ++i) usleep(5000);
    if (!a.is_open()) _exit(2);
    shm::SensorBlock s{};
    shm::CommandBlock c{};
    c.njoint = a.header().njoint;
    for (;;) {
      const shm::ReadResult r = a.read(&s);
      if (r == shm::ReadResult::kProducerStopped || r == shm::ReadResult::kProducerGone ||
          r == shm::ReadResult::kDropped)
        _exit(0);
      if (r != shm::ReadResult::kOk) continue;
      for (int j = 0; j < c.njoint; ++j) {
        c.joint[j].mode = shm::JointMode::kPosition;
        c.joint[j].q_ref = s.q[j];
        c.joint[j].kp = a.header().default_kp[j];
        c.joint[j].kd = a.header().default_kd[j];
      }
      c.joint[0].q_ref = std::numeric_limits<double>::quiet_NaN();
      c.joint[1].dq_ref = 1e300;
      a.write(c);
    }
  });
}

// one controller of the soak: what it is and how it is ended
struct SoakController {
  bool bad = false;     // BadController instead of posture
  int signal = SIGKILL;
  pid_t pid = -1;
  const char* lost_as() const { return signal == SIGTERM ? "controller_detached" : "controller_died"; }
};

TEST(SimHostSoak, ControllersComeAndGoUnderPushesAndBadCommandsWithoutLeaksOrLostRows) {
  const double seconds = SoakSeconds();
  const std::string segment = ct::UniqueSegment("soak");
  ct::RemoveSegment(segment);
  const std::string err = ct::TempPath("soak_stderr"), log = ct::TempPath("soak_log");
  const std::string summary = ct::TempPath("soak_summary"), ctl = ct::TempPath("soak_ctl");

  // pushes every kPushEvery s of simulated time, alternately forward and backward (4 N s)
  std::vector<std::string> args = {
      ct::Program("sim_host"), "--scene",
      std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", "--keyframe", "halfsit",
      "--segment", segment, "--realtime", "--duration", "0", "--on-controller-loss", "wait", "--on-fall", "continue",
      "--wait-controller", "60", "--log", log, "--summary", summary, "--progress", "0"};
  std::vector<double> push_t0;
  for (double t = 0.5 * kPushEvery; t < seconds; t += kPushEvery) {
    const double f = push_t0.size() % 2 == 0 ? 40.0 : -40.0;
    args.push_back("--push");
    args.push_back(std::to_string(t) + "," + std::to_string(t + 0.1) + "," + std::to_string(f) +
                   ",0,0,0,0,0");
    push_t0.push_back(t);
  }
  const pid_t sim = ct::Spawn(args, err);

  // controllers one after another until the time is up; each is ended and its loss seen
  std::vector<SoakController> runs;
  std::vector<long> rss;  // [kB] samples after the warm-up
  long rss_warm = -1;
  const double warm_up = std::min(10.0, seconds / 3);
  const auto t0 = Clock::now();
  while (Since(t0) + kControllerLife <= seconds) {
    SoakController r;
    r.bad = runs.size() % 3 == 2;
    r.signal = runs.size() % 3 == 1 ? SIGTERM : SIGKILL;
    r.pid = r.bad ? BadController(segment)
                  // no fall watch: each controller must live until it is ended (a pushed-over
                  // robot would end it at once)
                  : ct::Spawn({ct::Program("posture"), "--segment", segment, "--ramp", "0.5",
                               "--attach-timeout", "30", "--no-fall-watch"},
                              ctl);
    runs.push_back(r);
    const auto started = Clock::now();
    while (Since(started) < kControllerLife) {
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
      const long kb = RssKb(sim);
      ASSERT_GT(kb, 0) << "sim_host is gone: " << ct::ReadFile(err);
      if (Since(t0) >= warm_up) {
        if (rss_warm < 0) rss_warm = kb;
        rss.push_back(kb);
      }
    }
    kill(r.pid, r.signal);
    ohrp::testing::WaitExit(r.pid, ohrp::testing::kNoTimeout);
    // the loss is seen before the next controller starts, so every event is its own
    const auto lost = Clock::now();
    while (Count(ct::ReadFile(err), "waiting for a new controller") < runs.size() &&
           Since(lost) < 10)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(sim, SIGINT);
  // interrupted (130), or 6 when the pushes toppled the robot on the way (--on-fall continue
  // ran on: this test is about leaks and rows, and a fall decides the exit code)
  const int code = ct::WaitExit(sim, 30.0);
  ASSERT_TRUE(code == 130 || code == 6) << code << ": " << ct::ReadFile(err);
  const nlohmann::json s = nlohmann::json::parse(ct::ReadFile(summary));
  std::printf("soak: %.0f s, %zu controllers, %zu pushes, %lu cycles, RSS %ld kB after the "
              "warm-up, at most %ld kB\n",
              seconds, runs.size(), push_t0.size(), s["cycles"].get<unsigned long>(), rss_warm,
              rss.empty() ? -1 : *std::max_element(rss.begin(), rss.end()));

  // memory: no growth beyond the bound after the warm-up (under AddressSanitizer, whose
  // quarantine holds freed memory, LeakSanitizer checks sim_host's exit instead)
  ASSERT_FALSE(rss.empty());
#ifndef OHRP_SANITIZE
  EXPECT_LE(*std::max_element(rss.begin(), rss.end()) - rss_warm, kRssBound)
      << "sim_host's RSS grew from " << rss_warm << " kB";
#endif

  // the data log: one row per control cycle (and the first block), none lost
  EXPECT_EQ(s["log_dropped"].get<long>(), 0);
  std::ifstream in(log);
  std::string line;
  std::getline(in, line);  // header
  long rows = 0;
  double last = -1;
  long gaps = 0;
  while (std::getline(in, line)) {
    const double t = std::atof(line.c_str());
    if (rows > 0 && std::fabs(t - last - kControlPeriod) > 1e-6) ++gaps;
    last = t;
    ++rows;
  }
  EXPECT_EQ(rows, s["log_rows"].get<long>());
  EXPECT_EQ(rows, s["cycles"].get<long>() + 1);
  EXPECT_EQ(gaps, 0) << "rows not one control period apart";

  // the events: each controller attached, rejected (the bad ones) and lost as it was ended
  std::vector<nlohmann::json> controller_events, push_events;
  for (const auto& e : s["events"]) {
    const std::string kind = e["event"];
    if (kind == "fall") continue;  // the pushes may topple the robot (above)
    (kind.rfind("push_", 0) == 0 ? push_events : controller_events).push_back(e);
  }
  EXPECT_EQ(s["events_dropped"].get<long>(), 0);
  size_t at = 0;
  for (const SoakController& r : runs) {
    ASSERT_LT(at, controller_events.size()) << s["events"].dump(1);
    EXPECT_EQ(controller_events[at]["event"], "controller_attached");
    EXPECT_EQ(controller_events[at]["value"].get<pid_t>(), r.pid);
    ++at;
    if (r.bad) {
      ASSERT_LT(at, controller_events.size());
      EXPECT_EQ(controller_events[at]["event"], "commands_rejected");
      EXPECT_EQ(controller_events[at]["value"].get<int>(), 2);  // joints 0 and 1
      ++at;
    }
    ASSERT_LT(at, controller_events.size());
    EXPECT_EQ(controller_events[at]["event"], r.lost_as()) << "controller " << r.pid;
    EXPECT_EQ(controller_events[at]["value"].get<pid_t>(), r.pid);
    ++at;
  }
  EXPECT_EQ(at, controller_events.size()) << s["events"].dump(1);
  EXPECT_EQ(s["controllers_seen"].get<size_t>(), runs.size());
  EXPECT_EQ(s["controller_losses"].get<size_t>(), runs.size());
  EXPECT_GT(s["rejected_commands"].get<long>(), 0);

  // the pushes whose window the simulation passed: a start and an end at their times
  const double sim_time = s["sim_time"].get<double>();
  size_t passed = 0;
  for (size_t i = 0; i < push_t0.size(); ++i) {
    if (push_t0[i] + 0.2 > sim_time) continue;
    ++passed;
    int seen = 0;
    for (const auto& e : push_events) {
      if (e["value"].get<size_t>() != i) continue;
      const double want = e["event"] == "push_start" ? push_t0[i] : push_t0[i] + 0.1;
      EXPECT_NEAR(e["time"].get<double>(), want, 0.0015) << e.dump();
      ++seen;
    }
    EXPECT_EQ(seen, 2) << "push " << i;
  }
  EXPECT_GT(passed, 0u) << "no push window was simulated (simulated " << sim_time << " s)";
  for (const std::string& f : {err, log, summary, ctl}) std::remove(f.c_str());
}

}  // namespace
}  // namespace ohrp::sim
