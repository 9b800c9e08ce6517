// Tests the robot adaptor (controller end) across real processes: every refusal of open (a
// header with corrupt counts, gains or periods among them). The controller slot is tested in
// adaptor_slot_test.cc; the cycle and scribbled wake-up words in adaptor_cycle_test.cc.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "adaptor_fixture.h"
#include "shm_bridge/bridge.h"

namespace ohrp::shm {
namespace {

using testing::AdaptorTest;
using testing::RawSegment;
using testing::Spawn;
using testing::WaitExit;

//---------------- open: refusals ----------------

TEST_F(AdaptorTest, OpenReportsAMissingSegment) {
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kNoSegment);
  EXPECT_EQ(s.message, "no segment '" + name_ + "' (/dev/shm/ohrp_" + name_ +
                           "): is sim_host or hw_driver running with --segment " + name_ + "?");
  EXPECT_FALSE(adaptor.is_open());
}

TEST_F(AdaptorTest, OpenRefusesAnObjectThatIsNotASegment) {
  namespace bip = boost::interprocess;
  {
    bip::shared_memory_object junk(bip::create_only, SegmentObjectName(name_).c_str(),
                                   bip::read_write);
    junk.truncate(100);
  }
  RobotAdaptor adaptor;
  Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kNotASegment) << s.message;
  EXPECT_TRUE(Contains(s.message, "100 bytes")) << s.message;

  // full size, but filled with garbage
  {
    bip::shared_memory_object junk(bip::open_only, SegmentObjectName(name_).c_str(),
                                   bip::read_write);
    junk.truncate(sizeof(Segment));
    bip::mapped_region region(junk, bip::read_write);
    std::memset(region.get_address(), 0xab, region.get_size());
  }
  s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kNotASegment) << s.message;
  EXPECT_TRUE(Contains(s.message, "magic")) << s.message;
  EXPECT_FALSE(adaptor.is_open());
}

TEST_F(AdaptorTest, OpenRefusesAnotherLayoutHash) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  raw.get()->header.layout_hash ^= 0x5a5a;
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kLayoutMismatch);
  EXPECT_TRUE(Contains(s.message, "rebuild the controller against this producer's shm_bridge"))
      << s.message;
  char expected_hash[32];
  std::snprintf(expected_hash, sizeof(expected_hash), "0x%016llx",
                static_cast<unsigned long long>(LayoutHash()));
  EXPECT_TRUE(Contains(s.message, expected_hash)) << s.message;
  EXPECT_FALSE(adaptor.is_open());
  EXPECT_EQ(producer->controller_pid(), 0);  // nothing stays attached
}

TEST_F(AdaptorTest, OpenReportsADeadProducer) {
  const pid_t child = Spawn([&] {
    auto p = Create();
    raise(SIGKILL);
    return 1;
  });
  ASSERT_EQ(WaitExit(child), 128 + SIGKILL);
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kProducerDead) << s.message;
  EXPECT_TRUE(Contains(s.message, "stale segment '" + name_ + "'")) << s.message;
  EXPECT_TRUE(Contains(s.message, "pid " + std::to_string(child))) << s.message;
  EXPECT_TRUE(Contains(s.message, "restart the producer")) << s.message;
}

TEST_F(AdaptorTest, OpenReportsAStoppedProducer) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  producer->SetState(ProducerState::kFailed);
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kProducerStopped) << s.message;
  EXPECT_TRUE(Contains(s.message, "failed")) << s.message;
}

TEST_F(AdaptorTest, OpenWaitsBrieflyForAProducerStillCreating) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  producer->SetState(ProducerState::kCreating);
  std::thread finish([&] {
    usleep(100000);
    producer->SetState(ProducerState::kRunning);
  });
  RobotAdaptor adaptor;
  const double t0 = MonotonicSeconds();
  const Status s = adaptor.open(name_);
  const double waited = MonotonicSeconds() - t0;
  finish.join();
  EXPECT_TRUE(s.ok()) << s.message;
  EXPECT_GE(waited, 0.09);
  EXPECT_LT(waited, 0.9);
}

TEST_F(AdaptorTest, OpenReportsAProducerThatStaysInCreation) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  producer->SetState(ProducerState::kCreating);
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kProducerNotReady) << s.message;
  EXPECT_FALSE(adaptor.is_open());
}

// a header of the right layout whose values are corrupt: refused with the field and the value
struct CorruptHeader {
  const char* what;                         // the field as the message names it
  void (*corrupt)(SegmentHeader* h);
  const char* expected;                     // part of the message
};

TEST_F(AdaptorTest, OpenRefusesAHeaderWithNonPhysicalValues) {
  const CorruptHeader cases[] = {
      {"njoint", [](SegmentHeader* h) { h->njoint = 100000; }, "njoint = 100000 is outside [0, 64]"},
      {"nforce", [](SegmentHeader* h) { h->nforce = -1; }, "nforce = -1 is outside [0, 4]"},
      {"nimu", [](SegmentHeader* h) { h->nimu = 3; }, "nimu = 3 is outside [0, 2]"},
      {"default_kp", [](SegmentHeader* h) { h->default_kp[1] = -200.0; },
       "default_kp[1] = -200 (joint 'knee') must be finite and >= 0"},
      {"default_kd", [](SegmentHeader* h) { h->default_kd[2] = NAN; },
       "default_kd[2] = nan (joint 'ankle') must be finite and >= 0"},
      {"q_min > q_max", [](SegmentHeader* h) { h->q_min[0] = 2.0; },
       "q_min[0] = 2 and q_max[0] = 1 (joint 'hip') are not a range"},
      {"tau_max", [](SegmentHeader* h) { h->tau_max[0] = -1.0; },
       "tau_max[0] = -1 (joint 'hip') must be >= 0"},
      {"control_period", [](SegmentHeader* h) { h->control_period = 0.0; },
       "control_period = 0 must be finite and > 0"},
      {"control_period NaN", [](SegmentHeader* h) { h->control_period = NAN; },
       "control_period = nan"},
      {"physics_period", [](SegmentHeader* h) { h->physics_period = -0.001; },
       "physics_period = -0.001 must be in [0, control_period = 0.005]"},
      {"read_timeout_hint", [](SegmentHeader* h) { h->read_timeout_hint = INFINITY; },
       "read_timeout_hint = inf"},
      {"total_mass", [](SegmentHeader* h) { h->total_mass = -3.0; }, "total_mass = -3"},
  };
  for (const CorruptHeader& c : cases) {
    SCOPED_TRACE(c.what);
    auto producer = Create();
    ASSERT_NE(producer, nullptr);
    RawSegment raw(name_);
    c.corrupt(&raw.get()->header);
    RobotAdaptor adaptor;
    const Status s = adaptor.open(name_);
    EXPECT_EQ(s.code, Error::kInvalidHeader) << s.message;
    EXPECT_TRUE(Contains(s.message, c.expected)) << s.message;
    EXPECT_TRUE(Contains(s.message, "segment '" + name_ + "'")) << s.message;
    EXPECT_FALSE(adaptor.is_open());
    EXPECT_EQ(producer->controller_pid(), 0);  // nothing stays attached
  }
}

TEST_F(AdaptorTest, OpenAcceptsUnlimitedJointsAndAHardwarePeriod) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  raw.get()->header.q_min[0] = -INFINITY;  // a joint without limits
  raw.get()->header.q_max[0] = INFINITY;
  raw.get()->header.tau_max[1] = INFINITY;
  raw.get()->header.physics_period = 0.0;  // hardware
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_TRUE(s.ok()) << s.message;
}

}  // namespace
}  // namespace ohrp::shm
