// ReplaySource: a finished run's data log (sim_host/recorder.h columns) as frames by time, and
// the plots' whole curves (source.h).
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "cli/plausible.h"
#include "view/decimate.h"
#include "view/source.h"

namespace ohrp::view {

namespace {

// the plots' curves are decimated to at most this many points (min/max: decimate.h)
constexpr size_t kSeriesPoints = 800;
// the ZMP curve is computed at most at this many rows (evenly spaced), before its decimation
constexpr size_t kZmpRows = 20000;

bool IsDir(const std::string& p) {
  struct stat st {};
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

std::unique_ptr<ReplaySource> ReplaySource::Open(const std::string& run_dir, const std::string& scene_arg,
                                                 std::string* error) {
  std::unique_ptr<ReplaySource> src(new ReplaySource());
  // the folder, its log and its scene
  if (!IsDir(run_dir)) {
    *error = "no run folder '" + run_dir + "' (a folder written by './ohrp run SCENARIO --out DIR')";
    return nullptr;
  }
  const std::string log_path = run_dir + "/log.csv";
  if (!std::ifstream(log_path)) {
    *error = "'" + run_dir + "' has no log.csv (not a run folder, or the run was made without its "
             "log: a folder written by './ohrp run SCENARIO --out DIR' has one)";
    return nullptr;
  }
  std::string scene = scene_arg;
  if (scene.empty()) {
    std::ifstream s(run_dir + "/sim_summary.json");
    try {
      if (s) scene = nlohmann::json::parse(s).value("scene", "");
    } catch (const std::exception& e) {
      *error = run_dir + "/sim_summary.json: " + e.what() + " (or pass --scene FILE)";
      return nullptr;
    }
    if (scene.empty()) {
      *error = "no scene recorded in '" + run_dir + "/sim_summary.json': pass --scene FILE.xml";
      return nullptr;
    }
  }
  if (!src->log_.Load(log_path, error)) return nullptr;
  if (src->log_.rows() < 1) {
    *error = "'" + log_path + "' has no rows: nothing to replay";
    return nullptr;
  }
  src->geometry_ = SceneGeometry::Load(scene, error);
  if (!src->geometry_) return nullptr;
  // which column holds what
  const datalog::Table& log = src->log_;
  src->time_col_ = log.Column("time");
  const char* base[7] = {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
  for (int k = 0; k < 7; ++k) src->base_col_[k] = log.Column(base[k]);
  int joints = 0;
  for (const auto& jm : src->geometry_->robot().joints) {
    src->q_col_.push_back(log.Column("q_" + jm.name));
    src->qref_col_.push_back(log.Column("qref_" + jm.name));
    joints += src->q_col_.back() >= 0;
  }
  for (const auto& f : src->geometry_->robot().forces) {
    std::array<int, 6> c;
    const char* axes[6] = {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"};
    for (int k = 0; k < 6; ++k) c[k] = log.Column(f.name + axes[k]);
    src->ft_col_.push_back(c);
  }
  if (src->time_col_ < 0 || joints == 0) {
    *error = "'" + log_path + "' does not fit the scene '" + scene + "': " +
             (src->time_col_ < 0 ? "no 'time' column" : "no q_<joint> column names a joint of the scene") +
             " (the log's columns are time, base_*, q_<joint>...)";
    return nullptr;
  }
  // the log's times are numbers of the file: a plausible run's (the timeline spans them)
  *error = cli::CheckPlausibleEach("time", log.col(src->time_col_), log_path + ": time");
  if (!error->empty()) return nullptr;
  const size_t slash = run_dir.find_last_not_of('/');
  const std::string trimmed = run_dir.substr(0, slash + 1);
  src->LoadPlan(run_dir);
  src->LoadReach(run_dir);
  src->LoadImages(run_dir);
  src->title_ = "run " + trimmed.substr(trimmed.rfind('/') == std::string::npos ? 0 : trimmed.rfind('/') + 1);
  return src;
}

// the walk's plan (walk.csv), registered onto the soles the log shows at its first row
void ReplaySource::LoadPlan(const std::string& run_dir) {
  const std::string path = run_dir + "/walk.csv";
  if (!std::ifstream(path)) {
    plan_note_ = "no walk.csv in the run folder (the walk controller's --log)";
    return;
  }
  const std::array<int, 2> soles = LeftRightSoles(geometry_->model());
  if (soles[0] < 0) {
    plan_note_ = "the model has not two *_SOLE boxes (left, right)";
    return;
  }
  std::string error;
  plan_ = WalkPlan::Load(path, &error);
  if (!plan_) {
    plan_note_ = error;
    return;
  }
  const mjModel* m = geometry_->model();
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k) sole_half_[i][k] = m->geom_size[3 * soles[i] + k];
  RobotState state = StateAt(plan_->t0());
  geometry_->Poses(state);
  const std::array<double, 3> left = geometry_->BoxBottom(soles[0]), right = geometry_->BoxBottom(soles[1]);
  plan_->Register(left.data(), right.data());
}

// the plan overlays' part of the hello: {"note"} without a plan, else {"missing", "footsteps",
// "t0", "registration": [x, y, yaw, dz]}
nlohmann::json ReplaySource::PlanHello() const {
  if (!plan_) return {{"note", plan_note_}};
  const Planar& r = plan_->registration();
  return {{"missing", plan_->Missing()}, {"footsteps", plan_->Footsteps(sole_half_)}, {"t0", plan_->t0()},
          {"registration", {r.x, r.y, r.yaw, r.dz}}};
}

// the state at time t: linear interpolation between the rows around it
RobotState ReplaySource::StateAt(double t) {
  const std::vector<double>& times = log_.col(time_col_);
  const size_t next = std::lower_bound(times.begin(), times.end(), t) - times.begin();
  const size_t hi = std::min(next, times.size() - 1), lo = hi > 0 ? hi - 1 : 0;
  const double span = times[hi] - times[lo];
  const double s = span > 0 ? std::clamp((t - times[lo]) / span, 0.0, 1.0) : 1.0;
  auto at = [&](int c, double fallback) {
    if (c < 0) return fallback;
    return log_.col(c)[lo] + s * (log_.col(c)[hi] - log_.col(c)[lo]);
  };
  RobotState state;
  const mjModel* m = geometry_->model();
  const int adr = geometry_->robot().base_qpos;
  for (int k = 0; k < 3; ++k) state.p_WB[k] = at(base_col_[k], adr >= 0 ? m->qpos0[adr + k] : 0);
  for (int k = 0; k < 4; ++k) state.quat_WB[k] = at(base_col_[3 + k], adr >= 0 ? m->qpos0[adr + 3 + k] : k == 0);
  for (int c : q_col_) state.q.push_back(at(c, NAN));
  for (const auto& c : ft_col_) {
    shm::ForceTorque ft{};
    for (int k = 0; k < 3; ++k) {
      ft.force[k] = at(c[k], 0);
      ft.torque[k] = at(c[3 + k], 0);
    }
    state.ft.push_back(ft);
  }
  return state;
}

nlohmann::json ReplaySource::FrameAt(double t) {
  const std::vector<double>& times = log_.col(time_col_);
  t = std::clamp(t, times.front(), times.back());
  std::lock_guard lock(mutex_);
  RobotState state = StateAt(t);
  nlohmann::json j;
  j["t"] = t;
  j["poses"] = geometry_->Poses(state);
  double zmp[2];
  j["zmp"] = geometry_->Zmp(state, zmp) ? nlohmann::json{zmp[0], zmp[1]} : nlohmann::json(nullptr);
  j["balance"] = geometry_->Balance(state);
  if (plan_) j["plan"] = plan_->At(t);
  j["base"] = base_col_[0] >= 0 ? "ground truth" : "not logged";
  return j;
}

// one curve for the plots: the rows of `y` that min/max decimation keeps, {"t": [...], "y": [...]}
// (NaN written as null)
nlohmann::json ReplaySource::Series(const std::vector<double>& y) const {
  return Series(log_.col(time_col_), y);
}
nlohmann::json ReplaySource::Series(const std::vector<double>& times, const std::vector<double>& y) {
  nlohmann::json t = nlohmann::json::array(), v = nlohmann::json::array();
  for (size_t r : MinMaxRows(y, Buckets(times.size(), kSeriesPoints))) {
    t.push_back(times[r]);
    v.push_back(y[r]);
  }
  return {{"t", t}, {"y", v}};
}

nlohmann::json ReplaySource::Column(const std::string& name) {
  const int c = log_.Column(name);
  if (c < 0)
    return {{"column", name}, {"error", "no column '" + name + "' in the log (" +
                                            std::to_string(log_.names().size()) + " columns)"}};
  nlohmann::json j = Series(log_.col(c));
  j["column"] = name;
  return j;
}

nlohmann::json ReplaySource::Hello() {
  const std::vector<double>& times = log_.col(time_col_);
  nlohmann::json j;
  j["mode"] = "replay";
  j["title"] = title_;
  j["scene"] = geometry_->Describe();
  j["t0"] = times.front();
  j["t1"] = times.back();
  j["columns"] = log_.names();
  j["plan"] = PlanHello();
  j["reach"] = reach_;
  j["recorded_images"] = images_;
  // the plots' curves, min/max decimated (decimate.h): q and qref per joint, fz per sensor, the
  // ZMP (forward kinematics of every row: the sensors' poses)
  const auto& robot = geometry_->robot();
  std::lock_guard lock(mutex_);
  if (!series_.is_null()) {
    j["series"] = series_;
    return j;
  }
  const std::vector<double> none(times.size(), NAN);
  nlohmann::json q, qref, fz;
  for (size_t i = 0; i < robot.joints.size(); ++i) {
    q[robot.joints[i].name] = Series(q_col_[i] >= 0 ? log_.col(q_col_[i]) : none);
    qref[robot.joints[i].name] = Series(qref_col_[i] >= 0 ? log_.col(qref_col_[i]) : none);
  }
  for (size_t i = 0; i < robot.forces.size(); ++i)
    fz[robot.forces[i].name] = Series(ft_col_[i][2] >= 0 ? log_.col(ft_col_[i][2]) : none);
  // the ZMP at most at kZmpRows rows (forward kinematics costs about 12 us a row: a 30 s log at
  // 2 kHz took 0.75 s), then decimated
  const size_t stride = std::max<size_t>(1, (times.size() + kZmpRows - 1) / kZmpRows);
  std::vector<double> zmp_t, zmp_x, zmp_y;
  for (size_t r = 0; r < times.size(); r += stride) {
    RobotState state = StateAt(times[r]);
    geometry_->Poses(state);
    double z[2];
    const bool ok = geometry_->Zmp(state, z);
    zmp_t.push_back(times[r]);
    zmp_x.push_back(ok ? z[0] : NAN);
    zmp_y.push_back(ok ? z[1] : NAN);
  }
  // once per viewer: every page gets the same curves
  series_ = {{"q", q}, {"qref", qref}, {"fz", fz}, {"zmp_x", Series(zmp_t, zmp_x)}, {"zmp_y", Series(zmp_t, zmp_y)}};
  j["series"] = series_;
  return j;
}

}  // namespace ohrp::view
