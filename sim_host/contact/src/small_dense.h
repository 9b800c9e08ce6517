// The implicit soft soles' small dense algebra (implicit.cc), written out for its sizes: 6 rows
// per sole body, 12 for a biped. Eigen's dynamic-size PartialPivLU and lazy product dispatch
// and block for large matrices: on HRP-1S standing they took 9.7k instructions per step (the
// 12x12 factorisation and solve) and 2.3k per sole body (X^T X); written out, 5.4k and 1.0k
// (callgrind). No allocation, no exceptions.
#pragma once

#include <Eigen/Dense>

namespace ohrp::contact::internal {

// Solves S x = b in place by Gaussian elimination with partial pivoting (the row of the
// largest magnitude in each column, as PartialPivLU): S is overwritten by its factors, b by x.
// A zero pivot (a singular S) gives non-finite values, as the division would.
void SolveInPlace(Eigen::MatrixXd* s, Eigen::VectorXd* b);

// out = X^T X for X with six columns (row major), summed over X's rows; symmetric.
void Gram6(const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>& x,
           Eigen::Ref<Eigen::MatrixXd> out);

}  // namespace ohrp::contact::internal
