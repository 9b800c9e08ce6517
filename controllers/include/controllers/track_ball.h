// TrackBall: a vision example. Stands the robot as posture does (ramps to the pose, holds it)
// and turns one yaw joint (HRP-1S: CHEST) so that a red ball stays in the middle of one
// camera's image (HRP-1S: LeftCamera). Runs on any producer that publishes the camera's images
// (sim_host renders them; hw_driver's replay plugin replays recorded ones).
//
// Vision, per new frame (on_image): the pixels whose red channel is at least `min_red` and
// more than `red_ratio` times both green and blue are the ball; their centroid (cx, cy) [pixel,
// x right, y down, pixel centres at +0.5] gives the bearing of the ball to the right of the
// optical axis, b = atan((cx - W/2) / f) with the pinhole focal length f = (H/2) / tan(fovy/2)
// from the header's camera. Fewer than `min_pixels` red pixels: no ball in this frame.
//
// Control, per cycle after the ramp: a PI law on the last bearing seen,
//   dq_ref = -(kp b + ki integral of b dt), clamped to +-max_rate, q_ref += dq_ref dt
// (a ball to the right, b > 0, turns the joint to negative yaw, to the right), q_ref within
// the joint's limits (the integral stops growing at a limit). Without a ball in sight the
// joint holds its reference. Every other joint holds the pose.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "controllers/posture.h"

namespace ohrp::controllers {

struct TrackBallOptions {
  PostureOptions posture;          // the pose held by the other joints, its ramp, gains
  std::string camera = "LeftCamera";
  std::string joint = "CHEST";     // a yaw joint (axis up) that carries the camera
  double kp = 3.0;                 // [1/s] joint rate per radian of bearing
  double ki = 0.0;                 // [1/s^2]
  double max_rate = 0.6;           // [rad/s]
  int min_red = 80;                // [0, 255]
  double red_ratio = 1.8;          // red > ratio x green and > ratio x blue
  int min_pixels = 12;             // fewer red pixels: no ball
};

// What the vision saw last (for the report and tests).
struct BallSighting {
  uint64_t frame = 0;      // the camera's frame counter (0: none yet)
  double time = 0.0;       // its capture time [s]
  bool seen = false;       // the ball was in that frame
  int pixels = 0;          // red pixels
  double cx = 0, cy = 0;   // centroid [pixel], x right, y down (image centre: W/2, H/2)
  double bearing = 0.0;    // [rad], ball right of the optical axis > 0
};

// The red-pixel centroid of an RGB8 image (top row first) as described above; fills
// `*out` (frame and time are the caller's).
void FindBall(const uint8_t* rgb, int width, int height, double fovy_deg, const TrackBallOptions& o,
              BallSighting* out);

class TrackBallController : public PostureController {
 public:
  // Checks the options and loads the pose file; null with `*status` set on failure.
  static std::unique_ptr<TrackBallController> Create(const TrackBallOptions& options,
                                                     ConfigStatus* status);
  TrackBallController(const TrackBallOptions& options, Pose pose);

  uint32_t cameras() const override { return camera_ >= 0 ? 1u << camera_ : 0u; }
  void on_image(int camera, const shm::ImageSlot& image) noexcept override;
  void report(std::ostream& out) const override;
  const BallSighting& last() const { return last_; }

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void on_activate(const shm::SensorBlock& sensors) noexcept override;
  void on_update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept override;

 private:
  TrackBallOptions o_;
  int camera_ = -1;           // header camera index
  int joint_ = -1;            // joint id of the yaw joint
  double fovy_ = 45.0;        // [deg]
  BallSighting last_;
  uint64_t frames_ = 0, frames_seen_ = 0;
  double q_ref_ = 0.0;        // the yaw joint's reference [rad]
  double integral_ = 0.0;     // [rad s]
  double start_time_ = 0.0, last_time_ = 0.0;
  bool tracking_ = false;
};

}  // namespace ohrp::controllers
