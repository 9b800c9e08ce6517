// Recorded camera images for the replay plugin: a folder with an index of times and one binary
// PPM file per frame (the format: hw_driver/README.md, "Recorded images"), loaded whole at
// open and played by time, the latest frame at or before the replay's time per camera.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hw_driver/robot_io.h"

namespace ohrp::hw::replay {

struct ImageFrame {
  double time = 0.0;          // recording time [s] (the CSV log's time base)
  int width = 0, height = 0;  // [pixel]
  std::vector<uint8_t> rgb;   // width x height x 3, top row first
};

class ImageFrames {
 public:
  // Reads `dir`/index.csv (header `time,camera,file`; one row per frame; camera: a name of
  // `cameras`; file: a binary PPM (P6, maxval 255) relative to `dir`, at most the camera's
  // size; times not decreasing per camera). False with `*error` naming the file and line.
  bool Load(const std::string& dir, const std::vector<shm::CameraInfo>& cameras,
            std::string* error);

  // Called per cycle with the recording's time `t` [s]: per camera, the newest frame at or
  // before `t`; the ones of `wanted` cameras not yet handed out go to `sink` with the capture
  // time `driver_time - (t - frame time)`. A time before the last call (a looping replay)
  // starts the cameras over. Never allocates.
  void Play(double t, uint32_t wanted, double driver_time, ImageSink* sink) noexcept;

  size_t frames(int camera) const { return frames_[camera].size(); }
  int cameras() const { return static_cast<int>(frames_.size()); }
  uint64_t published() const { return published_; }

 private:
  std::vector<std::vector<ImageFrame>> frames_;  // per camera, by time
  std::vector<int> current_;                     // per camera: newest frame <= t (-1: none)
  std::vector<int> handed_;                      // per camera: last frame given to the sink
  double last_t_ = -1e300;
  uint64_t published_ = 0;
};

// Reads a binary PPM (P6, maxval 255; comments allowed in the header) into `*frame`'s size and
// pixels. False with `*error` naming the file.
bool ReadPpm(const std::string& path, ImageFrame* frame, std::string* error);

}  // namespace ohrp::hw::replay
