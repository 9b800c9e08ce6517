// Checks on what a camera sees (runner/vision_checks.h).
#include "runner/vision_checks.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "log_posture.h"
#include "robot_model/model.h"

namespace ohrp::runner {
namespace {

CheckResult Failed(CheckResult r, const std::string& why) {
  r.passed = false;
  r.detail = why;
  return r;
}

std::string Text(const CheckSpec& spec, const std::string& key) {
  const auto it = spec.params.find(key);
  return it == spec.params.end() ? "" : it->second;
}

}  // namespace

bool ProjectPinhole(const double p_C[3], double f, int width, int height, double* u, double* v) {
  const double depth = -p_C[2];
  if (!(depth > 0)) return false;
  *u = 0.5 * width + f * p_C[0] / depth;
  *v = 0.5 * height - f * p_C[1] / depth;
  return true;
}

CheckResult BallCentred(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim) {
  const std::string geom = Text(spec, "geom"), camera = Text(spec, "camera");
  CheckResult r{"ball_centred " + geom + " in " + camera, false, 0, "px", "", ""};
  const double tolerance = spec.Number("tolerance");
  const int width = static_cast<int>(spec.Number("width"));
  const int height = static_cast<int>(spec.Number("height"));
  r.limit = "<= " + std::to_string(tolerance).substr(0, 5) + " px from the centre of " +
            std::to_string(width) + "x" + std::to_string(height);

  // the row: at `at`, else the last one
  const std::vector<double>& time = log.col(log.Column("time"));
  if (time.empty()) return Failed(r, "the data log has no rows");
  size_t row = time.size() - 1;
  if (spec.Has("at")) {
    const double at = spec.Number("at");
    while (row > 0 && time[row] > at + 1e-9) --row;
  }

  // the scene's kinematics at that row
  const std::string scene_path = sim.value("scene", "");
  std::string error;
  auto scene = model::Scene::Load(scene_path, &error);
  if (!scene) return Failed(r, "the run's scene: " + error);
  const mjModel* m = scene->m();
  mjData* d = scene->d();
  const int g = mj_name2id(m, mjOBJ_GEOM, geom.c_str());
  const int c = mj_name2id(m, mjOBJ_CAMERA, camera.c_str());
  if (g < 0 || c < 0) {
    return Failed(r, scene_path + " has no " + (g < 0 ? "geom '" + geom : "camera '" + camera) + "'");
  }
  int joints = 0;
  std::string missing;
  if (!PostureFromLogRow(m, d, log, row, true, &joints, &missing)) return Failed(r, missing);
  mj_kinematics(m, d);
  mj_camlight(m, d);

  // the geom's centre in the camera frame: R^T (p - c), R's columns the camera's axes
  const double* R = d->cam_xmat + 9 * c;
  double rel[3], p_C[3];
  for (int k = 0; k < 3; ++k) rel[k] = d->geom_xpos[3 * g + k] - d->cam_xpos[3 * c + k];
  for (int k = 0; k < 3; ++k) p_C[k] = R[k] * rel[0] + R[3 + k] * rel[1] + R[6 + k] * rel[2];
  const double f = 0.5 * height / std::tan(0.5 * m->cam_fovy[c] * M_PI / 180.0);
  double u = 0, v = 0;
  if (!ProjectPinhole(p_C, f, width, height, &u, &v)) {
    return Failed(r, geom + " is behind camera " + camera + " at t=" + std::to_string(time[row]));
  }
  const double du = u - 0.5 * width, dv = v - 0.5 * height;
  r.value = std::hypot(du, dv);
  char text[200];
  std::snprintf(text, sizeof(text), "at t=%.3f s the centre of %s is at (%.1f, %.1f) px, %+.1f / %+.1f px from the image centre (%d joints from the log)",
                time[row], geom.c_str(), u, v, du, dv, joints);
  r.detail = text;
  r.passed = r.value <= tolerance;
  return r;
}

}  // namespace ohrp::runner
