#include "contact/params.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ohrp::contact {
namespace {

constexpr double kG = 9.81;

bool Finite(double x) { return std::isfinite(x); }

}  // namespace

double ImpactDuration(const SoftContactParams& p, double mass_scale) {
  const double n = p.exponent, k = p.stiffness, m = mass_scale;
  const double delta = std::pow(m * 9.81 / k, 1.0 / n);
  const double K = n * k * std::pow(delta, n - 1);
  return M_PI / std::sqrt(K / m);
}

std::string ImpactNote(const SoftContactParams& p, double dt, double mass_scale) {
  const double t = ImpactDuration(p, mass_scale);
  if (!(t > 0) || !(dt > 0) || t / dt >= kImpactSteps) return "";
  std::ostringstream s;
  s.precision(3);
  s << "an impact on the soft soles lasts about " << 1e3 * t << " ms under " << mass_scale
    << " kg, " << t / dt << " steps of " << 1e3 * dt << " ms: the step is stable and keeps an "
    << "impact's restitution (a 60 kg block's within 7 % up to 16 ms), but does not resolve "
    << "the force during an impact, its peak and shape (docs/accuracy.md); use dt <= "
    << 1e3 * t / kImpactSteps << " ms where landing forces matter";
  return s.str();
}

bool Validate(const SoftContactParams& p, double dt, double mass_scale, std::string* error,
              StepScheme scheme) {
  std::ostringstream out;
  auto problem = [&out](const std::string& s) { out << s << "\n"; };

  if (!Finite(p.stiffness) || p.stiffness <= 0) {
    std::ostringstream s;
    s << "stiffness = " << p.stiffness
      << " N/m^n: must be finite and > 0, the spring is what carries the load; a 120-130 kg "
         "humanoid's sole is about 3e6 N/m (0.2 mm of sink per foot standing)";
    problem(s.str());
  }
  if (!Finite(p.exponent) || p.exponent < 1.0 || p.exponent > 3.0) {
    std::ostringstream s;
    s << "exponent = " << p.exponent
      << ": must be in [1, 3]; below 1 the stiffness at zero penetration is infinite and no "
         "explicit step is stable, above 3 the law is unphysical; use 1 (linear mechanism "
         "spring) or 1.5 (Hertz-like pad)";
    problem(s.str());
  }
  if (!Finite(p.damping) || p.damping < 0) {
    std::ostringstream s;
    s << "damping = " << p.damping
      << " s/m: the Hunt-Crossley coefficient must be finite and >= 0 (a negative one adds "
         "energy at every impact); 0 is elastic, 10 s/m is a well damped rubber sole";
    problem(s.str());
  }
  if (!Finite(p.friction) || p.friction < 0) {
    std::ostringstream s;
    s << "friction = " << p.friction << ": the Coulomb coefficient must be finite and >= 0; "
      << "rubber on a floor is 0.6-1.0";
    problem(s.str());
  }
  if (!Finite(p.tangential_stiffness) || p.tangential_stiffness <= 0) {
    std::ostringstream s;
    s << "tangential_stiffness = " << p.tangential_stiffness
      << " N/m: must be finite and > 0, the sticking sole is held by this spring; use about "
         "1e6 N/m (0.6 mm of shear at the sliding limit of a standing foot)";
    problem(s.str());
  }
  if (!Finite(p.tangential_damping) || p.tangential_damping < 0) {
    std::ostringstream s;
    s << "tangential_damping = " << p.tangential_damping
      << " N s/m: must be finite and >= 0; about 3e3 N s/m damps the stick oscillation";
    problem(s.str());
  }
  if (p.grid_x < 2 || p.grid_y < 2 || p.grid_x > 64 || p.grid_y > 64) {
    std::ostringstream s;
    s << "grid = " << p.grid_x << " x " << p.grid_y
      << " points: each axis needs 2..64 points (at least 2 to resolve the tilt of the sole, "
         "more than 64 costs too many queries); use 5 x 3";
    problem(s.str());
  }
  if (!Finite(p.margin) || p.margin < 0) {
    std::ostringstream s;
    s << "margin = " << p.margin << " m: the broad-phase margin must be finite and >= 0; use 0.01";
    problem(s.str());
  }
  if (!Finite(dt) || dt <= 0) {
    std::ostringstream s;
    s << "dt = " << dt << " s: the physics step must be finite and > 0 (HRP-1S runs 0.001)";
    problem(s.str());
  }
  if (!Finite(mass_scale) || mass_scale <= 0) {
    std::ostringstream s;
    s << "mass_scale = " << mass_scale
      << " kg: the smallest mass on one sole must be finite and > 0 (the robot standing: half "
         "its mass)";
    problem(s.str());
  }

  if (out.str().empty() && scheme == StepScheme::kExplicit) {
    // Normal law, linearised at the peak load.
    const double m = mass_scale;
    const double load = kPeakLoadFactor * m * kG;
    const double delta = std::pow(load / p.stiffness, 1.0 / p.exponent);
    const double K = p.exponent * p.stiffness * std::pow(delta, p.exponent - 1.0);
    const double spring_term = dt * dt * K / m;
    const double beta = p.damping * p.stiffness * std::pow(delta, p.exponent) / m;  // = c L g
    const double total = spring_term + 2.0 * dt * beta;
    if (total > kStabilityBudget) {
      std::ostringstream s;
      s.precision(3);
      if (spring_term > 0.5 * kStabilityBudget) {
        // The spring alone uses most of the budget: blame the stiffness (or the step).
        const double k_max = 0.5 * kStabilityBudget * m / (dt * dt) /
                             (p.exponent * std::pow(delta, p.exponent - 1.0));
        const double dt_max = std::sqrt(0.5 * kStabilityBudget * m / K);
        s << "stiffness = " << p.stiffness << " N/m^n is too stiff for dt = " << dt
          << " s with " << m << " kg on a sole: the explicit step needs dt^2*K/m + 2*dt*beta <= "
          << kStabilityBudget << " (stable below 4) and got " << total << " (K = " << K
          << " N/m at " << kPeakLoadFactor << " m g); use stiffness <= about " << k_max
          << " or dt <= " << dt_max << " s";
      } else {
        const double c_max = (kStabilityBudget - spring_term) / (2.0 * dt * kPeakLoadFactor * kG);
        s << "damping = " << p.damping << " s/m makes the explicit step unstable at dt = " << dt
          << " s with " << m << " kg on a sole: the step needs dt^2*K/m + 2*dt*c*" << kPeakLoadFactor
          << "*g <= " << kStabilityBudget << " (stable below 4) and got " << total
          << "; use damping <= " << c_max << " s/m or a smaller dt";
      }
      problem(s.str());
    }
    // Tangential spring-damper.
    const double t_spring = dt * dt * p.tangential_stiffness / m;
    const double t_total = t_spring + 2.0 * dt * p.tangential_damping / m;
    if (p.friction > 0 && t_total > kStabilityBudget) {
      std::ostringstream s;
      s.precision(3);
      if (t_spring > 0.5 * kStabilityBudget) {
        s << "tangential_stiffness = " << p.tangential_stiffness << " N/m is too stiff for dt = "
          << dt << " s with " << m << " kg on a sole: dt^2*k_t/m + 2*dt*b_t/m = " << t_total
          << " > " << kStabilityBudget << "; use tangential_stiffness <= "
          << 0.5 * kStabilityBudget * m / (dt * dt) << " N/m or a smaller dt";
      } else {
        s << "tangential_damping = " << p.tangential_damping
          << " N s/m makes the explicit step unstable at dt = " << dt << " s with " << m
          << " kg on a sole: dt^2*k_t/m + 2*dt*b_t/m = " << t_total << " > " << kStabilityBudget
          << "; use tangential_damping <= " << (kStabilityBudget - t_spring) * m / (2.0 * dt)
          << " N s/m or a smaller dt";
      }
      problem(s.str());
    }
  }

  std::string msg = out.str();
  if (msg.empty()) return true;
  msg.pop_back();
  if (error) *error = msg;
  return false;
}

double HuntCrossleyRestitution(double k, double n, double c, double m, double v0, double h) {
  auto acc = [&](double x, double v) {
    if (x <= 0) return 0.0;
    return -k / m * std::pow(x, n) * std::max(0.0, 1.0 + c * v);
  };
  double x = 0, v = v0;
  for (long i = 0; i < 100000000L; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (i > 0 && xn <= 0 && vn < 0) {
      const double s = x / (x - xn);
      return -(v + s * (vn - v)) / v0;
    }
    x = xn;
    v = vn;
  }
  return std::nan("");
}

}  // namespace ohrp::contact
