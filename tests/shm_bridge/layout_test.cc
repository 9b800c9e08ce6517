// Tests the layout's identity (LayoutHash, FNV-1a) and the header checks (CheckHeader,
// SanitizedHeader) on headers built in memory.
#include "shm_bridge/layout.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include "common/process.h"
#include "shm_bridge/bridge.h"

#include <cstring>
#include <string>
#include <type_traits>

#include "shm_bridge/checks.h"

namespace ohrp::shm {
namespace {

// a header as a producer of this build writes it
SegmentHeader GoodHeader() {
  SegmentHeader h{};
  std::memcpy(h.magic, kMagic, sizeof(kMagic));
  h.layout_version = kLayoutVersion;
  h.header_size = sizeof(SegmentHeader);
  h.layout_hash = LayoutHash();
  h.segment_size = sizeof(Segment);
  h.state = static_cast<uint32_t>(ProducerState::kRunning);
  h.njoint = 3;
  return h;
}

//---------------- layout hash ----------------

TEST(LayoutHash, Fnv1aMatchesKnownVectors) {
  // reference values of 64-bit FNV-1a
  EXPECT_EQ(Fnv1a64("", 0), 0xcbf29ce484222325ull);
  EXPECT_EQ(Fnv1a64("a", 1), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(Fnv1a64("foobar", 6), 0x85944171f73967e8ull);
  static_assert(Fnv1a64("a", 1) == 0xaf63dc4c8601ec8cull, "usable at compile time");
}

TEST(LayoutHash, IsDeterministicAndNotTrivial) {
  const uint64_t h = LayoutHash();
  EXPECT_EQ(h, LayoutHash());
  EXPECT_NE(h, 0u);
  EXPECT_NE(h, kFnv1aOffsetBasis);
}

// Golden value for this layout on x86-64/aarch64 Linux (wake-up words of 16 bytes). If it fails,
// the layout changed: bump kLayoutVersion (which changes the hash again) and update the value,
// so that old controllers are refused by new producers.
TEST(LayoutHash, MatchesTheRecordedLayout) {
  EXPECT_EQ(kLayoutVersion, 6u);
  EXPECT_EQ(LayoutHash(), 0xa48c1670e30d37bbull) << std::hex << "LayoutHash() = 0x" << LayoutHash();
}

TEST(Layout, BlocksAreTriviallyCopyableAndAligned) {
  static_assert(std::is_trivially_copyable_v<Segment>);
  static_assert(std::is_standard_layout_v<Segment>);
  EXPECT_EQ(offsetof(Segment, sensors) % 64, 0u);
  EXPECT_EQ(offsetof(Segment, commands) % 64, 0u);
  EXPECT_EQ(offsetof(Segment, sync) % 64, 0u);
  // the image requests alone on a page (an observer maps that page for writing), the slots
  // on cache lines
  EXPECT_EQ(offsetof(Segment, images) % 4096, 0u);
  EXPECT_EQ(offsetof(ImageArea, requests), 0u);
  EXPECT_GE(offsetof(ImageArea, camera), 4096u);
  EXPECT_EQ(offsetof(ImageSlot, seq), 0u);
  EXPECT_EQ(offsetof(ImageSlot, rgb) % 64, 0u);
  EXPECT_EQ(offsetof(SensorBlock, seq), 0u);
  EXPECT_EQ(offsetof(CommandBlock, seq), 0u);
}

//---------------- header checks ----------------

TEST(CheckHeader, AcceptsAHeaderOfThisBuild) {
  const Status s = CheckHeader(GoodHeader(), sizeof(Segment), "x");
  EXPECT_TRUE(s.ok()) << s.message;
}

TEST(CheckHeader, RefusesAnObjectSmallerThanASegment) {
  const Status s = CheckHeader(GoodHeader(), sizeof(Segment) - 1, "x");
  EXPECT_EQ(s.code, Error::kNotASegment);
  EXPECT_NE(s.message.find("/dev/shm/ohrp_x"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("smaller than a robot segment"), std::string::npos) << s.message;
}

TEST(CheckHeader, RefusesAWrongMagic) {
  SegmentHeader h = GoodHeader();
  h.magic[7] = '2';
  const Status s = CheckHeader(h, sizeof(Segment), "x");
  EXPECT_EQ(s.code, Error::kNotASegment);
  EXPECT_NE(s.message.find("magic"), std::string::npos) << s.message;
}

TEST(CheckHeader, RefusesAnotherLayoutVersionNamingBoth) {
  SegmentHeader h = GoodHeader();
  h.layout_version = kLayoutVersion + 1;
  const Status s = CheckHeader(h, sizeof(Segment), "x");
  EXPECT_EQ(s.code, Error::kLayoutMismatch);
  EXPECT_NE(s.message.find("version " + std::to_string(kLayoutVersion + 1)), std::string::npos)
      << s.message;
  EXPECT_NE(s.message.find("built with version " + std::to_string(kLayoutVersion)),
            std::string::npos)
      << s.message;
  EXPECT_NE(s.message.find("rebuild the controller against this producer's shm_bridge"),
            std::string::npos)
      << s.message;
}

TEST(CheckHeader, RefusesAnotherLayoutHash) {
  SegmentHeader h = GoodHeader();
  h.layout_hash ^= 1;
  const Status s = CheckHeader(h, sizeof(Segment), "x");
  EXPECT_EQ(s.code, Error::kLayoutMismatch);
  EXPECT_NE(s.message.find("hash 0x"), std::string::npos) << s.message;
}

TEST(CheckHeader, RefusesOtherSizes) {
  SegmentHeader h = GoodHeader();
  h.header_size += 8;
  EXPECT_EQ(CheckHeader(h, sizeof(Segment), "x").code, Error::kLayoutMismatch);
  h = GoodHeader();
  h.segment_size += 64;
  EXPECT_EQ(CheckHeader(h, sizeof(Segment) + 64, "x").code, Error::kLayoutMismatch);
}

TEST(SanitizedHeader, ClampsCountsAndTerminatesNames) {
  SegmentHeader h = GoodHeader();
  h.njoint = kMaxJoints + 5;
  h.nforce = -3;
  h.nimu = 1000;
  h.ncamera = kMaxCameras;
  std::memset(h.robot_name, 'r', kNameLen);
  std::memset(h.joint_names[kMaxJoints - 1], 'j', kNameLen);
  std::memset(h.cameras[0].name, 'c', kNameLen);
  const SegmentHeader s = SanitizedHeader(h);
  EXPECT_EQ(s.njoint, kMaxJoints);
  EXPECT_EQ(s.nforce, 0);
  EXPECT_EQ(s.nimu, kMaxImus);
  EXPECT_EQ(s.ncamera, kMaxCameras);
  EXPECT_EQ(std::strlen(s.robot_name), static_cast<std::size_t>(kNameLen - 1));
  EXPECT_EQ(std::strlen(s.joint_names[kMaxJoints - 1]), static_cast<std::size_t>(kNameLen - 1));
  EXPECT_EQ(std::strlen(s.cameras[0].name), static_cast<std::size_t>(kNameLen - 1));
}

}  // namespace
}  // namespace ohrp::shm

// A dead child that its parent has not reaped yet is a zombie: it must count as gone.
TEST(ProcessAliveTest, ZombieIsNotAlive) {
  const pid_t child = ohrp::testing::Spawn([] { return 0; });
  EXPECT_TRUE(ohrp::shm::ProcessAlive(getpid()));
  // give the child time to exit, without reaping it
  for (int i = 0; i < 200 && ohrp::shm::ProcessAlive(child); ++i) usleep(1000);
  EXPECT_FALSE(ohrp::shm::ProcessAlive(child));
  ohrp::testing::WaitExit(child, ohrp::testing::kNoTimeout);  // reaped
  EXPECT_FALSE(ohrp::shm::ProcessAlive(child));
}
