// The `replay` IO plugin: plays sim_host's CSV data log into the driver as if it came from the
// boards, at the driver's period, by time (linear interpolation between rows, or steps), and
// ignores the commands. At the end of the log it reports io_fault::kEndOfData (the driver then
// ends its run cleanly), or starts over with loop=1.
//
// Arguments (--io-arg KEY=VALUE): file=PATH (required), loop=0|1 (default 0),
// interp=linear|step (default linear), images=DIR (recorded camera images, image_frames.h:
// each frame is handed to the segment when the replay's time reaches its own, while some
// program asks for its camera).
#include <cmath>
#include <string>

#include "csv_log.h"
#include "image_frames.h"
#include "hw_driver/robot_io.h"

namespace ohrp::hw::replay {
namespace {

class ReplayIo final : public RobotIo {
 public:
  bool open(const IoConfig& config, std::string* error) override {
    std::string file, images;
    for (const std::string& arg : config.args) {
      const auto eq = arg.find('=');
      const std::string key = arg.substr(0, eq);
      const std::string value = eq == std::string::npos ? "" : arg.substr(eq + 1);
      if (key == "file") {
        file = value;
      } else if (key == "loop" && (value == "0" || value == "1")) {
        loop_ = value == "1";
      } else if (key == "interp" && (value == "linear" || value == "step")) {
        step_ = value == "step";
      } else if (key == "images" && !value.empty()) {
        images = value;
      } else {
        *error = "replay: unknown argument '" + arg +
                 "' (use file=PATH, loop=0|1, interp=linear|step, images=DIR)";
        return false;
      }
    }
    if (file.empty()) {
      *error = "replay: no log given (--io-arg file=PATH, a CSV data log of sim_host --log)";
      return false;
    }
    if (!(config.period > 0)) {
      *error = "replay: the driver's period must be positive";
      return false;
    }
    if (!log_.Load(file, config, error)) return false;
    has_images_ = !images.empty();
    if (has_images_ && !images_.Load(images, config.cameras, error)) {
      *error = "replay: " + *error;
      return false;
    }
    period_ = config.period;
    njoint_ = static_cast<int>(config.joint_names.size());
    reads_ = 0;
    cursor_ = 0;
    return true;
  }

  IoResult read(IoState* state) noexcept override {
    const double span = log_.last_time() - log_.first_time();
    double elapsed = static_cast<double>(reads_++) * period_;
    bool ended = false;
    if (elapsed > span + 1e-9) {
      if (loop_ && span > 0) {
        elapsed = std::fmod(elapsed, span);
      } else {
        ended = true;
        elapsed = span;
      }
    }
    const double t = log_.first_time() + elapsed;
    t_ = t;
    log_.Sample(t, step_, &cursor_, state);
    state->time_ns = static_cast<uint64_t>(std::llround(std::fmax(0.0, t) * 1e9));
    state->silent_boards = 0;
    for (int j = 0; j < njoint_; ++j) state->servo_on[j] = true;
    state->faults = ended ? io_fault::kEndOfData : 0u;
    return ended ? IoResult::kFault : IoResult::kOk;
  }

  IoResult write(const IoCommand&) noexcept override { return IoResult::kOk; }
  void images(uint32_t wanted, double time, ImageSink* sink) noexcept override {
    if (has_images_) images_.Play(t_, wanted, time, sink);
  }
  void close() noexcept override {}

 private:
  CsvLog log_;
  ImageFrames images_;
  bool has_images_ = false;
  double t_ = 0.0;  // the recording's time of the last read [s]
  double period_ = 0.001;
  int njoint_ = 0;
  bool loop_ = false;
  bool step_ = false;
  uint64_t reads_ = 0;
  int cursor_ = 0;
};

}  // namespace
}  // namespace ohrp::hw::replay

extern "C" ohrp::hw::RobotIo* ohrp_create_robot_io(uint32_t abi_version) {
  if (abi_version != ohrp::hw::kRobotIoAbiVersion) return nullptr;
  return new ohrp::hw::replay::ReplayIo();
}
