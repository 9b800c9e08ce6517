// Tests of the live walk commands' channel (controllers/walk_channel.h): lines planned on the
// channel's thread from the published stance, taken by the cycle only for that stance's version,
// stops, refusals with the reason, and the local socket with its replies.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include "controllers/walk_channel.h"
#include "common/scratch.h"
#include "walking/footsteps.h"

namespace ohrp::controllers {
namespace {

using Clock = std::chrono::steady_clock;

walking::FeetPose Stance(double x) {
  walking::FeetPose f;
  f.p[walking::kLeft] = Eigen::Vector3d(x, 0.09, 0);
  f.p[walking::kRight] = Eigen::Vector3d(x, -0.09, 0);
  f.yaw[0] = f.yaw[1] = 0;
  return f;
}

LivePlanning Planning() {
  LivePlanning p;
  p.limits.width = 0.18;
  p.limits.sole_half_size = Eigen::Vector2d(0.125, 0.07);
  return p;
}

// polls as the cycle does (publishing `feet` as `version`) until something comes, 3 s at most
WalkChannel::Got Wait(WalkChannel* ch, const walking::FeetPose& feet, uint64_t version,
                      std::vector<walking::Footstep>* steps) {
  const auto end = Clock::now() + std::chrono::seconds(3);
  while (Clock::now() < end) {
    ch->Publish(feet, version);
    const WalkChannel::Got got = ch->Poll(version, steps);
    if (got != WalkChannel::Got::kNothing) return got;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WalkChannel::Got::kNothing;
}

struct Pipe {
  int fd[2];
  Pipe() { EXPECT_EQ(pipe(fd), 0); }
  ~Pipe() {
    close(fd[0]);
    close(fd[1]);
  }
  void Send(const std::string& s) { ASSERT_EQ(write(fd[1], s.data(), s.size()), static_cast<ssize_t>(s.size())); }
};

double MidX(walking::FeetPose f, const std::vector<walking::Footstep>& steps) {
  for (const auto& s : steps) f = walking::After(f, s);
  return walking::MidFrame(f).p.x();
}

TEST(WalkChannel, ALinePlannedFromThePublishedStanceIsTaken) {
  Pipe in;
  WalkChannel ch;
  std::string error;
  ASSERT_TRUE(ch.Open(in.fd[0], "", Planning(), &error)) << error;
  in.Send("# a comment, then a goal\n\ngoal 0.5 0 0\n");
  std::vector<walking::Footstep> steps;
  ASSERT_EQ(Wait(&ch, Stance(1.0), 7, &steps), WalkChannel::Got::kSteps);
  EXPECT_EQ(walking::CheckSteps(Stance(1.0), steps, Planning().limits), "");
  EXPECT_NEAR(MidX(Stance(1.0), steps), 1.5, 1e-9);  // from the stance published
  EXPECT_EQ(ch.received(), 1);
  EXPECT_EQ(ch.applied(), 1);
}

TEST(WalkChannel, APlanForAStanceThatMovedOnIsMadeAgain) {
  Pipe in;
  WalkChannel ch;
  std::string error;
  ASSERT_TRUE(ch.Open(in.fd[0], "", Planning(), &error)) << error;
  ch.Publish(Stance(0), 1);
  in.Send("goal 0.5 0 0\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // planned from version 1
  std::vector<walking::Footstep> steps;
  // the cycle is at version 2 now (a step began): the plan from version 1 is not taken
  ASSERT_EQ(Wait(&ch, Stance(2.0), 2, &steps), WalkChannel::Got::kSteps);
  EXPECT_NEAR(MidX(Stance(2.0), steps), 2.5, 1e-9);
}

TEST(WalkChannel, StopAndRefusals) {
  Pipe in;
  WalkChannel ch;
  std::string error;
  ASSERT_TRUE(ch.Open(in.fd[0], "", Planning(), &error)) << error;
  in.Send("wait 2\nfly 1 2\ngoal 1 0\nvelocity 0.2 0 0\n");
  std::vector<walking::Footstep> steps;
  // a velocity without a duration: until the next command (600 s of steps)
  ASSERT_EQ(Wait(&ch, Stance(0), 1, &steps), WalkChannel::Got::kSteps);
  EXPECT_GT(steps.size(), 600u);
  EXPECT_EQ(ch.refused(), 3);  // wait, an unknown verb, a goal without its yaw
  in.Send("stop\n");
  EXPECT_EQ(Wait(&ch, Stance(0), 2, &steps), WalkChannel::Got::kStop);
  // a goal beyond what can be planned is refused, nothing comes
  in.Send("random 20000 1\n");
  EXPECT_EQ(Wait(&ch, Stance(0), 3, &steps), WalkChannel::Got::kNothing);
  EXPECT_EQ(ch.refused(), 4);
}

std::string ReadLine(int fd) {
  std::string line;
  char c;
  const auto end = Clock::now() + std::chrono::seconds(3);
  while (Clock::now() < end && read(fd, &c, 1) == 1 && c != '\n') line += c;
  return line;
}

int Connect(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  for (int i = 0; i < 100; ++i) {
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) return fd;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  close(fd);
  return -1;
}

TEST(WalkChannel, TheSocketRepliesToEachCommandOneClientAtATime) {
  const std::string path = ohrp::testing::ScratchPath("walk", ".sock");
  WalkChannel ch;
  std::string error;
  ASSERT_TRUE(ch.Open(-1, path, Planning(), &error)) << error;
  const int a = Connect(path);
  ASSERT_GE(a, 0);
  std::vector<walking::Footstep> steps;
  ch.Publish(Stance(0), 1);
  ASSERT_EQ(write(a, "velocity 0.1 0 0 4\nturn left\n", 29), 29);
  // a refusal is answered at once, a plan when it is made: either may come first
  std::string one = ReadLine(a), two = ReadLine(a);
  if (one.rfind("error", 0) == 0) std::swap(one, two);
  EXPECT_EQ(one.rfind("ok: \"velocity 0.1 0 0 4\": ", 0), 0u) << one;
  EXPECT_EQ(two.rfind("error: unknown walk command \"turn left\"", 0), 0u) << two;
  EXPECT_EQ(Wait(&ch, Stance(0), 1, &steps), WalkChannel::Got::kSteps);
  const int b = Connect(path);
  ASSERT_GE(b, 0);
  EXPECT_EQ(ReadLine(b), "error: one client at a time");
  close(b);
  close(a);
  ch.Close();
  EXPECT_NE(access(path.c_str(), F_OK), 0);  // the socket file is removed
}

// goal_now: a goal from the feet as they are now (the viewer's click on the floor), planned from
// the stance after the step under way; farther than kLiveGoalRange refused with the distance
TEST(WalkChannel, AGoalFromTheFeetNowIsPlannedFromTheStanceAfterTheStep) {
  const std::string path = ohrp::testing::ScratchPath("walk_goal", ".sock");
  WalkChannel ch;
  std::string error;
  ASSERT_TRUE(ch.Open(-1, path, Planning(), &error)) << error;
  const int a = Connect(path);
  ASSERT_GE(a, 0);
  // the feet now: turned 90 deg left about the origin; the step under way ends 0.2 m further on
  walking::FeetPose now = Stance(0), after = Stance(0);
  for (int f : {walking::kLeft, walking::kRight}) {
    now.p[f] = Eigen::Vector3d(-Stance(0).p[f].y(), 0, 0);
    now.yaw[f] = M_PI / 2;
    after.p[f] = now.p[f] + Eigen::Vector3d(0, 0.2, 0);
    after.yaw[f] = M_PI / 2;
  }
  ch.Publish(after, 1, now);
  const std::string line = "goal_now 0.6 0 -90\n";
  ASSERT_EQ(write(a, line.data(), line.size()), static_cast<ssize_t>(line.size()));
  const std::string reply = ReadLine(a);
  EXPECT_EQ(reply.rfind("ok: \"goal_now 0.6 0 -90\": ", 0), 0u) << reply;
  std::vector<walking::Footstep> steps;
  ASSERT_EQ(Wait(&ch, after, 1, &steps), WalkChannel::Got::kSteps);
  walking::FeetPose end = after;
  for (const auto& s : steps) end = walking::After(end, s);
  // 0.6 m ahead of the feet now (along +y), facing +x again
  const walking::Frame2 m = walking::MidFrame(end);
  EXPECT_NEAR(m.p.x(), 0.0, 1e-9);
  EXPECT_NEAR(m.p.y(), 0.6, 1e-9);
  EXPECT_NEAR(m.yaw, 0.0, 1e-9);
  const std::string far = "goal_now 4 3.1 0\n";
  ASSERT_EQ(write(a, far.data(), far.size()), static_cast<ssize_t>(far.size()));
  EXPECT_EQ(ReadLine(a), "error: \"goal_now 4 3.1 0\": 5.06 m from the feet, farther than the 5 m a "
                         "live goal may be (choose a nearer point)");
  close(a);
  ch.Close();
}

TEST(WalkChannel, APathThatIsNotASocketIsRefused) {
  const std::string path = ohrp::testing::ScratchFile("notes", "keep me\n", ".txt");
  WalkChannel ch;
  std::string error;
  EXPECT_FALSE(ch.Open(-1, path, Planning(), &error));
  EXPECT_NE(error.find("not a socket"), std::string::npos) << error;
  EXPECT_EQ(access(path.c_str(), F_OK), 0);
}

}  // namespace
}  // namespace ohrp::controllers
