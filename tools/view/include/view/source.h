// Where the viewer's frames come from: a running segment (LiveSource, an observer) or a finished
// run's log (ReplaySource). The server (server.h) asks a source for the scene once per page,
// then for frames: the live source publishes the newest frame at a bounded rate, the replay
// source answers a request for a time.
//
// A frame is a JSON object: t [s], poses (world pose of each moving geom, see geometry.h),
// q and qref (all joints, segment order) [rad or m], fz (each force sensor's vertical force in
// its own frame) [N], zmp ([x, y] on z = 0 [m], or null), and for live frames cycle, status
// (bit names), counters and base ("ground truth" or "estimated from IMU").
//
// Live camera images (only while some page watches them, WatchImages): an image message is
// binary, little-endian: int32 camera, int32 width, int32 height, int32 0, float64 time of
// capture [s], float64 frame counter, then width x height x 3 bytes RGB8 (top row first).
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "datalog/table.h"  // the data log's reader
#include "shm_bridge/observer.h"
#include "view/geometry.h"
#include "view/plan.h"

namespace ohrp::view {

class Source {
 public:
  virtual ~Source() = default;
  virtual bool live() const = 0;
  // What the page needs first: {"mode": "live"|"replay", "scene": SceneGeometry::Describe(),
  // "title", ...}; the replay adds "t0", "t1" and "series" (the plots' whole curves).
  virtual nlohmann::json Hello() = 0;
  // live: the newest frame and its version (0: none yet); blocks up to `timeout` [s] for one
  // newer than `after`. replay: not used.
  virtual std::shared_ptr<const std::string> Newest(uint64_t after, double timeout, uint64_t* version) {
    return nullptr;
  }
  // replay: the frame at time `t` [s] (clamped to the log). live: not used.
  virtual nlohmann::json FrameAt(double t) { return {}; }
  // replay: the log column `name` as a curve for the plots, {"column", "t", "y"} (min/max
  // decimated), or {"column", "error"} when the log has no such column. live: not used.
  virtual nlohmann::json Column(const std::string& name) { return {{"column", name}, {"error", "not a replay"}}; }
  // live: the producer has stopped (its last frame is out)
  virtual bool ended() const { return false; }
  // replay: the path of the recorded camera image `name` (a file the run folder's
  // images/images.csv names, relative to images/; sim_host --record-images), or false
  virtual bool RecordedImage(const std::string& name, std::string* path) const { return false; }
  // live: a page starts (+1) or stops (-1) watching the camera images
  virtual void WatchImages(int delta) {}
  // live: blocks up to `timeout` [s] until some camera has an image message newer than
  // `sent[camera]`; copies the newest messages of those cameras into `out` (null: none) and
  // their versions into `sent`. False when nothing new came.
  virtual bool NewestImages(uint64_t sent[shm::kMaxCameras], double timeout,
                            std::shared_ptr<const std::string> out[shm::kMaxCameras]) {
    return false;
  }
};

//---------------- live: a running segment ----------------

class LiveSource : public Source {
 public:
  // Attaches to `segment` as an observer (waiting up to `attach_timeout` [s] for it to appear),
  // loads `scene` and checks its robot against the segment's model hash. Returns null with
  // `*error` set (no segment, not a segment, another robot); `rate` is the frame rate [Hz].
  // `image_rate` [Hz] bounds the images sent per camera (taken from the segment only while a
  // page watches them).
  static std::unique_ptr<LiveSource> Open(const std::string& segment, const std::string& scene,
                                          double rate, double image_rate, double attach_timeout,
                                          std::string* error);
  ~LiveSource() override;
  bool live() const override { return true; }
  nlohmann::json Hello() override;
  std::shared_ptr<const std::string> Newest(uint64_t after, double timeout, uint64_t* version) override;
  // frames made so far, and blocks read from the segment
  uint64_t frames() const { return version_.load(); }
  bool ended() const override { return ended_.load(); }
  void WatchImages(int delta) override;
  bool NewestImages(uint64_t sent[shm::kMaxCameras], double timeout,
                    std::shared_ptr<const std::string> out[shm::kMaxCameras]) override;

 private:
  LiveSource() = default;
  void Loop();
  void ImageLoop();
  std::string MakeFrame(const shm::SensorBlock& s, bool ended);

  shm::Observer observer_;
  std::unique_ptr<SceneGeometry> geometry_;
  std::string segment_;
  double period_ = 1.0 / 30;  // [s] between frames (wall clock)
  std::atomic<bool> stop_{false}, ended_{false};
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::shared_ptr<const std::string> frame_;
  std::atomic<uint64_t> version_{0};
  // images: asked from the producer only while image_watchers_ > 0
  double image_period_ = 0.1;  // [s] between images of one camera (wall clock)
  std::atomic<int> image_watchers_{0};
  std::atomic<bool> image_request_failed_{false};
  std::thread image_thread_;
  std::shared_ptr<const std::string> image_[shm::kMaxCameras];  // under mutex_
  uint64_t image_version_[shm::kMaxCameras] = {};              // under mutex_
};

//---------------- replay: a run folder ----------------

class ReplaySource : public Source {
 public:
  // Reads RUN_DIR/log.csv (and sim_summary.json for the scene when `scene` is empty), and the
  // walk's plan from RUN_DIR/walk.csv when there is one (plan.h; one that cannot be read is
  // said on the page, not refused). Returns null with `*error` set (no folder, no log, no
  // scene, a log that does not fit the scene).
  static std::unique_ptr<ReplaySource> Open(const std::string& run_dir, const std::string& scene,
                                            std::string* error);
  bool live() const override { return false; }
  nlohmann::json Hello() override;
  nlohmann::json FrameAt(double t) override;
  nlohmann::json Column(const std::string& name) override;
  bool RecordedImage(const std::string& name, std::string* path) const override;

 private:
  ReplaySource() = default;
  // the cameras' images of the run (RUN_DIR/images/images.csv, sim_host --record-images;
  // replay_images.cc): for the hello {"cameras": [names], "frames": {camera: {"t": [s],
  // "rgb": [file]}}}, or {"note": why none}
  void LoadImages(const std::string& run_dir);
  RobotState StateAt(double t);
  void LoadPlan(const std::string& run_dir);
  nlohmann::json PlanHello() const;
  // reach's plan (plan.csv, reach_plan.h) as hand paths in the world (replay_reach.cc):
  // {"goals": [{"goal", "solved", "t_start", "t_end" [s], "paths": [[[x, y, z]...] per hand],
  // "waypoints": [[[x, y, z]...] per hand]}], "hands": [body names]}, or {"note": why none}
  void LoadReach(const std::string& run_dir);
  nlohmann::json Series(const std::vector<double>& y) const;  // against the log's time
  static nlohmann::json Series(const std::vector<double>& times, const std::vector<double>& y);

  std::unique_ptr<SceneGeometry> geometry_;
  datalog::Table log_;
  std::string title_;
  int time_col_ = -1;
  int base_col_[7] = {-1, -1, -1, -1, -1, -1, -1};
  std::vector<int> q_col_, qref_col_;            // per joint, -1 when absent
  std::vector<std::array<int, 6>> ft_col_;       // per force sensor: fx fy fz tx ty tz
  std::mutex mutex_;                             // the geometry's mjData, series_
  nlohmann::json series_;                        // the plots' curves, made by the first Hello()
  std::unique_ptr<WalkPlan> plan_;               // walk.csv's plan, or null
  std::string plan_note_;                        // why there is no plan
  nlohmann::json reach_;                         // reach's plan for the hello (LoadReach)
  nlohmann::json images_;                        // the recorded images for the hello (LoadImages)
  std::string images_dir_;                       // RUN_DIR/images
  std::set<std::string> image_files_;            // the files its index names (served, nothing else)
  double sole_half_[2][2] = {{0, 0}, {0, 0}};    // left, right sole box half length, width [m]
};

}  // namespace ohrp::view
