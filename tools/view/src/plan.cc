// The walking controller's plan from walk.csv, in the world, for the plan overlays (plan.h).
#include "view/plan.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ohrp::view {

namespace {

constexpr double kMinHeight = 0.01;  // [m] the CoM's least height over the ground for omega

std::vector<int> Columns(const datalog::Table& t, std::initializer_list<const char*> names) {
  std::vector<int> out;
  for (const char* n : names) out.push_back(t.Column(n));
  return out;
}

bool All(const std::vector<int>& cols) {
  return std::all_of(cols.begin(), cols.end(), [](int c) { return c >= 0; });
}

nlohmann::json MissingOf(const datalog::Table& t, std::initializer_list<const char*> names) {
  nlohmann::json out = nlohmann::json::array();
  for (const char* n : names)
    if (t.Column(n) < 0) out.push_back(n);
  return out;
}

nlohmann::json Point(const std::array<double, 3>& p) { return {p[0], p[1], p[2]}; }

}  // namespace

std::array<double, 2> CapturePoint(const double c[3], const double v[2], double ground_z) {
  const double omega = std::sqrt(kPlanGravity / std::max(c[2] - ground_z, kMinHeight));
  return {c[0] + v[0] / omega, c[1] + v[1] / omega};
}

std::array<double, 3> Planar::Apply(const double p[3]) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * p[0] - s * p[1] + x, s * p[0] + c * p[1] + y, p[2] + dz};
}

Planar FitTwoPoints(const double a[3], const double b[3], const double A[3], const double B[3]) {
  Planar out;
  out.yaw = std::atan2(B[1] - A[1], B[0] - A[0]) - std::atan2(b[1] - a[1], b[0] - a[0]);
  const double m[3] = {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
  const std::array<double, 3> rotated = Planar{0, 0, out.yaw, 0}.Apply(m);
  out.x = (A[0] + B[0]) / 2 - rotated[0];
  out.y = (A[1] + B[1]) / 2 - rotated[1];
  out.dz = (A[2] + B[2]) / 2 - m[2];
  return out;
}

std::array<int, 2> LeftRightSoles(const mjModel* m) {
  std::vector<int> soles;
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    const size_t n = name ? std::strlen(name) : 0;
    if (n >= 5 && std::strcmp(name + n - 5, "_SOLE") == 0 && m->geom_type[g] == mjGEOM_BOX) soles.push_back(g);
  }
  if (soles.size() != 2) return {-1, -1};
  mjData* d = mj_makeData(m);
  mj_kinematics(m, d);
  // each sole's y in its root body's frame: the left one is further along +y
  double y[2];
  for (int i = 0; i < 2; ++i) {
    const int root = m->body_rootid[m->geom_bodyid[soles[i]]];
    const double* R = d->xmat + 9 * root;
    double rel[3];
    for (int k = 0; k < 3; ++k) rel[k] = d->geom_xpos[3 * soles[i] + k] - d->xpos[3 * root + k];
    y[i] = R[1] * rel[0] + R[4] * rel[1] + R[7] * rel[2];  // (R^T rel).y
  }
  mj_deleteData(d);
  return y[0] >= y[1] ? std::array<int, 2>{soles[0], soles[1]} : std::array<int, 2>{soles[1], soles[0]};
}

std::unique_ptr<WalkPlan> WalkPlan::Load(const std::string& path, std::string* error) {
  std::unique_ptr<WalkPlan> p(new WalkPlan());
  if (!p->table_.Load(path, error)) return nullptr;
  const datalog::Table& t = p->table_;
  p->t_ = t.Column("t");
  if (p->t_ < 0 || t.rows() == 0) {
    *error = path + ": " + (p->t_ < 0 ? "no 't' column" : "no rows") + " (not the walk controller's log)";
    return nullptr;
  }
  p->zmp_des_ = Columns(t, {"zmp_des_x", "zmp_des_y"});
  p->dcm_ = Columns(t, {"dcm_x", "dcm_y"});
  p->com_ref_ = Columns(t, {"com_ref_x", "com_ref_y", "com_ref_z"});
  p->left_ = Columns(t, {"left_x", "left_y", "left_z", "left_yaw"});
  p->right_ = Columns(t, {"right_x", "right_y", "right_z", "right_yaw"});
  p->support_ = Columns(t, {"support_left", "support_right"});
  p->frame_ = Columns(t, {"frame_x", "frame_y", "frame_yaw"});
  return p;
}

nlohmann::json WalkPlan::Missing() const {
  const datalog::Table& t = table_;
  nlohmann::json dcm = nlohmann::json::array();
  if (!All(com_ref_) && !All(dcm_)) dcm = MissingOf(t, {"com_ref_x", "com_ref_y", "com_ref_z", "dcm_x", "dcm_y"});
  return {{"desired_zmp", MissingOf(t, {"zmp_des_x", "zmp_des_y"})},
          {"dcm", dcm},
          {"footsteps", MissingOf(t, {"left_x", "left_y", "left_z", "left_yaw", "right_x", "right_y", "right_z",
                                      "right_yaw", "support_left", "support_right"})}};
}

double WalkPlan::t0() const { return table_.col(t_)[0]; }

Planar WalkPlan::WorldFromPlan(size_t r) const {
  // plan -> estimator: p_est = Rz(-yaw) (p - f); then the registration
  double fx = 0, fy = 0, fyaw = 0;
  if (All(frame_)) {
    fx = table_.col(frame_[0])[r];
    fy = table_.col(frame_[1])[r];
    fyaw = table_.col(frame_[2])[r];
  }
  Planar out = world_from_est_;
  out.yaw = world_from_est_.yaw - fyaw;
  const double f[3] = {fx, fy, 0};
  const std::array<double, 3> shifted = Planar{0, 0, out.yaw, 0}.Apply(f);
  out.x = world_from_est_.x - shifted[0];
  out.y = world_from_est_.y - shifted[1];
  return out;
}

void WalkPlan::Register(const double left_W[3], const double right_W[3]) {
  world_from_est_ = Planar{};
  if (!All(left_) || !All(right_)) return;
  const Planar to_est = WorldFromPlan(0);  // the registration is the identity here
  double l[3], r[3];
  for (int k = 0; k < 3; ++k) {
    l[k] = table_.col(left_[k])[0];
    r[k] = table_.col(right_[k])[0];
  }
  const std::array<double, 3> le = to_est.Apply(l), re = to_est.Apply(r);
  world_from_est_ = FitTwoPoints(le.data(), re.data(), left_W, right_W);
}

double WalkPlan::GroundZ(size_t r) const {
  if (!All(left_) || !All(right_)) return 0;
  const double zl = table_.col(left_[2])[r], zr = table_.col(right_[2])[r];
  if (!All(support_)) return (zl + zr) / 2;
  const bool sl = table_.col(support_[0])[r] >= 0.5, sr = table_.col(support_[1])[r] >= 0.5;
  if (sl && !sr) return zl;
  if (sr && !sl) return zr;
  return (zl + zr) / 2;
}

std::array<double, 2> WalkPlan::PlanCapturePoint(size_t r) const {
  const std::vector<double>& t = table_.col(t_);
  const size_t a = r > 0 ? r - 1 : r, b = std::min(r + 1, t.size() - 1);
  double c[3], v[2] = {0, 0};
  for (int k = 0; k < 3; ++k) c[k] = table_.col(com_ref_[k])[r];
  // the velocity by central differences (one-sided at the ends)
  if (t[b] > t[a])
    for (int k = 0; k < 2; ++k) v[k] = (table_.col(com_ref_[k])[b] - table_.col(com_ref_[k])[a]) / (t[b] - t[a]);
  return CapturePoint(c, v, GroundZ(r));
}

nlohmann::json WalkPlan::Footsteps(const double half[2][2]) const {
  nlohmann::json out = nlohmann::json::array();
  if (!All(left_) || !All(right_) || !All(support_)) return out;
  const std::vector<double>& t = table_.col(t_);
  const std::vector<int>* pose[2] = {&left_, &right_};
  struct Step {
    double t;
    int side;
    size_t row;
  };
  std::vector<Step> steps;
  for (int side = 0; side < 2; ++side) {
    const std::vector<double>& sup = table_.col(support_[side]);
    steps.push_back({t[0], side, 0});
    for (size_t r = 1; r < t.size(); ++r)
      if (sup[r] >= 0.5 && sup[r - 1] < 0.5) steps.push_back({t[r], side, r});
  }
  std::stable_sort(steps.begin(), steps.end(), [](const Step& a, const Step& b) { return a.t < b.t; });
  for (const Step& s : steps) {
    const std::vector<int>& c = *pose[s.side];
    const double p[3] = {table_.col(c[0])[s.row], table_.col(c[1])[s.row], table_.col(c[2])[s.row]};
    const Planar w = WorldFromPlan(s.row);
    const std::array<double, 3> centre = w.Apply(p);
    const double yaw = w.Yaw(table_.col(c[3])[s.row]);
    const double hx = half[s.side][0], hy = half[s.side][1];
    nlohmann::json corners = nlohmann::json::array();
    const double sx[4] = {1, 1, -1, -1}, sy[4] = {1, -1, -1, 1};
    for (int k = 0; k < 4; ++k) {
      const double local[3] = {sx[k] * hx, sy[k] * hy, 0};
      const std::array<double, 3> d = Planar{0, 0, yaw, 0}.Apply(local);
      corners.push_back({centre[0] + d[0], centre[1] + d[1], centre[2]});
    }
    out.push_back({{"side", s.side == 0 ? "left" : "right"}, {"t", s.t}, {"center", Point(centre)},
                   {"yaw", yaw}, {"corners", corners}});
  }
  return out;
}

double WalkPlan::Value(int c, size_t lo, size_t hi, double s) const {
  return table_.col(c)[lo] + s * (table_.col(c)[hi] - table_.col(c)[lo]);
}

nlohmann::json WalkPlan::At(double t) const {
  const std::vector<double>& times = table_.col(t_);
  if (t < times.front()) return nullptr;
  const size_t next = std::lower_bound(times.begin(), times.end(), t) - times.begin();
  const size_t hi = std::min(next, times.size() - 1), lo = hi > 0 ? hi - 1 : 0;
  const double span = times[hi] - times[lo];
  const double s = span > 0 ? std::clamp((t - times[lo]) / span, 0.0, 1.0) : 1.0;
  // a plan-frame point of each row to the world, then between the rows
  auto world = [&](auto point_of_row) {
    std::array<double, 3> p[2];
    const size_t rows[2] = {lo, hi};
    for (int i = 0; i < 2; ++i) {
      const std::array<double, 2> xy = point_of_row(rows[i]);
      const double q[3] = {xy[0], xy[1], GroundZ(rows[i])};
      p[i] = WorldFromPlan(rows[i]).Apply(q);
    }
    return nlohmann::json{p[0][0] + s * (p[1][0] - p[0][0]), p[0][1] + s * (p[1][1] - p[0][1]),
                          p[0][2] + s * (p[1][2] - p[0][2])};
  };
  nlohmann::json out;
  out["t"] = t;
  auto column_xy = [&](const std::vector<int>& c) {
    return [&, c](size_t r) { return std::array<double, 2>{table_.col(c[0])[r], table_.col(c[1])[r]}; };
  };
  out["zmp_des"] = All(zmp_des_) ? world(column_xy(zmp_des_)) : nlohmann::json(nullptr);
  out["dcm"] = All(dcm_) ? world(column_xy(dcm_)) : nlohmann::json(nullptr);
  out["cp"] = All(com_ref_) ? world([&](size_t r) { return PlanCapturePoint(r); }) : nlohmann::json(nullptr);
  out["support"] = All(support_) ? nlohmann::json{Value(support_[0], lo, hi, s) >= 0.5, Value(support_[1], lo, hi, s) >= 0.5}
                                 : nlohmann::json(nullptr);
  return out;
}

}  // namespace ohrp::view
