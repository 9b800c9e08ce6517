// Closed forms for bench_accuracy (see accuracy.h): the rigid pendulum's exact period, the
// Hunt-Crossley restitution, free fall, the soft-foot static sink, rolling at 5/7 v0, and the
// ball scene with icosphere meshes of increasing resolution.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "accuracy.h"

namespace ohrp::accuracy {
namespace {
constexpr double kG = 9.81;  // [m/s^2], the scenes' gravity
}  // namespace

//---------------- formulas ----------------

double PendulumPeriod(double inertia, double mass, double g, double d, double theta0) {
  // K(k) = pi / (2 AGM(1, sqrt(1 - k^2)))
  const double k = std::sin(theta0 / 2);
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 40 && std::fabs(a - b) > 1e-16 * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  const double K = M_PI / (2 * a);
  return 4 * std::sqrt(inertia / (mass * g * d)) * K;
}

double MeasurePendulumPeriod(const std::string& path, const Setting& setting, int periods) {
  SceneSpec scene;
  scene.name = "pendulum_single";
  scene.path = path;
  scene.keyframe = "release";
  std::string error;
  auto sim = Sim::Create(scene, setting, &error);
  if (!sim) return std::nan("");
  mjData* d = sim->d();
  std::vector<double> crossings;
  double t_prev = d->time, q_prev = d->qpos[0], v_prev = d->qvel[0];
  const int max_steps = static_cast<int>(std::ceil((periods + 2) * 1.5 / setting.dt));
  for (int i = 0; i < max_steps && static_cast<int>(crossings.size()) <= periods; ++i) {
    sim->Step();
    if (!sim->Finite()) return std::nan("");
    const double t = d->time, q = d->qpos[0], v = d->qvel[0];
    if (q_prev > 0 && q <= 0) {
      // root of the cubic Hermite interpolant on [t_prev, t] (positions and velocities at both
      // ends), by bisection: O(dt^4), below the integrators' own errors
      const double h = t - t_prev;
      auto H = [&](double s) {
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * q_prev + (s3 - 2 * s2 + s) * h * v_prev +
               (-2 * s3 + 3 * s2) * q + (s3 - s2) * h * v;
      };
      double lo = 0, hi = 1;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (H(mid) > 0 ? lo : hi) = mid;
      }
      crossings.push_back(t_prev + 0.5 * (lo + hi) * h);
    }
    t_prev = t;
    q_prev = q;
    v_prev = v;
  }
  if (static_cast<int>(crossings.size()) <= periods) return std::nan("");
  return (crossings[periods] - crossings[0]) / periods;
}

std::string IcosphereVertices(double r, int level) {
  const double p = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> v = {
      {-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
      {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  std::vector<std::array<int, 3>> f = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  auto normalize = [](std::array<double, 3> a) {
    const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return std::array<double, 3>{a[0] / n, a[1] / n, a[2] / n};
  };
  for (auto& x : v) x = normalize(x);
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(normalize({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> nf;
    for (const auto& t : f) {
      const int a = middle(t[0], t[1]), b = middle(t[1], t[2]), c = middle(t[2], t[0]);
      nf.push_back({t[0], a, c});
      nf.push_back({t[1], b, a});
      nf.push_back({t[2], c, b});
      nf.push_back({a, b, c});
    }
    f.swap(nf);
  }
  std::ostringstream o;
  o.precision(9);
  for (size_t i = 0; i < v.size(); ++i) {
    o << (i ? "  " : "") << r * v[i][0] << " " << r * v[i][1] << " " << r * v[i][2];
  }
  return o.str();
}

//---------------- on the scenes ----------------

double FreeFallError(const SceneSpec& scene, const Setting& s, double* value, double* exact) {
  std::string error;
  auto sim = Sim::Create(scene, s, &error);
  if (!sim) return std::nan("");
  const double z0 = sim->d()->qpos[2];
  const int n = static_cast<int>(std::lround(0.096 / s.dt));
  sim->Advance(n);
  const double t = n * s.dt;
  *value = sim->d()->qpos[2];
  *exact = z0 - 0.5 * kG * t * t;
  return std::fabs(*value - *exact);
}

// the block resting on the soft soles: sink against (m g / k)^(1/n)
double StaticSink(const SceneSpec& scene, const Setting& s, double* value, double* exact,
                  std::string* note) {
  std::string error;
  auto sim = Sim::Create(scene, s, &error);
  if (!sim) {
    *note = error;
    return std::nan("");
  }
  mjData* d = sim->d();
  const double half_z = 0.01;
  mju_zero(d->qvel, sim->m()->nv);
  d->qpos[0] = d->qpos[1] = 0;
  d->qpos[2] = half_z;
  sim->Advance(static_cast<int>(std::lround(1.5 / s.dt)));
  if (!sim->Finite()) {
    *note = "diverged";
    return kInf;
  }
  const contact::SoftContactParams p;
  *value = half_z - d->qpos[2];
  *exact = std::pow(scene.soft_mass * kG / p.stiffness, 1.0 / p.exponent);
  return std::fabs(*value - *exact) / *exact;
}

// the block (no gravity) entering the soft soles at 0.1 m/s: restitution against the
// Hunt-Crossley law's own answer
double Restitution(const SceneSpec& scene, const Setting& s, double* value, double* exact,
                   std::string* note) {
  std::string error;
  auto sim = Sim::Create(scene, s, &error);
  if (!sim) {
    *note = error;
    return std::nan("");
  }
  mjModel* m = sim->m();
  mjData* d = sim->d();
  m->opt.gravity[2] = 0;
  const double half_z = 0.01, v = 0.1;
  mju_zero(d->qvel, m->nv);
  d->qpos[0] = d->qpos[1] = 0;
  d->qpos[2] = half_z;
  d->qvel[2] = -v;
  const int max_steps = static_cast<int>(std::lround(0.5 / s.dt));
  for (int i = 0; i < max_steps; ++i) {
    sim->Step();
    if (!sim->Finite()) {
      *note = "diverged";
      return kInf;
    }
    if (i > 0 && d->qpos[2] > half_z && d->qvel[2] > 0) {
      const contact::SoftContactParams p;
      *value = d->qvel[2] / v;
      *exact = contact::HuntCrossleyRestitution(p.stiffness, p.exponent, p.damping, scene.soft_mass, v,
                                       1e-7);
      return std::fabs(*value - *exact) / *exact;
    }
  }
  *note = "never left the floor";
  return kInf;
}

// the ball sliding onto the floor at v0 without spin rolls at 5/7 v0 (angular momentum about
// the contact point is conserved)
double RollingError(const SceneSpec& scene, const Setting& s, double* value, double* exact) {
  std::string error;
  auto sim = Sim::Create(scene, s, &error);
  if (!sim) return std::nan("");
  const double v0 = sim->d()->qvel[0];
  sim->Advance(static_cast<int>(std::lround(1.0 / s.dt)));
  if (!sim->Finite()) return kInf;
  *value = sim->d()->qvel[0];
  *exact = 5.0 / 7.0 * v0;
  return std::fabs(*value - *exact);
}

std::string BallXml() {
  std::ostringstream o;
  o << "<mujoco model=\"ball_roll\">\n"
       "  <compiler angle=\"radian\"/>\n"
       "  <option timestep=\"0.001\" integrator=\"Euler\" gravity=\"0 0 -9.81\"/>\n"
       "  <asset>\n";
  for (int l = 0; l <= 3; ++l) {
    o << "    <mesh name=\"ico" << l << "\" vertex=\"" << IcosphereVertices(0.1, l) << "\"/>\n";
  }
  o << "  </asset>\n"
       "  <worldbody>\n"
       "    <geom name=\"floor\" type=\"plane\" size=\"0 0 1\" friction=\"0.3 0.005 0.0001\"/>\n"
       "    <body name=\"ball\" pos=\"0 0 0.1\">\n"
       "      <freejoint/>\n"
       "      <inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"0.004 0.004 0.004\"/>\n"
       "      <geom name=\"sphere\" type=\"sphere\" size=\"0.1\" friction=\"0.3 0.005 0.0001\"/>\n";
  for (int l = 0; l <= 3; ++l) {
    o << "      <geom name=\"ico" << l << "\" type=\"mesh\" mesh=\"ico" << l
      << "\" friction=\"0.3 0.005 0.0001\" group=\"3\"/>\n";
  }
  o << "    </body>\n"
       "  </worldbody>\n"
       "  <keyframe>\n"
       "    <key name=\"slide\" qpos=\"0 0 0.1 1 0 0 0\" qvel=\"2 0 0 0 0 0\"/>\n"
       "  </keyframe>\n"
       "</mujoco>\n";
  return o.str();
}

}  // namespace ohrp::accuracy
