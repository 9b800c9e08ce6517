// Tests the C API (ohrp_shm.h) through a controller and an observer written in C
// (c_api_user.c): the header's names and counts, the lock-step with data checks, the default
// command values, the observer's read-only view and the refusals; camera images from C.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "c_api_user.h"
#include "ohrp_shm.h"
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

// the controller's guard record (issue 29) as a C observer reads it
TEST(CApiTest, AnObserverReadsTheGuardRecordFromC) {
  const std::string name = testing::UniqueSegment("capi_guard");
  testing::RemoveSegment(name);
  Status status;
  auto producer = Producer::Create(testing::SmallConfig(name), &status);
  ASSERT_TRUE(status.ok()) << status.message;
  RobotAdaptor controller;
  ASSERT_TRUE(controller.open(name).ok());
  char err[512];
  ohrp_robot* o = ohrp_observe(name.c_str(), 2.0, err, sizeof err);
  ASSERT_NE(o, nullptr) << err;
  int32_t holding = -1;
  EXPECT_EQ(ohrp_last_guard(o, &holding, nullptr, nullptr, nullptr, nullptr), 0);  // none yet
  SensorBlock& s = producer->BeginSensors();
  s.cycle = 3;
  producer->PublishSensors();
  SensorBlock in{};
  ASSERT_EQ(controller.read(&in), ReadResult::kOk);
  CommandBlock c{};
  c.njoint = 3;
  c.guard.holding = 1;
  c.guard.holds = 2;
  c.guard.distance = -0.0015;
  std::strcpy(c.guard.link_a, "WAIST_R");
  std::strcpy(c.guard.link_b, "RARM_WRIST_R");
  ASSERT_EQ(controller.write(c), ReadResult::kOk);
  uint64_t holds = 0;
  double distance = 0;
  char a[OHRP_NAME_LEN], b[OHRP_NAME_LEN];
  ASSERT_EQ(ohrp_last_guard(o, &holding, &holds, &distance, a, b), 1);
  EXPECT_EQ(holding, 1);
  EXPECT_EQ(holds, 2u);
  EXPECT_EQ(distance, -0.0015);
  EXPECT_STREQ(a, "WAIST_R");
  EXPECT_STREQ(b, "RARM_WRIST_R");
  ohrp_close(o);
}

TEST(CApiTest, ImagesAreAskedForAndReadFromC) {
  const std::string name = testing::UniqueSegment("capi_images");
  testing::RemoveSegment(name);
  ProducerConfig config = testing::SmallConfig(name);
  CameraInfo cam{};
  std::strcpy(cam.name, "eye");
  cam.width = 16;
  cam.height = 8;
  cam.fovy = 50.0;
  config.cameras = {cam};
  Status status;
  auto producer = Producer::Create(config, &status);
  ASSERT_TRUE(status.ok()) << status.message;

  char err[256] = {};
  ohrp_robot* r = ohrp_observe(name.c_str(), 1.0, err, sizeof err);
  ASSERT_NE(r, nullptr) << err;
  ASSERT_EQ(ohrp_ncamera(r), 1);
  EXPECT_STREQ(ohrp_camera_name(r, 0), "eye");
  EXPECT_EQ(ohrp_camera_index(r, "eye"), 0);
  EXPECT_EQ(ohrp_camera_index(r, "nose"), -1);
  int w = 0, h = 0;
  double fovy = 0;
  ASSERT_EQ(ohrp_camera_info(r, 0, &w, &h, &fovy), 1);
  EXPECT_EQ(w, 16);
  EXPECT_EQ(h, 8);
  EXPECT_EQ(fovy, 50.0);
  EXPECT_EQ(ohrp_camera_info(r, 1, &w, &h, &fovy), 0);

  EXPECT_EQ(ohrp_request_images(r, 0b10), 0) << "camera 1 does not exist";
  ASSERT_EQ(ohrp_request_images(r, 0b01), 1);
  EXPECT_EQ(producer->ImagesRequested(), 1u);

  std::vector<uint8_t> rgb(3 * 16 * 8), got(rgb.size());
  std::vector<float> depth(16 * 8), got_depth(depth.size());
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(i * 13);
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = 0.25f * static_cast<float>(i);
  uint64_t frame = 0;
  double time = 0;
  int has_depth = 0;
  EXPECT_EQ(ohrp_read_image(r, 0, 0, &frame, &time, &w, &h, &has_depth, got.data(), got.size(),
                            got_depth.data(), got_depth.size()),
            OHRP_IMAGE_NO_FRAME);
  ASSERT_EQ(producer->PublishImage(0, 1.25, 16, 8, rgb.data(), depth.data()), ImageResult::kOk);
  EXPECT_EQ(ohrp_read_image(r, 0, 0, &frame, &time, &w, &h, &has_depth, got.data(),
                            got.size() - 1, nullptr, 0),
            OHRP_IMAGE_TOO_SMALL);
  ASSERT_EQ(ohrp_read_image(r, 0, 0, &frame, &time, &w, &h, &has_depth, got.data(), got.size(),
                            got_depth.data(), got_depth.size()),
            OHRP_IMAGE_OK);
  EXPECT_EQ(frame, 1u);
  EXPECT_EQ(time, 1.25);
  EXPECT_EQ(has_depth, 1);
  EXPECT_EQ(got, rgb);
  EXPECT_EQ(got_depth, depth);
  EXPECT_EQ(ohrp_read_image(r, 0, frame, nullptr, nullptr, nullptr, nullptr, nullptr, got.data(),
                            got.size(), nullptr, 0),
            OHRP_IMAGE_NO_FRAME);
  EXPECT_EQ(ohrp_read_image(r, 3, 0, nullptr, nullptr, nullptr, nullptr, nullptr, got.data(),
                            got.size(), nullptr, 0),
            OHRP_IMAGE_BAD_CAMERA);
  ohrp_close(r);  // withdraws the request
  EXPECT_EQ(producer->ImagesRequested(), 0u);
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
