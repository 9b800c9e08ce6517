// Reading the producers' CSV data log (see csv_log.h), through datalog::Table.
#include "csv_log.h"

#include <algorithm>
#include <cmath>

#include "datalog/table.h"

namespace ohrp::hw::replay {

bool CsvLog::Load(const std::string& path, const IoConfig& config, std::string* error) {
  datalog::Table table;
  if (!table.Load(path, error)) {
    error->insert(0, "replay log: ");
    return false;
  }
  const int time_col = table.Column("time");
  if (time_col < 0) {
    *error = "replay log '" + path + "' has no 'time' column (not a data log of sim_host or hw_driver?)";
    return false;
  }

  // where each value of a row comes from (-1: not logged)
  njoint_ = static_cast<int>(config.joint_names.size());
  nforce_ = static_cast<int>(config.force_names.size());
  nimu_ = static_cast<int>(config.imu_names.size());
  npassive_ = static_cast<int>(config.passive_names.size());
  width_ = 3 * njoint_ + 6 * nforce_ + 10 * nimu_ + 2 * npassive_;
  std::vector<int> source(width_, -1);
  auto find = [&](const std::string& name) { return table.Column(name); };
  for (int j = 0; j < njoint_; ++j) {
    const std::string& name = config.joint_names[j];
    source[j] = find("q_" + name);
    if (source[j] < 0) {
      *error = "replay log '" + path + "' has no column 'q_" + name +
               "': it was recorded from another robot than the model's";
      return false;
    }
    source[2 * njoint_ + j] = find("tau_" + name);
  }
  int k = 3 * njoint_;
  for (const std::string& f : config.force_names) {
    for (const char* c : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) source[k++] = find(f + c);
  }
  for (const std::string& u : config.imu_names) {
    for (const char* c : {"_gx", "_gy", "_gz", "_ax", "_ay", "_az", "_qw", "_qx", "_qy", "_qz"})
      source[k++] = find(u + c);
  }
  // the passive joints: q_<passive>, dq_<passive> (both logged by sim_host and hw_driver);
  // a log without them (an older one) reads 0
  for (const std::string& p : config.passive_names) source[k++] = find("q_" + p);
  for (const std::string& p : config.passive_names) source[k++] = find("dq_" + p);

  // rows: times strictly increasing
  const std::vector<double>& time = table.col(time_col);
  for (size_t r = 0; r < table.rows(); ++r) {
    if (r > 0 && !(time[r] > time[r - 1])) {
      *error = path + ":" + std::to_string(table.line(r)) + ": time " + std::to_string(time[r]) +
               " does not increase";
      return false;
    }
    time_.push_back(time[r]);
    for (int i = 0; i < width_; ++i) data_.push_back(source[i] >= 0 ? table.col(source[i])[r] : 0.0);
    // an IMU whose orientation was not logged reads the identity
    for (int u = 0; u < nimu_; ++u) {
      const int q0 = 3 * njoint_ + 6 * nforce_ + 10 * u + 6;
      if (source[q0] < 0) data_[data_.size() - width_ + q0] = 1.0;
    }
  }
  const int passive0 = 3 * njoint_ + 6 * nforce_ + 10 * nimu_;
  if (time_.empty()) {
    *error = "replay log '" + path + "' has a header but no rows";
    return false;
  }

  // joint velocities: central differences inside, one-sided at the ends
  const int n = rows();
  for (int r = 0; r < n; ++r) {
    const int a = std::max(0, r - 1), b = std::min(n - 1, r + 1);
    for (int j = 0; j < njoint_; ++j) {
      data_[r * width_ + njoint_ + j] =
          b > a ? (data_[b * width_ + j] - data_[a * width_ + j]) / (time_[b] - time_[a]) : 0.0;
    }
    // a passive joint whose velocity was not logged: the same differences
    for (int p = 0; p < npassive_; ++p) {
      const int qc = passive0 + p, dqc = passive0 + npassive_ + p;
      if (source[dqc] >= 0 || source[qc] < 0) continue;
      data_[r * width_ + dqc] =
          b > a ? (data_[b * width_ + qc] - data_[a * width_ + qc]) / (time_[b] - time_[a]) : 0.0;
    }
  }
  return true;
}

void CsvLog::Sample(double t, bool step, int* cursor, IoState* s) const {
  const int n = rows();
  int r = std::clamp(*cursor, 0, n - 1);
  if (time_[r] > t) r = 0;  // went back (a loop): search from the start
  while (r + 1 < n && time_[r + 1] <= t) ++r;
  *cursor = r;
  const double* a = &data_[r * width_];
  const double* b = r + 1 < n ? &data_[(r + 1) * width_] : a;
  double w = 0.0;
  if (!step && r + 1 < n && t > time_[r]) w = (t - time_[r]) / (time_[r + 1] - time_[r]);
  w = std::clamp(w, 0.0, 1.0);
  auto at = [&](int i) { return a[i] + w * (b[i] - a[i]); };
  for (int j = 0; j < njoint_; ++j) {
    s->q[j] = at(j);
    s->dq[j] = at(njoint_ + j);
    s->tau[j] = at(2 * njoint_ + j);
  }
  int k = 3 * njoint_;
  for (int f = 0; f < nforce_; ++f) {
    for (int i = 0; i < 3; ++i) s->force[f].force[i] = at(k++);
    for (int i = 0; i < 3; ++i) s->force[f].torque[i] = at(k++);
  }
  for (int u = 0; u < nimu_; ++u) {
    for (int i = 0; i < 3; ++i) s->imu[u].gyro[i] = at(k++);
    for (int i = 0; i < 3; ++i) s->imu[u].accel[i] = at(k++);
    double norm = 0;
    for (int i = 0; i < 4; ++i) {
      s->imu[u].quat_WI[i] = at(k++);
      norm += s->imu[u].quat_WI[i] * s->imu[u].quat_WI[i];
    }
    norm = std::sqrt(norm);
    if (norm > 0) {
      for (int i = 0; i < 4; ++i) s->imu[u].quat_WI[i] /= norm;
    }
  }
  for (int p = 0; p < npassive_; ++p) s->passive_q[p] = at(k++);
  for (int p = 0; p < npassive_; ++p) s->passive_dq[p] = at(k++);
}

}  // namespace ohrp::hw::replay
