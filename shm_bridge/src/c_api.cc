// The C API of the robot segment (include/ohrp_shm.h): a thin layer over RobotAdaptor (the
// controller) and Observer (read-only). Every entry point catches everything: no C++
// exception crosses into C.
#include "ohrp_shm.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/observer.h"

using ohrp::shm::CommandBlock;
using ohrp::shm::ReadResult;
using ohrp::shm::SegmentHeader;
using ohrp::shm::SensorBlock;

struct ohrp_robot {
  std::unique_ptr<ohrp::shm::RobotAdaptor> controller;  // one of the two is set
  std::unique_ptr<ohrp::shm::Observer> observer;
  double read_timeout = 2.0;
  SensorBlock sensors{};
  bool have_sensors = false;
  CommandBlock commands{};  // a controller's last written block
  std::unique_ptr<ohrp::shm::ImageSlot> image;  // ohrp_read_image's copy (made at request)

  const SegmentHeader& header() const {
    return controller ? controller->header() : observer->header();
  }
};

namespace {

// the C constants are the segment's values
using ohrp::shm::JointMode;
using ohrp::shm::ProducerKind;
static_assert(OHRP_MODE_OFF == static_cast<int>(JointMode::kOff) &&
              OHRP_MODE_POSITION == static_cast<int>(JointMode::kPosition) &&
              OHRP_MODE_VELOCITY == static_cast<int>(JointMode::kVelocity) &&
              OHRP_MODE_TORQUE == static_cast<int>(JointMode::kTorque));
static_assert(OHRP_PRODUCER_UNKNOWN == static_cast<int>(ProducerKind::kUnknown) &&
              OHRP_PRODUCER_SIMULATION == static_cast<int>(ProducerKind::kSimulation) &&
              OHRP_PRODUCER_HARDWARE == static_cast<int>(ProducerKind::kHardware) &&
              OHRP_PRODUCER_REPLAY == static_cast<int>(ProducerKind::kReplay));

void SetError(char* err, size_t errlen, const std::string& text) {
  if (err == nullptr || errlen == 0) return;
  const size_t n = std::min(errlen - 1, text.size());
  std::memcpy(err, text.data(), n);
  err[n] = '\0';
}

int Code(ReadResult r) {
  switch (r) {
    case ReadResult::kOk: return OHRP_OK;
    case ReadResult::kTimeout: return OHRP_TIMEOUT;
    case ReadResult::kProducerGone: return OHRP_PRODUCER_GONE;
    case ReadResult::kProducerStopped: return OHRP_PRODUCER_STOPPED;
    case ReadResult::kNotOpen: return OHRP_NOT_OPEN;
    case ReadResult::kDropped: return OHRP_DROPPED;
    case ReadResult::kSyncCorrupted: return OHRP_SYNC_CORRUPTED;
    case ReadResult::kSegmentCorrupted: return OHRP_SEGMENT_CORRUPTED;
  }
  return OHRP_NOT_OPEN;
}

bool Valid(const ohrp_robot* r) {
  return r != nullptr && ((r->controller && r->controller->is_open()) ||
                          (r->observer && r->observer->is_open()));
}

int Count(const ohrp_robot* r, int32_t SegmentHeader::*field) {
  return Valid(r) ? r->header().*field : 0;
}

template <size_t N, size_t L>
const char* NameAt(const ohrp_robot* r, const char (SegmentHeader::*names)[N][L],
                   int32_t SegmentHeader::*count, int i) {
  if (!Valid(r) || i < 0 || i >= r->header().*count) return nullptr;
  return (r->header().*names)[i];
}

template <size_t N, size_t L>
int IndexOf(const ohrp_robot* r, const char (SegmentHeader::*names)[N][L],
            int32_t SegmentHeader::*count, const char* name) {
  if (!Valid(r) || name == nullptr) return -1;
  for (int i = 0; i < r->header().*count; ++i) {
    if (std::strncmp((r->header().*names)[i], name, L) == 0) return i;
  }
  return -1;
}

// copies njoint values of the member array `field` of the block
template <class Block>
void CopyJoints(const ohrp_robot* r, const Block& block, const double (Block::*field)[ohrp::shm::kMaxJoints],
                double* out) {
  if (!Valid(r) || out == nullptr) return;
  std::copy_n(block.*field, r->header().njoint, out);
}

ohrp_robot* Attach(bool as_controller, const char* segment, double read_timeout, char* err,
                   size_t errlen) {
  try {
    if (segment == nullptr || segment[0] == '\0') {
      SetError(err, errlen, "no segment name given (e.g. \"hrp1s\", the --segment of sim_host)");
      return nullptr;
    }
    if (!(read_timeout >= 0.0)) {
      SetError(err, errlen, "read_timeout must be >= 0 [s]");
      return nullptr;
    }
    auto r = std::make_unique<ohrp_robot>();
    r->read_timeout = read_timeout;
    ohrp::shm::Status status;
    if (as_controller) {
      r->controller = std::make_unique<ohrp::shm::RobotAdaptor>();
      ohrp::shm::AdaptorOptions options;
      options.read_timeout = read_timeout;
      status = r->controller->open(segment, options);
    } else {
      r->observer = std::make_unique<ohrp::shm::Observer>();
      status = r->observer->open(segment);
    }
    if (!status.ok()) {
      SetError(err, errlen, status.message);
      return nullptr;
    }
    return r.release();
  } catch (const std::exception& e) {
    SetError(err, errlen, std::string("attach failed: ") + e.what());
  } catch (...) {
    SetError(err, errlen, "attach failed");
  }
  return nullptr;
}

}  // namespace

extern "C" {

int ohrp_max_joints(void) { return ohrp::shm::kMaxJoints; }
int ohrp_max_force_sensors(void) { return ohrp::shm::kMaxForceSensors; }
int ohrp_max_imus(void) { return ohrp::shm::kMaxImus; }

//---------------- attach / detach ----------------

ohrp_robot* ohrp_open(const char* segment, double read_timeout, char* err, size_t errlen) {
  return Attach(true, segment, read_timeout, err, errlen);
}

ohrp_robot* ohrp_observe(const char* segment, double read_timeout, char* err, size_t errlen) {
  return Attach(false, segment, read_timeout, err, errlen);
}

void ohrp_close(ohrp_robot* r) { delete r; }

//---------------- header ----------------

int ohrp_is_controller(const ohrp_robot* r) { return Valid(r) && r->controller ? 1 : 0; }
const char* ohrp_robot_name(const ohrp_robot* r) { return Valid(r) ? r->header().robot_name : ""; }
int ohrp_producer_kind(const ohrp_robot* r) {
  return Valid(r) ? static_cast<int>(r->header().producer_kind) : OHRP_PRODUCER_UNKNOWN;
}
int ohrp_njoint(const ohrp_robot* r) { return Count(r, &SegmentHeader::njoint); }
int ohrp_nforce(const ohrp_robot* r) { return Count(r, &SegmentHeader::nforce); }
int ohrp_nimu(const ohrp_robot* r) { return Count(r, &SegmentHeader::nimu); }
int ohrp_npassive(const ohrp_robot* r) { return Count(r, &SegmentHeader::npassive); }

const char* ohrp_joint_name(const ohrp_robot* r, int i) {
  return NameAt(r, &SegmentHeader::joint_names, &SegmentHeader::njoint, i);
}
const char* ohrp_force_name(const ohrp_robot* r, int i) {
  return NameAt(r, &SegmentHeader::force_names, &SegmentHeader::nforce, i);
}
const char* ohrp_imu_name(const ohrp_robot* r, int i) {
  return NameAt(r, &SegmentHeader::imu_names, &SegmentHeader::nimu, i);
}
const char* ohrp_passive_name(const ohrp_robot* r, int i) {
  return NameAt(r, &SegmentHeader::passive_names, &SegmentHeader::npassive, i);
}
int ohrp_joint_index(const ohrp_robot* r, const char* name) {
  return IndexOf(r, &SegmentHeader::joint_names, &SegmentHeader::njoint, name);
}
int ohrp_force_index(const ohrp_robot* r, const char* name) {
  return IndexOf(r, &SegmentHeader::force_names, &SegmentHeader::nforce, name);
}
int ohrp_imu_index(const ohrp_robot* r, const char* name) {
  return IndexOf(r, &SegmentHeader::imu_names, &SegmentHeader::nimu, name);
}

double ohrp_control_period(const ohrp_robot* r) { return Valid(r) ? r->header().control_period : 0; }
double ohrp_physics_period(const ohrp_robot* r) { return Valid(r) ? r->header().physics_period : 0; }

void ohrp_joint_limits(const ohrp_robot* r, double* q_min, double* q_max, double* tau_max) {
  if (!Valid(r)) return;
  CopyJoints(r, r->header(), &SegmentHeader::q_min, q_min);
  CopyJoints(r, r->header(), &SegmentHeader::q_max, q_max);
  CopyJoints(r, r->header(), &SegmentHeader::tau_max, tau_max);
}

void ohrp_default_gains(const ohrp_robot* r, double* kp, double* kd) {
  if (!Valid(r)) return;
  CopyJoints(r, r->header(), &SegmentHeader::default_kp, kp);
  CopyJoints(r, r->header(), &SegmentHeader::default_kd, kd);
}

//---------------- cycle ----------------

int ohrp_read(ohrp_robot* r) {
  if (!Valid(r)) return OHRP_NOT_OPEN;
  const ReadResult result = r->controller ? r->controller->read(&r->sensors)
                                          : r->observer->read(&r->sensors, r->read_timeout);
  if (result == ReadResult::kOk) r->have_sensors = true;
  return Code(result);
}

uint64_t ohrp_cycle(const ohrp_robot* r) { return Valid(r) ? r->sensors.cycle : 0; }
double ohrp_time(const ohrp_robot* r) { return Valid(r) ? r->sensors.time : 0.0; }
uint32_t ohrp_status(const ohrp_robot* r) { return Valid(r) ? r->sensors.status : 0; }

void ohrp_get_q(const ohrp_robot* r, double* q) {
  if (Valid(r)) CopyJoints(r, r->sensors, &SensorBlock::q, q);
}
void ohrp_get_dq(const ohrp_robot* r, double* dq) {
  if (Valid(r)) CopyJoints(r, r->sensors, &SensorBlock::dq, dq);
}
void ohrp_get_tau(const ohrp_robot* r, double* tau) {
  if (Valid(r)) CopyJoints(r, r->sensors, &SensorBlock::tau, tau);
}

void ohrp_get_passive_q(const ohrp_robot* r, double* q) {
  if (Valid(r) && q != nullptr) std::copy_n(r->sensors.passive_q, r->header().npassive, q);
}
void ohrp_get_passive_dq(const ohrp_robot* r, double* dq) {
  if (Valid(r) && dq != nullptr) std::copy_n(r->sensors.passive_dq, r->header().npassive, dq);
}

void ohrp_get_force(const ohrp_robot* r, double* ft) {
  if (!Valid(r) || ft == nullptr) return;
  for (int i = 0; i < r->header().nforce; ++i) {
    std::copy_n(r->sensors.force[i].force, 3, ft + 6 * i);
    std::copy_n(r->sensors.force[i].torque, 3, ft + 6 * i + 3);
  }
}

void ohrp_get_imu(const ohrp_robot* r, double* imu) {
  if (!Valid(r) || imu == nullptr) return;
  for (int i = 0; i < r->header().nimu; ++i) {
    std::copy_n(r->sensors.imu[i].gyro, 3, imu + 10 * i);
    std::copy_n(r->sensors.imu[i].accel, 3, imu + 10 * i + 3);
    std::copy_n(r->sensors.imu[i].quat_WI, 4, imu + 10 * i + 6);
  }
}

int ohrp_get_sim_truth(const ohrp_robot* r, double* truth) {
  if (!Valid(r) || truth == nullptr) return 0;
  const ohrp::shm::SimTruth& t = r->sensors.sim_truth;
  std::copy_n(t.p_WB, 3, truth);
  std::copy_n(t.quat_WB, 4, truth + 3);
  std::copy_n(t.v_WB, 3, truth + 7);
  std::copy_n(t.w_WB, 3, truth + 10);
  return (r->sensors.status & ohrp::shm::status::kSimulated) != 0 ? 1 : 0;
}

int ohrp_write(ohrp_robot* r, const int32_t* mode, const double* q_ref, const double* dq_ref,
               const double* tau_ff, const double* kp, const double* kd) {
  if (!Valid(r)) return OHRP_NOT_OPEN;
  if (!r->controller) return OHRP_NOT_CONTROLLER;
  const SegmentHeader& h = r->header();
  CommandBlock& c = r->commands;
  c.njoint = h.njoint;
  for (int i = 0; i < h.njoint; ++i) {
    ohrp::shm::JointCommand& j = c.joint[i];
    j.mode = static_cast<ohrp::shm::JointMode>(mode ? mode[i] : OHRP_MODE_POSITION);
    j.q_ref = q_ref ? q_ref[i] : r->sensors.q[i];
    j.dq_ref = dq_ref ? dq_ref[i] : 0.0;
    j.tau_ff = tau_ff ? tau_ff[i] : 0.0;
    j.kp = kp ? kp[i] : h.default_kp[i];
    j.kd = kd ? kd[i] : h.default_kd[i];
  }
  return Code(r->controller->write(c));
}

int ohrp_last_commands(const ohrp_robot* r, int32_t* mode, double* q_ref, double* dq_ref,
                       double* tau_ff, double* kp, double* kd) {
  if (!Valid(r)) return 0;
  CommandBlock block{};
  const CommandBlock* c = &r->commands;
  if (r->observer) {
    if (!r->observer->commands(&block)) return 0;
    c = &block;
  } else if (c->njoint == 0) {
    return 0;
  }
  const int n = std::min(c->njoint, r->header().njoint);
  for (int i = 0; i < n; ++i) {
    const ohrp::shm::JointCommand& j = c->joint[i];
    if (mode) mode[i] = static_cast<int32_t>(j.mode);
    if (q_ref) q_ref[i] = j.q_ref;
    if (dq_ref) dq_ref[i] = j.dq_ref;
    if (tau_ff) tau_ff[i] = j.tau_ff;
    if (kp) kp[i] = j.kp;
    if (kd) kd[i] = j.kd;
  }
  return 1;
}

int ohrp_last_guard(const ohrp_robot* r, int32_t* holding, uint64_t* holds, double* distance,
                    char* link_a, char* link_b) {
  static_assert(OHRP_NAME_LEN == ohrp::shm::kNameLen);
  if (!Valid(r)) return 0;
  CommandBlock block{};
  const CommandBlock* c = &r->commands;
  if (r->observer) {
    if (!r->observer->commands(&block)) return 0;
    c = &block;
  } else if (c->njoint == 0) {
    return 0;
  }
  const ohrp::shm::GuardRecord& g = c->guard;
  if (holding) *holding = static_cast<int32_t>(g.holding);
  if (holds) *holds = g.holds;
  if (distance) *distance = g.distance;
  // the bridge terminates the names within kNameLen
  if (link_a) std::memcpy(link_a, g.link_a, OHRP_NAME_LEN);
  if (link_b) std::memcpy(link_b, g.link_b, OHRP_NAME_LEN);
  return 1;
}

int ohrp_ncamera(const ohrp_robot* r) { return Count(r, &SegmentHeader::ncamera); }

const char* ohrp_camera_name(const ohrp_robot* r, int i) {
  if (!Valid(r) || i < 0 || i >= r->header().ncamera) return nullptr;
  return r->header().cameras[i].name;
}

int ohrp_camera_index(const ohrp_robot* r, const char* name) {
  if (!Valid(r) || name == nullptr) return -1;
  for (int i = 0; i < r->header().ncamera; ++i) {
    if (std::strcmp(r->header().cameras[i].name, name) == 0) return i;
  }
  return -1;
}

int ohrp_camera_info(const ohrp_robot* r, int i, int* width, int* height, double* fovy) {
  if (ohrp_camera_name(r, i) == nullptr) return 0;
  const ohrp::shm::CameraInfo& c = r->header().cameras[i];
  if (width != nullptr) *width = c.width;
  if (height != nullptr) *height = c.height;
  if (fovy != nullptr) *fovy = c.fovy;
  return 1;
}

int ohrp_request_images(ohrp_robot* r, uint32_t mask) {
  if (!Valid(r)) return 0;
  try {
    if (!r->image) r->image = std::make_unique<ohrp::shm::ImageSlot>();
    const bool ok = r->controller ? r->controller->request_images(mask)
                                  : r->observer->request_images(mask);
    return ok ? 1 : 0;
  } catch (...) {
    return 0;
  }
}

int ohrp_read_image(ohrp_robot* r, int camera, uint64_t after_frame, uint64_t* frame,
                    double* time, int* width, int* height, int* has_depth, uint8_t* rgb,
                    size_t rgb_len, float* depth, size_t depth_len) {
  using ohrp::shm::ImageResult;
  if (!Valid(r)) return OHRP_IMAGE_NOT_OPEN;
  try {
    if (!r->image) r->image = std::make_unique<ohrp::shm::ImageSlot>();
  } catch (...) {
    return OHRP_IMAGE_NOT_OPEN;
  }
  ohrp::shm::ImageSlot& s = *r->image;
  const ImageResult got = r->controller ? r->controller->read_image(camera, after_frame, &s)
                                        : r->observer->read_image(camera, after_frame, &s);
  switch (got) {
    case ImageResult::kOk: break;
    case ImageResult::kNoFrame: return OHRP_IMAGE_NO_FRAME;
    case ImageResult::kBusy: return OHRP_IMAGE_BUSY;
    case ImageResult::kBadCamera: return OHRP_IMAGE_BAD_CAMERA;
    default: return OHRP_IMAGE_NOT_OPEN;
  }
  const size_t n = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
  const bool with_depth = depth != nullptr && s.has_depth != 0;
  if (rgb == nullptr || rgb_len < 3 * n || (with_depth && depth_len < n)) {
    return OHRP_IMAGE_TOO_SMALL;
  }
  std::memcpy(rgb, s.rgb, 3 * n);
  if (with_depth) std::memcpy(depth, s.depth, sizeof(float) * n);
  if (frame != nullptr) *frame = s.frame;
  if (time != nullptr) *time = s.time;
  if (width != nullptr) *width = s.width;
  if (height != nullptr) *height = s.height;
  if (has_depth != nullptr) *has_depth = s.has_depth != 0 ? 1 : 0;
  return OHRP_IMAGE_OK;
}

int ohrp_producer_failed(const ohrp_robot* r) {
  if (!Valid(r)) return 0;
  const auto state = r->controller ? r->controller->producer_state() : r->observer->producer_state();
  return state == ohrp::shm::ProducerState::kFailed ? 1 : 0;
}

const char* ohrp_result_name(int result) {
  switch (result) {
    case OHRP_OK: return "ok";
    case OHRP_TIMEOUT: return "timeout";
    case OHRP_PRODUCER_GONE: return "producer_gone";
    case OHRP_PRODUCER_STOPPED: return "producer_stopped";
    case OHRP_NOT_OPEN: return "not_open";
    case OHRP_DROPPED: return "dropped";
    case OHRP_NOT_CONTROLLER: return "not_controller";
    case OHRP_SYNC_CORRUPTED: return "sync_corrupted";
    case OHRP_SEGMENT_CORRUPTED: return "segment_corrupted";
  }
  return "unknown";
}

}  // extern "C"
