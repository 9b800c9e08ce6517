// sim_host --record-images (see image_recorder.h).
#include "image_recorder.h"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include "render/png.h"
#include "shm_bridge/clock.h"

namespace ohrp::sim {
namespace {

constexpr size_t kSlots = 8;  // frames in flight between the loop and the writer

bool MakeDir(const std::string& path, std::string* error) {
  if (mkdir(path.c_str(), 0755) == 0 || errno == EEXIST) return true;
  *error = "cannot create the folder '" + path + "': " + std::strerror(errno);
  return false;
}

}  // namespace

std::unique_ptr<ImageRecorder> ImageRecorder::Open(const std::string& dir,
                                                   const std::vector<std::string>& cameras,
                                                   int width, int height, bool depth,
                                                   std::string* error) {
  std::unique_ptr<ImageRecorder> r(new ImageRecorder());
  r->dir_ = dir;
  r->cameras_ = cameras;
  r->width_ = width;
  r->height_ = height;
  r->depth_ = depth;
  r->per_camera_.assign(cameras.size(), 0);
  if (!MakeDir(dir, error)) return nullptr;
  for (const std::string& c : cameras)
    if (!MakeDir(dir + "/" + c, error)) return nullptr;
  r->index_ = std::fopen((dir + "/images.csv").c_str(), "w");
  if (!r->index_ || std::fprintf(r->index_, "time,camera,rgb,depth\n") < 0) {
    *error = "cannot write '" + dir + "/images.csv'";
    return nullptr;
  }
  const size_t pixels = static_cast<size_t>(width) * height;
  r->slots_.resize(kSlots);
  for (Slot& s : r->slots_) {
    s.rgb.resize(3 * pixels);
    if (depth) s.depth_m.resize(pixels);
  }
  if (depth) r->depth_mm_.resize(pixels);
  r->thread_ = std::thread([p = r.get()] { p->Run(); });
  return r;
}

ImageRecorder::~ImageRecorder() {
  std::string ignored;
  Close(&ignored);
}

void ImageRecorder::Push(int camera, double time, const uint8_t* rgb, const float* depth) {
  std::unique_lock<std::mutex> lock(mutex_);
  Slot& s = slots_[next_push_];
  if (s.full) {
    const double start = MonotonicSeconds();
    freed_.wait(lock, [&] { return !s.full; });
    waited_ += MonotonicSeconds() - start;
  }
  // a slot that is not full is the loop's alone (the writer takes full slots only): filled
  // without the lock
  lock.unlock();
  s.camera = camera;
  s.time = time;
  const size_t pixels = static_cast<size_t>(width_) * height_;
  std::memcpy(s.rgb.data(), rgb, 3 * pixels);
  s.has_depth = depth_ && depth != nullptr;
  if (s.has_depth) std::memcpy(s.depth_m.data(), depth, pixels * sizeof(float));
  lock.lock();
  s.full = true;
  next_push_ = (next_push_ + 1) % slots_.size();
  filled_.notify_one();
}

void ImageRecorder::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    filled_.wait(lock, [&] { return slots_[next_write_].full || closing_; });
    Slot& s = slots_[next_write_];
    if (!s.full) return;  // closing, nothing left
    const uint64_t index = per_camera_[s.camera]++;
    lock.unlock();
    const bool ok = error_.empty() && Write(s, index);  // after a failure: drained, not written
    lock.lock();
    if (ok) ++written_;
    s.full = false;
    next_write_ = (next_write_ + 1) % slots_.size();
    freed_.notify_one();
  }
}

void ImageRecorder::DepthToMillimetres(const Slot& s) {
  for (size_t k = 0; k < depth_mm_.size(); ++k) {
    const double mm = s.has_depth ? std::round(1000.0 * static_cast<double>(s.depth_m[k])) : 0.0;
    depth_mm_[k] = std::isfinite(mm) && mm > 0 && mm <= 65535 ? static_cast<uint16_t>(mm) : 0;
  }
}

bool ImageRecorder::Write(const Slot& s, uint64_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06lu", static_cast<unsigned long>(index));
  const std::string base = cameras_[s.camera] + "/" + name;
  std::string error;
  if (depth_) DepthToMillimetres(s);
  if (!render::WritePngRgb(dir_ + "/" + base + ".png", s.rgb.data(), width_, height_, true, &error) ||
      (depth_ && !render::WritePngGrey16(dir_ + "/" + base + "_depth.png", depth_mm_.data(), width_,
                                         height_, true, &error))) {
    error_ = error;
    return false;
  }
  if (std::fprintf(index_, "%.6f,%s,%s.png,%s\n", s.time, cameras_[s.camera].c_str(), base.c_str(),
                   depth_ ? (base + "_depth.png").c_str() : "") < 0) {
    error_ = "cannot write '" + dir_ + "/images.csv'";
    return false;
  }
  return true;
}

bool ImageRecorder::Close(std::string* error) {
  if (thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closing_ = true;
    }
    filled_.notify_one();
    thread_.join();
  }
  if (index_) {
    const bool flushed = std::fflush(index_) == 0 && !std::ferror(index_);
    if ((std::fclose(index_) != 0 || !flushed) && error_.empty())
      error_ = "'" + dir_ + "/images.csv' was not written whole (disk full?)";
    index_ = nullptr;
  }
  *error = error_;
  return error_.empty();
}

}  // namespace ohrp::sim
