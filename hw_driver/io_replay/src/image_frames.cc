// Recorded camera images for the replay plugin (image_frames.h).
#include "image_frames.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace ohrp::hw::replay {
namespace {

// the next header token of a PPM (whitespace and # comments skipped)
bool Token(std::istream& in, std::string* out) {
  out->clear();
  for (int c; (c = in.get()) != EOF;) {
    if (c == '#') {
      while ((c = in.get()) != EOF && c != '\n') {
      }
      continue;
    }
    if (std::isspace(c)) {
      if (!out->empty()) return true;
      continue;
    }
    out->push_back(static_cast<char>(c));
  }
  return !out->empty();
}

bool Integer(const std::string& s, long lo, long hi, long* out) {
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || v < lo || v > hi) return false;
  *out = v;
  return true;
}

}  // namespace

bool ReadPpm(const std::string& path, ImageFrame* frame, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = "cannot open '" + path + "'";
    return false;
  }
  std::string magic, w, h, maxval;
  long width = 0, height = 0, max = 0;
  if (!Token(in, &magic) || magic != "P6") {
    *error = "'" + path + "' is not a binary PPM (it must start with P6)";
    return false;
  }
  if (!Token(in, &w) || !Token(in, &h) || !Token(in, &maxval) ||
      !Integer(w, 1, shm::kMaxImageWidth, &width) || !Integer(h, 1, shm::kMaxImageHeight, &height) ||
      !Integer(maxval, 255, 255, &max)) {
    *error = "'" + path + "': a PPM header 'P6 WIDTH HEIGHT 255' with a size within " +
             std::to_string(shm::kMaxImageWidth) + "x" + std::to_string(shm::kMaxImageHeight) +
             " is expected (got '" + w + " " + h + " " + maxval + "')";
    return false;
  }
  frame->width = static_cast<int>(width);
  frame->height = static_cast<int>(height);
  frame->rgb.resize(static_cast<size_t>(3 * width * height));
  // (Token consumed the one whitespace byte after maxval)
  in.read(reinterpret_cast<char*>(frame->rgb.data()), static_cast<std::streamsize>(frame->rgb.size()));
  if (in.gcount() != static_cast<std::streamsize>(frame->rgb.size())) {
    *error = "'" + path + "' holds " + std::to_string(in.gcount()) + " bytes of pixels, " +
             std::to_string(frame->rgb.size()) + " expected for " + w + "x" + h + " RGB";
    return false;
  }
  return true;
}

bool ImageFrames::Load(const std::string& dir, const std::vector<shm::CameraInfo>& cameras,
                       std::string* error) {
  frames_.assign(cameras.size(), {});
  const std::string index = dir + "/index.csv";
  std::ifstream in(index);
  if (!in) {
    *error = "cannot open the image index '" + index +
             "' (images=DIR needs DIR/index.csv with the header time,camera,file)";
    return false;
  }
  std::string line;
  int n = 1;
  if (!std::getline(in, line) || line.rfind("time,camera,file", 0) != 0) {
    *error = index + ":1: the header must be 'time,camera,file'";
    return false;
  }
  while (std::getline(in, line)) {
    ++n;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    const std::string where = index + ":" + std::to_string(n) + ": ";
    std::stringstream ss(line);
    std::string time_text, camera, file;
    if (!std::getline(ss, time_text, ',') || !std::getline(ss, camera, ',') ||
        !std::getline(ss, file) || file.empty()) {
      *error = where + "a row is 'time,camera,file' (got '" + line + "')";
      return false;
    }
    char* end = nullptr;
    const double t = std::strtod(time_text.c_str(), &end);
    if (time_text.empty() || *end != '\0' || !std::isfinite(t)) {
      *error = where + "time '" + time_text + "' is not a number [s]";
      return false;
    }
    int c = -1;
    std::string names;
    for (size_t i = 0; i < cameras.size(); ++i) {
      const std::string name(cameras[i].name, strnlen(cameras[i].name, shm::kNameLen));
      names += (i ? ", " : "") + name;
      if (name == camera) c = static_cast<int>(i);
    }
    if (c < 0) {
      *error = where + "camera '" + camera + "' is not a camera of the robot (" +
               (names.empty() ? std::string("it has none") : names) + ")";
      return false;
    }
    if (!frames_[c].empty() && t < frames_[c].back().time) {
      *error = where + "time " + time_text + " goes back (camera " + camera + ")";
      return false;
    }
    ImageFrame frame;
    frame.time = t;
    if (!ReadPpm(dir + "/" + file, &frame, error)) {
      *error = where + *error;
      return false;
    }
    if (frame.width > cameras[c].width || frame.height > cameras[c].height) {
      *error = where + file + " is " + std::to_string(frame.width) + "x" +
               std::to_string(frame.height) + ", larger than camera " + camera + " (" +
               std::to_string(cameras[c].width) + "x" + std::to_string(cameras[c].height) + ")";
      return false;
    }
    frames_[c].push_back(std::move(frame));
  }
  current_.assign(cameras.size(), -1);
  handed_.assign(cameras.size(), -1);
  last_t_ = -1e300;
  published_ = 0;
  return true;
}

void ImageFrames::Play(double t, uint32_t wanted, double driver_time, ImageSink* sink) noexcept {
  if (t < last_t_) {  // the replay started over
    for (size_t c = 0; c < frames_.size(); ++c) current_[c] = handed_[c] = -1;
  }
  last_t_ = t;
  for (size_t c = 0; c < frames_.size(); ++c) {
    const std::vector<ImageFrame>& f = frames_[c];
    int& i = current_[c];
    while (i + 1 < static_cast<int>(f.size()) && f[i + 1].time <= t) ++i;
    if (i < 0 || i == handed_[c]) continue;
    if ((wanted & (1u << c)) == 0) {
      handed_[c] = i;  // passed while nobody asked: never handed out late
      continue;
    }
    handed_[c] = i;
    if (sink->Publish(static_cast<int>(c), driver_time - (t - f[i].time), f[i].width,
                      f[i].height, f[i].rgb.data(), nullptr)) {
      ++published_;
    }
  }
}

}  // namespace ohrp::hw::replay
