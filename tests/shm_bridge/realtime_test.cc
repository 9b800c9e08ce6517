// Tests the real-time set-up of the calling thread (shm_bridge/realtime.h): what it sets that needs no privilege.
#include "shm_bridge/realtime.h"

#include <sys/prctl.h>

#include <gtest/gtest.h>

#include <thread>

namespace ohrp::rt {
namespace {

TEST(SetUpRealTime, SetsTheThreadsTimerSlackSoItsSleepsEndWhenAsked) {
  // in a thread of its own, so that the test's main thread keeps its settings
  std::thread t([] {
    ASSERT_EQ(prctl(PR_SET_TIMERSLACK, 50000UL, 0, 0, 0), 0);
    RtSettings s;
    s.priority = 0;
    s.lock_memory = false;
    s.stack_prefault_kb = 0;
    const RtReport r = SetUpRealTime(s);
    EXPECT_EQ(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0), 1);
    EXPECT_EQ(r.timer_slack_ns, 1);
    EXPECT_TRUE(r.warnings.empty());
  });
  t.join();
}

TEST(SetUpRealTime, LeavesTheTimerSlackWhenAskedTo) {
  std::thread t([] {
    ASSERT_EQ(prctl(PR_SET_TIMERSLACK, 50000UL, 0, 0, 0), 0);
    RtSettings s;
    s.priority = 0;
    s.lock_memory = false;
    s.stack_prefault_kb = 0;
    s.timer_slack_ns = 0;
    EXPECT_EQ(SetUpRealTime(s).timer_slack_ns, 50000);
  });
  t.join();
}

}  // namespace
}  // namespace ohrp::rt
