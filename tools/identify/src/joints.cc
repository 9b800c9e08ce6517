// ohrp identify --joints (see identify/joints.h).
#include "identify/joints.h"
#include "identify/sensors.h"

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
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

// The standard errors of x by a moving-block bootstrap of the residuals (joints.h): y* = A x + r*,
// r* blocks of kBootstrapBlock consecutive residuals drawn with replacement, x* refitted; the std
// of x* over kBootstrapRefits refits, from a fixed seed.
Eigen::VectorXd BootstrapSe(const Eigen::MatrixXd& a, const Eigen::VectorXd& y, const Eigen::VectorXd& x) {
  const long n = a.rows();
  const long block = std::min<long>(kBootstrapBlock, n);
  const Eigen::VectorXd fitted = a * x, r = y - fitted;
  std::mt19937_64 rng(kBootstrapSeed);
  std::uniform_int_distribution<long> start(0, n - block);
  const auto qr = a.colPivHouseholderQr();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(x.size()), sum2 = sum, ys(n);
  for (int i = 0; i < kBootstrapRefits; ++i) {
    for (long k = 0; k < n; k += block) {
      const long s = start(rng);
      for (long m = 0; m < block && k + m < n; ++m) ys(k + m) = fitted(k + m) + r(s + m);
    }
    const Eigen::VectorXd xs = qr.solve(ys);
    sum += xs;
    sum2 += xs.cwiseProduct(xs);
  }
  const double m = kBootstrapRefits;
  return ((sum2 - sum.cwiseProduct(sum) / m) / (m - 1)).cwiseMax(0.0).cwiseSqrt();
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
  // consecutive cycles only (a row missed by the logger leaves a longer interval)
  for (size_t k = 1; k < l.t.size(); ++k)
    if (std::fabs(l.dq[k - 1]) >= o.v_min &&
        std::fabs(l.t[k] - l.t[k - 1] - e->period) < 0.1 * e->period)
      rows.push_back(k);
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
  const Eigen::VectorXd se = BootstrapSe(a, y, f.x);
  e->moving = rows.size();
  e->inertia = f.x(0), e->inertia_se = se(0), e->inertia_se_ols = f.se(0);
  e->viscous = f.x(1), e->viscous_se = se(1), e->viscous_se_ols = f.se(1);
  e->coulomb = f.x(2), e->coulomb_se = se(2), e->coulomb_se_ols = f.se(2);
  e->dynamics_rms = f.rms;
  e->tau_rms = std::sqrt(y.squaredNorm() / static_cast<double>(y.size()));
  return true;
}

// the servo: tau_k = kp (ref_{k-L} - q_k) + kd (dref_{k-L} - qd_k) + tau0, the L of least residual
// (the lag in cycles of the period: each row's cycle number from its time; only the rows whose
// last L + 2 cycles are all logged)
void FitServo(const JointLog& l, const JointFitOptions& o, JointEstimate* e) {
  const long n = static_cast<long>(l.t.size());
  std::vector<long> cycle(n);
  for (long k = 0; k < n; ++k) cycle[k] = std::lround((l.t[k] - l.t[0]) / e->period);
  // per cycle, the reference in force and its rate as commanded (excite: the move over the
  // interval since its previous cycle)
  std::vector<double> ref(static_cast<size_t>(cycle.back() + 1), l.ref[0]);
  std::vector<double> rate(ref.size(), 0.0);
  // per cycle, how many cycles up to it the log holds without a gap: a cycle the logger missed
  // may have had the row before's reference or a newer one, and a board whose delay counts
  // commands (hw_emulator --delay-ms) shifts nothing in a cycle without one (the driver's missed
  // cycles in the boards' time base, docs/identify.md)
  std::vector<long> run(ref.size(), 0);
  for (long k = 0, c = 0; c <= cycle.back(); ++c) {
    while (k + 1 < n && cycle[k + 1] <= c) ++k;
    ref[c] = l.ref[k];
    rate[c] = !l.dref.empty() ? l.dref[k]
              : k > 0         ? (l.ref[k] - l.ref[k - 1]) / (l.t[k] - l.t[k - 1])
                              : 0.0;
    run[c] = cycle[k] == c ? (c > 0 ? run[c - 1] : 0) + 1 : 0;
  }
  // a servo at its torque limit is not the PD law: the rows within kSaturated of the largest
  // |tau| logged stay out
  double tau_max = 0;
  for (double t : l.tau) tau_max = std::fmax(tau_max, std::fabs(t));
  std::vector<long> rows;
  for (long k = 1; k < n; ++k)
    if (cycle[k] == cycle[k - 1] + 1 && std::fabs(l.tau[k]) < (1 - kSaturated) * tau_max)
      rows.push_back(k);
  e->saturated = 0;
  for (double t : l.tau) e->saturated += std::fabs(t) >= (1 - kSaturated) * tau_max;
  // the regression at lag L (false: too few rows)
  const auto regress = [&](int lag, Eigen::MatrixXd* a, Eigen::VectorXd* y) {
    std::vector<long> use;
    // the rows whose cycles back to the reference L cycles earlier and the one before it (its
    // rate) are all in the log
    for (long k : rows)
      if (cycle[k] - lag >= 1 && run[cycle[k]] >= lag + 2) use.push_back(k);
    if (use.size() < 20) return false;
    a->resize(static_cast<long>(use.size()), 3);
    y->resize(static_cast<long>(use.size()));
    for (size_t i = 0; i < use.size(); ++i) {
      const long k = use[i], c = cycle[k] - lag;
      a->row(static_cast<long>(i)) << ref[c] - l.q[k - 1], rate[c] - l.dq[k - 1], 1.0;
      (*y)(static_cast<long>(i)) = l.tau[k];
    }
    return true;
  };
  double best = -1;
  Eigen::MatrixXd a;
  Eigen::VectorXd y;
  // each lag's residual relative to the torque's spread over its own rows (with gaps in the log
  // a longer lag keeps fewer rows, the long runs the driver kept up, which need not move alike)
  for (int lag = 0; lag <= o.max_lag && regress(lag, &a, &y); ++lag) {
    const Fit f = LeastSquares(a, y);
    const double spread = std::sqrt((y.array() - y.mean()).square().mean());
    const double score = f.rms / std::fmax(spread, 1e-12);
    if (best < 0 || score < best) {
      best = score;
      e->lag_cycles = lag;
      e->kp = f.x(0);
      e->kd = f.x(1);
      e->servo_rms = f.rms;
    }
  }
  e->lag = e->lag_cycles * e->period;
  if (best >= 0 && regress(e->lag_cycles, &a, &y)) {
    const Fit f = LeastSquares(a, y);
    const Eigen::VectorXd se = BootstrapSe(a, y, f.x);
    e->kp_se = se(0), e->kd_se = se(1);
  }
}

// DIR/joints.yaml for sim_host --joint-file (robot_model/joint_params.h)
int WriteJointFile(const std::string& log, const std::vector<JointLog>& joints,
                   const std::vector<JointEstimate>& estimates, const JointModel& model,
                   const std::string& path) {
  std::vector<model::JointParams> params;
  std::vector<std::string> warnings;
  std::string error;
  if (!JointParamsFromEstimates(joints, estimates, model, &params, &warnings, &error)) {
    std::fprintf(stderr, "ohrp_identify: --model %s: %s\n", model.model.c_str(), error.c_str());
    return 2;
  }
  for (const std::string& w : warnings) std::fprintf(stderr, "ohrp_identify: warning: %s\n", w.c_str());
  const std::vector<std::string> header = {
      "the joints as identified by ohrp identify --joints from " + log,
      "on the model " + model.model + (model.keyframe.empty() ? "" : ", keyframe " + model.keyframe),
      "armature [kg m^2] = the identified inertia less the links' (the model's), damping [N m s/rad],",
      "frictionloss [N m]; sim_host --joint-file THIS (or a profile's joint_file:) applies them"};
  if (!model::WriteJointParamsFile(path, params, header, &error)) {
    std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
    return 2;
  }
  std::printf("the model's joint parameters: %s (sim_host --joint-file)\n", path.c_str());
  if (model.draws_for.empty()) return 0;
  return WriteDrawSweep(log, params, estimates, model,
                        (std::filesystem::path(path).parent_path() / "joints_draws.yaml").string());
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
  // the period: the median interval between rows
  std::vector<double> dt;
  for (size_t k = 1; k < log.t.size(); ++k) dt.push_back(log.t[k] - log.t[k - 1]);
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  e->period = dt[dt.size() / 2];
  if (!(e->period > 0)) {
    *error = log.joint + ": the log's time does not increase";
    return false;
  }
  for (size_t k = 1; k < log.t.size(); ++k) e->gaps += log.t[k] - log.t[k - 1] > 1.5 * e->period;
  if (!FitDynamics(log, o, e, error)) return false;
  FitServo(log, o, e);
  return true;
}

int IdentifyJoints(const std::string& log, const std::string& out_dir, const JointFitOptions& o,
                   const JointModel& model) {
  std::vector<JointLog> joints;
  std::string error, note;
  if (!ReadJointLog(log, &joints, &note, &error)) {
    std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
    return 2;
  }
  if (!note.empty()) std::printf("%s: %s\n", log.c_str(), note.c_str());
  nlohmann::json all = nlohmann::json::array();
  std::printf("%-18s %9s %9s %9s %9s %9s %9s %7s %9s %8s\n", "joint", "I", "+-", "b", "+-", "c",
              "+-", "lag_ms", "kp", "kd");
  std::vector<std::string> bandwidths;
  std::vector<JointEstimate> estimates;
  for (const JointLog& l : joints) {
    JointEstimate& e = estimates.emplace_back();
    if (!EstimateJoint(l, o, &e, &error)) {
      std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
      return 2;
    }
    std::printf("%-18s %9.4g %9.2g %9.4g %9.2g %9.4g %9.2g %7.1f %9.4g %8.4g\n", e.joint.c_str(),
                e.inertia, e.inertia_se, e.viscous, e.viscous_se, e.coulomb, e.coulomb_se,
                1e3 * e.lag, e.kp, e.kd);
    all.push_back({{"joint", e.joint}, {"samples", e.samples}, {"moving", e.moving},
                   {"inertia", e.inertia}, {"inertia_se", e.inertia_se},
                   {"viscous", e.viscous}, {"viscous_se", e.viscous_se},
                   {"coulomb", e.coulomb}, {"coulomb_se", e.coulomb_se},
                   {"inertia_se_ols", e.inertia_se_ols}, {"viscous_se_ols", e.viscous_se_ols},
                   {"coulomb_se_ols", e.coulomb_se_ols}, {"kp_se", e.kp_se}, {"kd_se", e.kd_se},
                   {"gaps", e.gaps}, {"saturated", e.saturated},
                   {"dynamics_rms", e.dynamics_rms}, {"tau_rms", e.tau_rms},
                   {"lag_cycles", e.lag_cycles}, {"period", e.period}, {"lag", e.lag},
                   {"kp", e.kp}, {"kd", e.kd}, {"servo_rms", e.servo_rms}});
    // the -3 dB bandwidth of q / ref (identify/sensors.h): reported, never a refusal
    Bandwidth b;
    std::string why;
    char line[160];
    if (!EstimateBandwidth(l, &b, &why)) {
      all.back()["bandwidth_error"] = why;
      std::snprintf(line, sizeof(line), "%-18s bandwidth not estimated: %s", e.joint.c_str(), why.c_str());
    } else if (!b.found) {
      all.back()["bandwidth_above"] = b.f_max;
      std::snprintf(line, sizeof(line), "%-18s bandwidth above %.3g Hz (the chirp's highest: -3 dB not "
                    "reached)", e.joint.c_str(), b.f_max);
    } else {
      all.back()["bandwidth"] = b.f, all.back()["bandwidth_se"] = b.f_se;
      all.back()["bandwidth_gain0"] = b.gain0;
      std::snprintf(line, sizeof(line), "%-18s bandwidth (-3 dB of q/ref) %.4g +- %.2g Hz (low-frequency "
                    "gain %.4g)", e.joint.c_str(), b.f, b.f_se, b.gain0);
    }
    bandwidths.push_back(line);
  }
  for (const std::string& b : bandwidths) std::printf("%s\n", b.c_str());
  const std::string path = out_dir + "/joints.json";
  std::ofstream f(path);
  f << nlohmann::json{{"log", log}, {"joints", all}}.dump(2) << "\n";
  if (!f) {
    std::fprintf(stderr, "ohrp_identify: cannot write %s\n", path.c_str());
    return 2;
  }
  std::printf("(I [kg m^2] total about the axis, b [N m s/rad], c [N m], the servo's lag with the "
              "loop's own cycle, kp, kd as realised; %s)\n", path.c_str());
  if (model.model.empty()) return 0;
  return WriteJointFile(log, joints, estimates, model, out_dir + "/joints.yaml");
}

}  // namespace ohrp::identify
