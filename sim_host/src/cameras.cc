// sim_host's cameras (cameras.h).
#include "sim_host/cameras.h"

#include "image_recorder.h"
#include "shm_bridge/clock.h"

#include <time.h>

#include <cstdio>
#include <cstdlib>

namespace ohrp::sim {
namespace {

}  // namespace

bool ParseCameraSize(const std::string& text, int* width, int* height, std::string* error) {
  int w = 0, h = 0, used = 0;
  if (std::sscanf(text.c_str(), "%dx%d%n", &w, &h, &used) != 2 ||
      used != static_cast<int>(text.size()) || w <= 0 || h <= 0 || w > shm::kMaxImageWidth ||
      h > shm::kMaxImageHeight) {
    *error = "camera size '" + text + "' must be WIDTHxHEIGHT within 1x1 to " +
             std::to_string(shm::kMaxImageWidth) + "x" + std::to_string(shm::kMaxImageHeight) +
             " (the segment's image slots), e.g. 320x240";
    return false;
  }
  *width = w;
  *height = h;
  return true;
}

Cameras::Cameras(const model::RobotMap& robot, const CameraOptions& options, bool enabled)
    : options_(options), enabled_(enabled && !robot.cameras.empty() && options.rate > 0) {
  for (const model::CameraMap& c : robot.cameras) camera_ids_.push_back(c.camera_id);
}

Cameras::~Cameras() {
  renderer_.reset();  // MuJoCo's context and OSMesa's, before the data
  if (pose_ != nullptr) mj_deleteData(pose_);
}

bool Cameras::SetUp(mjModel* m, std::string* error) {
  render::OffscreenOptions ro;
  ro.width = options_.width;
  ro.height = options_.height;
  ro.samples = 0;  // each pixel's own depth and colour (offscreen.h)
  renderer_ = render::Offscreen::Create(m, ro, error);
  if (!renderer_) {
    enabled_ = false;
    return false;
  }
  pose_ = mj_makeData(m);
  const std::size_t pixels = static_cast<std::size_t>(options_.width) * options_.height;
  rgb_.resize(3 * pixels);
  if (options_.depth) depth_.resize(pixels);
  return true;
}

bool Cameras::Tick(mjModel* m, const mjData* d, shm::Producer* producer, std::string* error) {
  if (!enabled_ || d->time < next_frame_) return true;
  const double period = 1.0 / options_.rate;
  while (next_frame_ <= d->time) next_frame_ += period;
  const uint32_t asked = producer->ImagesRequested();
  const uint32_t all = camera_ids_.size() >= 32 ? ~0u : (1u << camera_ids_.size()) - 1;
  const uint32_t wanted = recorder_ ? all : asked;
  if (wanted == 0) return true;
  if (!renderer_ && !SetUp(m, error)) return false;

  const double start = MonotonicSeconds();
  // the camera poses at the end of the cycle, in the cameras' own mjData
  pose_->time = d->time;
  mju_copy(pose_->qpos, d->qpos, m->nq);
  if (m->nmocap > 0) {
    mju_copy(pose_->mocap_pos, d->mocap_pos, 3 * m->nmocap);
    mju_copy(pose_->mocap_quat, d->mocap_quat, 4 * m->nmocap);
  }
  mj_kinematics(m, pose_);
  mj_comPos(m, pose_);
  mj_camlight(m, pose_);
  for (std::size_t i = 0; i < camera_ids_.size(); ++i) {
    if ((wanted & (1u << i)) == 0) continue;
    mjvCamera cam;
    mjv_defaultCamera(&cam);
    cam.type = mjCAMERA_FIXED;
    cam.fixedcamid = camera_ids_[i];
    renderer_->Draw(m, pose_, &cam, options_.width, options_.height);
    renderer_->Read(options_.width, options_.height, rgb_.data(),
                    options_.depth ? depth_.data() : nullptr);
    if (asked & (1u << i))
      producer->PublishImage(static_cast<int>(i), d->time, options_.width, options_.height,
                             rgb_.data(), options_.depth ? depth_.data() : nullptr);
    if (recorder_)
      recorder_->Push(static_cast<int>(i), d->time, rgb_.data(), options_.depth ? depth_.data() : nullptr);
    ++frames_;
  }
  seconds_ += MonotonicSeconds() - start;
  return true;
}

}  // namespace ohrp::sim
