// Tests the implicit soles' small dense algebra (sim_host/contact/src/small_dense.h) against
// Eigen's own: the solve against PartialPivLU and the residual, on the sizes the soles use (6
// per sole body: 6 and 12, unrolled, and 18 by the general loop), including matrices that need
// row exchanges; the Gram product against X^T X.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "small_dense.h"

namespace ohrp::contact::internal {
namespace {

// the kind of matrix the soles solve: I - h B A, A symmetric positive semidefinite, B symmetric
// negative semidefinite per 6x6 block, scaled so that h B A is far from small
Eigen::MatrixXd SoleSystem(int n, double scale) {
  const Eigen::MatrixXd j = Eigen::MatrixXd::Random(n, n + 6);
  const Eigen::MatrixXd a = j * j.transpose();
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; k += 6) {
    const Eigen::MatrixXd p = Eigen::MatrixXd::Random(6, 6);
    b.block(k, k, 6, 6) = -scale * p * p.transpose();
  }
  return Eigen::MatrixXd::Identity(n, n) - b * a;
}

TEST(SmallDense, SolveMatchesEigensPartialPivLu) {
  std::srand(3);
  for (int n : {6, 12, 18}) {
    for (double scale : {0.0, 0.1, 10.0, 1e4}) {
      for (int trial = 0; trial < 20; ++trial) {
        const Eigen::MatrixXd s = SoleSystem(n, scale);
        const Eigen::VectorXd rhs = Eigen::VectorXd::Random(n);
        const Eigen::VectorXd expected = s.partialPivLu().solve(rhs);
        Eigen::MatrixXd work = s;
        Eigen::VectorXd x = rhs;
        SolveInPlace(&work, &x);
        const double cond = s.norm() * s.inverse().norm();
        EXPECT_LE((x - expected).norm(), 1e-13 * cond * expected.norm())
            << "n " << n << ", scale " << scale << ", trial " << trial;
        EXPECT_LE((s * x - rhs).norm(), 1e-12 * s.norm() * x.norm()) << "n " << n;
      }
    }
  }
}

TEST(SmallDense, SolveExchangesRows) {
  // a zero on the diagonal: without a row exchange the first pivot would divide by zero
  for (int n : {6, 12, 7}) {
    Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) s(i, (i + 1) % n) = 1.0 + i;  // a scaled cyclic permutation
    s(n - 1, n - 1) = 0.5;
    const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, 1, n);
    Eigen::MatrixXd work = s;
    Eigen::VectorXd x = rhs;
    SolveInPlace(&work, &x);
    EXPECT_TRUE(x.allFinite()) << "n " << n;
    EXPECT_LE((s * x - rhs).norm(), 1e-12 * rhs.norm()) << "n " << n;
  }
}

TEST(SmallDense, GramIsXTransposeX) {
  std::srand(5);
  for (int rows : {1, 6, 12, 13}) {
    const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> x =
        Eigen::MatrixXd::Random(rows, 6);
    Eigen::MatrixXd out = Eigen::MatrixXd::Constant(8, 8, -7.0);
    Gram6(x, out.block(1, 2, 6, 6));
    const Eigen::MatrixXd expected = x.transpose() * x;
    EXPECT_LE((out.block(1, 2, 6, 6) - expected).norm(), 1e-14 * expected.norm()) << rows;
    EXPECT_EQ(out(0, 0), -7.0);  // nothing outside the block is written
    EXPECT_EQ(out(7, 7), -7.0);
    EXPECT_EQ(out(1, 1), -7.0);
  }
}

}  // namespace
}  // namespace ohrp::contact::internal
