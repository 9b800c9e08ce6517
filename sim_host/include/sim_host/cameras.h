// sim_host's cameras: the robot's cameras (RobotMap::cameras, the header's cameras in that
// order) rendered offscreen with MuJoCo's renderer on OSMesa (render/offscreen.h) and published
// into the segment's image slots (shm_bridge/images.h), at a rate of simulated time, and only
// while some attached program asks for them (Producer::ImagesRequested).
//
// With a recorder (sim_host --record-images) every camera renders at every frame time, asked
// or not, and each image goes to the run folder too (image_recorder.h).
//
// Cost when nobody asks: one comparison per control cycle, and at each frame time (e.g. 30 Hz of
// simulated time) a look at the segment's request entries (16 loads). Nothing is set up: the
// OSMesa context, MuJoCo's rendering context and a second mjData for the camera poses are made
// at the first request (tens of milliseconds, once). A frame renders the state at the end of the
// control cycle (the time of the sensors published with it) in its own mjData, so the
// simulation's mjData is never touched.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/offscreen.h"
#include "shm_bridge/bridge.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {

class ImageRecorder;

struct CameraOptions {
  double rate = 30.0;    // frames per second of simulated time, per requested camera
  int width = 640;       // image size [pixel] (<= shm::kMaxImageWidth x kMaxImageHeight)
  int height = 480;
  bool depth = true;     // publish the depth image [m] beside the RGB one
};

// Parses "WxH" (e.g. 320x240) within the image slots' capacity. False with `*error`.
bool ParseCameraSize(const std::string& text, int* width, int* height, std::string* error);

class Cameras {
 public:
  // `enabled` false (the effect is off, or the scene has no camera): Tick never renders.
  Cameras(const model::RobotMap& robot, const CameraOptions& options, bool enabled);
  ~Cameras();

  // Once per control cycle, after the physics steps: when a frame is due (simulated time) and
  // some camera is requested, renders the requested cameras from `d`'s state and publishes them
  // (capture time d->time). Returns false once, with `*error`, when the renderer cannot be set
  // up (then the cameras stay off).
  bool Tick(mjModel* m, const mjData* d, shm::Producer* producer, std::string* error);

  // Every camera rendered at every frame time, published (when asked) and handed to
  // `recorder` (sim_host --record-images; not owned; null: none).
  void Record(ImageRecorder* recorder) { recorder_ = recorder; }

  uint64_t frames() const { return frames_; }        // camera images published
  double render_seconds() const { return seconds_; }  // wall time spent rendering them [s]
  bool rendering() const { return renderer_ != nullptr; }

 private:
  bool SetUp(mjModel* m, std::string* error);

  std::vector<int> camera_ids_;  // MuJoCo camera id of header camera i
  CameraOptions options_;
  bool enabled_ = false;
  double next_frame_ = 0.0;      // simulated time of the next frame [s]
  std::unique_ptr<render::Offscreen> renderer_;
  mjData* pose_ = nullptr;       // the camera poses' own mjData
  std::vector<uint8_t> rgb_;
  std::vector<float> depth_;
  uint64_t frames_ = 0;
  double seconds_ = 0.0;
  ImageRecorder* recorder_ = nullptr;
};

}  // namespace ohrp::sim
