// The layout's identity (LayoutHash) and the header checks a controller runs before trusting a
// segment (CheckHeader, SanitizedHeader).
#include "shm_bridge/layout.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <string>

#include "shm_bridge/checks.h"

namespace ohrp::shm {
namespace {

//---------------- layout hash ----------------

// feeds `v` as 8 little-endian bytes, so the hash does not depend on the host's byte order
constexpr uint64_t Mix(uint64_t h, uint64_t v) {
  for (int i = 0; i < 8; ++i) {
    h ^= (v >> (8 * i)) & 0xffu;
    h *= kFnv1aPrime;
  }
  return h;
}

// one entry per struct size and per field offset: any change of type, order or capacity moves
// at least one of them
constexpr uint64_t ComputeLayoutHash() {
  uint64_t h = kFnv1aOffsetBasis;
  for (char c : kMagic) h = Mix(h, static_cast<uint8_t>(c));
  const uint64_t values[] = {
      kLayoutVersion,
      kMaxJoints,
      kMaxForceSensors,
      kMaxImus,
      kMaxCameras,
      kMaxPassiveJoints,
      kNameLen,
      kMaxImageWidth,
      kMaxImageHeight,
      kImageSlots,
      kMaxImageRequesters,
      // camera
      sizeof(CameraInfo),
      offsetof(CameraInfo, name),
      offsetof(CameraInfo, width),
      offsetof(CameraInfo, height),
      offsetof(CameraInfo, fovy),
      offsetof(CameraInfo, p_BC),
      // header
      sizeof(SegmentHeader),
      offsetof(SegmentHeader, magic),
      offsetof(SegmentHeader, layout_version),
      offsetof(SegmentHeader, header_size),
      offsetof(SegmentHeader, layout_hash),
      offsetof(SegmentHeader, segment_size),
      offsetof(SegmentHeader, producer_kind),
      offsetof(SegmentHeader, producer_pid),
      offsetof(SegmentHeader, state),
      offsetof(SegmentHeader, controller_pid),
      offsetof(SegmentHeader, robot_name),
      offsetof(SegmentHeader, njoint),
      offsetof(SegmentHeader, nforce),
      offsetof(SegmentHeader, nimu),
      offsetof(SegmentHeader, ncamera),
      offsetof(SegmentHeader, joint_names),
      offsetof(SegmentHeader, force_names),
      offsetof(SegmentHeader, imu_names),
      offsetof(SegmentHeader, cameras),
      offsetof(SegmentHeader, q_min),
      offsetof(SegmentHeader, q_max),
      offsetof(SegmentHeader, tau_max),
      offsetof(SegmentHeader, default_kp),
      offsetof(SegmentHeader, default_kd),
      offsetof(SegmentHeader, physics_period),
      offsetof(SegmentHeader, control_period),
      offsetof(SegmentHeader, read_timeout_hint),
      offsetof(SegmentHeader, model_hash),
      offsetof(SegmentHeader, nbody),
      offsetof(SegmentHeader, total_mass),
      offsetof(SegmentHeader, joint_axis),
      offsetof(SegmentHeader, link_mass),
      offsetof(SegmentHeader, npassive),
      offsetof(SegmentHeader, passive_names),
      // sensors
      sizeof(ForceTorque),
      offsetof(ForceTorque, force),
      offsetof(ForceTorque, torque),
      sizeof(Imu),
      offsetof(Imu, gyro),
      offsetof(Imu, accel),
      offsetof(Imu, quat_WI),
      sizeof(SimTruth),
      offsetof(SimTruth, p_WB),
      offsetof(SimTruth, quat_WB),
      offsetof(SimTruth, v_WB),
      offsetof(SimTruth, w_WB),
      sizeof(SensorBlock),
      offsetof(SensorBlock, seq),
      offsetof(SensorBlock, cycle),
      offsetof(SensorBlock, time),
      offsetof(SensorBlock, status),
      offsetof(SensorBlock, last_command_cycle),
      offsetof(SensorBlock, late_commands),
      offsetof(SensorBlock, rejected_commands),
      offsetof(SensorBlock, rejected_per_joint),
      offsetof(SensorBlock, q),
      offsetof(SensorBlock, dq),
      offsetof(SensorBlock, tau),
      offsetof(SensorBlock, force),
      offsetof(SensorBlock, imu),
      offsetof(SensorBlock, sim_truth),
      offsetof(SensorBlock, passive_q),
      offsetof(SensorBlock, passive_dq),
      // commands
      sizeof(JointCommand),
      offsetof(JointCommand, mode),
      offsetof(JointCommand, q_ref),
      offsetof(JointCommand, dq_ref),
      offsetof(JointCommand, tau_ff),
      offsetof(JointCommand, kp),
      offsetof(JointCommand, kd),
      sizeof(CommandBlock),
      offsetof(CommandBlock, seq),
      offsetof(CommandBlock, answers_cycle),
      offsetof(CommandBlock, njoint),
      offsetof(CommandBlock, guard),
      offsetof(CommandBlock, joint),
      sizeof(GuardRecord),
      offsetof(GuardRecord, holding),
      offsetof(GuardRecord, holds),
      offsetof(GuardRecord, distance),
      offsetof(GuardRecord, link_a),
      offsetof(GuardRecord, link_b),
      // synchronisation and the whole segment
      sizeof(SignalWord),
      offsetof(SignalWord, word),
      offsetof(SignalWord, poster_cpu),
      offsetof(SignalWord, post_ns),
      sizeof(Sync),
      offsetof(Sync, sensors_ready),
      offsetof(Sync, commands_ready),
      // images
      sizeof(ImageSlot),
      offsetof(ImageSlot, seq),
      offsetof(ImageSlot, frame),
      offsetof(ImageSlot, time),
      offsetof(ImageSlot, width),
      offsetof(ImageSlot, height),
      offsetof(ImageSlot, has_depth),
      offsetof(ImageSlot, rgb),
      offsetof(ImageSlot, depth),
      sizeof(CameraImages),
      offsetof(CameraImages, latest),
      offsetof(CameraImages, slot),
      sizeof(ImageRequest),
      offsetof(ImageRequest, pid),
      offsetof(ImageRequest, cameras),
      sizeof(ImageArea),
      offsetof(ImageArea, requests),
      offsetof(ImageArea, camera),
      sizeof(Segment),
      offsetof(Segment, header),
      offsetof(Segment, sensors),
      offsetof(Segment, commands),
      offsetof(Segment, sync),
      offsetof(Segment, images),
  };
  for (uint64_t v : values) h = Mix(h, v);
  return h;
}

constexpr uint64_t kLayoutHash = ComputeLayoutHash();
static_assert(kLayoutHash != 0 && kLayoutHash != kFnv1aOffsetBasis);

//---------------- helpers ----------------

std::string Hex(uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof(text), "0x%016llx", static_cast<unsigned long long>(v));
  return text;
}

void Terminate(char* name) { name[kNameLen - 1] = '\0'; }

}  // namespace

uint64_t LayoutHash() { return kLayoutHash; }

//---------------- header checks ----------------

Status CheckHeader(const SegmentHeader& header, uint64_t object_size,
                   const std::string& segment_name) {
  const std::string where =
      "segment '" + segment_name + "' (/dev/shm/" + SegmentObjectName(segment_name) + ")";
  if (object_size < sizeof(Segment)) {
    return {Error::kNotASegment, where + " is " + std::to_string(object_size) +
                                     " bytes, smaller than a robot segment (" +
                                     std::to_string(sizeof(Segment)) +
                                     " bytes): not a robot segment; remove it or choose "
                                     "another --segment"};
  }
  if (std::memcmp(header.magic, kMagic, sizeof(kMagic)) != 0) {
    return {Error::kNotASegment, where +
                                     " does not start with the robot segment magic "
                                     "'OHRPSEG1': not a robot segment; remove it or choose "
                                     "another --segment"};
  }
  const std::string rebuild = ": rebuild the controller against this producer's shm_bridge";
  if (header.layout_version != kLayoutVersion || header.layout_hash != LayoutHash()) {
    return {Error::kLayoutMismatch,
            where + " has layout version " + std::to_string(header.layout_version) + " hash " +
                Hex(header.layout_hash) + ", this controller was built with version " +
                std::to_string(kLayoutVersion) + " hash " + Hex(LayoutHash()) + rebuild};
  }
  if (header.header_size != sizeof(SegmentHeader) || header.segment_size != sizeof(Segment) ||
      header.segment_size > object_size) {
    return {Error::kLayoutMismatch,
            where + " declares header_size " + std::to_string(header.header_size) +
                " and segment_size " + std::to_string(header.segment_size) + " (object " +
                std::to_string(object_size) + " bytes), this controller expects " +
                std::to_string(sizeof(SegmentHeader)) + " and " + std::to_string(sizeof(Segment)) +
                rebuild};
  }
  return Status::Ok();
}

SegmentHeader SanitizedHeader(const SegmentHeader& header) {
  SegmentHeader h = header;
  h.njoint = std::clamp(h.njoint, 0, kMaxJoints);
  h.nforce = std::clamp(h.nforce, 0, kMaxForceSensors);
  h.nimu = std::clamp(h.nimu, 0, kMaxImus);
  h.ncamera = std::clamp(h.ncamera, 0, kMaxCameras);
  h.npassive = std::clamp(h.npassive, 0, kMaxPassiveJoints);
  Terminate(h.robot_name);
  for (auto& name : h.joint_names) Terminate(name);
  for (auto& name : h.force_names) Terminate(name);
  for (auto& name : h.imu_names) Terminate(name);
  for (auto& name : h.passive_names) Terminate(name);
  for (auto& camera : h.cameras) Terminate(camera.name);
  return h;
}

}  // namespace ohrp::shm
