// The harness of the hard-case stability suite: load a model, step it with the divergence
// watch after every step, count MuJoCo's warnings, and write one row per run into
// build/stability/<case>.md (docs/stability.md quotes those rows).
#pragma once

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>

#include "common/scratch.h"
#include "sim_host/divergence.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim::stability {

inline std::string Src(const std::string& rel) { return std::string(OHRP_SOURCE_DIR) + "/" + rel; }

inline std::string Fmt(const char* format, double x) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, x);
  return buf;
}

// what one run did
struct RunResult {
  bool diverged = false;
  Diagnosis diagnosis;       // when diverged
  double sim_time = 0;       // [s] reached
  long steps = 0;
  double energy0 = 0, energy = 0, work = 0, max_excess = 0;  // [J] (the watch's account)
  int warnings[mjNWARNING] = {};  // d->warning[].number grown during the run
  long handler_warnings = 0;      // calls to sim_host's MuJoCo warning handler
  double wall = 0;                // [s]
  int total_warnings() const {
    int n = 0;
    for (int w = 0; w < mjNWARNING; ++w) n += warnings[w];
    return n;
  }
};

// Owns a model and its data; loads from a file or an inline MJCF string.
class Sim {
 public:
  static std::unique_ptr<Sim> FromFile(const std::string& path) {
    model::InstallMujocoHandlers(nullptr);
    char err[1000] = "";
    mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
    EXPECT_NE(m, nullptr) << path << ": " << err;
    if (!m) return nullptr;
    return std::unique_ptr<Sim>(new Sim(m));
  }
  static std::unique_ptr<Sim> FromString(const std::string& xml) {
    const std::string path = ohrp::testing::ScratchPath("model", ".xml");
    std::ofstream(path) << xml;
    auto s = FromFile(path);
    std::filesystem::remove(path);
    return s;
  }
  // a scene through sim_host's loader (keyframes, robot mapping)
  static std::unique_ptr<Sim> FromScene(const std::string& path) {
    model::InstallMujocoHandlers(nullptr);
    std::string error;
    auto scene = model::Scene::Load(path, &error);
    EXPECT_TRUE(scene) << error;
    if (!scene) return nullptr;
    auto s = std::unique_ptr<Sim>(new Sim(scene->m(), scene->d()));
    s->scene_ = std::move(scene);
    return s;
  }
  ~Sim() {
    if (scene_) return;  // the scene owns them
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  model::Scene* scene() const { return scene_.get(); }
  mjModel* m() const { return m_; }
  mjData* d() const { return d_; }

  // Runs for `duration` [s] of simulated time (or until the watch fires): `before` runs before
  // each mj_step, `after` after it. `passive` bodies carry soft-foot forces in xfrc_applied.
  RunResult Run(double duration, const std::function<void()>& before = {},
                const std::function<void()>& after = {},
                const std::vector<int>& passive = {}) {
    RunResult r;  // the scene's flags as they are: the watch needs no `energy` flag
    DivergenceWatch watch(m_);
    watch.SetPassiveBodies(passive);
    watch.Start(m_, d_);
    int start[mjNWARNING];
    for (int w = 0; w < mjNWARNING; ++w) start[w] = d_->warning[w].number;
    const long handler0 = model::WarningCount();
    const auto t0 = std::chrono::steady_clock::now();
    const double t_end = d_->time + duration - 0.5 * m_->opt.timestep;
    while (d_->time < t_end) {
      if (before) before();
      mj_step(m_, d_);
      ++r.steps;
      if (after) after();
      if (watch.Check(m_, d_, r.steps)) {
        r.diverged = true;
        r.diagnosis = watch.Diagnose(m_, d_, context);
        break;
      }
    }
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.sim_time = d_->time;
    r.energy0 = watch.energy_start();
    r.energy = watch.energy();
    r.work = watch.input_work();
    r.max_excess = watch.max_excess();
    for (int w = 0; w < mjNWARNING; ++w) r.warnings[w] = d_->warning[w].number - start[w];
    r.handler_warnings = model::WarningCount() - handler0;
    return r;
  }

  DiagnosisContext context;  // handed to Diagnose

 private:
  explicit Sim(mjModel* m) : m_(m), d_(mj_makeData(m)) {}
  Sim(mjModel* m, mjData* d) : m_(m), d_(d) {}
  mjModel* m_;
  mjData* d_;
  std::unique_ptr<model::Scene> scene_;
};

// A stable run: finite throughout, energy within `energy_tol` [J] of what the sources supplied,
// no MuJoCo warning (unless `allowed_warnings` names why).
inline void ExpectStable(const RunResult& r, double duration, double energy_tol,
                         const std::string& allowed_warnings = "") {
  EXPECT_FALSE(r.diverged) << r.diagnosis.Text();
  EXPECT_GE(r.sim_time, duration * (1 - 1e-3)) << "the run stopped early";
  EXPECT_LE(r.max_excess, energy_tol)
      << "energy grew beyond what gravity, motors and pushes supplied: E(0) = " << r.energy0
      << " J, E = " << r.energy << " J, input work " << r.work << " J";
  if (allowed_warnings.empty()) {
    EXPECT_EQ(r.total_warnings(), 0) << "MuJoCo warned: " << model::LastWarning();
    EXPECT_EQ(r.handler_warnings, 0) << model::LastWarning();
  }
}

// An unstable run: the watch fired within the run; `cause` (if any) appears in the diagnosis.
inline void ExpectDetected(const RunResult& r, const std::string& cause_part = "") {
  ASSERT_TRUE(r.diverged) << "the unstable setting ran " << r.sim_time
                          << " s without the watch firing (max energy excess " << r.max_excess
                          << " J)";
  if (!cause_part.empty()) {
    EXPECT_NE(r.diagnosis.cause.find(cause_part), std::string::npos) << r.diagnosis.Text();
  }
}

// One row of the case table: | case | setting | simulated | outcome | figure | wall |
inline void WriteRow(const std::string& file, const std::string& case_name,
                     const std::string& setting, const RunResult& r, const std::string& figure) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(OHRP_BIN_DIR) / ".." / "stability";
  fs::create_directories(dir);
  std::ostringstream row;
  std::string outcome;
  if (r.diverged) {
    outcome = std::string("**diverged** (") + DivergenceKindName(r.diagnosis.kind) + ") at t = " +
              Fmt("%.4g", r.diagnosis.time) + " s, step " + std::to_string(r.diagnosis.step) +
              ": " + r.diagnosis.cause;
  } else {
    outcome = "stable; max E - E(0) - W = " + Fmt("%.3g", r.max_excess) + " J (E(0) = " +
              Fmt("%.4g", r.energy0) + " J, W = " + Fmt("%.3g", r.work) + " J), " +
              std::to_string(r.total_warnings()) + " warnings";
  }
  std::string figure_cell = figure;
  for (std::string* cell : {&outcome, &figure_cell})
    for (auto& c : *cell)
      if (c == '|' || c == '\n') c = ' ';
  row << "| " << case_name << " | " << setting << " | " << Fmt("%.3g", r.sim_time) << " s | "
      << outcome << " | " << figure_cell << " | " << Fmt("%.2f", r.wall) << " s |\n";
  std::ofstream(dir / (file + ".md"), std::ios::app) << row.str();
}

// Writes one line into build/stability/<file> (replacing it).
inline void Note(const std::string& file, const std::string& line) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(OHRP_BIN_DIR) / ".." / "stability";
  fs::create_directories(dir);
  std::ofstream(dir / file) << line << "\n";
}

// Starts a case's row file afresh (call once at the start of each test).
inline void ResetRows(const std::string& file) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(OHRP_BIN_DIR) / ".." / "stability";
  fs::create_directories(dir);
  fs::remove(dir / (file + ".md"));
}

// HRP-1S on its soft soles, joints held by sim_host's servo
struct Robot {
  std::unique_ptr<Sim> sim;
  model::RobotMap map;
  std::unique_ptr<contact::SoftFootContact> soft;
  std::unique_ptr<model::Servo> servo;
  std::vector<int> soles;
};

// Fills `r` in place (the servo keeps a reference to r.map): the scene, the contact under the
// soles (soft: through SetUpFeet, which validates the parameters for half the robot's mass;
// `claimed_mass_scale` > 0 creates the soft contact directly with that mass instead, to force
// parameters the check refuses), the keyframe, and the servo holding it.
inline void LoadRobot(Robot& r, const std::string& scene, const std::string& keyframe,
                      const contact::SoftContactParams& params = {},
                      ContactModel model = ContactModel::kSoft, double claimed_mass_scale = 0) {
  r.sim = Sim::FromScene(Src(scene));
  if (!r.sim) return;
  mjModel* m = r.sim->m();
  std::string error;
  EXPECT_TRUE(model::MapRobot(m, &r.map, &error)) << error;
  if (claimed_mass_scale > 0) {
    std::vector<std::string> soles;
    for (int g = 0; g < m->ngeom; ++g) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, g);
      const std::string n = name ? name : "";
      if (n.size() > 5 && n.compare(n.size() - 5, 5, "_SOLE") == 0) {
        soles.push_back(n);
        m->geom_contype[g] = m->geom_conaffinity[g] = 0;
      }
    }
    r.soft = contact::SoftFootContact::Create(m, soles, {}, params, claimed_mass_scale, &error);
    EXPECT_TRUE(r.soft) << error;
  } else {
    FeetOptions feet;
    feet.model = model;
    feet.params = params;
    EXPECT_TRUE(SetUpFeet(m, feet, r.map.total_mass, &r.soft, &error)) << error;
  }
  EXPECT_TRUE(r.sim->scene()->Reset(keyframe, &error)) << error;
  mj_forward(m, r.sim->d());
  r.servo = std::make_unique<model::Servo>(r.map);
  r.servo->HoldCurrent(r.sim->d());
  if (r.soft) {
    for (int g : r.soft->sole_geoms()) r.soles.push_back(m->geom_bodyid[g]);
    r.sim->context.soft = r.soft.get();
    r.sim->context.soft_mass_scale = 0.5 * r.map.total_mass;
  }
}

// Runs the robot with its servo (and soft soles); `before` runs first in each step.
inline RunResult RunRobot(Robot& r, double duration, const std::function<void()>& before = {},
                          const std::function<void()>& after = {}) {
  mjModel* m = r.sim->m();
  mjData* d = r.sim->d();
  return r.sim->Run(
      duration,
      [&] {
        if (before) before();
        r.servo->Apply(m, d);
        if (r.soft) r.soft->ApplyBeforeStep(m, d);
      },
      [&] {
        if (r.soft) r.soft->Commit();
        if (after) after();
      },
      r.soles);
}

}  // namespace ohrp::sim::stability
