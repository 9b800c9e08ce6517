// Footsteps on a scene's surfaces (terrain.h).
#include "walking/terrain.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "robot_model/kinematics.h"
#include "robot_model/model.h"

namespace ohrp::walking {
namespace {

constexpr double kInset = 0.005;      // [m] samples this far inside the sole's edges
constexpr int kNx = 5, kNy = 3;       // samples along and across the sole
constexpr double kPlanar = 0.002;     // [m] hits within this of one plane: a planar surface
constexpr double kSearchStep = 0.01;  // [m] grid of the shifts tried off an edge
constexpr double kTie = 1e-6;         // [m] planes this close at the centre are equally low

}  // namespace

TerrainMap::~TerrainMap() {
  if (d_) mj_deleteData(d_);
  if (m_) mj_deleteModel(m_);
}

std::unique_ptr<TerrainMap> TerrainMap::Load(const std::string& path, const std::string& keyframe,
                                             std::string* error) {
  auto scene = model::Scene::Load(path, error);
  if (!scene) return nullptr;
  if (!scene->Reset(keyframe, error)) return nullptr;
  mjModel* m = scene->m();
  mjData* d = scene->d();
  mj_forward(m, d);
  // the robot's soles and base, through the same map the controllers use
  std::string why;
  auto kin = model::Kinematics::FromModel(m, &why);
  if (!kin || !kin->floating() || kin->left_sole() < 0 || kin->right_sole() < 0) {
    *error = path + ": no robot with a floating base and two soles (*_SOLE geoms) to start from" +
             (why.empty() ? "" : ": " + why);
    return nullptr;
  }
  std::unique_ptr<TerrainMap> t(new TerrainMap());
  t->m_ = mj_copyModel(nullptr, m);
  t->d_ = mj_makeData(t->m_);
  mju_copy(t->d_->qpos, d->qpos, m->nq);
  mj_forward(t->m_, t->d_);
  // the start frame: between the soles' bottoms, the base's heading
  const int base = kin->robot().base_body;
  const mjtNum* R = d->xmat + 9 * base;
  t->yaw_ = std::atan2(R[3], R[0]);
  Eigen::Vector3d mid = Eigen::Vector3d::Zero();
  for (int side : {kin->left_sole(), kin->right_sole()}) {
    const int g = kin->soles()[side].geom_id;
    const Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> Rg(d->geom_xmat + 9 * g);
    const Eigen::Vector3d c(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]);
    mid += 0.5 * (c - Rg.col(2) * m->geom_size[3 * g + 2]);
  }
  t->origin_ = mid;
  // the terrain: geoms on bodies welded to the world
  t->top_ = mid.z() + 1.0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->body_weldid[m->geom_bodyid[g]] != 0) continue;
    t->geoms_.push_back(g);
    if (m->geom_type[g] != mjGEOM_PLANE)
      t->top_ = std::max(t->top_, d->geom_xpos[3 * g + 2] + m->geom_rbound[g] + 0.1);
  }
  if (t->geoms_.empty()) {
    *error = path + ": the scene has no static geometry (a floor) to walk on";
    return nullptr;
  }
  return t;
}

bool TerrainMap::Height(double x, double y, double* z) const {
  const mjtNum pnt[3] = {x, y, top_};
  const mjtNum vec[3] = {0, 0, -1};
  double best = -1;
  for (int g : geoms_) {
    double dist = -1;
    switch (m_->geom_type[g]) {
      case mjGEOM_HFIELD: dist = mj_rayHfield(m_, d_, g, pnt, vec); break;
      case mjGEOM_MESH: dist = mj_rayMesh(m_, d_, g, pnt, vec); break;
      default:
        dist = mju_rayGeom(d_->geom_xpos + 3 * g, d_->geom_xmat + 9 * g, m_->geom_size + 3 * g, pnt,
                           vec, m_->geom_type[g]);
    }
    if (dist >= 0 && (best < 0 || dist < best)) best = dist;
  }
  if (best < 0) return false;
  *z = top_ - best;
  return true;
}

bool TerrainMap::SurfaceUnder(const Eigen::Vector2d& p, double yaw, const Eigen::Vector2d& half,
                              SurfaceSample* out, std::string* why) const {
  // the sole's samples, in the world
  const Eigen::Rotation2Dd R0(yaw_), Rs(yaw);
  Eigen::Matrix<double, kNx * kNy, 3> A;
  Eigen::Matrix<double, kNx * kNy, 1> z;
  int n = 0;
  for (int i = 0; i < kNx; ++i) {
    for (int j = 0; j < kNy; ++j, ++n) {
      const Eigen::Vector2d local((2.0 * i / (kNx - 1) - 1) * std::max(half.x() - kInset, 0.0),
                                  (2.0 * j / (kNy - 1) - 1) * std::max(half.y() - kInset, 0.0));
      const Eigen::Vector2d q_start = p + Rs * local;
      const Eigen::Vector2d q = origin_.head<2>() + R0 * q_start;
      double h;
      if (!Height(q.x(), q.y(), &h)) {
        *why = "no surface under the sole at (" + std::to_string(q_start.x()) + ", " +
               std::to_string(q_start.y()) + ") of the start frame";
        return false;
      }
      A.row(n) << 1.0, local.x(), local.y();
      z(n) = h - origin_.z();
    }
  }
  // the plane a rigid sole rests on: of the planes through three samples that leave every
  // sample on or below them, the lowest at the sole's centre (the upper hull's facet over the
  // centre); z = a + b x + c y in the sole's frame
  Eigen::Vector3d best(0, 0, 0);
  bool found = false;
  const int m = kNx * kNy;
  for (int i = 0; i < m; ++i) {
    for (int j = i + 1; j < m; ++j) {
      for (int k = j + 1; k < m; ++k) {
        Eigen::Matrix3d M;
        M << A.row(i), A.row(j), A.row(k);
        if (std::abs(M.determinant()) < 1e-9) continue;  // collinear samples
        const Eigen::Vector3d abc = M.partialPivLu().solve(Eigen::Vector3d(z(i), z(j), z(k)));
        if ((A * abc - z).minCoeff() < -1e-9) continue;  // a sample above the plane
        // the lowest at the centre; of equally low ones (a sole over a riser rests as low on
        // the stair's top as on any plane through the nose), the least tilted
        const bool lower = abc(0) < best(0) - kTie;
        const bool level = std::abs(abc(0) - best(0)) <= kTie &&
                           abc.tail<2>().squaredNorm() < best.tail<2>().squaredNorm();
        if (!found || lower || level) best = abc;
        found = true;
      }
    }
  }
  if (!found) best = Eigen::Vector3d(z.maxCoeff(), 0, 0);
  out->planar = (A * best - z).maxCoeff() < kPlanar;
  out->z = best(0);
  // the bearing region: the samples on the plane, out to the sole's edge beyond the outermost
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  const Eigen::Vector2d inner(std::max(half.x() - kInset, 0.0), std::max(half.y() - kInset, 0.0));
  for (int i = 0; i < kNx * kNy; ++i) {
    if (A.row(i).dot(best) - z(i) > kPlanar) continue;
    const Eigen::Vector2d q(A(i, 1), A(i, 2));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  for (int a = 0; a < 2; ++a) {
    if (lo[a] <= -inner[a] + 1e-9) lo[a] = -half[a];
    if (hi[a] >= inner[a] - 1e-9) hi[a] = half[a];
  }
  out->contact_centre = 0.5 * (lo + hi);
  out->contact_half = 0.5 * (hi - lo);
  // the normal in the sole's frame, then in the start frame (turned by the sole's yaw)
  Eigen::Vector3d nrm(-best(1), -best(2), 1.0);
  nrm = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * nrm.normalized();
  out->roll = std::atan2(-nrm.y(), nrm.z());
  out->pitch = std::asin(std::clamp(nrm.x(), -1.0, 1.0));
  return true;
}

bool TerrainMap::PlaceSteps(std::vector<Footstep>* steps, const FeetPose& start,
                            const StepLimits& limits, double search, std::string* error) const {
  const Eigen::Vector2d& half = limits.sole_half_size;
  FeetPose feet = start;
  // candidate shifts within `search`, nearest first (the planned spot itself first)
  std::vector<Eigen::Vector2d> shifts;
  const int n = search > 0 ? static_cast<int>(std::floor(search / kSearchStep + 1e-9)) : 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      if (std::hypot(i, j) * kSearchStep <= search + 1e-9) shifts.emplace_back(i * kSearchStep, j * kSearchStep);
  std::stable_sort(shifts.begin(), shifts.end(),
                   [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.norm() < b.norm(); });
  for (size_t k = 0; k < steps->size(); ++k) {
    Footstep& s = (*steps)[k];
    SurfaceSample sample;
    std::string why;
    if (!SurfaceUnder(s.p.head<2>(), s.yaw, half, &sample, &why)) {
      *error = "step " + std::to_string(k + 1) + " (" + SideName(s.foot) + "): " + why;
      return false;
    }
    // a sole across an edge (a stone's, a stair's nose) rests on a line, and one whose toes come
    // nearer a riser than kShinLean of its height puts the shin against it: move it, within
    // `search`, to where the surface under it is one plane and the toes clear a riser (and where
    // the step and the next one still keep the limits)
    Footstep placed = s;
    placed.p.z() = sample.z;
    placed.roll = sample.roll;
    placed.pitch = sample.pitch;
    double need = 0;
    const double clearance = ToeClearance(placed, limits, &need);
    if (!sample.planar || clearance < need) {
      bool found = false;
      for (const Eigen::Vector2d& d : shifts) {
        SurfaceSample other;
        std::string ignored;
        Footstep moved = s;
        moved.p.head<2>() += d;
        if (!CheckStep(feet, moved, limits).empty()) continue;
        if (k + 1 < steps->size() && !CheckStep(After(feet, moved), (*steps)[k + 1], limits).empty())
          continue;
        if (!SurfaceUnder(moved.p.head<2>(), s.yaw, half, &other, &ignored) || !other.planar) continue;
        moved.p.z() = other.z;
        moved.roll = other.roll;
        moved.pitch = other.pitch;
        if (!ToesClear(moved, limits)) continue;
        s.p.head<2>() = moved.p.head<2>();
        sample = other;
        found = true;
        break;
      }
      if (!found && clearance < need) {
        char buf[400];
        std::snprintf(buf, sizeof buf,
                      "step %zu (%s): its toes %.0f mm from a riser %.0f mm high ahead; a sole keeps "
                      "%.2f of a riser's height from it (%.0f mm; TerrainMap::kShinLean: the shin "
                      "leans over the toes as the robot rises onto a stair) and no spot within the "
                      "step search (%.2f m) does within the limits",
                      k + 1, SideName(s.foot), clearance * 1000, need / kShinLean * 1000, kShinLean,
                      need * 1000, search);
        *error = buf;
        return false;
      }
    }
    s.p.z() = sample.z;
    s.roll = sample.roll;
    s.pitch = sample.pitch;
    if (!sample.planar) {
      s.contact_centre = sample.contact_centre;
      s.contact_half = sample.contact_half;
    }
    feet = After(feet, s);
  }
  SetSwingClearance(steps, start, limits);
  return true;
}

void TerrainMap::SetSwingClearance(std::vector<Footstep>* steps, const FeetPose& start,
                                   const StepLimits& limits) const {
  constexpr double kWay = 0.005;      // [m] between the sole's positions along its way
  constexpr int kAlong = 11, kAcross = 3;
  const Eigen::Rotation2Dd R0(yaw_);
  const Eigen::Vector2d& half = limits.sole_half_size;
  FeetPose feet = start;
  for (Footstep& s : *steps) {
    const Eigen::Vector2d a = feet.p[s.foot].head<2>(), b = s.p.head<2>();
    const double turn = std::remainder(s.yaw - feet.yaw[s.foot], 2 * M_PI);
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kWay)));
    // a point under the sole where it stands or lands: that surface is the ends' own (on a
    // slope the toes' end of the landing sole is higher than its centre, and the sole is tilted
    // with it)
    auto on_end = [&](const Eigen::Vector2d& q, const Eigen::Vector2d& c, double yaw) {
      const Eigen::Vector2d l = Eigen::Rotation2Dd(-yaw) * (q - c);
      return std::fabs(l.x()) <= half.x() + 1e-9 && std::fabs(l.y()) <= half.y() + 1e-9;
    };
    double highest = -1e9, first_half = -1e9, second_half = -1e9;
    for (int i = 0; i <= n; ++i) {
      const double f = static_cast<double>(i) / n;
      const Eigen::Rotation2Dd Rs(feet.yaw[s.foot] + f * turn);
      for (int u = 0; u < kAlong; ++u) {
        for (int v = 0; v < kAcross; ++v) {
          const Eigen::Vector2d local((2.0 * u / (kAlong - 1) - 1) * half.x(),
                                      (2.0 * v / (kAcross - 1) - 1) * half.y());
          const Eigen::Vector2d p = a + f * (b - a) + Rs * local;
          // the first half leaves out the lift-off's footprint, the second the landing's
          const bool start = on_end(p, a, feet.yaw[s.foot]), landing = on_end(p, b, s.yaw);
          const bool first = 2 * i <= n, second = 2 * i >= n;
          if ((start || !first) && (landing || !second)) continue;
          const Eigen::Vector2d q = origin_.head<2>() + R0 * p;
          double h = 0;
          if (!Height(q.x(), q.y(), &h)) continue;
          h -= origin_.z();
          if (!start && !landing) highest = std::max(highest, h);
          if (first && !start) first_half = std::max(first_half, h);
          if (second && !landing) second_half = std::max(second_half, h);
        }
      }
    }
    s.clear_z = highest;
    s.lift_z = first_half;
    s.land_z = second_half;
    feet = After(feet, s);
  }
}

}  // namespace ohrp::walking
