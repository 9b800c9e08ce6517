// Small dense algebra for the implicit soft soles (small_dense.h).
#include "small_dense.h"

#include <cmath>
#include <utility>

namespace ohrp::contact::internal {

namespace {

// column-major n x n `a` (n = N where N > 0: fixed at compile time, its loops unrolled)
template <int N>
void Solve(double* a, double* x, int n) {
  if constexpr (N > 0) n = N;
  auto at = [a, n](int i, int j) -> double& { return a[i + j * n]; };
  for (int k = 0; k < n; ++k) {
    int p = k;
    double largest = std::fabs(at(k, k));
    for (int i = k + 1; i < n; ++i) {
      if (std::fabs(at(i, k)) > largest) {
        largest = std::fabs(at(i, k));
        p = i;
      }
    }
    if (p != k) {
      for (int j = 0; j < n; ++j) std::swap(at(k, j), at(p, j));
      std::swap(x[k], x[p]);
    }
    const double inv = 1.0 / at(k, k);
    for (int i = k + 1; i < n; ++i) at(i, k) *= inv;
    for (int j = k + 1; j < n; ++j) {
      const double akj = at(k, j);
      for (int i = k + 1; i < n; ++i) at(i, j) -= at(i, k) * akj;
    }
    const double xk = x[k];
    for (int i = k + 1; i < n; ++i) x[i] -= at(i, k) * xk;
  }
  for (int i = n - 1; i >= 0; --i) {
    double v = x[i];
    for (int j = i + 1; j < n; ++j) v -= at(i, j) * x[j];
    x[i] = v / at(i, i);
  }
}

}  // namespace

void SolveInPlace(Eigen::MatrixXd* s, Eigen::VectorXd* b) {
  const int n = static_cast<int>(s->rows());
  switch (n) {  // one and two sole bodies (a biped) get their own unrolled copies
    case 6: Solve<6>(s->data(), b->data(), n); break;
    case 12: Solve<12>(s->data(), b->data(), n); break;
    default: Solve<0>(s->data(), b->data(), n);
  }
}

void Gram6(const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>& x,
           Eigen::Ref<Eigen::MatrixXd> out) {
  double g[6][6] = {};
  for (Eigen::Index p = 0; p < x.rows(); ++p) {
    const double* r = x.data() + 6 * p;
    for (int i = 0; i < 6; ++i)
      for (int j = i; j < 6; ++j) g[i][j] += r[i] * r[j];
  }
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) {
      out(i, j) = g[i][j];
      out(j, i) = g[i][j];
    }
  }
}

}  // namespace ohrp::contact::internal
