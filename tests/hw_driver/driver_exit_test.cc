// Tests that hw_driver, as a process with the real binary, removes its segment on every exit
// path: a normal end, SIGINT (servos off first), --quiet, a plugin that fails to open or is
// missing, a malformed MJCF or VRML model.
#include "driver_process.h"

namespace ohrp::hw {
namespace {

namespace fs = std::filesystem;
using testing::Clock;
using testing::HwDriverProcess;
using testing::Peek;
using testing::Since;

//---------------- the segment is removed on every exit path ----------------

TEST_F(HwDriverProcess, NormalEndRemovesTheSegment) {
  Start({"--duration", "0.3"});
  EXPECT_EQ(Wait(), 0) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "completed");
  EXPECT_GE(s["lateness"]["count"].get<long>(), 100);
  EXPECT_TRUE(s["lateness"].contains("p99_us"));
}

TEST_F(HwDriverProcess, SigintServosOffAndRemovesTheSegment) {
  Start({"--duration", "60", "--servo-off-time", "0.05"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  const auto t0 = Clock::now();
  while (peek.cycle() < 50 && Since(t0) < 20) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  const auto rec = Records();
  ASSERT_GE(rec.size(), 3u);
  EXPECT_EQ(rec.back().servo, 0);
  // the damped hold before servo-off: lower kp than the servo-on hold
  EXPECT_LT(rec[rec.size() - 2].kp[0], rec.front().kp[0]);
  EXPECT_EQ(Summary()["outcome"], "interrupted");
}

TEST_F(HwDriverProcess, QuietReportsOnlyAFailureAndWithoutTheLatenessTable) {
  // stopped by SIGINT, the normal end of a run without --duration: no report
  Start({"--duration", "60", "--servo-off-time", "0.05", "--quiet"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  std::string e = Stderr();
  EXPECT_EQ(e.find("interrupted after"), std::string::npos) << e;
  EXPECT_EQ(e.find("wake-up lateness"), std::string::npos) << e;
  EXPECT_EQ(e.find("events:"), std::string::npos) << e;
  // a board failure: the outcome and its cause, still without the lateness table
  Start({"--io-arg", "silent_at=300", "--board-timeout-cycles", "5", "--safe-time", "0.05",
         "--duration", "60", "--quiet"});
  EXPECT_EQ(Wait(), 6) << Stderr();
  e = Stderr();
  EXPECT_NE(e.find("hw_driver: board_fault after"), std::string::npos) << e;
  EXPECT_NE(e.find("board silent"), std::string::npos) << e;
  EXPECT_EQ(e.find("wake-up lateness"), std::string::npos) << e;
}

TEST_F(HwDriverProcess, PluginOpenErrorExitsWithItsMessageAndNoSegment) {
  Start({"--io-arg", "fail_open=1"});
  EXPECT_EQ(Wait(), 3) << Stderr();
  EXPECT_NE(Stderr().find("fake: told to fail"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
}

TEST_F(HwDriverProcess, MissingPluginNamesTheFileAndDlerror) {
  Start({}, "/nonexistent/libohrp_io_nothing.so");
  EXPECT_EQ(Wait(), 2) << Stderr();
  const std::string e = Stderr();
  EXPECT_NE(e.find("/nonexistent/libohrp_io_nothing.so"), std::string::npos) << e;
  EXPECT_NE(e.find("No such file"), std::string::npos) << e;  // dlerror's text
  EXPECT_FALSE(fs::exists(ShmPath()));
}

TEST_F(HwDriverProcess, MalformedModelExitsWithMujocosText) {
  model_ = Write("bad.xml", "<mujoco><worldbody><body></worldbody>");
  Start({});
  EXPECT_EQ(Wait(), 2) << Stderr();
  EXPECT_NE(Stderr().find("bad.xml"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
}

TEST_F(HwDriverProcess, MalformedVrmlModelExitsWithFileLineAndColumn) {
  model_ = Write("bad.wrl", "#VRML V2.0 utf8\nTransform { translation 0 1.2.3 0 }\n");
  Start({});
  EXPECT_EQ(Wait(), 2) << Stderr();
  EXPECT_NE(Stderr().find("bad.wrl:2:27: '1.2.3' is not a number"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
}

}  // namespace
}  // namespace ohrp::hw
