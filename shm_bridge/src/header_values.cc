// CheckHeaderValues: the contents of a header of the right layout checked before a controller
// trusts them (counts within their capacities, physical limits, gains and periods), with a
// message that names the field, its value and what a producer should have written.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "shm_bridge/checks.h"

namespace ohrp::shm {
namespace {

// a value as text: enough digits to tell 1e300 and -0.5 apart, "nan" and "inf" readable
std::string Text(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", v);
  return text;
}

std::string Indexed(const char* field, int i) {
  return std::string(field) + "[" + std::to_string(i) + "]";
}

// the joint's name for messages, read without trusting its terminator
std::string JointName(const SegmentHeader& h, int j) {
  return std::string(h.joint_names[j], strnlen(h.joint_names[j], kNameLen));
}

// a count must lie in [0, capacity]
std::string CountProblem(const char* field, int32_t n, int capacity) {
  if (n >= 0 && n <= capacity) return "";
  return std::string(field) + " = " + std::to_string(n) + " is outside [0, " +
         std::to_string(capacity) + "]";
}

// the first joint whose limits, torque limit, gains or identity are not physical
std::string JointProblem(const SegmentHeader& h) {
  for (int j = 0; j < h.njoint; ++j) {
    const std::string joint = " (joint '" + JointName(h, j) + "')";
    // limits may be infinite (an unlimited joint) but ordered and not NaN
    if (std::isnan(h.q_min[j]) || std::isnan(h.q_max[j]) || h.q_min[j] > h.q_max[j]) {
      return Indexed("q_min", j) + " = " + Text(h.q_min[j]) + " and " + Indexed("q_max", j) +
             " = " + Text(h.q_max[j]) + joint + " are not a range q_min <= q_max [rad or m]";
    }
    if (!(h.tau_max[j] >= 0.0)) {
      return Indexed("tau_max", j) + " = " + Text(h.tau_max[j]) + joint +
             " must be >= 0 [N m or N]";
    }
    const struct {
      const char* field;
      double value;
      const char* unit;
    } finite_non_negative[] = {{"default_kp", h.default_kp[j], "[N m/rad]"},
                               {"default_kd", h.default_kd[j], "[N m s/rad]"},
                               {"link_mass", h.link_mass[j], "[kg]"}};
    for (const auto& f : finite_non_negative) {
      if (!(f.value >= 0.0) || !std::isfinite(f.value)) {
        return Indexed(f.field, j) + " = " + Text(f.value) + joint + " must be finite and >= 0 " +
               f.unit;
      }
    }
    for (double a : h.joint_axis[j]) {
      if (!std::isfinite(a)) return Indexed("joint_axis", j) + joint + " is not finite";
    }
  }
  return "";
}

// the cameras declared must have a size and a field of view
std::string CameraProblem(const SegmentHeader& h) {
  for (int i = 0; i < h.ncamera; ++i) {
    const CameraInfo& c = h.cameras[i];
    if (c.width <= 0 || c.height <= 0 || c.width > kMaxImageWidth ||
        c.height > kMaxImageHeight || !(c.fovy > 0.0 && c.fovy < 180.0)) {
      return Indexed("cameras", i) + " has size " + std::to_string(c.width) + "x" +
             std::to_string(c.height) + " and fovy " + Text(c.fovy) +
             ": sizes must be in [1, " + std::to_string(kMaxImageWidth) + "] x [1, " +
             std::to_string(kMaxImageHeight) + "] and fovy in (0, 180) [deg]";
    }
  }
  return "";
}

// periods [s]: a positive control period, an integration step within it (0 for hardware)
std::string PeriodProblem(const SegmentHeader& h) {
  if (!(h.control_period > 0.0) || !std::isfinite(h.control_period)) {
    return "control_period = " + Text(h.control_period) + " must be finite and > 0 [s]";
  }
  if (!(h.physics_period >= 0.0) || !(h.physics_period <= h.control_period)) {
    return "physics_period = " + Text(h.physics_period) +
           " must be in [0, control_period = " + Text(h.control_period) + "] [s] (0 for hardware)";
  }
  if (!(h.read_timeout_hint > 0.0) || !std::isfinite(h.read_timeout_hint)) {
    return "read_timeout_hint = " + Text(h.read_timeout_hint) + " must be finite and > 0 [s]";
  }
  return "";
}

// the robot model's identity as a whole
std::string IdentityProblem(const SegmentHeader& h) {
  if (h.nbody < 0) return "nbody = " + std::to_string(h.nbody) + " is negative";
  if (!(h.total_mass >= 0.0) || !std::isfinite(h.total_mass)) {
    return "total_mass = " + Text(h.total_mass) + " must be finite and >= 0 [kg]";
  }
  return "";
}

}  // namespace

Status CheckHeaderValues(const SegmentHeader& header, const std::string& segment_name) {
  // counts first: every per-joint check below indexes with them
  std::string problem = CountProblem("njoint", header.njoint, kMaxJoints);
  if (problem.empty()) problem = CountProblem("nforce", header.nforce, kMaxForceSensors);
  if (problem.empty()) problem = CountProblem("nimu", header.nimu, kMaxImus);
  if (problem.empty()) problem = CountProblem("ncamera", header.ncamera, kMaxCameras);
  if (problem.empty()) problem = CountProblem("npassive", header.npassive, kMaxPassiveJoints);
  if (problem.empty()) problem = JointProblem(header);
  if (problem.empty()) problem = CameraProblem(header);
  if (problem.empty()) problem = PeriodProblem(header);
  if (problem.empty()) problem = IdentityProblem(header);
  if (problem.empty()) return Status::Ok();
  return {Error::kInvalidHeader,
          "segment '" + segment_name + "' (/dev/shm/" + SegmentObjectName(segment_name) +
              "): its header " + problem +
              "; the producer (pid " + std::to_string(header.producer_pid) +
              ") wrote a header this controller cannot trust: restart it, or fix the robot "
              "description it publishes"};
}

}  // namespace ohrp::shm
