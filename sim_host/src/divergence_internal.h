// Internal to sim_host's divergence watch (divergence.cc, divergence_diagnosis.cc): the
// thresholds and small helpers the per-step check and the diagnostic share.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdio>
#include <string>

namespace ohrp::sim::divergence_internal {

// the warnings after which MuJoCo has reset (part of) the state
constexpr int kResetWarnings[] = {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC, mjWARN_BADCTRL};

// explicit-step number of a spring-damper on an inertia: dt^2 K / I + 2 dt D / I; the
// semi-implicit Euler step is stable below 4 (the soft-foot check keeps half of it)
constexpr double kStableStepNumber = 4.0;
constexpr double kDeepPenetration = 0.01;  // [m] a contact deeper than this is "deep"

inline std::string Fmt(const char* format, double x) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, x);
  return buf;
}

inline std::string Name(const mjModel* m, int type, int id) {
  const char* n = mj_id2name(m, type, id);
  if (n && n[0]) return n;
  const char* kind = type == mjOBJ_BODY ? "body" : type == mjOBJ_JOINT ? "joint" : "geom";
  return std::string(kind) + " #" + std::to_string(id);
}

// body velocity at its centre of mass (linear) and angular velocity, world frame, from cvel
inline void BodyVelocity(const mjModel* m, const mjData* d, int b, double v[3], double w[3]) {
  const double* cv = d->cvel + 6 * b;  // [angular; linear at subtree_com of the root]
  const double* c = d->subtree_com + 3 * m->body_rootid[b];
  const double* p = d->xipos + 3 * b;
  const double r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
  for (int k = 0; k < 3; ++k) w[k] = cv[k];
  v[0] = cv[3] + w[1] * r[2] - w[2] * r[1];
  v[1] = cv[4] + w[2] * r[0] - w[0] * r[2];
  v[2] = cv[5] + w[0] * r[1] - w[1] * r[0];
}

inline double Inertia(const mjModel* m, const mjData* d, int dof) {
  return d->qM[m->dof_Madr[dof]];
}

}  // namespace ohrp::sim::divergence_internal
