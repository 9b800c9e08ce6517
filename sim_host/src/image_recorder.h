// sim_host --record-images DIR (issue 33): every image the cameras render written to the run's
// folder, so that a replay shows what the robot saw. Per camera and frame DIR/CAMERA/NNNNNN.png
// (8-bit RGB) and, with depth, DIR/CAMERA/NNNNNN_depth.png (16-bit grey: the depth in millimetres,
// 0 where nothing is within 65.535 m); DIR/images.csv indexes them (time [s of simulated time],
// camera, rgb, depth: file names relative to DIR).
//
// The writing runs on a thread of its own: Push copies the frame into one of a few preallocated
// slots and returns (no allocation, no file system and no conversion on the loop's thread: the
// depth is turned into millimetres by the writer); when every slot is
// still being written it waits for one (nothing is lost: a lock-step run is slowed, a real-time
// one is late, and the time waited is counted). Close drains the slots; a file not written
// whole (disk full) is the recorder's failure, named there.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ohrp::sim {

class ImageRecorder {
 public:
  // Creates DIR, a folder per camera (names: the robot's cameras) and DIR/images.csv. Null with
  // `*error` naming the path when they cannot be made.
  static std::unique_ptr<ImageRecorder> Open(const std::string& dir,
                                             const std::vector<std::string>& cameras, int width,
                                             int height, bool depth, std::string* error);
  ~ImageRecorder();
  ImageRecorder(const ImageRecorder&) = delete;
  ImageRecorder& operator=(const ImageRecorder&) = delete;

  // One rendered frame of camera `camera` at simulated time `time`: rows bottom-up as the
  // renderer reads them; `depth` [m] or null. Waits only when every slot is being written.
  void Push(int camera, double time, const uint8_t* rgb, const float* depth);

  // Writes what is left and closes the index. False with `*error` (the first file that failed).
  bool Close(std::string* error);

  uint64_t frames() const { return written_; }        // frames written whole
  double waited_seconds() const { return waited_; }   // the loop's wait for a free slot [s]
  const std::string& dir() const { return dir_; }

 private:
  struct Slot {
    int camera = 0;
    double time = 0;
    bool full = false;
    bool has_depth = false;
    std::vector<uint8_t> rgb;
    std::vector<float> depth_m;  // as rendered [m]
  };
  ImageRecorder() = default;
  void Run();
  bool Write(const Slot& s, uint64_t index);
  void DepthToMillimetres(const Slot& s);  // into depth_mm_ (the writer's)

  std::string dir_;
  std::vector<std::string> cameras_;
  int width_ = 0, height_ = 0;
  bool depth_ = false;
  FILE* index_ = nullptr;
  std::vector<Slot> slots_;
  std::vector<uint16_t> depth_mm_;  // the writer's: the slot being written, in mm
  size_t next_push_ = 0, next_write_ = 0;  // ring positions
  std::mutex mutex_;
  std::condition_variable filled_, freed_;
  bool closing_ = false;
  std::string error_;
  uint64_t written_ = 0;
  std::vector<uint64_t> per_camera_;
  double waited_ = 0;
  std::thread thread_;
};

}  // namespace ohrp::sim
