// Producer: creates and owns the robot segment, publishes sensors, waits for commands
// (handshake: layout.h).
#include <unistd.h>

#include <algorithm>
#include <boost/interprocess/exceptions.hpp>
#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/permissions.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>

#include "shm_bridge/bridge.h"
#include "segment_guard.h"
#include "shm_bridge/checks.h"
#include "signal_word.h"
#include "sync.h"

namespace bip = boost::interprocess;

namespace ohrp::shm {
namespace {

constexpr unsigned kOwnerOnly = 0600;  // segment file permissions: owner read/write only

//---------------- set-up helpers ----------------

// creates the object exclusively; false when an object of that name exists already
bool TryCreate(const std::string& object_name, bip::shared_memory_object* out) {
  try {
    *out = bip::shared_memory_object(bip::create_only, object_name.c_str(), bip::read_write,
                                     bip::permissions(kOwnerOnly));
    return true;
  } catch (const bip::interprocess_exception& e) {
    if (e.get_error_code() == bip::already_exists_error) return false;
    throw;
  }
}

// Looks at an existing object of our name. Returns kSegmentBusy when a live producer (another
// process) owns it; otherwise removes it, describes what was removed in `*note` and returns kOk.
Status ClearExisting(const std::string& segment_name, const std::string& object_name,
                     std::string* note) {
  pid_t owner = 0;
  bool is_segment = false;
  bip::offset_t size = 0;
  try {
    bip::shared_memory_object shm(bip::open_only, object_name.c_str(), bip::read_only);
    shm.get_size(size);
    if (size >= static_cast<bip::offset_t>(sizeof(SegmentHeader))) {
      bip::mapped_region region(shm, bip::read_only, 0, sizeof(SegmentHeader));
      SegmentHeader header;
      std::memcpy(&header, region.get_address(), sizeof(header));
      is_segment = std::memcmp(header.magic, kMagic, sizeof(kMagic)) == 0;
      owner = header.producer_pid;
    }
  } catch (const bip::interprocess_exception& e) {
    if (e.get_error_code() != bip::not_found_error) throw;
    return Status::Ok();  // gone meanwhile: nothing to replace
  }

  if (is_segment && owner > 0 && owner != getpid() && ProcessAlive(owner)) {
    return {Error::kSegmentBusy, "segment '" + segment_name + "' is owned by live producer pid " +
                                     std::to_string(owner) +
                                     "; stop it or choose another --segment"};
  }
  bip::shared_memory_object::remove(object_name.c_str());
  if (!is_segment) {
    *note = "replaced object '/dev/shm/" + object_name + "' (" + std::to_string(size) +
            " bytes) that was not a robot segment";
  } else if (owner == getpid()) {
    *note = "replaced segment '" + segment_name +
            "' left by an earlier producer of this process (pid " + std::to_string(owner) + ")";
  } else {
    *note = "replaced stale segment '" + segment_name + "' left by dead producer pid " +
            std::to_string(owner);
  }
  return Status::Ok();
}

void CopyName(char* dst, const std::string& src) {
  std::memset(dst, 0, kNameLen);
  std::memcpy(dst, src.data(), std::min<std::size_t>(src.size(), kNameLen - 1));
}

void CopyPerJoint(double* dst, const std::vector<double>& src, std::size_t njoint,
                  double fallback) {
  for (std::size_t i = 0; i < njoint; ++i) dst[i] = src.empty() ? fallback : src[i];
}

// the header as the config describes it, state kCreating, no controller
void FillHeader(const ProducerConfig& config, SegmentHeader* h) {
  std::memcpy(h->magic, kMagic, sizeof(kMagic));
  h->layout_version = kLayoutVersion;
  h->header_size = sizeof(SegmentHeader);
  h->layout_hash = LayoutHash();
  h->segment_size = sizeof(Segment);
  h->producer_kind = config.kind;
  h->producer_pid = getpid();
  h->state = static_cast<uint32_t>(ProducerState::kCreating);
  h->controller_pid = 0;
  CopyName(h->robot_name, config.robot_name);

  const std::size_t njoint = config.joint_names.size();
  h->njoint = static_cast<int32_t>(njoint);
  h->nforce = static_cast<int32_t>(config.force_names.size());
  h->nimu = static_cast<int32_t>(config.imu_names.size());
  h->ncamera = static_cast<int32_t>(config.cameras.size());
  for (std::size_t i = 0; i < njoint; ++i) CopyName(h->joint_names[i], config.joint_names[i]);
  for (std::size_t i = 0; i < config.force_names.size(); ++i) {
    CopyName(h->force_names[i], config.force_names[i]);
  }
  h->npassive = static_cast<int32_t>(config.passive_names.size());
  for (std::size_t i = 0; i < config.passive_names.size(); ++i) {
    CopyName(h->passive_names[i], config.passive_names[i]);
  }
  for (std::size_t i = 0; i < config.imu_names.size(); ++i) {
    CopyName(h->imu_names[i], config.imu_names[i]);
  }
  for (std::size_t i = 0; i < config.cameras.size(); ++i) h->cameras[i] = config.cameras[i];

  CopyPerJoint(h->q_min, config.q_min, njoint, -HUGE_VAL);
  CopyPerJoint(h->q_max, config.q_max, njoint, HUGE_VAL);
  CopyPerJoint(h->tau_max, config.tau_max, njoint, HUGE_VAL);
  CopyPerJoint(h->default_kp, config.default_kp, njoint, 0.0);
  CopyPerJoint(h->default_kd, config.default_kd, njoint, 0.0);
  h->physics_period = config.physics_period;
  h->control_period = config.control_period;
  h->read_timeout_hint = config.read_timeout_hint;

  h->model_hash = config.model_hash;
  h->nbody = config.nbody;
  h->total_mass = config.total_mass;
  for (std::size_t i = 0; i < njoint && i < config.joint_axis.size(); ++i) {
    for (int k = 0; k < 3; ++k) h->joint_axis[i][k] = config.joint_axis[i][k];
  }
  CopyPerJoint(h->link_mass, config.link_mass, njoint, 0.0);
}

}  // namespace

//---------------- creation and teardown ----------------

std::unique_ptr<Producer> Producer::Create(const ProducerConfig& config, Status* status) {
  Status ignored;
  Status& st = status != nullptr ? *status : ignored;
  st = ValidateConfig(config);
  if (!st.ok()) return nullptr;

  const std::string object_name = SegmentObjectName(config.segment_name);
  bool created = false;
  try {
    // claim the name, replacing what a dead producer left behind
    std::string note;
    bip::shared_memory_object shm;
    if (!TryCreate(object_name, &shm)) {
      st = ClearExisting(config.segment_name, object_name, &note);
      if (!st.ok()) return nullptr;
      if (!TryCreate(object_name, &shm)) {
        st = {Error::kSegmentBusy, "segment '" + config.segment_name +
                                       "' was created again by another process while this "
                                       "producer replaced it; stop it or choose another "
                                       "--segment"};
        return nullptr;
      }
    }
    created = true;
    // from here on every way out of this process removes the object (segment_guard.h)
    struct Registered {
      int slot;
      bool keep = false;
      ~Registered() {
        if (!keep) internal::RemoveCreated(slot);
      }
    } registered{internal::RegisterCreated(object_name, shm.get_mapping_handle().handle)};
    shm.truncate(sizeof(Segment));
    auto region = std::make_unique<bip::mapped_region>(shm, bip::read_write, 0, sizeof(Segment));
    auto* segment = static_cast<Segment*>(region->get_address());

    // header first (state kCreating), then kRunning; the zeroed wake-up words are ready
    // (the image area, about 17 MB, is left as the new object's zeros: untouched pages cost
    // no memory until a camera publishes)
    std::memset(static_cast<void*>(segment), 0, offsetof(Segment, images));
    segment->sync.sensors_ready.poster_cpu = -1;
    segment->sync.commands_ready.poster_cpu = -1;
    FillHeader(config, &segment->header);
    Status check = CheckHeader(segment->header, sizeof(Segment), config.segment_name);
    if (!check.ok()) {
      bip::shared_memory_object::remove(object_name.c_str());
      st = {Error::kSystem, "producer wrote an inconsistent header: " + check.message};
      return nullptr;
    }
    std::atomic_ref<uint32_t>(segment->header.state)
        .store(static_cast<uint32_t>(ProducerState::kRunning), std::memory_order_release);

    std::unique_ptr<Producer> producer(new Producer());
    producer->segment_ = segment;
    producer->object_name_ = object_name;
    producer->creator_ = getpid();
    producer->fd_ = internal::KeepDescriptor(shm.get_mapping_handle().handle);
    producer->watch_ = internal::WatchMapping(region->get_address(), region->get_size(), true);
    producer->created_ = registered.slot;
    registered.keep = true;
    producer->region_ = region.release();
    st = Status::Ok();
    st.message = std::move(note);
    return producer;
  } catch (const bip::interprocess_exception& e) {
    if (created) bip::shared_memory_object::remove(object_name.c_str());
    st = {Error::kSystem,
          "segment '" + config.segment_name + "' (/dev/shm/" + object_name + "): " + e.what()};
    return nullptr;
  }
}

Producer::~Producer() {
  if (segment_ == nullptr) return;
  // only the creating process tears down (a forked child's copy just unmaps); the creator is
  // this object's record, not the header's pid, which another process may have overwritten
  if (creator_ == getpid()) {
    SetState(ProducerState::kStopped);  // kFailed stays, a faulty segment becomes kFailed
    internal::Post(&segment_->sync.sensors_ready);  // a blocked read wakes, sees the state
    internal::WakeAll(&segment_->sync.sensors_ready);
    if (created_ >= 0) {
      internal::RemoveCreated(created_);  // only the object this process created
    } else {
      bip::shared_memory_object::remove(object_name_.c_str());
    }
  }
  internal::UnwatchMapping(watch_);
  internal::CloseDescriptor(&fd_);
  delete static_cast<bip::mapped_region*>(region_);
  segment_ = nullptr;
  region_ = nullptr;
}

//---------------- the segment's health ----------------

bool Producer::Healthy() const {
  if (fault_ == SegmentFault::kNone) {
    fault_ = internal::CheckSegment(*segment_, creator_, fd_, watch_);
  }
  return fault_ == SegmentFault::kNone;
}

bool Producer::sync_corrupted() const { return !Healthy(); }

//---------------- cycle ----------------

SensorBlock& Producer::BeginSensors() {
  if (sensors_odd_seq_ == 0) sensors_odd_seq_ = internal::SeqlockBegin(&segment_->sensors);
  return segment_->sensors;
}

void Producer::PublishSensors() {
  if (sensors_odd_seq_ == 0) BeginSensors();  // publishing without Begin still keeps the rule
  internal::SeqlockEnd(&segment_->sensors, sensors_odd_seq_);
  sensors_odd_seq_ = 0;
  published_cycle_ = segment_->sensors.cycle;
  published_ = true;
  if (!internal::Post(&segment_->sync.sensors_ready) && Healthy()) {
    fault_ = SegmentFault::kWakeUpWords;
  }
  Healthy();  // once a cycle: the segment's memory, the SIGBUS watch, the file's size
}

WaitResult Producer::WaitCommands(double timeout, CommandBlock* out, double slice) {
  SegmentHeader& h = segment_->header;
  if (fault_ != SegmentFault::kNone) return WaitResult::kTimeout;  // never wait on it
  // a faulty segment reads as "no controller" too (a zero page): it is checked first
  if (internal::LoadControllerPid(h) == 0) {
    return Healthy() ? WaitResult::kNoController : WaitResult::kTimeout;
  }

  const int64_t start = MonotonicNs();
  const int64_t deadline = start + internal::SecondsToNs(timeout);
  const int64_t slice_ns = std::max<int64_t>(internal::SecondsToNs(slice), 1000000);  // >= 1 ms
  for (int64_t now = start;; now = MonotonicNs()) {
    const int64_t until = std::min(deadline, now + slice_ns);
    const internal::SignalResult r =
        internal::Wait(&segment_->sync.commands_ready, until, &wait_typical_ns_);
    if (r == internal::SignalResult::kCorrupt) {
      if (Healthy()) fault_ = SegmentFault::kWakeUpWords;
      return WaitResult::kTimeout;
    }
    if (r == internal::SignalResult::kSignalled) {
      // a post: fresh unless it answers a cycle older than the last one published
      CommandBlock& block = segment_->commands;
      const uint64_t answers =
          std::atomic_ref<uint64_t>(block.answers_cycle).load(std::memory_order_relaxed);
      if (published_ && answers < published_cycle_) {
        if (MonotonicNs() >= deadline) return WaitResult::kTimeout;
        continue;  // stale: consumed, ignored
      }
      const pid_t writer = internal::LoadControllerPid(h);
      const auto copied =
          internal::SeqlockCopy(&block, out, internal::CopyCommands, writer, deadline);
      if (!Healthy()) return WaitResult::kTimeout;  // e.g. commands copied from zero pages
      if (copied == internal::CopyResult::kOk) return WaitResult::kCommands;
      if (copied == internal::CopyResult::kTimeout) return WaitResult::kTimeout;
      pid_t dead = writer;
      internal::SwapControllerPid(h, &dead, 0);
      return WaitResult::kControllerDied;
    }
    // the slice ended: check the segment, the controller, then the deadline
    if (!Healthy()) return WaitResult::kTimeout;
    pid_t controller = internal::LoadControllerPid(h);
    if (controller == 0) return WaitResult::kNoController;  // it closed cleanly
    if (!ProcessAlive(controller)) {
      internal::SwapControllerPid(h, &controller, 0);
      return WaitResult::kControllerDied;
    }
    if (MonotonicNs() >= deadline) return WaitResult::kTimeout;
  }
}

pid_t Producer::controller_pid() const { return internal::LoadControllerPid(segment_->header); }

bool Producer::DropController(pid_t pid) {
  if (pid <= 0) return false;
  return internal::SwapControllerPid(segment_->header, &pid, 0);
}

void Producer::SetState(ProducerState state) {
  std::atomic_ref<uint32_t> word(segment_->header.state);
  const bool ending = state == ProducerState::kStopped || state == ProducerState::kFailed;
  if (ending && (word.load(std::memory_order_acquire) ==
                     static_cast<uint32_t>(ProducerState::kFailed) ||
                 !Healthy())) {
    state = ProducerState::kFailed;  // final; and a faulty segment is no normal end
  }
  word.store(static_cast<uint32_t>(state), std::memory_order_release);
}

}  // namespace ohrp::shm
