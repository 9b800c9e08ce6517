// Tests the C API (ohrp_shm.h) through a controller and an observer written in C
// (c_api_user.c): the header's names and counts, the lock-step with data checks, the default
// command values, the observer's read-only view and the refusals.
#include <gtest/gtest.h>

#include <string>

#include "c_api_user.h"
#include "shm_bridge/bridge.h"
#include "test_util.h"

namespace ohrp::shm {
namespace {

using testing::Spawn;
using testing::WaitExit;
using testing::WaitFor;

TEST(CApiTest, ACControllerAndACObserverFollowTheLockStep) {
  const std::string name = testing::UniqueSegment("capi");
  testing::RemoveSegment(name);
  Status status;
  auto producer = Producer::Create(testing::SmallConfig(name), &status);
  ASSERT_TRUE(status.ok()) << status.message;
  constexpr int kCycles = 500;
  const pid_t observer = Spawn([&] {
    uint64_t last = 0;
    const int r = c_observer(name.c_str(), &last);
    return r != 0 ? r : last == kCycles - 1 ? 0 : 20;
  });
  const pid_t controller = Spawn([&] { return c_controller(name.c_str(), kCycles); });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == controller; }));
  for (uint64_t k = 0; k < kCycles; ++k) {
    SensorBlock& s = producer->BeginSensors();
    s.cycle = k;
    for (int j = 0; j < 3; ++j) s.q[j] = 100.0 * static_cast<double>(k) + j;
    s.force[0].force[2] = 10.0 * static_cast<double>(k);
    producer->PublishSensors();
    CommandBlock c{};
    ASSERT_EQ(producer->WaitCommands(2.0, &c), WaitResult::kCommands) << "cycle " << k;
    EXPECT_EQ(c.answers_cycle, k);
    EXPECT_EQ(c.joint[1].mode, JointMode::kPosition);  // NULL mode: position
    EXPECT_EQ(c.joint[1].q_ref, -(100.0 * static_cast<double>(k) + 1));
    EXPECT_EQ(c.joint[1].kp, 200.0);  // NULL gains: the producer's defaults
    EXPECT_EQ(c.joint[1].kd, 2.0);
  }
  usleep(20000);  // the observer polls: let it see the last block
  producer.reset();
  EXPECT_EQ(WaitExit(controller), 0);
  EXPECT_EQ(WaitExit(observer), 0);
}

TEST(CApiTest, RefusalsSaySoInC) {
  char err[512] = {};
  const std::string missing = testing::UniqueSegment("capi_missing");
  EXPECT_EQ(c_refusals(missing.c_str(), err, sizeof err), 0);
  EXPECT_NE(std::string(err).find("no segment '" + missing + "'"), std::string::npos) << err;
  // a short buffer gets a truncated, terminated message
  char tiny[8];
  EXPECT_EQ(c_refusals(missing.c_str(), tiny, sizeof tiny), 0);
  EXPECT_EQ(std::string(tiny), "no segm");
}

}  // namespace
}  // namespace ohrp::shm
