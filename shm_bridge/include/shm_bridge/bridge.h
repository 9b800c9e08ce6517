// The two ends of a robot segment (layout and handshake: see layout.h).
//
//   Producer      created by sim_host / hw_driver: owns the segment, publishes sensors every
//                 control cycle, waits for the controller's commands.
//   RobotAdaptor  the controller's end, the paper's robot adaptor: open / read / write / close.
//                 It never learns (and never needs) which kind of producer is on the other side.
//
// Set-up calls (Producer::Create, RobotAdaptor::open) return a Status that names what failed.
// The cycle calls (PublishSensors, WaitCommands, read, write) never allocate, throw or log:
// they return a result code and the caller counts problems.
//
// What another process can do to the segment, and what each end then does (layout.h has the
// protocol; src/segment_guard.h the mechanisms):
//   - truncate its file (/dev/shm/ohrp_<name>): an access past the new end would raise SIGBUS
//     and kill the process silently. Both ends watch their mapping: a SIGBUS inside it is
//     answered with zero pages (the access completes) and a flag, and each end checks the
//     flag and the file's size (one fstat) at least once a control cycle. The producer then
//     reports SegmentFault::kTruncated (sync_corrupted(), fault()), the controller
//     ReadResult::kSegmentCorrupted; both end their run with an error, never with the signal.
//   - overwrite the header's magic, producer pid or state: SegmentFault::kHeader, the same ends.
//   - overwrite a wake-up word: SegmentFault::kWakeUpWords (ReadResult::kSyncCorrupted).
//   A producer that finds its segment faulty marks it kFailed (when the memory is still
//   shared), and a controller that sees the producer end checks the segment first: a corrupted
//   segment is never reported as a normal end on either side.
//   - create the segment's name first (name squatting): a controller (and an observer) refuses
//     a segment whose file belongs to another user than its effective uid (Error::kForeignOwner)
//     unless told otherwise (AdaptorOptions::allow_other_owner, or the environment variable
//     OHRP_ALLOW_FOREIGN_SEGMENT=1).
//   - attach while the producer creates the segment (its file still 0 bytes, or the header not
//     written): open waits up to 1 s for it, then answers kProducerNotReady (retried by the
//     controllers' runner up to --attach-timeout).
// The producer removes its segment on every way out of the process it can see: destructor,
// exit(), the signals that end a process, an uncaught exception (SIGABRT); see segment_guard.h.
#pragma once

#include <sys/types.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "shm_bridge/images.h"
#include "shm_bridge/layout.h"

namespace ohrp::shm {

//---------------- errors ----------------

enum class Error {
  kOk = 0,
  kNoSegment,          // no segment of that name (the producer is not running)
  kNotASegment,        // the object exists but has the wrong size or magic
  kLayoutMismatch,     // version or layout hash differ: producer and controller were built apart
  kInvalidHeader,      // the header's counts, limits, gains or periods are not physical
  kProducerNotReady,   // the producer is still writing the header
  kProducerDead,       // the segment is stale: its producer process is gone
  kProducerStopped,    // the producer has ended its run
  kControllerPresent,  // another live controller is attached
  kSegmentBusy,        // (producer) a live producer already owns a segment of that name
  kInvalidConfig,      // (producer) counts or names do not fit the layout
  kSystem,             // an operating-system call failed (errno text in the message)
  kForeignOwner,       // the segment's file belongs to another user (a squatted name?)
};

// What a check of a mapped segment found wrong (the segment comment above).
enum class SegmentFault {
  kNone = 0,
  kWakeUpWords,  // a wake-up word holds a value the bridge never writes
  kHeader,       // the header's magic, producer pid or state was overwritten
  kTruncated,    // the segment's file was truncated (its memory is gone)
};

// A sentence for `f`, e.g. "the segment's file was truncated by another process".
const char* SegmentFaultText(SegmentFault f);

// The environment variable that lets a controller or observer attach to a segment owned by
// another user ("1"); see AdaptorOptions::allow_other_owner.
inline constexpr const char* kAllowForeignSegmentEnv = "OHRP_ALLOW_FOREIGN_SEGMENT";

// Outcome of a set-up call: a code and a sentence for the user (what failed, what to do).
struct Status {
  Error code = Error::kOk;
  std::string message;
  bool ok() const { return code == Error::kOk; }
  static Status Ok() { return {}; }
};

const char* ErrorName(Error e);

// The file name used for a segment name: "ohrp_<name>" under /dev/shm.
std::string SegmentObjectName(const std::string& segment_name);

// True when process `pid` exists (signal 0 succeeds or fails with EPERM).
bool ProcessAlive(pid_t pid);

//---------------- producer side ----------------

struct ProducerConfig {
  std::string segment_name;   // e.g. "hrp1s"; see SegmentObjectName
  ProducerKind kind = ProducerKind::kSimulation;
  std::string robot_name;
  std::vector<std::string> joint_names;  // joint-id order; <= kMaxJoints, each < kNameLen
  std::vector<std::string> force_names;
  std::vector<std::string> imu_names;
  std::vector<std::string> passive_names;  // passive joints (read-only); <= kMaxPassiveJoints
  std::vector<CameraInfo> cameras;
  std::vector<double> q_min, q_max, tau_max, default_kp, default_kd;  // njoint each
  double physics_period = 0.0;      // [s]
  double control_period = 0.005;    // [s]
  double read_timeout_hint = 1.0;   // [s]
  // the robot model's identity (SegmentHeader: model_hash...; robot_model/model_hash.h)
  uint64_t model_hash = 0;          // 0: not published
  int nbody = 0;                    // bodies of the robot
  double total_mass = 0.0;          // [kg]
  std::vector<std::array<double, 3>> joint_axis;  // njoint or empty (zeros) [unit vector]
  std::vector<double> link_mass;    // njoint or empty (zeros) [kg]
};

enum class WaitResult {
  kCommands,        // a fresh command block was copied out
  kTimeout,         // the controller did not answer in time (it is still alive), or the
                    // segment's wake-up words are corrupted (Producer::sync_corrupted)
  kNoController,    // nobody is attached
  kControllerDied,  // the attached controller's process is gone (its claim was released)
};

class Producer {
 public:
  // Creates the segment `config.segment_name` with owner-only permissions (0600), writes and
  // checks the header, and sets the state to kRunning. A segment of that name left by a dead
  // producer is removed and replaced (the message of `*status` says so); one owned by a live
  // producer is refused with kSegmentBusy. Returns null on failure with `*status` set.
  static std::unique_ptr<Producer> Create(const ProducerConfig& config, Status* status);

  // Marks the segment kStopped (unless already kFailed), wakes a waiting controller and
  // removes the segment.
  ~Producer();
  Producer(const Producer&) = delete;
  Producer& operator=(const Producer&) = delete;

  const SegmentHeader& header() const { return segment_->header; }
  const std::string& object_name() const { return object_name_; }

  // Opens the sensor block for writing (seqlock odd); fill it, then call PublishSensors.
  SensorBlock& BeginSensors();
  // Closes the seqlock and posts sensors_ready (never more than one pending post).
  void PublishSensors();

  // Waits until the controller posts commands for the last published cycle, or until
  // `timeout` [s] passes, checking the controller's pid every `slice` [s]. Copies the command
  // block into `*out` on kCommands. On kControllerDied the controller slot is freed.
  // Only the block's first njoint joints are copied; the rest of `*out` is left as it was, and
  // `*out` is not touched unless the result is kCommands. A post answering a cycle older than
  // the last one published (a late answer) is consumed and ignored.
  // The wait spins for a bounded time before it sleeps (layout.h: handshake). Once the
  // segment's wake-up words are found corrupted, it returns kTimeout at once, every time, and
  // sync_corrupted() is true: the caller ends its run with an error. The same once the
  // segment is found faulty in any other way (fault(): truncated file, overwritten header);
  // kNoController and kControllerDied are never answered for a faulty segment.
  WaitResult WaitCommands(double timeout, CommandBlock* out, double slice = 0.02);

  // True once the segment can no longer be trusted: a wake-up word held a value the bridge
  // never writes, the header's identity or state was overwritten, or the file was truncated
  // (another process wrote into or truncated the segment). Checks now (memory, the SIGBUS
  // watch and one fstat: real-time safe) and remembers: call it once a cycle.
  bool sync_corrupted() const;
  // What was found (kNone while nothing was); SegmentFaultText says it in words.
  SegmentFault fault() const { return fault_; }

  // The attached controller's pid, 0 if none.
  pid_t controller_pid() const;

  // Lets go of controller `pid` (one that missed its timeout, see controller_loss.h): frees
  // the controller slot if `pid` still holds it, so that a new controller can attach; the
  // dropped controller's next read or write returns ReadResult::kDropped. True when `pid` held
  // the slot. Real-time safe.
  bool DropController(pid_t pid);

  // Sets the producer state seen by controllers (kStopped / kFailed end their reads). kFailed
  // is final: a later kStopped keeps kFailed; and a faulty segment (fault()) is marked kFailed.
  void SetState(ProducerState state);

  // Camera images (images.h). PublishImage: a frame of header camera `camera` (RGB8
  // width x height x 3, top row first; depth [m] or null), never waits for a reader.
  // ImagesRequested: the cameras (bit i: camera i) some live attached program asks for; the
  // producer renders only those. Both real-time safe (ImagesRequested makes one kill(pid, 0)
  // per requesting entry).
  ImageResult PublishImage(int camera, double time, int width, int height, const uint8_t* rgb,
                           const float* depth = nullptr) {
    return shm::PublishImage(segment_, camera, time, width, height, rgb, depth);
  }
  uint32_t ImagesRequested() const { return shm::ImagesRequested(segment_->images.requests); }

 private:
  Producer() = default;
  // looks at the segment once (CheckSegment) and remembers a fault; true while none
  bool Healthy() const;

  Segment* segment_ = nullptr;
  std::string object_name_;
  void* region_ = nullptr;  // boost mapped_region, owned
  pid_t creator_ = 0;       // the creating process (only it removes the segment)
  int fd_ = -1;             // the segment's file, for fstat
  int watch_ = -1;          // the mapping watch's slot (segment_guard.h)
  int created_ = -1;        // the clean-up's slot (segment_guard.h)
  mutable SegmentFault fault_ = SegmentFault::kNone;
  uint64_t sensors_odd_seq_ = 0;    // sensors.seq while BeginSensors' write is open (else 0)
  uint64_t published_cycle_ = 0;    // SensorBlock::cycle of the last PublishSensors
  bool published_ = false;          // PublishSensors was called at least once
  int64_t wait_typical_ns_ = 0;     // what WaitCommands' waits took, smoothed (its spin budget)
};

//---------------- controller side: the robot adaptor ----------------

enum class ReadResult {
  kOk,               // fresh sensors copied out
  kTimeout,          // nothing arrived in time, the producer is still alive
  kProducerGone,     // the producer's process is gone
  kProducerStopped,  // the producer ended its run (state kStopped or kFailed)
  kNotOpen,
  kDropped,          // the producer gave up on this controller (it missed the producer's
                     // timeout) and freed its slot (controller_loss.h); nothing more is written
  kSyncCorrupted,    // the segment's wake-up words hold values the bridge never writes
                     // (another process scribbled on the segment): the handshake is unusable
  kSegmentCorrupted, // the segment's file was truncated or its header overwritten by another
                     // process (RobotAdaptor::fault() says which): the segment is unusable
};

const char* ReadResultName(ReadResult r);

struct AdaptorOptions {
  double read_timeout = 2.0;   // [s] how long read() waits for the next cycle
  double slice = 0.02;         // [s] how often a waiting read checks the producer's pid
  // attach to a segment whose file belongs to another user (its uid is not this process's
  // effective uid). Off by default: another user may have created the name first to feed this
  // controller its sensors (name squatting); kAllowForeignSegmentEnv=1 turns it on too.
  bool allow_other_owner = false;
};

class RobotAdaptor {
 public:
  RobotAdaptor() = default;
  ~RobotAdaptor();  // close()
  RobotAdaptor(const RobotAdaptor&) = delete;
  RobotAdaptor& operator=(const RobotAdaptor&) = delete;

  // Attaches to the segment by name: checks magic, layout version and hash, size, the header's
  // values (CheckHeaderValues in checks.h: counts within capacity, physical limits, gains and
  // periods), that the producer is alive and running, that the segment's file belongs to this
  // process's effective uid (else kForeignOwner, unless options.allow_other_owner or
  // OHRP_ALLOW_FOREIGN_SEGMENT=1), and claims the controller slot (a slot held by a dead
  // controller is taken over). A segment still being created (0 bytes, or its header not yet
  // written) is waited for up to 1 s, then kProducerNotReady. On failure nothing stays
  // attached and the Status message says which check failed and what to do.
  Status open(const std::string& segment_name, const AdaptorOptions& options = {});

  // Blocks until the sensors of the next cycle are published, then copies them into `*out`.
  // Checks the segment first and whenever a wait slice ends (CheckSegment: memory, the SIGBUS
  // watch, one fstat): a truncated file or overwritten header gives kSegmentCorrupted, a
  // corrupted wake-up word kSyncCorrupted, now and on every later call, before any other result
  // (a producer that ended its run over a corrupted segment is not a normal end).
  // Only the entries in use (njoint, nforce, nimu of header()) are copied; the rest of `*out`
  // is left as it was. A cycle published before open (and not yet answered) is returned first.
  // A cycle is returned once: a wake-up for the cycle already returned (the producer posted
  // again before the copy) waits on for the next one.
  // Returns kDropped, before anything else, once the producer has let this controller go
  // (Producer::DropController): the slot is no longer this process's. The wait spins for a
  // bounded time before it sleeps (layout.h: handshake). Returns kSyncCorrupted, now and on
  // every later call, once the wake-up words are found corrupted.
  ReadResult read(SensorBlock* out);
  // The status word of the block the producer published last, read or not (0 when not open):
  // after read() returned kProducerStopped, what the producer said in its final block (e.g.
  // status::kFallen) even when that block came with the end of the run and was not returned.
  uint32_t published_status() const;

  // Writes the commands answering the last cycle read (answers_cycle is set here) and posts
  // commands_ready. Copies the guard record and commands.njoint (clamped to kMaxJoints) joints; `seq` and
  // `answers_cycle` of `commands` are ignored. Returns kDropped once the producer has let this
  // controller go, and kProducerStopped once the producer has ended its run, writing nothing;
  // kSyncCorrupted when the wake-up word was found corrupted (the commands are written, but
  // the producer will not take them); kSegmentCorrupted when the segment's file was truncated
  // or its header overwritten (a fault seen by read, or during this write).
  ReadResult write(const CommandBlock& commands);

  // Asks the producer for the images of the cameras in `cameras` (bit i: camera i of the
  // header; 0 withdraws). close() withdraws too, and a dead process's request is ignored. False
  // when not open, when a bit names no camera of the header, or when kMaxImageRequesters
  // programs already ask.
  bool request_images(uint32_t cameras);

  // Copies the latest frame of camera `camera` when it is newer than `after_frame` (0: any)
  // into `*out` (allocate it once: about 2 MB). kOk, kNoFrame, kBusy, kBadCamera or kNotOpen
  // (images.h: ReadLatestImage). Real-time safe; never waits for a new frame.
  ImageResult read_image(int camera, uint64_t after_frame, ImageSlot* out) const;

  // True once the producer has let this controller go (its slot holds another pid or none).
  bool dropped() const;

  // Releases the controller slot and unmaps the segment. Safe to call twice.
  void close();

  bool is_open() const { return segment_ != nullptr; }
  // A copy of the header, validated at open (CheckHeaderValues; names NUL-terminated).
  const SegmentHeader& header() const { return header_; }
  // The producer's state now (read from the segment, not the copy): after read() returned
  // kProducerStopped, kFailed tells a failed run (e.g. a diverged simulation) from a clean end.
  ProducerState producer_state() const;
  // What was found wrong with the segment (kNone while nothing).
  SegmentFault fault() const { return fault_; }

 private:
  // `r`, unless the segment is faulty (checked now): then kSyncCorrupted or kSegmentCorrupted
  ReadResult Checked(ReadResult r);
  ReadResult FaultResult() const;

  Segment* segment_ = nullptr;
  void* region_ = nullptr;  // boost mapped_region, owned
  int fd_ = -1;             // the segment's file, for fstat
  int watch_ = -1;          // the mapping watch's slot (segment_guard.h)
  SegmentFault fault_ = SegmentFault::kNone;
  SegmentHeader header_{};
  AdaptorOptions options_;
  uint64_t last_cycle_ = 0;
  bool have_cycle_ = false;
  int64_t wait_typical_ns_ = 0;  // what read's waits took, smoothed (its spin budget)
};

}  // namespace ohrp::shm
