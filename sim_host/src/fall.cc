// The fall watch (see fall.h).
#include "sim_host/fall.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "robot_model/kinematics.h"

namespace ohrp::sim {
namespace {

const char* Name(const mjModel* m, int type, int id, const char* fallback) {
  const char* n = id >= 0 ? mj_id2name(m, type, id) : nullptr;
  return n && *n ? n : fallback;
}

// body `b` is `root` or below it
bool InSubtree(const mjModel* m, int b, int root) {
  for (; b > 0; b = m->body_parentid[b])
    if (b == root) return true;
  return root == 0;
}

// held by the world: the world itself, a body welded to it, a mocap body
bool WorldHeld(const mjModel* m, int b) {
  return b == 0 || m->body_weldid[b] == 0 || m->body_mocapid[b] >= 0;
}

// the robot is held to the world by an active weld or connect equality: why, or ""
std::string Harness(const mjModel* m, int root) {
  for (int e = 0; e < m->neq; ++e) {
    if (!m->eq_active[e] || (m->eq_type[e] != mjEQ_WELD && m->eq_type[e] != mjEQ_CONNECT)) continue;
    const int b1 = m->eq_obj1id[e], b2 = m->eq_obj2id[e];
    const bool r1 = b1 > 0 && m->body_rootid[b1] == root, r2 = b2 > 0 && m->body_rootid[b2] == root;
    if ((r1 && WorldHeld(m, b2)) || (r2 && WorldHeld(m, b1))) {
      return std::string("the robot is held to the world by the ") +
             (m->eq_type[e] == mjEQ_WELD ? "weld" : "connect") + " equality '" +
             Name(m, mjOBJ_EQUALITY, e, "(unnamed)") + "'";
    }
  }
  return "";
}

double Dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

bool ParseOnFall(const std::string& name, OnFall* out) {
  if (name == "end") *out = OnFall::kEnd;
  else if (name == "continue") *out = OnFall::kContinue;
  else return false;
  return true;
}

const char* OnFallName(OnFall on_fall) { return on_fall == OnFall::kEnd ? "end" : "continue"; }

const char* FallKindName(FallKind kind) {
  switch (kind) {
    case FallKind::kNone: return "none";
    case FallKind::kContact: return "contact";
    case FallKind::kHeight: return "height";
    case FallKind::kTilt: return "tilt";
  }
  return "?";
}

double GeomLowestPoint(const mjModel* m, const mjData* d, int g) {
  const mjtNum* R = d->geom_xmat + 9 * g;  // row-major: R[6 + i] is the z part of axis i
  const mjtNum* s = m->geom_size + 3 * g;
  const double z = d->geom_xpos[3 * g + 2];
  const double az = std::fabs(R[8]);  // the geom's own z axis, vertical part
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE: return z - s[0];
    case mjGEOM_CAPSULE: return z - az * s[1] - s[0];
    case mjGEOM_CYLINDER: return z - az * s[1] - s[0] * std::sqrt(std::max(0.0, 1 - az * az));
    case mjGEOM_BOX:
      return z - std::fabs(R[6]) * s[0] - std::fabs(R[7]) * s[1] - az * s[2];
    case mjGEOM_ELLIPSOID:
      return z - std::sqrt(R[6] * R[6] * s[0] * s[0] + R[7] * R[7] * s[1] * s[1] + R[8] * R[8] * s[2] * s[2]);
    default: return z - m->geom_rbound[g];
  }
}

std::unique_ptr<FallWatch> FallWatch::Create(const mjModel* m, const mjData* d0,
                                             const model::RobotMap& robot,
                                             const std::vector<std::string>& sole_names,
                                             const FallOptions& o, std::string* error) {
  std::unique_ptr<FallWatch> w(new FallWatch());
  // the bodies allowed to touch: bodies of the robot (checked even when the watch is off)
  const int root = robot.base_body >= 0 ? m->body_rootid[robot.base_body] : -1;
  std::vector<int> allowed;
  for (const std::string& name : o.allow_contact) {
    const int b = mj_name2id(m, mjOBJ_BODY, name.c_str());
    if (b <= 0 || (root >= 0 && m->body_rootid[b] != root)) {
      std::string bodies;
      for (int k = 1; k < m->nbody && bodies.size() < 400; ++k)
        if (root < 0 || m->body_rootid[k] == root) bodies += std::string(bodies.empty() ? "" : ", ") + Name(m, mjOBJ_BODY, k, "?");
      *error = "--fall-allow-contact: '" + name + "' is not a body of the robot (its bodies: " +
               bodies + ")";
      return nullptr;
    }
    allowed.push_back(b);
  }
  // off: a fixed robot, a hung one
  if (robot.base_body < 0) {
    w->description_ = "fall watch off: the robot has no free joint (it is fixed to the world)";
    return w;
  }
  // the free body MapRobot took as the base carries the robot's joints, or the robot is fixed
  // and that body is something beside it (a ball, a box)
  bool carries = false;
  for (const auto& j : robot.joints) carries = carries || m->body_rootid[m->jnt_bodyid[j.joint_id]] == root;
  if (!carries) {
    w->description_ = std::string("fall watch off: the robot's joints are not below its free body '") +
                      Name(m, mjOBJ_BODY, robot.base_body, "?") + "' (the robot is fixed to the world)";
    return w;
  }
  if (const std::string hung = Harness(m, root); !hung.empty()) {
    w->description_ = "fall watch off: " + hung;
    return w;
  }
  w->on_ = true;
  w->base_ = robot.base_body;
  w->cos_tilt_ = std::cos(kFallTiltDeg * M_PI / 180);
  w->contacts_.resize(mjMAXCONPAIR);

  // the initial state's kinematics, on a copy
  mjData* d = mj_makeData(m);
  if (!d) {
    *error = "fall watch: cannot allocate MuJoCo data";
    return nullptr;
  }
  std::copy(d0->qpos, d0->qpos + m->nq, d->qpos);
  std::copy(d0->mocap_pos, d0->mocap_pos + 3 * m->nmocap, d->mocap_pos);
  std::copy(d0->mocap_quat, d0->mocap_quat + 4 * m->nmocap, d->mocap_quat);
  mj_kinematics(m, d);

  // the soles and the feet
  if (sole_names.empty()) {
    for (const model::SoleMap& s : model::FindSoles(m, robot)) w->soles_.push_back(s.geom_id);
  } else {
    for (const std::string& s : sole_names) {
      const int g = mj_name2id(m, mjOBJ_GEOM, s.c_str());
      if (g >= 0) w->soles_.push_back(g);
    }
  }
  std::vector<int> feet;
  for (int g : w->soles_)
    if (m->body_rootid[m->geom_bodyid[g]] == root) feet.push_back(m->geom_bodyid[g]);
  w->soles_.erase(std::remove_if(w->soles_.begin(), w->soles_.end(),
                                 [&](int g) { return m->body_rootid[m->geom_bodyid[g]] != root; }),
                  w->soles_.end());

  // the height and the vertical at the start
  if (w->soles_.empty()) {
    w->floor0_ = 1e300;
    for (int g = 0; g < m->ngeom; ++g)
      if (m->body_rootid[m->geom_bodyid[g]] == root) w->floor0_ = std::min(w->floor0_, GeomLowestPoint(m, d, g));
  }
  w->h0_ = d->xpos[3 * w->base_ + 2] - w->FeetHeight(m, d);
  for (int i = 0; i < 3; ++i) w->up0_[i] = d->xmat[9 * w->base_ + 6 + i];
  mj_deleteData(d);

  // the pairs (robot geom, ground geom) of the contact test: only with feet to tell apart
  int skipped = 0;
  if (!feet.empty()) {
    std::vector<int> ground, mine;
    for (int g = 0; g < m->ngeom; ++g) {
      const int b = m->geom_bodyid[g];
      if (m->body_rootid[b] == root) {
        bool free_to_touch = false;
        for (int f : feet) free_to_touch = free_to_touch || InSubtree(m, b, f);
        for (int a : allowed) free_to_touch = free_to_touch || InSubtree(m, b, a);
        if (free_to_touch) continue;
        // a mesh MuJoCo compiled without its convex hull (visual only) has no narrow phase
        if (m->geom_type[g] == mjGEOM_MESH && m->mesh_graphadr[m->geom_dataid[g]] < 0) {
          ++skipped;
          continue;
        }
        mine.push_back(g);
      } else if (m->body_weldid[b] == 0 && (m->geom_contype[g] || m->geom_conaffinity[g])) {
        ground.push_back(g);
      }
    }
    for (int r : mine) {
      for (int g : ground) {
        const int tr = m->geom_type[r], tg = m->geom_type[g];
        const bool swapped = tg < tr;
        mjfCollision f = swapped ? mjCOLLISIONFUNC[tg][tr] : mjCOLLISIONFUNC[tr][tg];
        if (!f) {
          ++skipped;
          continue;
        }
        w->pairs_.push_back({r, g, f, swapped});
      }
    }
  }

  // what is watched, said once
  char b[512];
  std::string text = "fall watch: ";
  if (feet.empty()) {
    text += "no soles found (no box geom named *_SOLE, no --soles): no contact test, the height "
            "above the robot's lowest point at the start; ";
  } else {
    std::string names;
    for (int f : feet) names += std::string(names.empty() ? "" : ", ") + Name(m, mjOBJ_BODY, f, "?");
    std::string allow;
    for (int a : allowed) allow += std::string(allow.empty() ? "" : ", ") + Name(m, mjOBJ_BODY, a, "?");
    std::snprintf(b, sizeof(b), "no body but the feet (%s)%s%s touches the ground (%zu geom pairs%s); ",
                  names.c_str(), allow.empty() ? "" : " and ", allow.c_str(), w->pairs_.size(),
                  skipped ? ", some geoms without a narrow phase not tested" : "");
    text += b;
  }
  std::snprintf(b, sizeof(b), "the base stays above %.3f m over the %s (half its %.3f m at the "
                "start) and within %.0f deg of its start's vertical",
                w->min_height(), feet.empty() ? "start's lowest point" : "soles", w->h0_, kFallTiltDeg);
  text += b;
  w->description_ = text;
  if (w->h0_ <= 0) {
    w->description_ += " (the base starts at or below the feet: no height test)";
  }
  return w;
}

double FallWatch::FeetHeight(const mjModel* m, const mjData* d) const {
  if (soles_.empty()) return floor0_;
  double low = 1e300;
  for (int g : soles_) low = std::min(low, GeomLowestPoint(m, d, g));
  return low;
}

bool FallWatch::Touching(const mjModel* m, const mjData* d, const Pair& p, double* depth) {
  const int r = p.robot_geom, g = p.ground_geom;
  const mjtNum* pr = d->geom_xpos + 3 * r;
  const mjtNum* pg = d->geom_xpos + 3 * g;
  // the bounding test: planes and height fields by the height along their normal, others by
  // bounding spheres
  const int tg = m->geom_type[g];
  if (tg == mjGEOM_PLANE || tg == mjGEOM_HFIELD) {
    const mjtNum* R = d->geom_xmat + 9 * g;
    const double n[3] = {R[2], R[5], R[8]};
    const double rel[3] = {pr[0] - pg[0], pr[1] - pg[1], pr[2] - pg[2]};
    const double top = tg == mjGEOM_HFIELD ? m->hfield_size[4 * m->geom_dataid[g] + 2] : 0.0;
    if (Dot3(n, rel) - m->geom_rbound[r] > top) return false;
  } else {
    const double dx = pr[0] - pg[0], dy = pr[1] - pg[1], dz = pr[2] - pg[2];
    const double reach = m->geom_rbound[r] + m->geom_rbound[g];
    if (dx * dx + dy * dy + dz * dz > reach * reach) return false;
  }
  const int n = p.swapped ? p.collide(m, d, contacts_.data(), g, r, 0)
                          : p.collide(m, d, contacts_.data(), r, g, 0);
  double deepest = 0;
  for (int i = 0; i < n; ++i) deepest = std::min(deepest, static_cast<double>(contacts_[i].dist));
  *depth = -deepest;
  return deepest < 0;
}

bool FallWatch::Check(const mjModel* m, const mjData* d, double time, uint64_t cycle) {
  if (!on_ || fell()) return false;
  FallRecord& f = fall_;
  f.height = d->xpos[3 * base_ + 2] - FeetHeight(m, d);
  const double cos_tilt = Dot3(up0_, d->xmat + 9 * base_ + 6);
  f.tilt = std::acos(std::clamp(cos_tilt, -1.0, 1.0)) * 180 / M_PI;
  for (const Pair& p : pairs_) {
    double depth = 0;
    if (!Touching(m, d, p, &depth)) continue;
    f.kind = FallKind::kContact;
    f.geom = p.robot_geom;
    f.body = m->geom_bodyid[p.robot_geom];
    f.ground = p.ground_geom;
    f.depth = depth;
    std::snprintf(f.cause, sizeof(f.cause), "body %s touched %s (%.1f mm deep; base %.3f m above the feet, tilted %.0f deg)",
                  Name(m, mjOBJ_BODY, f.body, "?"), Name(m, mjOBJ_GEOM, f.ground, "the ground"),
                  1e3 * depth, f.height, f.tilt);
    break;
  }
  if (f.kind == FallKind::kNone && h0_ > 0 && f.height < kFallHeightFraction * h0_) {
    f.kind = FallKind::kHeight;
    std::snprintf(f.cause, sizeof(f.cause), "the base was %.3f m above the feet, below %.3f m (half its %.3f m at the start; tilted %.0f deg)",
                  f.height, kFallHeightFraction * h0_, h0_, f.tilt);
  }
  if (f.kind == FallKind::kNone && cos_tilt < cos_tilt_) {
    f.kind = FallKind::kTilt;
    std::snprintf(f.cause, sizeof(f.cause), "the base tilted %.1f deg from its start's vertical, past %.0f deg (base %.3f m above the feet)",
                  f.tilt, kFallTiltDeg, f.height);
  }
  if (f.kind == FallKind::kNone) return false;
  f.time = time;
  f.cycle = cycle;
  return true;
}

FallSummary FallWatch::Summary(const mjModel* m) const {
  FallSummary s;
  s.on = on_;
  s.watch = description_;
  s.start_height = h0_;
  s.min_height = min_height();
  s.max_tilt = kFallTiltDeg;
  s.fell = fell();
  s.record = fall_;
  s.cause = fall_.cause;
  if (fall_.kind == FallKind::kContact) {
    s.body = Name(m, mjOBJ_BODY, fall_.body, "");
    s.geom = Name(m, mjOBJ_GEOM, fall_.geom, "");
    s.ground = Name(m, mjOBJ_GEOM, fall_.ground, "");
  }
  return s;
}

}  // namespace ohrp::sim
