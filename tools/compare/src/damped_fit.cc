// A damped sine fitted by least squares (see damped_fit.h).
#include "compare/damped_fit.h"

#include <Eigen/Dense>

#include <cmath>

namespace ohrp::compare {
namespace {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

// the model's value and its gradient in (c, a, b, sigma, omega) at u
double Model(const Vec5& p, double u, Vec5* grad) {
  const double e = std::exp(-p[3] * u), co = std::cos(p[4] * u), si = std::sin(p[4] * u);
  const double wave = p[1] * co + p[2] * si;
  if (grad != nullptr) {
    (*grad)[0] = 1;
    (*grad)[1] = e * co;
    (*grad)[2] = e * si;
    (*grad)[3] = -u * e * wave;
    (*grad)[4] = u * e * (-p[1] * si + p[2] * co);
  }
  return p[0] + e * wave;
}

double Rss(const std::vector<double>& t, const std::vector<double>& x, size_t begin, size_t end,
           const Vec5& p) {
  double s = 0;
  for (size_t i = begin; i < end; ++i) {
    const double r = x[i] - Model(p, t[i] - t[begin], nullptr);
    s += r * r;
  }
  return s;
}

// the linear parameters (c, a, b) for given (sigma, omega) by least squares; false when singular
bool LinearPart(const std::vector<double>& t, const std::vector<double>& x, size_t begin, size_t end,
                double sigma, double omega, Vec5* p) {
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d aty = Eigen::Vector3d::Zero();
  for (size_t i = begin; i < end; ++i) {
    const double u = t[i] - t[begin], e = std::exp(-sigma * u);
    const Eigen::Vector3d row(1, e * std::cos(omega * u), e * std::sin(omega * u));
    ata += row * row.transpose();
    aty += row * x[i];
  }
  const auto ldlt = ata.ldlt();
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::Vector3d lin = ldlt.solve(aty);
  if (!lin.allFinite()) return false;
  *p << lin[0], lin[1], lin[2], sigma, omega;
  return true;
}

}  // namespace

bool GridStart(const std::vector<double>& t, const std::vector<double>& x, size_t begin, size_t end,
               double* sigma0, double* omega0) {
  if (end < begin + 10) return false;
  const double span = t[end - 1] - t[begin];
  const double step = span / static_cast<double>(end - begin - 1);
  // periods from the whole window down to 8 samples, log-spaced; damping ratios 0 .. 0.7
  const double w_lo = 2 * M_PI / span, w_hi = 2 * M_PI / (8 * step);
  double best = HUGE_VAL;
  constexpr int kOmegas = 80, kZetas = 8;
  for (int i = 0; i < kOmegas; ++i) {
    const double w = w_lo * std::pow(w_hi / w_lo, static_cast<double>(i) / (kOmegas - 1));
    for (int j = 0; j < kZetas; ++j) {
      const double zeta = 0.1 * j;
      const double sigma = zeta * w / std::sqrt(1 - zeta * zeta);
      Vec5 p;
      if (!LinearPart(t, x, begin, end, sigma, w, &p)) continue;
      const double r = Rss(t, x, begin, end, p);
      if (r < best) {
        best = r;
        *sigma0 = sigma;
        *omega0 = w;
      }
    }
  }
  return std::isfinite(best);
}

DampedFit FitDampedSine(const std::vector<double>& t, const std::vector<double>& x, size_t begin,
                        size_t end, double sigma0, double omega0) {
  DampedFit f;
  const size_t n = end > begin ? end - begin : 0;
  if (n < 10 || !(omega0 > 0) || !(sigma0 >= 0)) {
    f.why = "too few samples or no start for the fit";
    return f;
  }
  // the linear parameters at the start: least squares on (1, e cos, e sin)
  Vec5 p;
  if (!LinearPart(t, x, begin, end, sigma0, omega0, &p)) {
    f.why = "the start of the fit is singular";
    return f;
  }

  // Levenberg-Marquardt
  double rss = Rss(t, x, begin, end, p), lambda = 1e-3;
  for (f.iterations = 0; f.iterations < 200; ++f.iterations) {
    Mat5 jtj = Mat5::Zero();
    Vec5 jtr = Vec5::Zero(), g;
    for (size_t i = begin; i < end; ++i) {
      const double r = x[i] - Model(p, t[i] - t[begin], &g);
      jtj += g * g.transpose();
      jtr += g * r;
    }
    bool improved = false;
    for (int tries = 0; tries < 20 && !improved; ++tries) {
      Mat5 a = jtj;
      for (int k = 0; k < 5; ++k) a(k, k) *= 1 + lambda;
      const Vec5 step = a.ldlt().solve(jtr);
      const Vec5 q = p + step;
      const double rq = Rss(t, x, begin, end, q);
      if (std::isfinite(rq) && rq < rss) {
        const double gain = (rss - rq) / rss;
        p = q;
        rss = rq;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        if (gain < 1e-12) f.iterations = 1000;  // converged
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;  // no step lowers the sum: a minimum
  }

  // the fit's quality and its covariance
  double mean = 0;
  for (size_t i = begin; i < end; ++i) mean += x[i];
  mean /= static_cast<double>(n);
  double var = 0;
  for (size_t i = begin; i < end; ++i) var += (x[i] - mean) * (x[i] - mean);
  Mat5 jtj = Mat5::Zero();
  Vec5 g;
  for (size_t i = begin; i < end; ++i) {
    Model(p, t[i] - t[begin], &g);
    jtj += g * g.transpose();
  }
  const Mat5 cov = jtj.inverse() * (rss / static_cast<double>(n - 5));
  f.c = p[0];
  f.a = p[1];
  f.b = p[2];
  f.sigma = p[3];
  f.omega = p[4];
  f.sigma_se = std::sqrt(std::max(0.0, cov(3, 3)));
  f.omega_se = std::sqrt(std::max(0.0, cov(4, 4)));
  f.cov_sigma_omega = cov(3, 4);
  f.rms = std::sqrt(rss / static_cast<double>(n));
  f.explained = var > 0 ? 1 - rss / var : 0;
  if (!std::isfinite(rss) || !cov.allFinite()) {
    f.why = "the fit did not converge";
  } else if (!(f.sigma > 0) || !(f.omega > 0)) {
    f.why = "the fitted sine does not decay";
  } else {
    f.ok = true;
  }
  return f;
}

}  // namespace ohrp::compare
