// ohrp identify --joints (see identify/joints.h).
#include "identify/joints.h"

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ohrp::identify {
namespace {

// least squares x of A x = y with standard errors and the residual RMS
struct Fit {
  Eigen::VectorXd x, se;
  double rms = 0;
};

Fit LeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& y) {
  Fit f;
  f.x = a.colPivHouseholderQr().solve(y);
  const Eigen::VectorXd r = y - a * f.x;
  const long dof = std::max<long>(1, a.rows() - a.cols());
  const double s2 = r.squaredNorm() / static_cast<double>(dof);
  f.rms = std::sqrt(r.squaredNorm() / static_cast<double>(a.rows()));
  const Eigen::MatrixXd cov = s2 * (a.transpose() * a).completeOrthogonalDecomposition().pseudoInverse();
  f.se = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  return f;
}

bool SplitNumbers(const std::string& line, std::vector<double>* out) {
  out->clear();
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) {
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || *end != 0) return false;
    out->push_back(v);
  }
  return true;
}

// the dynamics: tau = I qdd + b qd + c sign(qd) + A sin q + B cos q over the moving samples
bool FitDynamics(const JointLog& l, const JointFitOptions& o, JointEstimate* e, std::string* error) {
  std::vector<size_t> rows;
  for (size_t k = 1; k < l.t.size(); ++k)
    if (std::fabs(l.dq[k - 1]) >= o.v_min && l.t[k] > l.t[k - 1]) rows.push_back(k);
  if (rows.size() < 50) {
    *error = l.joint + ": " + std::to_string(rows.size()) +
             " samples move faster than " + std::to_string(o.v_min) +
             " rad/s (need 50): a larger amplitude or a higher frequency";
    return false;
  }
  Eigen::MatrixXd a(rows.size(), 5);
  Eigen::VectorXd y(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const size_t k = rows[i];
    // the torque of row k moved the joint from row k - 1's state to row k's
    const double qdd = (l.dq[k] - l.dq[k - 1]) / (l.t[k] - l.t[k - 1]);
    const double v = l.dq[k - 1], q = l.q[k - 1];
    a.row(i) << qdd, v, v > 0 ? 1.0 : -1.0, std::sin(q), std::cos(q);
    y(i) = l.tau[k];
  }
  const Fit f = LeastSquares(a, y);
  e->moving = rows.size();
  e->inertia = f.x(0), e->inertia_se = f.se(0);
  e->viscous = f.x(1), e->viscous_se = f.se(1);
  e->coulomb = f.x(2), e->coulomb_se = f.se(2);
  e->dynamics_rms = f.rms;
  e->tau_rms = std::sqrt(y.squaredNorm() / static_cast<double>(y.size()));
  return true;
}

// the servo: tau_k = kp (ref_{k-L} - q_k) + kd (dref_{k-L} - qd_k) + tau0, the L of least residual
void FitServo(const JointLog& l, const JointFitOptions& o, JointEstimate* e) {
  const long n = static_cast<long>(l.t.size());
  double best = -1;
  for (int lag = 0; lag <= o.max_lag && n - lag - 2 > 20; ++lag) {
    const long first = lag + 1;
    Eigen::MatrixXd a(n - first, 3);
    Eigen::VectorXd y(n - first);
    for (long k = first; k < n; ++k) {
      const long j = k - lag;
      const double dref = (l.ref[j] - l.ref[j - 1]) / (l.t[j] - l.t[j - 1]);
      a.row(k - first) << l.ref[j] - l.q[k - 1], dref - l.dq[k - 1], 1.0;
      y(k - first) = l.tau[k];
    }
    const Fit f = LeastSquares(a, y);
    if (best < 0 || f.rms < best) {
      best = f.rms;
      e->lag_cycles = lag;
      e->kp = f.x(0);
      e->kd = f.x(1);
      e->servo_rms = f.rms;
    }
  }
  e->lag = e->lag_cycles * e->period;
}

}  // namespace

bool ReadExciteLog(const std::string& path, std::vector<JointLog>* joints, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read " + path;
    return false;
  }
  std::string header;
  std::getline(in, header);
  std::vector<std::string> cols;
  {
    std::stringstream h(header);
    std::string c;
    while (std::getline(h, c, ',')) cols.push_back(c);
  }
  const size_t nj = cols.size() >= 5 ? (cols.size() - 1) / 4 : 0;
  if (cols.empty() || cols[0] != "time" || nj == 0 || cols.size() != 1 + 4 * nj) {
    *error = path + ": not an excite log (time, then JOINT_ref, JOINT_q, JOINT_dq, JOINT_tau per joint)";
    return false;
  }
  joints->assign(nj, JointLog{});
  for (size_t j = 0; j < nj; ++j) {
    const std::string& c = cols[1 + 4 * j];
    if (c.size() < 5 || c.compare(c.size() - 4, 4, "_ref") != 0) {
      *error = path + ": column " + std::to_string(2 + 4 * j) + " is '" + c + "', want JOINT_ref";
      return false;
    }
    (*joints)[j].joint = c.substr(0, c.size() - 4);
  }
  std::string line;
  std::vector<double> v;
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    if (!SplitNumbers(line, &v) || v.size() != cols.size()) {
      *error = path + ": line " + std::to_string(row) + " is not " + std::to_string(cols.size()) + " numbers";
      return false;
    }
    for (size_t j = 0; j < nj; ++j) {
      JointLog& l = (*joints)[j];
      l.t.push_back(v[0]);
      l.ref.push_back(v[1 + 4 * j]);
      l.q.push_back(v[2 + 4 * j]);
      l.dq.push_back(v[3 + 4 * j]);
      l.tau.push_back(v[4 + 4 * j]);
    }
  }
  return true;
}

bool EstimateJoint(const JointLog& log, const JointFitOptions& o, JointEstimate* e,
                   std::string* error) {
  *e = JointEstimate{};
  e->joint = log.joint;
  e->samples = log.t.size();
  if (log.t.size() < 100) {
    *error = log.joint + ": " + std::to_string(log.t.size()) + " samples (need 100)";
    return false;
  }
  e->period = (log.t.back() - log.t.front()) / static_cast<double>(log.t.size() - 1);
  if (!FitDynamics(log, o, e, error)) return false;
  FitServo(log, o, e);
  return true;
}

}  // namespace ohrp::identify
