// The robot's clearance from the scene's static obstacles on the logged motion
// (runner/obstacle_checks.h).
#include "runner/obstacle_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "collision/from_mjcf.h"
#include "collision/shape_distance.h"
#include "log_posture.h"
#include "robot_model/model.h"

namespace ohrp::runner {
namespace {

struct Pair {
  int robot, obstacle;
};

std::string GeomText(const mjModel* m, int g) {
  const char* n = mj_id2name(m, mjOBJ_GEOM, g);
  const char* b = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]);
  if (n && *n) return n;
  return std::string(b ? b : "?") + ":geom" + std::to_string(g);
}

// the pairs: the robot's geoms (under a free joint) against the static obstacles
std::vector<Pair> ObstaclePairs(const mjModel* m, int* obstacles) {
  std::vector<int> robot, fixed;
  for (int g = 0; g < m->ngeom; ++g) {
    const int b = m->geom_bodyid[g], t = m->geom_type[g];
    if (m->body_weldid[b] != 0) robot.push_back(g);
    else if (t != mjGEOM_PLANE && t != mjGEOM_HFIELD) fixed.push_back(g);
  }
  *obstacles = static_cast<int>(fixed.size());
  std::vector<Pair> pairs;
  for (int r : robot)
    for (int o : fixed) pairs.push_back({r, o});
  return pairs;
}

// the pair's penetration (a negative distance) as MuJoCo's collision function finds it with no
// margin, else 0 (apart). Not a clearance: with a margin MuJoCo's box-box function reports
// distances of non-touching boxes wrongly (-322 mm for boxes 19 mm apart), so none is asked.
double Penetration(const mjModel* m, const mjData* d, const Pair& p, std::vector<mjContact>* con) {
  const mjtNum* a = d->geom_xpos + 3 * p.robot;
  const mjtNum* b = d->geom_xpos + 3 * p.obstacle;
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  const double reach = m->geom_rbound[p.robot] + m->geom_rbound[p.obstacle];
  if (dx * dx + dy * dy + dz * dz > reach * reach) return 0;
  int g1 = p.robot, g2 = p.obstacle;
  if (m->geom_type[g1] > m->geom_type[g2]) std::swap(g1, g2);
  mjfCollision collide = mjCOLLISIONFUNC[m->geom_type[g1]][m->geom_type[g2]];
  if (!collide) return 0;
  const int n = collide(m, d, con->data(), g1, g2, 0);
  double closest = 0;
  for (int i = 0; i < n; ++i) closest = std::min(closest, static_cast<double>((*con)[i].dist));
  return closest;
}

// the run's scene and its robot-obstacle pairs; false with `*why` (the scene does not load, or
// has no static obstacle)
struct ObstacleScene {
  std::string path;
  std::unique_ptr<model::Scene> scene;
  std::vector<Pair> pairs;
  int obstacles = 0;
  bool Load(const nlohmann::json& sim, std::string* why) {
    path = sim.value("scene", "");
    std::string error;
    scene = model::Scene::Load(path, &error);
    if (!scene) return *why = "the run's scene: " + error, false;
    pairs = ObstaclePairs(scene->m(), &obstacles);
    if (obstacles == 0) return *why = path + " has no static obstacle (only the floor)", false;
    return true;
  }
};

// each geom of `pairs` as a shape for distances (null for a geom that cannot be one); false with
// the reason for the first such geom
bool GeomShapes(const mjModel* m, const std::vector<Pair>& pairs,
                std::vector<std::unique_ptr<collision::ShapeDistance>>* shapes, std::string* error) {
  shapes->clear();
  shapes->resize(m->ngeom);
  for (const Pair& p : pairs) {
    for (int g : {p.robot, p.obstacle}) {
      if ((*shapes)[g]) continue;
      collision::Shape s;
      std::string why;
      if (!collision::GeomShape(m, g, &s, &why)) return *error = "geom " + GeomText(m, g) + " " + why, false;
      (*shapes)[g] = std::make_unique<collision::ShapeDistance>(s);
    }
  }
  return true;
}

Eigen::Isometry3d BodyPose(const mjData* d, int body) {
  const mjtNum* p = d->xpos + 3 * body;
  const mjtNum* q = d->xquat + 4 * body;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translate(Eigen::Vector3d(p[0], p[1], p[2]));
  X.rotate(Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix());
  return X;
}

std::string Mm(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", 1e3 * metres);
  return text;
}

std::string Seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", t);
  return text;
}

}  // namespace

CheckResult ObstacleContacts(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim) {
  CheckResult r{"obstacle_contacts", false, 0, "cycles", "", ""};
  ObstacleScene o;
  std::string error;
  if (!o.Load(sim, &r.detail)) return r;
  const mjModel* m = o.scene->m();
  mjData* d = o.scene->d();
  const std::vector<Pair>& pairs = o.pairs;
  const int obstacles = o.obstacles;
  const std::vector<double>& time = log.col(log.Column("time"));
  std::vector<mjContact> con(mjMAXCONPAIR);
  double first_t = -1, deepest = 0, deepest_t = 0;
  Pair first_pair{-1, -1}, deepest_pair{-1, -1};
  long in_contact = 0;
  for (size_t row = 0; row < time.size(); ++row) {
    if (!PostureFromLogRow(m, d, log, row, false, nullptr, &error)) return r.detail = error, r;
    mj_kinematics(m, d);
    bool touching = false;
    for (const Pair& p : pairs) {
      const double x = Penetration(m, d, p, &con);
      if (x < 0) {
        touching = true;
        if (x < deepest) deepest = x, deepest_t = time[row], deepest_pair = p;
        if (first_t < 0) first_t = time[row], first_pair = p;
      }
    }
    in_contact += touching;
  }
  const std::string contact = first_t < 0 ? "in contact: none"
      : "first contact " + GeomText(m, first_pair.robot) + " / " + GeomText(m, first_pair.obstacle) +
            " at " + Seconds(first_t) + " s; deepest " + Mm(-deepest) + " mm (" +
            GeomText(m, deepest_pair.robot) + " / " + GeomText(m, deepest_pair.obstacle) + " at " +
            Seconds(deepest_t) + " s)";
  r.detail = std::to_string(pairs.size()) + " robot-obstacle geom pairs (" + std::to_string(obstacles) +
             " static obstacles) in " + std::to_string(time.size()) + " logged cycles; " + contact;
  const double max = spec.Number("max", 0);
  r.value = static_cast<double>(in_contact);
  r.passed = r.value <= max;
  r.limit = "<= " + std::to_string(static_cast<long>(max));
  return r;
}

CheckResult ObstacleClearance(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim) {
  CheckResult r{"obstacle_clearance", false, 0, "m", "", ""};
  const double min = spec.Number("min", 0);
  r.limit = ">= " + Mm(min) + " mm";
  ObstacleScene o;
  std::string error;
  if (!o.Load(sim, &r.detail)) return r;
  const mjModel* m = o.scene->m();
  mjData* d = o.scene->d();
  const std::vector<Pair>& pairs = o.pairs;
  const int obstacles = o.obstacles;
  const std::string& scene_path = o.path;
  std::vector<std::unique_ptr<collision::ShapeDistance>> shape;
  if (!GeomShapes(m, pairs, &shape, &error)) return r.detail = scene_path + ": " + error, r;
  const std::vector<double>& time = log.col(log.Column("time"));
  std::vector<Eigen::Isometry3d> X_WF(m->ngeom);  // each geom's body pose this row
  double best = INFINITY, best_t = 0;
  Pair best_pair{-1, -1};
  long below = 0;
  for (size_t row = 0; row < time.size(); ++row) {
    if (!PostureFromLogRow(m, d, log, row, false, nullptr, &error)) return r.detail = error, r;
    mj_kinematics(m, d);
    for (int g = 0; g < m->ngeom; ++g)
      if (shape[g]) X_WF[g] = BodyPose(d, m->geom_bodyid[g]);
    // a pair is measured only where its bounding spheres could be closer than both the
    // smallest distance so far and the limit: nothing closer is missed
    const double threshold = std::max(best, min);
    double row_least = INFINITY;
    for (const Pair& p : pairs) {
      const collision::ShapeDistance &a = *shape[p.robot], &b = *shape[p.obstacle];
      const double spheres = (X_WF[p.robot] * a.centre_F() - X_WF[p.obstacle] * b.centre_F()).norm() -
                             a.radius() - b.radius();
      if (spheres >= threshold) continue;
      const double gap = a.To(X_WF[p.robot], b, X_WF[p.obstacle]);
      row_least = std::min(row_least, gap);
      if (gap < best) best = gap, best_t = time[row], best_pair = p;
    }
    below += row_least < min;
  }
  if (best_pair.robot < 0) return r.detail = "no robot geom to measure in " + scene_path, r;
  r.value = best;
  r.passed = best >= min;
  r.detail = "closest " + GeomText(m, best_pair.robot) + " / " + GeomText(m, best_pair.obstacle) +
             " at " + Mm(best) + " mm (" + Seconds(best_t) + " s); " + std::to_string(below) +
             " of " + std::to_string(time.size()) + " logged cycles closer than " + Mm(min) +
             " mm; " + std::to_string(pairs.size()) + " robot-obstacle geom pairs (" +
             std::to_string(obstacles) + " static obstacles)";
  return r;
}

}  // namespace ohrp::runner
