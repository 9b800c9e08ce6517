// The posture controller.
#include "controllers/posture.h"

#include <cmath>
#include <cstdio>

#include "cli/data_dir.h"
#include "controllers/ramp.h"

namespace ohrp::controllers {

std::string DefaultPoseFile() { return cli::DataPath("controllers/poses/hrp1s_halfsit.yaml"); }

ConfigStatus CheckWithinLimits(const shm::SegmentHeader& header, const double* q,
                               const std::string& what, const std::vector<bool>* only) {
  for (int j = 0; j < header.njoint; ++j) {
    if (only && (j >= static_cast<int>(only->size()) || !(*only)[j])) continue;
    if (HasLimits(header, j) && (q[j] < header.q_min[j] || q[j] > header.q_max[j])) {
      char buf[256];
      std::snprintf(buf, sizeof buf, ": joint %d (%.*s) = %.6g is outside its limits [%.6g, %.6g]",
                    j, shm::kNameLen, header.joint_names[j], q[j], header.q_min[j],
                    header.q_max[j]);
      return ConfigStatus::Fail(ConfigError::kLimits, what + buf);
    }
  }
  return ConfigStatus::Ok();
}

namespace {

ConfigStatus CheckOptions(const PostureOptions& o) {
  if (!(std::isfinite(o.ramp) && o.ramp >= 0.0)) {
    return ConfigStatus::Fail(ConfigError::kOption, "--ramp must be a finite time >= 0 s");
  }
  if (!(std::isfinite(o.kp_scale) && o.kp_scale >= 0.0 && std::isfinite(o.kd_scale) &&
        o.kd_scale >= 0.0)) {
    return ConfigStatus::Fail(ConfigError::kOption, "--kp-scale/--kd-scale must be finite and >= 0");
  }
  return ConfigStatus::Ok();
}

}  // namespace

std::unique_ptr<PostureController> PostureController::Create(const PostureOptions& options,
                                                             ConfigStatus* status) {
  *status = CheckOptions(options);
  if (!status->ok()) return nullptr;
  PostureOptions o = options;
  if (o.pose_file.empty()) o.pose_file = DefaultPoseFile();
  Pose pose;
  *status = LoadPoseFile(o.pose_file, &pose);
  if (!status->ok()) return nullptr;
  return std::make_unique<PostureController>(o, std::move(pose));
}

std::unique_ptr<PostureController> PostureController::Create(const PostureOptions& options,
                                                             Pose pose, ConfigStatus* status) {
  *status = CheckOptions(options);
  if (!status->ok()) return nullptr;
  return std::make_unique<PostureController>(options, std::move(pose));
}

PostureController::PostureController(const PostureOptions& options, Pose pose)
    : options_(options), pose_(std::move(pose)) {}

ConfigStatus PostureController::on_configure(const shm::SegmentHeader& header) {
  if (ConfigStatus s = CheckOptions(options_); !s.ok()) return s;
  if (ConfigStatus s = ResolvePose(pose_, joint_names(), &target_, &named_); !s.ok()) return s;
  return CheckWithinLimits(header, target_.data(), pose_.source, &named_);
}

void PostureController::on_activate(const shm::SensorBlock& sensors) noexcept {
  for (int j = 0; j < njoint(); ++j) start_[j] = std::isfinite(sensors.q[j]) ? sensors.q[j] : target_[j];
  // the joints the pose leaves out hold where they are
  for (int j = 0; j < njoint(); ++j) {
    if (!named_[j]) target_[j] = start_[j];
  }
  start_time_ = sensors.time;
}

void PostureController::on_update(const shm::SensorBlock& sensors,
                                  shm::CommandBlock* commands) noexcept {
  const int n = njoint();
  SampleRamp(start_.data(), target_.data(), n, sensors.time - start_time_, options_.ramp,
             q_ref_.data(), dq_ref_.data());
  const shm::SegmentHeader& h = header();
  for (int j = 0; j < n; ++j) {
    shm::JointCommand& c = commands->joint[j];
    c.mode = shm::JointMode::kPosition;
    c.q_ref = q_ref_[j];
    c.dq_ref = dq_ref_[j];
    c.tau_ff = 0.0;
    c.kp = h.default_kp[j] * options_.kp_scale;
    c.kd = h.default_kd[j] * options_.kd_scale;
  }
}

}  // namespace ohrp::controllers
