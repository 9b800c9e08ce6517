// The track_ball controller (controllers/track_ball.h).
#include "controllers/track_ball.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>

namespace ohrp::controllers {

void FindBall(const uint8_t* rgb, int width, int height, double fovy_deg, const TrackBallOptions& o,
              BallSighting* out) {
  double sx = 0, sy = 0;
  int n = 0;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = rgb + static_cast<std::size_t>(y) * width * 3;
    for (int x = 0; x < width; ++x) {
      const double r = row[3 * x], g = row[3 * x + 1], b = row[3 * x + 2];
      if (r >= o.min_red && r > o.red_ratio * g && r > o.red_ratio * b) {
        sx += x + 0.5;
        sy += y + 0.5;
        ++n;
      }
    }
  }
  out->pixels = n;
  out->seen = n >= o.min_pixels;
  if (!out->seen) return;
  out->cx = sx / n;
  out->cy = sy / n;
  const double f = 0.5 * height / std::tan(0.5 * fovy_deg * M_PI / 180.0);
  out->bearing = std::atan((out->cx - 0.5 * width) / f);
}

std::unique_ptr<TrackBallController> TrackBallController::Create(const TrackBallOptions& options,
                                                                  ConfigStatus* status) {
  const TrackBallOptions& o = options;
  if (!(std::isfinite(o.kp) && o.kp >= 0 && std::isfinite(o.ki) && o.ki >= 0 &&
        std::isfinite(o.max_rate) && o.max_rate > 0 && o.red_ratio >= 1 && o.min_red >= 0 &&
        o.min_red <= 255 && o.min_pixels >= 1)) {
    *status = ConfigStatus::Fail(ConfigError::kOption,
                                 "--kp, --ki >= 0, --max-rate > 0, --red-ratio >= 1, --min-red in "
                                 "[0, 255] and --min-pixels >= 1");
    return nullptr;
  }
  // the pose and its options are checked as posture checks them
  auto posture = PostureController::Create(o.posture, status);
  if (!posture) return nullptr;
  PostureOptions po = o.posture;
  if (po.pose_file.empty()) po.pose_file = DefaultPoseFile();
  Pose pose;
  *status = LoadPoseFile(po.pose_file, &pose);
  if (!status->ok()) return nullptr;
  TrackBallOptions with_file = o;
  with_file.posture = po;
  return std::make_unique<TrackBallController>(with_file, std::move(pose));
}

TrackBallController::TrackBallController(const TrackBallOptions& options, Pose pose)
    : PostureController(options.posture, std::move(pose)), o_(options) {}

ConfigStatus TrackBallController::on_configure(const shm::SegmentHeader& header) {
  if (ConfigStatus s = PostureController::on_configure(header); !s.ok()) return s;
  camera_ = -1;
  std::string cameras;
  for (int i = 0; i < header.ncamera; ++i) {
    const std::string name(header.cameras[i].name, strnlen(header.cameras[i].name, shm::kNameLen));
    cameras += (i ? ", " : "") + name;
    if (name == o_.camera) camera_ = i;
  }
  if (camera_ < 0) {
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              "--camera " + o_.camera + ": the producer's robot has no such camera (" +
                                  (cameras.empty() ? std::string("it has none") : "it has " + cameras) + ")");
  }
  fovy_ = header.cameras[camera_].fovy;
  const auto& names = joint_names();
  const auto it = std::find(names.begin(), names.end(), o_.joint);
  if (it == names.end()) {
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              "--joint " + o_.joint + ": the producer's robot has no such joint");
  }
  joint_ = static_cast<int>(it - names.begin());
  return ConfigStatus::Ok();
}

void TrackBallController::on_activate(const shm::SensorBlock& sensors) noexcept {
  PostureController::on_activate(sensors);
  start_time_ = last_time_ = sensors.time;
  q_ref_ = std::isfinite(sensors.q[joint_]) ? sensors.q[joint_] : 0.0;
  integral_ = 0.0;
  tracking_ = false;
}

void TrackBallController::on_image(int camera, const shm::ImageSlot& image) noexcept {
  if (camera != camera_) return;
  ++frames_;
  BallSighting s;
  s.frame = image.frame;
  s.time = image.time;
  FindBall(image.rgb, image.width, image.height, fovy_, o_, &s);
  if (s.seen) ++frames_seen_;
  last_ = s;
}

void TrackBallController::on_update(const shm::SensorBlock& sensors,
                                    shm::CommandBlock* commands) noexcept {
  PostureController::on_update(sensors, commands);  // the pose (and its ramp) for every joint
  const double dt = std::clamp(sensors.time - last_time_, 0.0, 0.1);
  last_time_ = sensors.time;
  if (!tracking_) {
    // the yaw joint starts moving once the pose's ramp is over
    tracking_ = sensors.time - start_time_ >= o_.posture.ramp;
    q_ref_ = commands->joint[joint_].q_ref;
    if (!tracking_) return;
  }
  double rate = 0.0;
  if (last_.seen) {
    integral_ += last_.bearing * dt;
    rate = std::clamp(-(o_.kp * last_.bearing + o_.ki * integral_), -o_.max_rate, o_.max_rate);
  }
  const shm::SegmentHeader& h = header();
  double q = q_ref_ + rate * dt;
  if (HasLimits(h, joint_) && (q < h.q_min[joint_] || q > h.q_max[joint_])) {
    q = std::clamp(q, h.q_min[joint_], h.q_max[joint_]);
    integral_ -= last_.bearing * dt;  // no wind-up against a limit
    rate = 0.0;
  }
  q_ref_ = q;
  commands->joint[joint_].q_ref = q_ref_;
  commands->joint[joint_].dq_ref = rate;
}

void TrackBallController::report(std::ostream& out) const {
  out << "track_ball: " << frames_ << " frames of camera " << o_.camera << ", the ball in "
      << frames_seen_;
  if (last_.frame > 0) {
    out << "; last frame " << last_.frame << " at t=" << last_.time << " s: ";
    if (last_.seen) {
      out << last_.pixels << " red pixels, centroid (" << last_.cx << ", " << last_.cy
          << ") px, bearing " << last_.bearing * 180.0 / M_PI << " deg";
    } else {
      out << "no ball (" << last_.pixels << " red pixels)";
    }
  }
  out << "; " << o_.joint << " reference " << q_ref_ << " rad\n";
}

}  // namespace ohrp::controllers
