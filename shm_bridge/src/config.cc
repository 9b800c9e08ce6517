// ValidateConfig: a producer's configuration checked against the layout before any segment is
// created, with messages that name the offending field.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "shm_bridge/checks.h"

namespace ohrp::shm {
namespace {

constexpr std::size_t kMaxSegmentName = 200;  // keeps "/dev/shm/ohrp_<name>" under NAME_MAX

Status Invalid(const std::string& what) {
  return {Error::kInvalidConfig, "invalid producer config: " + what};
}

std::string Indexed(const char* field, std::size_t i) {
  return std::string(field) + "[" + std::to_string(i) + "]";
}

// names must be non-empty, fit kNameLen with their NUL and be unique within their list
Status CheckNames(const char* field, const std::vector<std::string>& names, int capacity) {
  if (names.size() > static_cast<std::size_t>(capacity)) {
    return Invalid(std::string(field) + " has " + std::to_string(names.size()) +
                   " entries, the layout holds at most " + std::to_string(capacity));
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) return Invalid(Indexed(field, i) + " is empty");
    if (names[i].size() >= static_cast<std::size_t>(kNameLen)) {
      return Invalid(Indexed(field, i) + " '" + names[i] + "' is " +
                     std::to_string(names[i].size()) + " bytes, names must be shorter than " +
                     std::to_string(kNameLen));
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (names[j] == names[i]) {
        return Invalid(Indexed(field, i) + " '" + names[i] + "' repeats " + Indexed(field, j));
      }
    }
  }
  return Status::Ok();
}

// per-joint vectors: empty (defaults) or one finite entry per joint
Status CheckPerJoint(const char* field, const std::vector<double>& v, std::size_t njoint) {
  if (!v.empty() && v.size() != njoint) {
    return Invalid(std::string(field) + " has " + std::to_string(v.size()) +
                   " entries, expected 0 or njoint = " + std::to_string(njoint));
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isnan(v[i])) return Invalid(Indexed(field, i) + " is NaN");
  }
  return Status::Ok();
}

}  // namespace

Status ValidateConfig(const ProducerConfig& config) {
  // segment name: becomes a file name under /dev/shm
  const std::string& segment = config.segment_name;
  if (segment.empty()) return Invalid("segment_name is empty");
  if (segment.size() > kMaxSegmentName) {
    return Invalid("segment_name is " + std::to_string(segment.size()) + " bytes, at most " +
                   std::to_string(kMaxSegmentName));
  }
  for (char c : segment) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) {
      return Invalid("segment_name '" + segment +
                     "' may only contain letters, digits, '_', '-' and '.'");
    }
  }
  switch (config.kind) {
    case ProducerKind::kUnknown:
    case ProducerKind::kSimulation:
    case ProducerKind::kHardware:
    case ProducerKind::kReplay:
      break;
    default:
      return Invalid("kind " + std::to_string(static_cast<uint32_t>(config.kind)) +
                     " is not a ProducerKind");
  }
  if (config.robot_name.size() >= static_cast<std::size_t>(kNameLen)) {
    return Invalid("robot_name '" + config.robot_name + "' is " +
                   std::to_string(config.robot_name.size()) +
                   " bytes, names must be shorter than " + std::to_string(kNameLen));
  }

  // names and counts
  Status s = CheckNames("joint_names", config.joint_names, kMaxJoints);
  if (!s.ok()) return s;
  s = CheckNames("force_names", config.force_names, kMaxForceSensors);
  if (!s.ok()) return s;
  s = CheckNames("imu_names", config.imu_names, kMaxImus);
  if (!s.ok()) return s;
  s = CheckNames("passive_names", config.passive_names, kMaxPassiveJoints);
  if (!s.ok()) return s;
  if (config.cameras.size() > static_cast<std::size_t>(kMaxCameras)) {
    return Invalid("cameras has " + std::to_string(config.cameras.size()) +
                   " entries, the layout holds at most " + std::to_string(kMaxCameras));
  }
  for (std::size_t i = 0; i < config.cameras.size(); ++i) {
    const CameraInfo& cam = config.cameras[i];
    const std::size_t len = strnlen(cam.name, kNameLen);
    if (len == 0) return Invalid(Indexed("cameras", i) + ".name is empty");
    if (len >= static_cast<std::size_t>(kNameLen)) {
      return Invalid(Indexed("cameras", i) + ".name is not NUL-terminated within " +
                     std::to_string(kNameLen) + " bytes");
    }
    if (cam.width <= 0 || cam.height <= 0) {
      return Invalid(Indexed("cameras", i) + " '" + cam.name + "' has size " +
                     std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                     ", both must be > 0");
    }
    if (cam.width > kMaxImageWidth || cam.height > kMaxImageHeight) {
      return Invalid(Indexed("cameras", i) + " '" + cam.name + "' has size " +
                     std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                     ", larger than the segment's image slots (" + std::to_string(kMaxImageWidth) +
                     "x" + std::to_string(kMaxImageHeight) + "): choose a smaller camera size");
    }
    if (!(cam.fovy > 0.0 && cam.fovy < 180.0)) {
      return Invalid(Indexed("cameras", i) + " '" + cam.name + "' fovy must be in (0, 180) deg");
    }
  }

  // per-joint limits and gains
  const std::size_t njoint = config.joint_names.size();
  const struct {
    const char* field;
    const std::vector<double>& v;
  } per_joint[] = {{"q_min", config.q_min},
                   {"q_max", config.q_max},
                   {"tau_max", config.tau_max},
                   {"default_kp", config.default_kp},
                   {"default_kd", config.default_kd}};
  for (const auto& p : per_joint) {
    s = CheckPerJoint(p.field, p.v, njoint);
    if (!s.ok()) return s;
  }
  if (!config.q_min.empty() && !config.q_max.empty()) {
    for (std::size_t i = 0; i < njoint; ++i) {
      if (config.q_min[i] > config.q_max[i]) {
        return Invalid(Indexed("q_min", i) + " > " + Indexed("q_max", i) + " (joint '" +
                       config.joint_names[i] + "')");
      }
    }
  }
  for (std::size_t i = 0; i < config.tau_max.size(); ++i) {
    if (config.tau_max[i] < 0.0) return Invalid(Indexed("tau_max", i) + " is negative");
  }
  // suggested gains: a controller refuses a header with negative or infinite ones
  for (const auto* gains : {&config.default_kp, &config.default_kd}) {
    const char* field = gains == &config.default_kp ? "default_kp" : "default_kd";
    for (std::size_t i = 0; i < gains->size(); ++i) {
      if (!((*gains)[i] >= 0.0) || !std::isfinite((*gains)[i])) {
        return Invalid(Indexed(field, i) + " must be finite and >= 0, got " +
                       std::to_string((*gains)[i]));
      }
    }
  }

  // the robot model's identity: per-joint entries as above, masses not negative
  s = CheckPerJoint("link_mass", config.link_mass, njoint);
  if (!s.ok()) return s;
  for (std::size_t i = 0; i < config.link_mass.size(); ++i) {
    if (config.link_mass[i] < 0.0) return Invalid(Indexed("link_mass", i) + " is negative");
  }
  if (!config.joint_axis.empty() && config.joint_axis.size() != njoint) {
    return Invalid("joint_axis has " + std::to_string(config.joint_axis.size()) +
                   " entries, expected 0 or njoint = " + std::to_string(njoint));
  }
  for (std::size_t i = 0; i < config.joint_axis.size(); ++i) {
    for (double v : config.joint_axis[i]) {
      if (!std::isfinite(v)) return Invalid(Indexed("joint_axis", i) + " is not finite");
    }
  }
  if (!(config.total_mass >= 0.0) || !std::isfinite(config.total_mass)) {
    return Invalid("total_mass must be >= 0 [kg], got " + std::to_string(config.total_mass));
  }
  if (config.nbody < 0) {
    return Invalid("nbody must be >= 0, got " + std::to_string(config.nbody));
  }

  // periods [s]
  if (!(config.control_period > 0.0) || !std::isfinite(config.control_period)) {
    return Invalid("control_period must be > 0 [s], got " + std::to_string(config.control_period));
  }
  if (!(config.physics_period >= 0.0) || !std::isfinite(config.physics_period)) {
    return Invalid("physics_period must be >= 0 [s] (0 for hardware), got " +
                   std::to_string(config.physics_period));
  }
  if (config.physics_period > config.control_period) {
    return Invalid("physics_period " + std::to_string(config.physics_period) +
                   " s is longer than control_period " + std::to_string(config.control_period) +
                   " s: a control cycle is a whole number of physics steps");
  }
  if (!(config.read_timeout_hint > 0.0) || !std::isfinite(config.read_timeout_hint)) {
    return Invalid("read_timeout_hint must be > 0 [s], got " +
                   std::to_string(config.read_timeout_hint));
  }
  return Status::Ok();
}

}  // namespace ohrp::shm
