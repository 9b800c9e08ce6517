// ohrp_video's replay of a run (see replay.h).
#include "replay.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

namespace ohrp::video {
namespace {

bool IsDir(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// the scene sim_host recorded in the run's sim_summary.json ("" when none)
std::string RecordedScene(const std::string& run_dir) {
  std::ifstream s(run_dir + "/sim_summary.json");
  if (!s) return "";
  try {
    return nlohmann::json::parse(s).value("scene", "");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ohrp_video: %s/sim_summary.json: %s\n", run_dir.c_str(), e.what());
    return "";
  }
}

}  // namespace

bool ReadRunInputs(const std::string& input, const std::string& scene, RunInputs* out,
                   std::string* error) {
  out->log_path = input;
  if (IsDir(input)) {
    out->run_dir = input;
    out->log_path = input + "/log.csv";
  } else {
    const size_t slash = input.rfind('/');
    out->run_dir = slash == std::string::npos ? "." : input.substr(0, slash);
  }
  out->scene = scene.empty() ? RecordedScene(out->run_dir) : scene;
  if (out->scene.empty()) {
    *error = "no scene recorded beside '" + out->log_path + "': pass --scene FILE.xml";
    return false;
  }
  if (!out->log.Load(out->log_path, error)) return false;
  if (out->log.rows() < 2) {
    *error = "'" + out->log_path + "' has fewer than two rows: nothing to replay";
    return false;
  }
  return true;
}

bool LogReplay::Map(const mjModel* m, const datalog::Table& log, std::string* missing,
                    std::string* error) {
  log_ = &log;
  drives_.clear();
  base_body_ = -1;
  const int time_col = log.Column("time");
  for (int j = 0; j < m->njnt && base_body_ < 0; ++j) {
    if (m->jnt_type[j] != mjJNT_FREE) continue;
    base_body_ = m->jnt_bodyid[j];
    const char* names[7] = {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
    for (int k = 0; k < 7; ++k) {
      const int c = log.Column(names[k]);
      if (c >= 0) drives_.push_back({c, m->jnt_qposadr[j] + k});
    }
  }
  int joints = 0;
  missing->clear();
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    const char* name = mj_id2name(m, mjOBJ_JOINT, j);
    const int c = name ? log.Column(std::string("q_") + name) : -1;
    if (c >= 0) {
      drives_.push_back({c, m->jnt_qposadr[j]});
      ++joints;
    } else if (name) {
      *missing += std::string(missing->empty() ? "" : ", ") + name;
    }
  }
  if (time_col < 0 || joints == 0) {
    *error = time_col < 0 ? "no 'time' column" : "no q_<joint> column names a joint of the scene";
    return false;
  }
  times_ = &log.col(time_col);
  row_ = 0;
  return true;
}

void LogReplay::Pose(const mjModel* m, double t, mjData* d) {
  const std::vector<double>& times = *times_;
  while (row_ + 2 < times.size() && times[row_ + 1] <= t) ++row_;
  while (row_ > 0 && times[row_] > t) --row_;
  const size_t next = std::min(row_ + 1, times.size() - 1);
  const double span = times[next] - times[row_];
  const double s = span > 0 ? std::clamp((t - times[row_]) / span, 0.0, 1.0) : 0.0;
  for (const Drive& dr : drives_) {
    const std::vector<double>& v = log_->col(dr.column);
    d->qpos[dr.qpos] = v[row_] + s * (v[next] - v[row_]);
  }
  for (int j = 0; j < m->njnt; ++j)
    if (m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL) {
      const int q = m->jnt_qposadr[j] + (m->jnt_type[j] == mjJNT_FREE ? 3 : 0);
      mju_normalize4(d->qpos + q);
    }
  d->time = t;
}

std::unique_ptr<FrameRenderer> FrameRenderer::Create(mjModel* m, const FrameOptions& o,
                                                     std::string* error) {
  std::unique_ptr<FrameRenderer> r(new FrameRenderer());
  r->o_ = o;
  render::OffscreenOptions render_options;
  render_options.width = o.width;
  render_options.height = o.height;
  render_options.shadows = o.shadows;
  r->offscreen_ = render::Offscreen::Create(m, render_options, error);
  if (!r->offscreen_) return nullptr;
  mjv_defaultCamera(&r->cam_);
  r->cam_.type = mjCAMERA_FREE;
  r->cam_.distance = o.distance;
  r->cam_.azimuth = o.azimuth;
  r->cam_.elevation = o.elevation;
  r->pixels_.resize(static_cast<size_t>(o.width) * o.height * 3);
  return r;
}

void FrameRenderer::Render(const mjModel* m, mjData* d, int base_body, double t) {
  if (base_body >= 0) {  // follow the base horizontally, look at its height
    const int q = m->jnt_qposadr[m->body_jntadr[base_body]];
    for (int k = 0; k < 3; ++k) cam_.lookat[k] = d->qpos[q + k];
    cam_.lookat[2] = std::max(0.3, d->qpos[q + 2] - 0.05);
  }
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_camlight(m, d);
  offscreen_->Draw(m, d, &cam_, o_.width, o_.height);
  char text[64];
  std::snprintf(text, sizeof(text), "t = %.2f s", t);
  const mjrRect viewport{0, 0, o_.width, o_.height};
  mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, o_.title.c_str(), text, offscreen_->context());
  offscreen_->Read(o_.width, o_.height, pixels_.data(), nullptr);
}

}  // namespace ohrp::video
