// ohrp_video's replay of a run (video.cc): the run's inputs found (its log and scene), the log's
// columns mapped onto the model's qpos, and the model posed and rendered at any time of the log
// (linear interpolation between rows), offscreen (render/offscreen.h: OSMesa, no display).
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>
#include <vector>

#include "datalog/table.h"
#include "render/offscreen.h"

namespace ohrp::video {

// A run folder (ohrp_run --out DIR: log.csv, sim_summary.json) or a log file, and its scene.
struct RunInputs {
  std::string run_dir;   // where stills and the default video go
  std::string log_path;
  std::string scene;     // --scene, else the one sim_summary.json records
  datalog::Table log;
};

// Finds and reads the inputs: false with `*error` (the file and what is wrong) when the scene is
// not recorded and not given, or the log cannot be read or has fewer than two rows.
bool ReadRunInputs(const std::string& input, const std::string& scene, RunInputs* out,
                   std::string* error);

// The log replayed through the model: which column drives which qpos.
class LogReplay {
 public:
  // False with `*error` when the log has no time column or no q_<joint> of the model; joints of
  // the model the log lacks keep their initial angle and are named in `*missing`.
  bool Map(const mjModel* m, const datalog::Table& log, std::string* missing, std::string* error);
  // `d` posed as the log was at time t (rows interpolated, quaternions normalised).
  void Pose(const mjModel* m, double t, mjData* d);
  const std::vector<double>& times() const { return *times_; }
  int base_body() const { return base_body_; }  // the free joint's body, -1 without one

 private:
  struct Drive {
    int column, qpos;
  };
  std::vector<Drive> drives_;
  const datalog::Table* log_ = nullptr;
  const std::vector<double>* times_ = nullptr;
  int base_body_ = -1;
  size_t row_ = 0;  // the row at or before the last time posed
};

// What a frame looks like.
struct FrameOptions {
  int width = 640, height = 480;
  bool shadows = false;
  double distance = 3.2, azimuth = 135, elevation = -12;  // the camera [m, deg, deg]
  std::string title;                                       // drawn top left with the time
};

// Frames of the posed model: a free camera following the base horizontally at its height.
class FrameRenderer {
 public:
  static std::unique_ptr<FrameRenderer> Create(mjModel* m, const FrameOptions& o,
                                               std::string* error);
  // renders `d` (posed) at time t into pixels(): RGB, top row first
  void Render(const mjModel* m, mjData* d, int base_body, double t);
  const std::vector<unsigned char>& pixels() const { return pixels_; }

 private:
  FrameOptions o_;
  std::unique_ptr<render::Offscreen> offscreen_;
  mjvCamera cam_{};
  std::vector<unsigned char> pixels_;
};

}  // namespace ohrp::video
