// bench_accuracy's scenes, swept settings and closed forms (bench_plan.h).
#include "bench_plan.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "robot_model/load.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::accuracy {
namespace {

SceneSpec Pendulum(const BenchOptions& o, const std::string& src, double quick_duration) {
  SceneSpec s;
  s.name = "pendulum";
  s.description = "chain of 4 hinged links released from a bent pose (no contact)";
  s.path = src + "/mjcf/bench/pendulum_chain.xml";
  s.keyframe = "release";
  s.contacts = {Contact::kNone};
  s.duration = o.quick ? quick_duration : 2.0;
  return s;
}

SceneSpec Box(const BenchOptions& o, const std::string& src, double quick_duration) {
  SceneSpec s;
  s.name = "box";
  s.description = "60 kg sole-sized block dropped from 6 cm at 1 m/s, lands and slides";
  s.path = src + "/mjcf/bench/box_slide.xml";
  s.keyframe = "drop";
  s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
  s.geometries = {"box", "mesh8"};
  s.soles = {"box"};
  s.soft_mass = 60;
  s.duration = o.quick ? quick_duration : 0.5;
  return s;
}

SceneSpec Ball(const BenchOptions& o, double quick_duration) {
  SceneSpec s;
  s.name = "ball";
  s.description = "1 kg ball (r 0.1 m) set down sliding at 2 m/s without spin: slides, rolls";
  s.xml = BallXml();
  s.keyframe = "slide";
  s.contacts = {Contact::kNative, Contact::kRigid};
  s.geometries = {"sphere", "ico0", "ico1", "ico2", "ico3"};
  s.soles = {"sphere"};
  s.duration = o.quick ? quick_duration : 0.5;
  return s;
}

SceneSpec Hrp1sStand(const BenchOptions& o, const std::string& hrp1s, double quick_duration) {
  SceneSpec s;
  s.name = "hrp1s_stand";
  s.description = "HRP-1S (mjcf/hrp1s/scene_flat.xml) from key halfsit, joints held by the Servo";
  s.path = hrp1s;
  s.keyframe = "halfsit";
  s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
  s.servo = true;
  s.duration = o.quick ? quick_duration : 2.0;
  return s;
}

SceneSpec Hrp1sWalk(const BenchOptions& o, const std::string& hrp1s, const Walk* walk,
                    double quick_duration) {
  SceneSpec s;
  s.name = "hrp1s_walk";
  s.description = "HRP-1S playing SamplePD's angle.dat/vel.dat/PDgain.dat (references a "
                  "function of simulated time), from 4.2 s: the first steps";
  s.path = hrp1s;
  s.keyframe = "init";
  s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
  s.walk = walk;
  s.preroll = o.quick ? 4.4 : 4.2;
  s.duration = o.quick ? quick_duration : 2.0;
  return s;
}

// MuJoCo's humanoid; "rigid" makes every body geom near-rigid
bool Humanoid(const BenchOptions& o, const std::string& path, double quick_duration,
              SceneSpec* s, std::string* error) {
  if (!std::filesystem::exists(path)) {
    *error = "MuJoCo's humanoid.xml is not at " + path + " (it comes with the shared external "
             "data beside the repository); leave the scene out with --scenes";
    return false;
  }
  s->name = "humanoid";
  s->description = "MuJoCo 2.2.2's humanoid.xml, controls zero: it collapses onto the floor";
  s->path = path;
  s->contacts = {Contact::kNative, Contact::kRigid};
  s->duration = o.quick ? quick_duration : 1.5;
  mjModel* m = model::LoadMujocoModel(path, error);  // a profile, VRML, MJCF, URDF
  if (!m) return false;
  for (int g = 0; g < m->ngeom; ++g)
    if (m->geom_bodyid[g] != 0) s->soles.push_back(mj_id2name(m, mjOBJ_GEOM, g));
  mj_deleteModel(m);
  return true;
}

// the soft soles of the HRP-1S scenes carry half the robot's mass each
bool SetSoftMass(SceneSpec* s, std::string* error) {
  auto scene = model::Scene::Load(s->path, error);
  model::RobotMap robot;
  if (!scene || !model::MapRobot(scene->m(), &robot, error)) return false;
  s->soft_mass = 0.5 * robot.total_mass;
  return true;
}

}  // namespace

bool MakeScenes(const BenchOptions& o, const std::string& src, Walk* walk,
                std::vector<SceneSpec>* scenes, std::string* error) {
  auto wanted = [&](const std::string& n) {
    return o.scenes.empty() || std::find(o.scenes.begin(), o.scenes.end(), n) != o.scenes.end();
  };
  const std::string ext = src + "/../shared/external";
  const std::string hrp1s = src + "/mjcf/hrp1s/scene_flat.xml";
  const double quick_duration = 0.25;  // quick: every reference 0.25 s
  if (wanted("pendulum")) scenes->push_back(Pendulum(o, src, quick_duration));
  if (wanted("box")) scenes->push_back(Box(o, src, quick_duration));
  if (wanted("ball")) scenes->push_back(Ball(o, quick_duration));
  if (wanted("hrp1s_stand")) scenes->push_back(Hrp1sStand(o, hrp1s, quick_duration));
  if (wanted("hrp1s_walk")) {
    if (!LoadWalk(ext + "/openhrp3-sample/SamplePD", walk, error)) {
      *error += "\n(the hrp1s_walk scene needs OpenHRP's SamplePD data beside the repository; "
                "leave it out with --scenes)";
      return false;
    }
    scenes->push_back(Hrp1sWalk(o, hrp1s, walk, quick_duration));
  }
  if (wanted("humanoid")) {
    SceneSpec s;
    if (!Humanoid(o, ext + "/mujoco-2.2.2-models/humanoid/humanoid.xml", quick_duration, &s,
                  error)) {
      return false;
    }
    scenes->push_back(s);
  }
  for (auto& s : *scenes) {
    if ((s.name == "hrp1s_stand" || s.name == "hrp1s_walk") && !SetSoftMass(&s, error)) {
      return false;
    }
  }
  return true;
}

bool HasDamping(const SceneSpec& scene) {
  Setting s;
  s.contact = scene.contacts.front();
  std::string error;
  auto sim = Sim::Create(scene, s, &error);
  if (!sim) return false;
  const mjModel* m = sim->m();
  for (int i = 0; i < m->nv; ++i)
    if (m->dof_damping[i] > 0) return true;
  return false;
}

Setting ReferenceSetting(const BenchOptions& o, const SceneSpec& scene, Contact c) {
  Setting rs;
  rs.integrator = Integrator::kRK4;
  rs.dt = o.ref_dt;
  rs.contact = c;
  rs.iterations = 200;
  rs.tolerance = 1e-12;
  rs.geometry = scene.geometries.empty() ? "" : scene.geometries[0];
  return rs;
}

std::vector<std::pair<std::string, Setting>> SettingsFor(const BenchOptions& o,
                                                         const SceneSpec& scene,
                                                         const Setting& rs,
                                                         const std::vector<double>& dts,
                                                         bool damping) {
  std::vector<Integrator> integrators = {Integrator::kEuler, Integrator::kRK4};
  if (damping) integrators.push_back(Integrator::kImplicit);
  const Contact c = rs.contact;
  std::vector<std::pair<std::string, Setting>> settings;
  for (double dt : dts) {
    for (Integrator in : integrators) {
      if (o.quick && in == Integrator::kImplicit && dt != 1e-3) continue;
      Setting s;
      s.integrator = in;
      s.dt = dt;
      s.contact = c;
      s.geometry = rs.geometry;
      settings.push_back({"dt", s});
    }
  }
  if (!o.quick) {
    // the reference's own error: its setting at half its step, compared with it
    Setting s = rs;
    s.dt = rs.dt / 2;
    settings.push_back({"refcheck", s});
  }
  if (c != Contact::kNative && c != Contact::kRigid) return settings;
  const std::vector<std::pair<int, double>> solver =
      o.quick ? std::vector<std::pair<int, double>>{{2, 1e-3}}
              : std::vector<std::pair<int, double>>{{1, 1e-3}, {3, 1e-3}, {10, 1e-3},
                                                     {1, 1e-8}, {3, 1e-8}, {10, 1e-8}};
  for (auto [it, tol] : solver) {
    Setting s;
    s.dt = 1e-3;
    s.contact = c;
    s.iterations = it;
    s.tolerance = tol;
    s.geometry = rs.geometry;
    settings.push_back({"solver", s});
  }
  for (size_t g = 1; g < scene.geometries.size(); ++g) {
    for (double dt : o.quick ? std::vector<double>{1e-3}
                             : std::vector<double>{0.25e-3, 1e-3, 4e-3}) {
      Setting s;
      s.dt = dt;
      s.contact = c;
      s.geometry = scene.geometries[g];
      settings.push_back({"geometry", s});
    }
  }
  return settings;
}

void MeasureClosedForms(const SceneSpec& scene, const std::string& src, Row* row,
                        std::vector<ClosedRow>* closed) {
  double value = std::nan(""), exact = std::nan("");
  std::string note;
  auto add_closed = [&](const std::string& q, const std::string& unit, double err) {
    ClosedRow cr;
    cr.scene = scene.name;
    cr.s = row->s;
    cr.quantity = q;
    cr.unit = unit;
    cr.value = value;
    cr.exact = exact;
    cr.error = err;
    cr.note = note;
    closed->push_back(cr);
    value = exact = std::nan("");
    note.clear();
  };
  const bool dt_or_geometry = row->sweep == "dt" || row->sweep == "geometry";
  if (scene.name == "pendulum" && row->sweep == "dt") {
    exact = PendulumPeriod(0.26, 1.0, kG, 0.5, 0.1);
    value = MeasurePendulumPeriod(src + "/mjcf/bench/pendulum_single.xml", row->s, 3);
    row->closed_form = "period_rel";
    row->closed_form_error = std::fabs(value - exact) / exact;
    add_closed("pendulum period (exact, elliptic K; small-angle 2 pi sqrt(I/mgd) = " +
                   Num(2 * M_PI * std::sqrt(0.26 / (kG * 0.5)), "%.6f") + " s)",
               "s", row->closed_form_error);
  }
  if (scene.name == "box" && dt_or_geometry) {
    row->closed_form = "freefall_m";
    row->closed_form_error = FreeFallError(scene, row->s, &value, &exact);
    add_closed("free fall z(0.096 s) = z0 - g t^2/2", "m", row->closed_form_error);
    if (row->s.contact == Contact::kSoft) {
      const double e1 = StaticSink(scene, row->s, &value, &exact, &note);
      add_closed("soft-foot static sink (m g / k)^(1/n)", "m", e1);
      const double e2 = Restitution(scene, row->s, &value, &exact, &note);
      add_closed("soft-foot restitution at 0.1 m/s (Hunt-Crossley law)", "-", e2);
    }
  }
  if (scene.name == "ball" && dt_or_geometry) {
    row->closed_form = "rolling_mps";
    row->closed_form_error = RollingError(scene, row->s, &value, &exact);
    add_closed("rolling speed after sliding 5/7 v0", "m/s", row->closed_form_error);
  }
}

}  // namespace ohrp::accuracy
