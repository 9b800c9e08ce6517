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
  e->moving = rows.size();
  e->inertia = f.x(0), e->inertia_se = f.se(0);
  e->viscous = f.x(1), e->viscous_se = f.se(1);
  e->coulomb = f.x(2), e->coulomb_se = f.se(2);
  e->dynamics_rms = f.rms;
  e->tau_rms = std::sqrt(y.squaredNorm() / static_cast<double>(y.size()));
  return true;
}

// the servo: tau_k = kp (ref_{k-L} - q_k) + kd (dref_{k-L} - qd_k) + tau0, the L of least residual
// (the lag in cycles of the period: each row's cycle number from its time, the reference of a
// cycle the logger missed the one before it)
void FitServo(const JointLog& l, const JointFitOptions& o, JointEstimate* e) {
  const long n = static_cast<long>(l.t.size());
  std::vector<long> cycle(n);
  for (long k = 0; k < n; ++k) cycle[k] = std::lround((l.t[k] - l.t[0]) / e->period);
  // per cycle, the reference in force and its rate as commanded (excite: the move over the
  // interval since its previous cycle)
  std::vector<double> ref(static_cast<size_t>(cycle.back() + 1), l.ref[0]);
  std::vector<double> rate(ref.size(), 0.0);
  for (long k = 0, c = 0; c <= cycle.back(); ++c) {
    while (k + 1 < n && cycle[k + 1] <= c) ++k;
    ref[c] = l.ref[k];
    rate[c] = k > 0 ? (l.ref[k] - l.ref[k - 1]) / (l.t[k] - l.t[k - 1]) : 0.0;
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
  double best = -1;
  for (int lag = 0; lag <= o.max_lag; ++lag) {
    std::vector<long> use;
    for (long k : rows)
      if (cycle[k] - lag >= 1) use.push_back(k);
    if (use.size() < 20) break;
    Eigen::MatrixXd a(use.size(), 3);
    Eigen::VectorXd y(use.size());
    for (size_t i = 0; i < use.size(); ++i) {
      const long k = use[i], c = cycle[k] - lag;
      a.row(i) << ref[c] - l.q[k - 1], rate[c] - l.dq[k - 1], 1.0;
      y(i) = l.tau[k];
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
  if (!FitDynamics(log, o, e, error)) return false;
  FitServo(log, o, e);
  return true;
}

int IdentifyJoints(const std::string& log, const std::string& out_dir, const JointFitOptions& o,
                   const JointModel& model) {
  std::vector<JointLog> joints;
  std::string error;
  if (!ReadExciteLog(log, &joints, &error)) {
    std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
    return 2;
  }
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
