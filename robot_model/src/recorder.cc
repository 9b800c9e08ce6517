// CSV data log with a background writer (see recorder.h).
#include "robot_model/recorder.h"

#include <cerrno>
#include <chrono>
#include <cstring>

#include "robot_model/format_g9.h"

namespace ohrp::model {

LogNames LogNamesOf(const RobotMap& robot) {
  LogNames n;
  for (const auto& j : robot.joints) n.joints.push_back(j.name);
  for (const auto& f : robot.forces) n.forces.push_back(f.name);
  for (const auto& u : robot.imus) n.imus.push_back(u.name);
  return n;
}


std::unique_ptr<Recorder> Recorder::Open(const std::string& path, const LogNames& names,
                                         std::string* error, size_t capacity,
                                         const RecorderChannels& channels) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    *error = "cannot write the log '" + path + "': " + std::strerror(errno);
    return nullptr;
  }
  std::unique_ptr<Recorder> r(new Recorder());
  r->file_ = f;
  r->base_ = channels.base;
  r->njoint_ = channels.joints ? static_cast<int>(names.joints.size()) : 0;
  r->nforce_ = channels.force_torque ? static_cast<int>(names.forces.size()) : 0;
  r->nimu_ = channels.imu ? static_cast<int>(names.imus.size()) : 0;
  r->width_ = 1 + (r->base_ ? 10 : 0) + 3 * r->njoint_ + 6 * r->nforce_ + 10 * r->nimu_ + 2;
  r->capacity_ = capacity;
  r->ring_.assign(r->width_ * capacity, 0.0);

  // header line
  std::string h = "time";
  if (r->base_) h += ",base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,base_vx,base_vy,base_vz";
  auto column = [&h](const std::string& a, const char* b) {
    h += ',';
    h += a;
    h += b;
  };
  for (const char* prefix : {"q_", "qref_", "tau_"})
    for (int i = 0; i < r->njoint_; ++i) column(prefix, names.joints[i].c_str());
  for (int f = 0; f < r->nforce_; ++f)
    for (const char* c : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) column(names.forces[f], c);
  for (int u = 0; u < r->nimu_; ++u)
    for (const char* c : {"_gx", "_gy", "_gz", "_ax", "_ay", "_az", "_qw", "_qx", "_qy", "_qz"})
      column(names.imus[u], c);
  h += ",status,rejected\n";
  std::fputs(h.c_str(), f);
  r->line_.reserve(r->width_ * 24);
  r->writer_ = std::thread([p = r.get()] { p->WriterLoop(); });
  return r;
}

Recorder::~Recorder() {
  stop_.store(true);
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
  Flush();
  if (file_) std::fclose(file_);
}

bool Recorder::Push(const shm::SensorBlock& s, const shm::JointCommand* refs) {
  const uint64_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) >= capacity_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  double* row = &ring_[(head % capacity_) * width_];
  size_t k = 0;
  row[k++] = s.time;
  if (base_) {
    for (int i = 0; i < 3; ++i) row[k++] = s.sim_truth.p_WB[i];
    for (int i = 0; i < 4; ++i) row[k++] = s.sim_truth.quat_WB[i];
    for (int i = 0; i < 3; ++i) row[k++] = s.sim_truth.v_WB[i];
  }
  for (int i = 0; i < njoint_; ++i) row[k++] = s.q[i];
  for (int i = 0; i < njoint_; ++i) row[k++] = refs[i].q_ref;
  for (int i = 0; i < njoint_; ++i) row[k++] = s.tau[i];
  for (int f = 0; f < nforce_; ++f) {
    for (int i = 0; i < 3; ++i) row[k++] = s.force[f].force[i];
    for (int i = 0; i < 3; ++i) row[k++] = s.force[f].torque[i];
  }
  for (int u = 0; u < nimu_; ++u) {
    for (int i = 0; i < 3; ++i) row[k++] = s.imu[u].gyro[i];
    for (int i = 0; i < 3; ++i) row[k++] = s.imu[u].accel[i];
    for (int i = 0; i < 4; ++i) row[k++] = s.imu[u].quat_WI[i];
  }
  row[k++] = s.status;
  row[k++] = static_cast<double>(s.rejected_commands);
  head_.store(head + 1, std::memory_order_release);
  return true;
}

void Recorder::WriteRow(const double* row) {
  line_.clear();
  // printf's "%.9g" (format_g9.h): the writer thread shares the CPUs with a lock-step run
  char buf[kFormatG9Max + 1];
  for (size_t i = 0; i < width_; ++i) {
    char* p = buf;
    if (i) *p++ = ',';
    p = FormatG9(p, row[i]);
    line_.append(buf, static_cast<size_t>(p - buf));
  }
  line_ += '\n';
  std::fwrite(line_.data(), 1, line_.size(), file_);
  ++written_;
}

void Recorder::Flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  uint64_t tail = tail_.load(std::memory_order_relaxed);
  const uint64_t head = head_.load(std::memory_order_acquire);
  for (; tail < head; ++tail) {
    WriteRow(&ring_[(tail % capacity_) * width_]);
    tail_.store(tail + 1, std::memory_order_release);
  }
  std::fflush(file_);
}

void Recorder::WriterLoop() {
  while (!stop_.load()) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(50), [this] { return stop_.load(); });
    }
    Flush();
  }
}

}  // namespace ohrp::model
