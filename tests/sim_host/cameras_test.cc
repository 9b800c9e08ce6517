// Tests sim_host's cameras as a process (sim_host/cameras.h): nothing is rendered while nobody
// asks; once an observer asks for the left camera, frames arrive at the camera rate of
// simulated time, the other camera stays dark, and the depth image is the floor's distance
// along the optical axis that a pinhole camera at the camera's pose computes (MuJoCo's
// kinematics in this process, not the renderer); once the request is withdrawn the frames stop.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "../shm_bridge/test_util.h"
#include "common/scratch.h"
#include "shm_bridge/observer.h"

namespace ohrp::sim {
namespace {

using shm::testing::Spawn;
using shm::testing::WaitExit;
using shm::testing::WaitFor;

const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
constexpr int kWidth = 160, kHeight = 120;
constexpr double kRate = 20.0;  // frames per simulated second

using ohrp::testing::ReadFile;

// the expected depth [m] of pixel (u, v) (top row first) of camera `cam`: where the ray of a
// pinhole camera with MuJoCo's convention (looking along -z, y up, fovy vertical) meets the
// floor z = 0, as a distance along the optical axis
double FloorDepth(const mjModel* m, const mjData* d, int cam, double u, double v) {
  const double f = 0.5 * kHeight / std::tan(0.5 * m->cam_fovy[cam] * M_PI / 180.0);
  const double dc[3] = {(u + 0.5 - 0.5 * kWidth) / f, -(v + 0.5 - 0.5 * kHeight) / f, -1.0};
  const double* R = d->cam_xmat + 9 * cam;  // camera axes in world, row-major
  double dw[3];
  for (int i = 0; i < 3; ++i) dw[i] = R[3 * i] * dc[0] + R[3 * i + 1] * dc[1] + R[3 * i + 2] * dc[2];
  const double z = d->cam_xpos[3 * cam + 2];
  return dw[2] < 0 ? -z / dw[2] : INFINITY;  // the ray's parameter is the axial distance
}

TEST(SimHostCameras, RenderOnlyWhileAskedAtTheRateWithTheFloorsDepth) {
  const std::string segment = "cams_" + std::to_string(getpid());
  const std::string err = ohrp::testing::ScratchPath("sim_host", ".stderr");
  const pid_t host = Spawn({std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", kScene,
                            "--keyframe", "halfsit", "--segment", segment, "--wait-controller",
                            "0", "--duration", "0", "--realtime", "--progress", "0",
                            "--camera-size", "160x120", "--camera-rate", "20"},
                           {.err = err});
  shm::Observer o;
  ASSERT_TRUE(WaitFor([&] { return o.open(segment).ok(); }, 10.0)) << ReadFile(err);
  ASSERT_EQ(o.header().ncamera, 2);
  EXPECT_STREQ(o.header().cameras[0].name, "LeftCamera");
  EXPECT_EQ(o.header().cameras[0].width, kWidth);
  EXPECT_EQ(o.header().cameras[0].height, kHeight);

  // nobody asks: after half a simulated second, no camera has a frame
  shm::SensorBlock s{};
  ASSERT_TRUE(WaitFor([&] { return o.read(&s, 1.0) == shm::ReadResult::kOk && s.time > 0.5; }, 10.0));
  auto image = std::make_unique<shm::ImageSlot>();
  EXPECT_EQ(o.read_image(0, 0, image.get()), shm::ImageResult::kNoFrame);
  EXPECT_EQ(o.read_image(1, 0, image.get()), shm::ImageResult::kNoFrame);

  // the left camera asked for: frames at the rate, the right one still dark
  ASSERT_TRUE(o.request_images(0b01));
  const double asked_at = s.time;
  // the frames, and the sensors published with the last one (same cycle, same time): the
  // observer sees every cycle (real time, 5 ms) and keeps the last block it read
  std::vector<std::pair<uint64_t, double>> frames;  // counter, capture time
  shm::SensorBlock at_frame{};
  bool matched = false;
  ASSERT_TRUE(WaitFor([&] {
    if (o.read(&s, 0.1) == shm::ReadResult::kOk && !frames.empty() && !matched &&
        s.time == frames.back().second) {
      at_frame = s;
      matched = true;
    }
    if (o.read_image(0, frames.empty() ? 0 : frames.back().first, image.get()) == shm::ImageResult::kOk) {
      frames.emplace_back(image->frame, image->time);
      matched = s.time == image->time;  // its sensors were read just before
      if (matched) at_frame = s;
    }
    return frames.size() >= 6 && matched;
  }, 20.0)) << frames.size() << " frames; " << ReadFile(err);
  EXPECT_EQ(o.read_image(1, 0, image.get()), shm::ImageResult::kNoFrame);
  EXPECT_GE(frames.front().second, asked_at - 1e-9);
  int consecutive = 0;
  for (size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].first != frames[i - 1].first + 1) continue;
    ++consecutive;
    // one frame per 1/rate of simulated time, at the end of the first control cycle past it
    EXPECT_NEAR(frames[i].second - frames[i - 1].second, 1.0 / kRate, 0.005 + 1e-9);
  }
  EXPECT_GE(consecutive, 2);

  // the last frame: size, depth, and the floor's depth from the camera's pose
  ASSERT_EQ(image->width, kWidth);
  ASSERT_EQ(image->height, kHeight);
  ASSERT_EQ(image->has_depth, 1u);
  char error[1000] = "";
  mjModel* m = mj_loadXML(kScene.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  const int key = mj_name2id(m, mjOBJ_KEY, "halfsit");
  const int cam = mj_name2id(m, mjOBJ_CAMERA, "LeftCamera");
  ASSERT_GE(key, 0);
  ASSERT_GE(cam, 0);
  // the robot's pose when the frame was taken: the base's ground truth and the joint angles
  // published with it
  s = at_frame;
  mju_copy(d->qpos, m->key_qpos + key * m->nq, m->nq);
  const int base = mj_name2id(m, mjOBJ_JOINT, "root");  // HRP-1S's free joint
  ASSERT_GE(base, 0) << "the scene's free joint";
  mju_copy(d->qpos + m->jnt_qposadr[base], s.sim_truth.p_WB, 3);
  mju_copy(d->qpos + m->jnt_qposadr[base] + 3, s.sim_truth.quat_WB, 4);
  for (int j = 0; j < o.header().njoint; ++j) {
    const int id = mj_name2id(m, mjOBJ_JOINT, o.header().joint_names[j]);
    ASSERT_GE(id, 0) << o.header().joint_names[j];
    d->qpos[m->jnt_qposadr[id]] = s.q[j];
  }
  mj_kinematics(m, d);
  mj_camlight(m, d);
  // 0.2 % of the range (the depth buffer resolves millimetres at these ranges of 1.6 to 8 m)
  const struct {
    int u, v;
  } pixels[] = {{kWidth / 2, kHeight / 2}, {kWidth / 2, 5}, {kWidth / 2, kHeight - 6},
                {10, kHeight / 2}, {kWidth - 11, kHeight - 20}};
  double top = 0, bottom = 0;
  for (const auto& p : pixels) {
    const double expected = FloorDepth(m, d, cam, p.u, p.v);
    const double got = image->depth[p.v * kWidth + p.u];
    EXPECT_NEAR(got, expected, 0.002 * expected) << "pixel (" << p.u << ", " << p.v << ")";
    if (p.v == 5) top = got;
    if (p.v == kHeight - 6) bottom = got;
  }
  EXPECT_GT(top, bottom) << "the top row looks farther along the floor (rows top first)";
  // the floor's checker texture: more than one colour in the image
  int differing = 0;
  for (int i = 1; i < kWidth * kHeight; ++i) differing += image->rgb[3 * i] != image->rgb[0];
  EXPECT_GT(differing, kWidth * kHeight / 10);
  mj_deleteData(d);
  mj_deleteModel(m);

  // withdrawn: no new frame over a simulated second
  ASSERT_TRUE(o.request_images(0));
  ASSERT_EQ(o.read(&s, 1.0), shm::ReadResult::kOk);
  const double asked_off = s.time;  // a frame begun before the withdrawal is published by now:
  ASSERT_TRUE(WaitFor([&] { return o.read(&s, 1.0) == shm::ReadResult::kOk && s.time > asked_off + 0.02; }));
  const uint64_t last = o.read_image(0, 0, image.get()) == shm::ImageResult::kOk ? image->frame : 0;
  const double withdrawn_at = s.time;
  ASSERT_TRUE(WaitFor([&] { return o.read(&s, 1.0) == shm::ReadResult::kOk && s.time > withdrawn_at + 1.0; }, 10.0));
  EXPECT_EQ(o.read_image(0, last, image.get()), shm::ImageResult::kNoFrame) << "frame " << image->frame;

  o.close();
  kill(host, SIGINT);
  EXPECT_EQ(WaitExit(host, 10.0), 130) << ReadFile(err);
  EXPECT_NE(ReadFile(err).find("sim_host: cameras: "), std::string::npos) << ReadFile(err);
  std::filesystem::remove(err);
}

}  // namespace
}  // namespace ohrp::sim
