// Tests the robot adaptor's controller slot across real processes: a second controller is
// refused, a dead controller's slot is taken over, close releases it, a dropped controller
// learns it on its next write and read.
#include <gtest/gtest.h>

#include <string>

#include "adaptor_fixture.h"
#include "shm_bridge/bridge.h"

namespace ohrp::shm {
namespace {

using testing::AdaptorTest;
using testing::Pipe;
using testing::Spawn;
using testing::WaitExit;

//---------------- open: the controller slot ----------------

TEST_F(AdaptorTest, SecondControllerIsRefused) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  Pipe attached, done;
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!adaptor.open(name_).ok()) return 1;
    attached.Send();
    return done.Receive() ? 0 : 2;
  });
  ASSERT_TRUE(attached.Receive());

  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kControllerPresent);
  EXPECT_EQ(s.message, "segment '" + name_ + "' already has a controller (pid " +
                           std::to_string(child) + "); stop it first");
  EXPECT_FALSE(adaptor.is_open());
  EXPECT_EQ(producer->controller_pid(), child);
  done.Send();
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(AdaptorTest, DeadControllersSlotIsTakenOver) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!adaptor.open(name_).ok()) return 1;
    raise(SIGKILL);  // never closes
    return 2;
  });
  ASSERT_EQ(WaitExit(child), 128 + SIGKILL);
  ASSERT_EQ(producer->controller_pid(), child);

  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(producer->controller_pid(), getpid());
  EXPECT_EQ(adaptor.header().controller_pid, getpid());
}

TEST_F(AdaptorTest, CloseReleasesTheSlotAndIsIdempotent) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  EXPECT_EQ(producer->controller_pid(), getpid());
  EXPECT_EQ(adaptor.header().njoint, 3);
  EXPECT_STREQ(adaptor.header().joint_names[1], "knee");
  adaptor.close();
  adaptor.close();
  EXPECT_FALSE(adaptor.is_open());
  EXPECT_EQ(producer->controller_pid(), 0);
  SensorBlock s{};
  EXPECT_EQ(adaptor.read(&s), ReadResult::kNotOpen);
  EXPECT_EQ(adaptor.write(CommandBlock{}), ReadResult::kNotOpen);
}

// a controller the producer let go (it missed the producer's timeout) learns it on its next
// write and read, writes nothing more, and the slot is free for a new controller
TEST_F(AdaptorTest, ADroppedControllerLearnsItOnItsNextWriteAndRead) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  producer->BeginSensors().cycle = 1;
  producer->PublishSensors();
  SensorBlock s{};
  ASSERT_EQ(adaptor.read(&s), ReadResult::kOk);

  EXPECT_FALSE(producer->DropController(getpid() + 1));  // not the holder: nothing changes
  EXPECT_FALSE(adaptor.dropped());
  EXPECT_TRUE(producer->DropController(getpid()));
  EXPECT_EQ(producer->controller_pid(), 0);
  EXPECT_TRUE(adaptor.dropped());
  CommandBlock c{};
  c.njoint = 3;
  EXPECT_EQ(adaptor.write(c), ReadResult::kDropped);
  CommandBlock out{};
  EXPECT_EQ(producer->WaitCommands(0.05, &out), WaitResult::kNoController);  // nothing posted
  producer->BeginSensors().cycle = 2;
  producer->PublishSensors();
  EXPECT_EQ(adaptor.read(&s), ReadResult::kDropped);
  EXPECT_STREQ(ReadResultName(ReadResult::kDropped), "dropped by the producer");

  // a new controller attaches; closing the dropped adaptor leaves its claim alone
  const pid_t child = Spawn([&] {
    RobotAdaptor b;
    if (!b.open(name_).ok()) return 1;
    raise(SIGKILL);  // never closes: its claim stays
    return 2;
  });
  EXPECT_EQ(WaitExit(child), 128 + SIGKILL);
  EXPECT_EQ(producer->controller_pid(), child);
  adaptor.close();
  EXPECT_EQ(producer->controller_pid(), child);
}

}  // namespace
}  // namespace ohrp::shm
