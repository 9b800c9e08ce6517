// CSV data log with a background writer (see recorder.h).
#include "datalog/recorder.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "datalog/format_g9.h"

namespace ohrp::datalog {

namespace {

constexpr size_t kBatchBytes = 64 * 1024;  // the writer's write(2) size

// write(2) of bytes [0, n) of `p`, through short writes and EINTR; the bytes written in *done,
// and 0 or the errno that stopped it
int WriteAll(int fd, const char* p, size_t n, size_t* done) {
  *done = 0;
  while (*done < n) {
    const ssize_t k = ::write(fd, p + *done, n - *done);
    if (k > 0) {
      *done += static_cast<size_t>(k);
    } else if (k < 0 && errno == EINTR) {
      continue;
    } else {
      return k < 0 ? errno : ENOSPC;  // nothing taken of a non-empty buffer: no room
    }
  }
  return 0;
}

std::string Bytes(uint64_t b) {
  char t[32];
  if (b < 10000) std::snprintf(t, sizeof(t), "%lu bytes", static_cast<unsigned long>(b));
  else if (b < 10000000) std::snprintf(t, sizeof(t), "%.0f kB", b / 1e3);
  else std::snprintf(t, sizeof(t), "%.1f MB", b / 1e6);
  return t;
}

}  // namespace

std::unique_ptr<Recorder> Recorder::Open(const std::string& path, const LogNames& names,
                                         std::string* error, size_t capacity,
                                         const RecorderChannels& channels, uint64_t max_bytes) {
  std::unique_ptr<Recorder> r(new Recorder());
  r->path_ = path;
  r->base_ = channels.base;
  r->njoint_ = channels.joints ? static_cast<int>(names.joints.size()) : 0;
  r->nforce_ = channels.force_torque ? static_cast<int>(names.forces.size()) : 0;
  r->nimu_ = channels.imu ? static_cast<int>(names.imus.size()) : 0;
  r->npassive_ = channels.joints ? static_cast<int>(names.passive.size()) : 0;
  r->ndq_ = channels.joint_velocities ? r->njoint_ : 0;
  r->ndqref_ = channels.reference_velocities ? r->njoint_ : 0;
  r->width_ = 1 + (r->base_ ? 10 : 0) + 3 * r->njoint_ + r->ndq_ + r->ndqref_ + 2 * r->npassive_ + 6 * r->nforce_ +
              10 * r->nimu_ + 3;
  r->capacity_ = capacity;
  r->max_bytes_ = max_bytes;
  r->ring_.assign(r->width_ * capacity, 0.0);
  r->cycles_.assign(capacity, 0);

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
  for (int i = 0; i < r->ndq_; ++i) column("dq_", names.joints[i].c_str());
  for (int i = 0; i < r->ndqref_; ++i) column("dqref_", names.joints[i].c_str());
  for (const char* prefix : {"q_", "dq_"})
    for (int i = 0; i < r->npassive_; ++i) column(prefix, names.passive[i].c_str());
  for (int f = 0; f < r->nforce_; ++f)
    for (const char* c : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) column(names.forces[f], c);
  for (int u = 0; u < r->nimu_; ++u)
    for (const char* c : {"_gx", "_gy", "_gz", "_ax", "_ay", "_az", "_qw", "_qx", "_qy", "_qz"})
      column(names.imus[u], c);
  h += ",status,rejected,guard_holding\n";
  const uint64_t longest_row = r->width_ * (kFormatG9Max + 1);
  if (max_bytes > 0 && max_bytes < h.size() + longest_row) {
    *error = "the log's size bound of " + std::to_string(max_bytes) + " bytes cannot hold its " +
             std::to_string(h.size()) + "-byte header and one row (up to " +
             std::to_string(longest_row) + " bytes): give at least " +
             std::to_string(h.size() + longest_row) + " bytes";
    return nullptr;
  }

  r->fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (r->fd_ < 0) {
    *error = "cannot write the log '" + path + "': " + std::strerror(errno);
    return nullptr;
  }
  // the header now, checked: a file that takes no data is refused before the run
  size_t done = 0;
  if (const int err = WriteAll(r->fd_, h.data(), h.size(), &done); err != 0) {
    *error = "cannot write the log '" + path + "': " + std::strerror(err);
    return nullptr;  // the destructor closes the file
  }
  r->bytes_on_disk_.store(h.size());
  r->batch_.reserve(kBatchBytes + longest_row);
  const size_t batch_rows = kBatchBytes / (2 * r->width_) + 2;  // rows of 2 bytes a number at least
  r->ends_.reserve(batch_rows);
  r->times_.reserve(batch_rows);
  r->batch_cycles_.reserve(batch_rows);
  r->writer_ = std::thread([p = r.get()] { p->WriterLoop(); });
  return r;
}

Recorder::~Recorder() { Close(); }

bool Recorder::Push(const shm::SensorBlock& s, const shm::JointCommand* refs,
                    uint32_t guard_holding, double time) {
  const uint64_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) >= capacity_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  cycles_[head % capacity_] = s.cycle;
  double* row = &ring_[(head % capacity_) * width_];
  size_t k = 0;
  row[k++] = std::isnan(time) ? s.time : time;
  if (base_) {
    for (int i = 0; i < 3; ++i) row[k++] = s.sim_truth.p_WB[i];
    for (int i = 0; i < 4; ++i) row[k++] = s.sim_truth.quat_WB[i];
    for (int i = 0; i < 3; ++i) row[k++] = s.sim_truth.v_WB[i];
  }
  for (int i = 0; i < njoint_; ++i) row[k++] = s.q[i];
  for (int i = 0; i < njoint_; ++i) row[k++] = refs[i].q_ref;
  for (int i = 0; i < njoint_; ++i) row[k++] = s.tau[i];
  for (int i = 0; i < ndq_; ++i) row[k++] = s.dq[i];
  for (int i = 0; i < ndqref_; ++i) row[k++] = refs[i].dq_ref;
  for (int i = 0; i < npassive_; ++i) row[k++] = s.passive_q[i];
  for (int i = 0; i < npassive_; ++i) row[k++] = s.passive_dq[i];
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
  row[k++] = guard_holding;
  head_.store(head + 1, std::memory_order_release);
  return true;
}

void Recorder::AppendRow(const double* row) {
  // printf's "%.9g" (format_g9.h): the writer thread shares the CPUs with a lock-step run
  char buf[kFormatG9Max + 1];
  for (size_t i = 0; i < width_; ++i) {
    char* p = buf;
    if (i) *p++ = ',';
    p = FormatG9(p, row[i]);
    batch_.append(buf, static_cast<size_t>(p - buf));
  }
  batch_ += '\n';
}

void Recorder::Fail(int err, const char* what) {
  if (failed_.load()) return;
  error_ = std::string(what) + " failed after " + std::to_string(rows_on_disk_.load()) +
           " rows (" + Bytes(bytes_on_disk_.load()) + "): " + std::strerror(err);
  failed_.store(true, std::memory_order_release);
}

// writes the batch; on a failure keeps the whole rows written, cuts the file back to them and
// counts the rest as lost
void Recorder::WriteBatch() {
  if (batch_.empty()) return;
  size_t done = 0;
  const int err = WriteAll(fd_, batch_.data(), batch_.size(), &done);
  size_t whole = 0;  // rows written whole
  while (whole < ends_.size() && ends_[whole] <= done) ++whole;
  rows_on_disk_.fetch_add(whole);
  bytes_on_disk_.fetch_add(whole ? ends_[whole - 1] : 0);
  if (err != 0) {
    failure_time_ = times_[whole];
    failure_cycle_ = batch_cycles_[whole];
    lost_.fetch_add(ends_.size() - whole);
    bool cut = true;
    if (done > (whole ? ends_[whole - 1] : 0)) {
      // a row cut in the middle: the file ends with the last whole row
      const off_t keep = static_cast<off_t>(bytes_on_disk_.load());
      cut = ::ftruncate(fd_, keep) == 0 && ::lseek(fd_, keep, SEEK_SET) == keep;
    }
    Fail(err, cut ? "write" : "write (a half row is left at the end: cutting it off failed too)");
  }
  batch_.clear();
  ends_.clear();
  times_.clear();
  batch_cycles_.clear();
}

void Recorder::Flush() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (fd_ < 0) return;
  uint64_t tail = tail_.load(std::memory_order_relaxed);
  const uint64_t head = head_.load(std::memory_order_acquire);
  for (; tail < head; ++tail) {
    const double* row = &ring_[(tail % capacity_) * width_];
    const uint64_t cycle = cycles_[tail % capacity_];
    if (failed_.load()) {
      lost_.fetch_add(1);
    } else if (limit_reached_.load()) {
      over_limit_.fetch_add(1);
    } else {
      const size_t before = batch_.size();
      AppendRow(row);
      if (max_bytes_ > 0 && bytes_on_disk_.load() + batch_.size() > max_bytes_) {
        batch_.resize(before);  // this row would pass the bound: the log stops before it
        limit_time_ = row[0];
        limit_cycle_ = cycle;
        limit_reached_.store(true, std::memory_order_release);
        over_limit_.fetch_add(1);
      } else {
        ends_.push_back(batch_.size());
        times_.push_back(row[0]);
        batch_cycles_.push_back(cycle);
      }
    }
    tail_.store(tail + 1, std::memory_order_release);  // the slot is copied: free it
    if (batch_.size() >= kBatchBytes) WriteBatch();
  }
  WriteBatch();
}

bool Recorder::Close() {
  if (closed_) return !failed();
  closed_ = true;
  stop_.store(true);
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
  Flush();
  std::lock_guard<std::mutex> lock(mutex_);
  if (fd_ >= 0) {
    // the rows written are in the kernel: on the disk only once synced (a network or a full
    // file system may refuse them only now); special files cannot be synced (EINVAL)
    if (::fdatasync(fd_) != 0 && errno != EINVAL && errno != EROFS) Fail(errno, "sync to the disk");
    if (::close(fd_) != 0 && errno != EINTR) Fail(errno, "close");
    fd_ = -1;
  }
  return !failed();
}

std::string Recorder::error() const {
  return failed() ? error_ : std::string();
}

std::string Recorder::Describe() const {
  std::string d = "data log " + path_ + ": " + std::to_string(rows_on_disk()) + " rows on disk (" +
                  Bytes(bytes_on_disk()) + ")";
  char b[96];
  if (failed()) {
    std::snprintf(b, sizeof(b), "; INCOMPLETE: from t=%.4f s (cycle %lu) ", failure_time_,
                  static_cast<unsigned long>(failure_cycle_));
    d += b + error_ + "; " + std::to_string(lost()) + " rows not written";
  }
  if (limit_reached()) {
    std::snprintf(b, sizeof(b), "; its size bound (%s) reached at t=%.4f s (cycle %lu): ",
                  Bytes(max_bytes_).c_str(), limit_time_, static_cast<unsigned long>(limit_cycle_));
    d += b + std::to_string(over_limit()) + " later rows not written";
  }
  if (dropped() > 0)
    d += "; " + std::to_string(dropped()) + " rows dropped (the writer fell behind; try a larger "
         "--log-every)";
  return d;
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

}  // namespace ohrp::datalog
