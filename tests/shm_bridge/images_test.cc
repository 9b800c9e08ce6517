// Tests the camera images of the segment (images.h): a frame published is read back whole with
// its counter and capture time; a reader racing a writer that rewrites the slots without pause
// never gets a torn frame (while a plain copy of the same memory does, so the check is what
// protects it); requests of the controller and of observers reach the producer and are
// withdrawn at close or when the requesting process dies; sizes beyond the header's camera or
// the slots are refused.
#include "shm_bridge/images.h"

#include <gtest/gtest.h>
#include <sched.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "shm_bridge/bridge.h"
#include "shm_bridge/checks.h"
#include "shm_bridge/observer.h"
#include "test_util.h"

namespace ohrp::shm {
namespace {

using testing::RawSegment;
using testing::Spawn;
using testing::WaitExit;

CameraInfo Camera(const char* name, int width, int height) {
  CameraInfo c{};
  std::strncpy(c.name, name, kNameLen - 1);
  c.width = width;
  c.height = height;
  c.fovy = 45.0;
  return c;
}

// the torn-frame test's size: copies long enough to be lapped by the writer, short enough for
// many of them in a second (at 640x480 reader and writer sweep the slot in the same direction
// and an unchecked copy tears only about once in 50, here about once in 6)
constexpr int kTornWidth = 160, kTornHeight = 120;

class ImagesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = testing::UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    testing::RemoveSegment(name_);
    ProducerConfig c = testing::SmallConfig(name_);
    c.cameras = {Camera("left", kMaxImageWidth, kMaxImageHeight), Camera("small", 32, 24),
                 Camera("mid", kTornWidth, kTornHeight)};
    Status status;
    producer_ = Producer::Create(c, &status);
    ASSERT_TRUE(status.ok()) << status.message;
    out_ = std::make_unique<ImageSlot>();
  }
  void TearDown() override {
    producer_.reset();
    testing::RemoveSegment(name_);
  }

  std::string name_;
  std::unique_ptr<Producer> producer_;
  std::unique_ptr<ImageSlot> out_;
};

// pixel (x, y) of a test pattern that differs at every pixel, channel and frame
uint8_t Pattern(int x, int y, int c, uint64_t frame) {
  return static_cast<uint8_t>(x * 7 + y * 13 + c * 101 + static_cast<int>(frame) * 29);
}

TEST_F(ImagesTest, AFramePublishedIsReadBackWholeWithItsCounterAndTime) {
  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  EXPECT_EQ(adaptor.read_image(1, 0, out_.get()), ImageResult::kNoFrame);

  const int w = 32, h = 24;
  for (uint64_t frame = 1; frame <= 3; ++frame) {
    std::vector<uint8_t> rgb(3 * w * h);
    std::vector<float> depth(w * h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) rgb[3 * (y * w + x) + c] = Pattern(x, y, c, frame);
        depth[y * w + x] = 0.5f + 0.01f * static_cast<float>(x + y) + static_cast<float>(frame);
      }
    }
    const double time = 0.1 * static_cast<double>(frame);
    ASSERT_EQ(producer_->PublishImage(1, time, w, h, rgb.data(), frame == 2 ? nullptr : depth.data()),
              ImageResult::kOk);
    ASSERT_EQ(adaptor.read_image(1, frame - 1, out_.get()), ImageResult::kOk);
    EXPECT_EQ(out_->frame, frame);
    EXPECT_EQ(out_->time, time);
    EXPECT_EQ(out_->width, w);
    EXPECT_EQ(out_->height, h);
    EXPECT_EQ(out_->has_depth, frame == 2 ? 0u : 1u);
    EXPECT_EQ(std::memcmp(out_->rgb, rgb.data(), rgb.size()), 0) << "frame " << frame;
    if (frame != 2) {
      EXPECT_EQ(std::memcmp(out_->depth, depth.data(), depth.size() * sizeof(float)), 0);
    }
    // nothing newer yet; the other camera has none at all
    EXPECT_EQ(adaptor.read_image(1, frame, out_.get()), ImageResult::kNoFrame);
    EXPECT_EQ(adaptor.read_image(0, 0, out_.get()), ImageResult::kNoFrame);
  }
  EXPECT_EQ(adaptor.read_image(3, 0, out_.get()), ImageResult::kBadCamera);
  EXPECT_EQ(adaptor.read_image(-1, 0, out_.get()), ImageResult::kBadCamera);
}

TEST_F(ImagesTest, PublishRefusesSizesBeyondTheHeadersCameraAndUnknownCameras) {
  std::vector<uint8_t> rgb(3 * kMaxImageWidth * (kMaxImageHeight + 1));
  EXPECT_EQ(producer_->PublishImage(1, 0.0, 33, 24, rgb.data()), ImageResult::kBadSize);
  EXPECT_EQ(producer_->PublishImage(1, 0.0, 32, 25, rgb.data()), ImageResult::kBadSize);
  EXPECT_EQ(producer_->PublishImage(1, 0.0, 0, 24, rgb.data()), ImageResult::kBadSize);
  EXPECT_EQ(producer_->PublishImage(0, 0.0, kMaxImageWidth, kMaxImageHeight + 1, rgb.data()),
            ImageResult::kBadSize);
  EXPECT_EQ(producer_->PublishImage(3, 0.0, 8, 8, rgb.data()), ImageResult::kBadCamera);
  // a smaller frame than the camera's size is allowed
  EXPECT_EQ(producer_->PublishImage(0, 0.0, 320, 240, rgb.data()), ImageResult::kOk);
}

TEST(ImagesConfig, CreateRefusesACameraLargerThanTheSlots) {
  const std::string name = testing::UniqueSegment("images_config");
  for (const CameraInfo& cam : {Camera("big", kMaxImageWidth + 1, kMaxImageHeight),
                                Camera("big", kMaxImageWidth, kMaxImageHeight + 1)}) {
    ProducerConfig c = testing::SmallConfig(name);
    c.cameras = {cam};
    Status status;
    EXPECT_EQ(Producer::Create(c, &status), nullptr);
    EXPECT_EQ(status.code, Error::kInvalidConfig);
    EXPECT_NE(status.message.find("cameras[0] 'big' has size " + std::to_string(cam.width) + "x" +
                                  std::to_string(cam.height) + ", larger than the segment's "
                                  "image slots (640x480)"),
              std::string::npos)
        << status.message;
  }
}

TEST_F(ImagesTest, AttachRefusesAHeaderCameraLargerThanTheSlots) {
  RawSegment raw(name_);
  raw.get()->header.cameras[0].width = kMaxImageWidth + 1;
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kInvalidHeader);
  EXPECT_NE(s.message.find("cameras[0] has size 641x480"), std::string::npos) << s.message;
}

//---------------- torn frames ----------------

// The writer below publishes frame f from buffer f % 4, every byte of its rgb and every depth
// equal to 1 + f % 4: successive frames of one slot (f and f + 2) differ everywhere.
uint8_t FrameValue(uint64_t frame) { return static_cast<uint8_t>(1 + frame % 4); }

// true when the frame is whole: every value the one its frame counter gives
bool Uniform(const ImageSlot& s) {
  const uint8_t v = FrameValue(s.frame);
  const std::size_t n = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    if (s.rgb[i] != v) return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (s.depth[i] != static_cast<float>(v)) return false;
  }
  return true;
}

// What ReadLatestImage does without its seqlock check: the latest slot's fields and pixels
// copied as they are. The test below runs it beside the real read to show that the writer does
// tear frames under the reader, so that a reader without the check would fail it.
void UncheckedCopy(const CameraImages& images, ImageSlot* out) {
  const uint64_t f = std::atomic_ref<uint64_t>(const_cast<uint64_t&>(images.latest)).load();
  const ImageSlot& slot = images.slot[f % kImageSlots];
  std::memcpy(static_cast<void*>(out), &slot, offsetof(ImageSlot, rgb));
  const std::size_t n = static_cast<std::size_t>(kTornWidth) * kTornHeight;
  std::memcpy(out->rgb, slot.rgb, 3 * n);
  std::memcpy(out->depth, slot.depth, sizeof(float) * n);
}

// Puts the calling process on the `index`-th CPU it may use; false when it may use fewer.
bool PinToCpu(int index, cpu_set_t* previous) {
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof(allowed), &allowed) != 0) return false;
  if (previous != nullptr) *previous = allowed;
  for (int cpu = 0, seen = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (!CPU_ISSET(cpu, &allowed) || seen++ != index) continue;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    return sched_setaffinity(0, sizeof(one), &one) == 0;
  }
  return false;
}

TEST_F(ImagesTest, AReaderNeverSeesATornFrameWhileTheWriterRewritesWithoutPause) {
  // the writer: another process publishing frames back to back (no work between them) on a CPU
  // of its own, so that it laps a reader inside its copy
  const pid_t writer = Spawn([this] {
    PinToCpu(0, nullptr);
    constexpr std::size_t kPixels = kTornWidth * kTornHeight;
    std::vector<std::vector<uint8_t>> rgb(4);
    std::vector<std::vector<float>> depth(4);
    for (uint64_t b = 0; b < 4; ++b) {
      rgb[b].assign(3 * kPixels, FrameValue(b));
      depth[b].assign(kPixels, static_cast<float>(FrameValue(b)));
    }
    for (uint64_t frame = 1;; ++frame) {
      if (producer_->PublishImage(2, 1e-3 * static_cast<double>(frame), kTornWidth, kTornHeight,
                                  rgb[frame % 4].data(),
                                  depth[frame % 4].data()) != ImageResult::kOk) {
        return 3;
      }
    }
    return 0;
  });
  ASSERT_GT(writer, 0);
  cpu_set_t previous;
  const bool pinned = PinToCpu(1, &previous);
  if (!pinned) std::printf("one CPU only: the reader and the writer share it\n");

  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  ASSERT_TRUE(
      testing::WaitFor([&] { return adaptor.read_image(2, 0, out_.get()) == ImageResult::kOk; }));

  // in turn, in the same conditions: the read through the seqlock (every frame whole, the
  // counter only moving forward) and the unchecked copy (torn frames: the test can fail)
  RawSegment raw(name_);
  const CameraImages& images = raw.get()->images.camera[2];
  auto plain_out = std::make_unique<ImageSlot>();
  int whole = 0, torn = 0, busy = 0, plain = 0, plain_torn = 0;
  uint64_t last = 0;
  const double end = MonotonicSeconds() + 5.0;
  while (MonotonicSeconds() < end && (whole < 200 || plain_torn < 5)) {
    const ImageResult r = adaptor.read_image(2, last, out_.get());
    if (r == ImageResult::kBusy) ++busy;
    if (r == ImageResult::kOk) {
      EXPECT_GT(out_->frame, last);
      last = out_->frame;
      (Uniform(*out_) ? whole : torn) += 1;
    }
    UncheckedCopy(images, plain_out.get());
    ++plain;
    if (!Uniform(*plain_out)) ++plain_torn;
  }
  const uint64_t written = std::atomic_ref<uint64_t>(const_cast<uint64_t&>(images.latest)).load();
  kill(writer, SIGKILL);
  WaitExit(writer);
  if (pinned) sched_setaffinity(0, sizeof(previous), &previous);

  std::printf("%lu frames written; seqlocked reads: %d whole, %d torn, %d busy; unchecked "
              "copies: %d torn of %d\n",
              static_cast<unsigned long>(written), whole, torn, busy, plain_torn, plain);
  EXPECT_EQ(torn, 0);
  EXPECT_GE(whole, 10);
  EXPECT_GT(plain_torn, 0) << "the writer never tore a frame under the reader: the test "
                              "cannot tell a reader with the seqlock check from one without";
}

//---------------- requests ----------------

TEST_F(ImagesTest, RequestsOfTheControllerAndObserversReachTheProducerAndAreWithdrawnAtClose) {
  EXPECT_EQ(producer_->ImagesRequested(), 0u);
  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  EXPECT_FALSE(adaptor.request_images(0b1000)) << "camera 3 does not exist";
  ASSERT_TRUE(adaptor.request_images(0b01));
  EXPECT_EQ(producer_->ImagesRequested(), 0b01u);

  // an observer in another process (the same process would share the controller's entry)
  testing::Pipe asked, done;
  const pid_t viewer = Spawn([&] {
    Observer o;
    if (!o.open(name_).ok() || !o.request_images(0b10)) return 3;
    asked.Send();
    done.Receive(10.0);
    o.close();
    asked.Send();
    done.Receive(10.0);
    return 0;
  });
  ASSERT_TRUE(asked.Receive());
  EXPECT_EQ(producer_->ImagesRequested(), 0b11u);

  ASSERT_TRUE(adaptor.request_images(0b10));  // changes its own entry, takes no other
  EXPECT_EQ(producer_->ImagesRequested(), 0b10u);
  ASSERT_TRUE(adaptor.request_images(0b01));
  adaptor.close();
  EXPECT_EQ(producer_->ImagesRequested(), 0b10u);

  done.Send();
  ASSERT_TRUE(asked.Receive());  // the observer closed, its process still alive
  EXPECT_EQ(producer_->ImagesRequested(), 0u);
  done.Send();
  EXPECT_EQ(WaitExit(viewer), 0);
}

TEST_F(ImagesTest, ARequestOfADeadProcessIsIgnoredAndItsEntryReused) {
  testing::Pipe asked;
  const pid_t child = Spawn([&] {
    RobotAdaptor a;
    if (!a.open(name_).ok() || !a.request_images(0b11)) return 3;
    asked.Send();
    pause();  // killed while holding its request: close never runs
    return 0;
  });
  ASSERT_TRUE(asked.Receive());
  EXPECT_EQ(producer_->ImagesRequested(), 0b11u);
  kill(child, SIGKILL);
  EXPECT_EQ(WaitExit(child), 128 + SIGKILL);
  EXPECT_EQ(producer_->ImagesRequested(), 0u);

  // every entry: the first kMaxImageRequesters processes get one, the next is refused
  std::vector<pid_t> holders;
  for (int i = 0; i < kMaxImageRequesters; ++i) {
    holders.push_back(Spawn([&] {
      Observer o;
      if (!o.open(name_).ok() || !o.request_images(0b01)) return 3;
      asked.Send();
      pause();
      return 0;
    }));
    ASSERT_TRUE(asked.Receive()) << "requester " << i;
  }
  Observer late;
  ASSERT_TRUE(late.open(name_).ok());
  EXPECT_FALSE(late.request_images(0b10));
  EXPECT_EQ(producer_->ImagesRequested(), 0b01u);
  kill(holders.back(), SIGKILL);
  EXPECT_EQ(WaitExit(holders.back()), 128 + SIGKILL);
  EXPECT_TRUE(late.request_images(0b10)) << "the dead holder's entry is reused";
  EXPECT_EQ(producer_->ImagesRequested(), 0b11u);
  holders.pop_back();
  for (pid_t p : holders) {
    kill(p, SIGKILL);
    WaitExit(p);
  }
  EXPECT_EQ(producer_->ImagesRequested(), 0b10u);
}

}  // namespace
}  // namespace ohrp::shm
