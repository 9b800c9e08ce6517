// Pushes on the base: parsing `--push`, the wrench of the pushes at a step, and putting it on
// the base's row of xfrc_applied (see pushes.h).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "cli/plausible.h"
#include "sim_host/pushes.h"

namespace ohrp::sim {

bool ParsePerturbation(const std::string& spec, Perturbation* out, std::string* error) {
  const char* kForm = " (write t0,t1,fx,fy,fz,tx,ty,tz: start and end [s of simulated time], "
                      "then the world-frame force [N] and torque [N m] at the base's centre of mass)";
  double v[8];
  int n = 0;
  const char* p = spec.c_str();
  while (true) {
    char* end = nullptr;
    const double x = std::strtod(p, &end);
    if (end == p || (*end != ',' && *end != '\0')) {
      *error = "--push '" + spec + "': value " + std::to_string(n + 1) + " is not a number" + kForm;
      return false;
    }
    if (n == 8) {
      *error = "--push '" + spec + "': more than 8 values" + kForm;
      return false;
    }
    if (!std::isfinite(x)) {
      *error = "--push '" + spec + "': value " + std::to_string(n + 1) + " is not finite" + kForm;
      return false;
    }
    v[n++] = x;
    if (*end == '\0') break;
    p = end + 1;
  }
  if (n != 8) {
    *error = "--push '" + spec + "': " + std::to_string(n) + " values, expected 8" + kForm;
    return false;
  }
  if (v[0] < 0 || !(v[1] > v[0])) {
    *error = "--push '" + spec + "': the window must have 0 <= t0 < t1" + kForm;
    return false;
  }
  // plausible magnitudes (cli/plausible.h) of the force and the torque (a push may last the run)
  const double f = std::sqrt(v[2] * v[2] + v[3] * v[3] + v[4] * v[4]);
  const double t = std::sqrt(v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
  for (const std::string& e : {cli::CheckPlausible("force", f, "--push '" + spec + "': |force|"),
                               cli::CheckPlausible("torque", t, "--push '" + spec + "': |torque|")}) {
    if (e.empty()) continue;
    *error = e;
    return false;
  }
  out->t0 = v[0];
  out->t1 = v[1];
  for (int k = 0; k < 3; ++k) {
    out->force[k] = v[2 + k];
    out->torque[k] = v[5 + k];
  }
  return true;
}

std::string PerturbationText(const Perturbation& p) {
  char b[320];
  std::snprintf(b, sizeof(b), "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", p.t0, p.t1,
                p.force[0], p.force[1], p.force[2], p.torque[0], p.torque[1], p.torque[2]);
  return b;
}

void ApplyPushes(const std::vector<Perturbation>& pushes, const mjModel* m, mjData* d, int body,
                 double pushed[6]) {
  double want[6];
  PushWrenchAt(pushes, d->time, m->opt.timestep, want);
  double* row = d->xfrc_applied + 6 * body;
  for (int k = 0; k < 6; ++k) {
    row[k] += want[k] - pushed[k];
    pushed[k] = want[k];
  }
}

bool PushActiveAt(const Perturbation& p, double time, double dt) {
  // a step belongs to a window when it starts in [t0, t1), with half a step of slack against
  // the rounding of the accumulated time
  const double t = time + 0.5 * dt;
  return t >= p.t0 && t < p.t1;
}

void PushWrenchAt(const std::vector<Perturbation>& pushes, double time, double dt, double wrench[6]) {
  for (int k = 0; k < 6; ++k) wrench[k] = 0;
  for (const Perturbation& p : pushes) {
    if (!PushActiveAt(p, time, dt)) continue;
    for (int k = 0; k < 3; ++k) {
      wrench[k] += p.force[k];
      wrench[3 + k] += p.torque[k];
    }
  }
}

}  // namespace ohrp::sim
