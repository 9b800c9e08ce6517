// The robot segment: the fixed, self-describing memory layout shared by a producer (sim_host,
// hw_driver, a replay) and one controller. Plain data only, no pointers, SI units throughout
// (positions [m] or [rad], velocities [m/s] or [rad/s], forces [N], torques [N m], time [s]).
//
// ---------------------------------------------------------------------------------------------
// Segment = SegmentHeader | SensorBlock | CommandBlock | Sync | ImageArea, at the offsets of
// `Segment` below.
//
// Who writes what (one writer per block):
//   header        producer, once before `state` becomes kRunning (then read-only), except
//                 `controller_pid` (claimed by a controller with compare-and-swap) and `state`.
//   sensors       producer, every control cycle, under the `sensors.seq` seqlock.
//   commands      controller, every control cycle, under the `commands.seq` seqlock.
//   images        producer, per camera frame, under each slot's seqlock (images.h); the
//                 request entries: each attached program (controller or observer) its own.
//
// Lock-step handshake (two wake-up words in `Sync`, futexes the bridge owns, both start at 0):
//   1. producer  : finishes the physics steps of cycle k, writes sensors (cycle = k),
//                  posts `sensors_ready` (a post sets a bit: never more than one pending).
//   2. controller: `read` waits on `sensors_ready` (CLOCK_MONOTONIC deadline), copies the block.
//   3. controller: `write` fills commands (answers_cycle = k), posts `commands_ready`.
//   4. producer  : waits on `commands_ready` until its timeout (lock-step) or until the cycle's
//                  deadline (real time), copies the commands; they act from step k+1 on.
// A wake-up word holds only two bits: kSignalPosted (a post is pending) and kSignalSleeping (its
// waiter sleeps in FUTEX_WAIT). A post sets kSignalPosted and makes the wake system call only
// when kSignalSleeping was set; the waiter takes the post by clearing the word. A waiter first
// stays awake for a bounded time: about twice what its peer took to answer lately (from the
// start of the wait to the post time the poster stamps in `post_ns`, so that the waiter's own
// wake-up latency does not count), at most 300 us, not at all when its peer takes longer. It
// spins when the poster last ran on another CPU (`poster_cpu`) and hands its CPU to the poster
// (sched_yield) when they share one; then it sleeps in FUTEX_WAIT. Any other value of a word is
// a corrupted segment: both ends report it (never abort, never spin on it).
// Waits are cut into short slices; between slices each side checks that its peer's pid is
// still alive, so a dead peer is noticed within one slice, not at the end of the timeout.
// Timeouts are on CLOCK_MONOTONIC, which does not jump with the system clock.
// Seqlock rule for both data blocks: the writer increments `seq` to an odd value, writes, then
// increments it to an even value (release). A reader copies the block and retries when `seq`
// was odd or changed during the copy. Readers never trust counts read from the segment: a
// controller refuses a header whose counts exceed the k* maxima below (CheckHeaderValues), and
// every count is clamped to them before use.
// Fields shared across processes while both run (`state`, `controller_pid`, `seq`) are plain
// integers accessed only through std::atomic_ref, so every block stays trivially copyable.
// ---------------------------------------------------------------------------------------------
#pragma once

#include <cstddef>
#include <cstdint>

namespace ohrp::shm {

//---------------- capacities and identification ----------------

inline constexpr char kMagic[8] = {'O', 'H', 'R', 'P', 'S', 'E', 'G', '1'};
inline constexpr uint32_t kLayoutVersion = 6;  // 2: the robot model's identity (model_hash...);
                                               // 3: futex wake-up words instead of sem_t;
                                               // 4: passive joints (npassive, passive_q...);
                                               // 5: camera images (ImageArea);
                                               // 6: the guard record (CommandBlock::guard)
inline constexpr int kMaxJoints = 64;   // actuated joints
inline constexpr int kMaxPassiveJoints = 32;  // joints no actuator drives, published read-only
inline constexpr int kMaxForceSensors = 4;  // 6-axis force/torque sensors
inline constexpr int kMaxImus = 2;
inline constexpr int kMaxCameras = 4;
inline constexpr int kNameLen = 32;     // bytes per name, NUL-terminated
inline constexpr int kMaxImageWidth = 640;   // largest camera image [pixel]
inline constexpr int kMaxImageHeight = 480;
inline constexpr int kImageSlots = 2;        // slots per camera (double-buffered)
inline constexpr int kMaxImageRequesters = 16;  // programs that may ask for images at once

// who fills the segment; a controller never needs to ask, but tools and logs do
enum class ProducerKind : uint32_t { kUnknown = 0, kSimulation = 1, kHardware = 2, kReplay = 3 };

// producer lifecycle, in SegmentHeader::state
enum class ProducerState : uint32_t {
  kCreating = 0,  // header being written: do not attach yet
  kRunning = 1,   // sensors published every cycle
  kStopped = 2,   // producer ended its run cleanly (the segment is about to be removed)
  kFailed = 3,    // producer stopped on an error (e.g. the simulation diverged)
};

// per-joint command mode
enum class JointMode : uint32_t {
  kOff = 0,       // no torque from the servo (the joint is limp)
  kPosition = 1,  // tau = kp (q_ref - q) + kd (dq_ref - dq) + tau_ff
  kVelocity = 2,  // tau = kd (dq_ref - dq) + tau_ff
  kTorque = 3,    // tau = tau_ff
};

// bits of SensorBlock::status
namespace status {
inline constexpr uint32_t kRunning = 1u << 0;            // producer is cycling normally
inline constexpr uint32_t kNoController = 1u << 1;       // no controller attached
inline constexpr uint32_t kHolding = 1u << 2;            // holding last references (peer lost)
inline constexpr uint32_t kCommandRejected = 1u << 3;    // a joint command was rejected this cycle
inline constexpr uint32_t kCommandLate = 1u << 4;        // the last commands came too late
inline constexpr uint32_t kShuttingDown = 1u << 5;       // last cycle: producer is ending
inline constexpr uint32_t kDiverged = 1u << 6;           // simulation diverged; data invalid
inline constexpr uint32_t kSimulated = 1u << 16;         // sim_truth is valid (simulation only)
// set by hw_driver (a simulation producer never sets them)
inline constexpr uint32_t kServoOff = 1u << 7;           // the robot's servos are off (before servo-on,
                                                         // after safe mode or an emergency stop)
inline constexpr uint32_t kBoardFault = 1u << 8;         // a board is silent, reset, or reports a
                                                         // stuck or saturated sensor this cycle
inline constexpr uint32_t kEmergencyStop = 1u << 9;      // the emergency stop was triggered
// set by a producer that judges falls (sim_host's fall watch), in every block from the first
// fall on, the last one included: a controller whose own watch saw nothing still learns it
inline constexpr uint32_t kFallen = 1u << 10;
// set by sim_host while paused from its control channel: the last block is republished (same
// cycle) every 0.25 s as a heartbeat; a controller's read() waits on through it (its
// --read-timeout starts again at each one) instead of taking the pause for a dead producer
inline constexpr uint32_t kPaused = 1u << 11;
}  // namespace status

//---------------- header ----------------

struct CameraInfo {
  char name[kNameLen];
  int32_t width;       // [pixel]
  int32_t height;      // [pixel]
  double fovy;         // vertical field of view [deg]
  double p_BC[3];      // camera position in its parent body frame [m]
};

struct SegmentHeader {
  char magic[8];                    // kMagic
  uint32_t layout_version;          // kLayoutVersion
  uint32_t header_size;             // sizeof(SegmentHeader) as the producer built it [byte]
  uint64_t layout_hash;             // LayoutHash() as the producer built it
  uint64_t segment_size;            // sizeof(Segment) [byte]
  ProducerKind producer_kind;
  int32_t producer_pid;             // process id of the producer
  uint32_t state;                   // ProducerState (atomic access: std::atomic_ref)
  int32_t controller_pid;           // 0: free; else the attached controller's pid (atomic)
  char robot_name[kNameLen];

  int32_t njoint;                   // actuated joints, <= kMaxJoints
  int32_t nforce;                   // force/torque sensors, <= kMaxForceSensors
  int32_t nimu;                     // IMUs, <= kMaxImus
  int32_t ncamera;                  // cameras declared, <= kMaxCameras
  char joint_names[kMaxJoints][kNameLen];        // in joint-id order
  char force_names[kMaxForceSensors][kNameLen];
  char imu_names[kMaxImus][kNameLen];
  CameraInfo cameras[kMaxCameras];

  double q_min[kMaxJoints];         // joint position limits (njoint) [rad or m]
  double q_max[kMaxJoints];
  double tau_max[kMaxJoints];       // torque limit magnitude (njoint) [N m or N]
  double default_kp[kMaxJoints];    // producer's suggested position gains (njoint) [N m/rad]
  double default_kd[kMaxJoints];    // producer's suggested damping gains (njoint) [N m s/rad]

  double physics_period;            // integration step [s] (0 for hardware)
  double control_period;            // period of the sensor/command cycle [s]
  double read_timeout_hint;         // how long a producer may take per cycle [s]

  // the robot model's identity: a controller that loads its own MJCF compares it with these
  // (robot_model/model_hash.h: CheckModelMatches) and refuses a producer whose robot differs
  uint64_t model_hash;              // ModelHash of the producer's robot (0: not published)
  int32_t nbody;                    // bodies of the robot (the base's subtree, or all bodies
                                    // but the world for a fixed robot)
  int32_t pad0;
  double total_mass;                // mass of those bodies [kg]
  double joint_axis[kMaxJoints][3]; // joint axis in its body's frame (njoint x 3) [unit vector]
  double link_mass[kMaxJoints];     // mass of the body each joint moves (njoint) [kg]

  // passive joints: the robot's hinge and slide joints no actuator drives (e.g. Cassie's shin
  // and tarsus), published read-only in SensorBlock::passive_q/passive_dq, never commanded
  int32_t npassive;                 // passive joints, <= kMaxPassiveJoints
  int32_t pad1;
  char passive_names[kMaxPassiveJoints][kNameLen];  // in the model's joint order
};

//---------------- sensor block (producer -> controller) ----------------

// Convention (OpenHRP's): what the child side (e.g. the foot and whatever it touches) exerts on
// the parent side (the leg), in the sensor frame. A robot standing still on two feet reads
// about +m g / 2 along the sensor's z at each ankle when the sensor frame is upright.
struct ForceTorque {
  double force[3];   // force exerted by the child side on the parent side, sensor frame [N]
  double torque[3];  // moment of that force about the sensor origin, sensor frame [N m]
};

struct Imu {
  double gyro[3];    // angular velocity in the IMU frame [rad/s]
  double accel[3];   // specific force in the IMU frame (reads +g when at rest) [m/s^2]
  double quat_WI[4]; // orientation of the IMU frame in the world, (w, x, y, z)
};

// Simulation-only ground truth: valid only when status has kSimulated. A controller that
// uses it cannot run on the robot; it is here for logging and for test checks.
struct SimTruth {
  double p_WB[3];     // base (root body) position in world [m]
  double quat_WB[4];  // base orientation (w, x, y, z)
  double v_WB[3];     // base linear velocity in world [m/s]
  double w_WB[3];     // base angular velocity in world [rad/s]
};

struct SensorBlock {
  uint64_t seq;                     // seqlock counter, odd while written (atomic access)
  uint64_t cycle;                   // control cycle index k, starts at 0
  double time;                      // simulated (or robot) time at the end of cycle k [s]
  uint32_t status;                  // status:: bits
  uint32_t pad0;
  uint64_t last_command_cycle;      // answers_cycle of the last accepted command block
  uint64_t late_commands;           // cycles whose commands missed their deadline/timeout
  uint64_t rejected_commands;       // joint commands rejected so far (NaN, out of range)
  uint32_t rejected_per_joint[kMaxJoints];  // same, per joint (njoint)

  double q[kMaxJoints];             // joint position (njoint) [rad or m]
  double dq[kMaxJoints];            // joint velocity (njoint) [rad/s or m/s]
  double tau[kMaxJoints];           // joint torque applied by the servo (njoint) [N m or N]
  ForceTorque force[kMaxForceSensors];  // (nforce)
  Imu imu[kMaxImus];                // (nimu)
  SimTruth sim_truth;
  double passive_q[kMaxPassiveJoints];   // passive joint position (npassive) [rad or m]
  double passive_dq[kMaxPassiveJoints];  // passive joint velocity (npassive) [rad/s or m/s]
};

//---------------- command block (controller -> producer) ----------------

struct JointCommand {
  JointMode mode;
  uint32_t pad0;
  double q_ref;    // reference position [rad or m]
  double dq_ref;   // reference velocity [rad/s or m/s]
  double tau_ff;   // feed-forward torque [N m or N]
  double kp;       // position gain [N m/rad]
  double kd;       // velocity gain [N m s/rad]
};

// What the controller's self-collision guard did this cycle (controllers/self_collision_guard.h),
// so that a hold is a result the producer records (sim_host: an event when a hold begins and
// ends, the summary's "self_collision_guard", the data log's guard_holding) and not only a line
// of the controller's report. All zero from a controller without the guard.
struct GuardRecord {
  uint32_t holding;          // 1: the guard braked or held the motion this cycle, else 0
  uint32_t pad0;
  uint64_t holds;            // hold episodes begun since the controller started
  double distance;           // the held pair's predicted distance [m] (0 when not holding)
  char link_a[kNameLen];     // the held pair's links (NUL-terminated; empty when not holding)
  char link_b[kNameLen];
};

struct CommandBlock {
  uint64_t seq;                     // seqlock counter, odd while written (atomic access)
  uint64_t answers_cycle;           // the sensor cycle k these commands answer
  int32_t njoint;                   // joints filled, must equal header njoint
  int32_t pad0;
  GuardRecord guard;                // the controller's self-collision guard this cycle
  JointCommand joint[kMaxJoints];   // (njoint), joint-id order
};

//---------------- synchronisation ----------------

// bits of SignalWord::word (handshake above); any other bit set means a corrupted segment
inline constexpr uint32_t kSignalPosted = 1u << 0;    // a post is pending
inline constexpr uint32_t kSignalSleeping = 1u << 1;  // the waiter sleeps in FUTEX_WAIT

// one direction of the handshake, alone on its cache line
struct SignalWord {
  uint32_t word;        // futex word: kSignalPosted | kSignalSleeping (atomic access)
  int32_t poster_cpu;   // CPU the poster ran on at its last post, -1 unknown (atomic access)
  int64_t post_ns;      // CLOCK_MONOTONIC time of the last post [ns] (atomic access)
  // poster_cpu and post_ns are hints for the waiter's spin, never trusted for anything else
};

struct Sync {
  alignas(64) SignalWord sensors_ready;   // posted by the producer when sensors are published
  alignas(64) SignalWord commands_ready;  // posted by the controller when commands are written
};

//---------------- camera images (producer -> readers; API: images.h) ----------------
//
// Kept apart from the sensor block: the per-cycle copy of the sensors never touches them, and
// the producer renders only while some program asks (requests below). Camera i of the header
// (cameras[i]) publishes into images.camera[i].
//
// Frames of a camera go alternately into its two slots (frame f into slot f % 2), each under
// its own seqlock (same rule as the data blocks), then `latest` is set to f (release). A reader
// loads `latest`, copies slot latest % 2 and keeps the copy only when the slot's seq was even
// and unchanged across the copy; otherwise it retries with the new `latest`. The producer never
// waits for a reader: a reader slower than two frames retries (and gives up at its deadline).
//
// Requests: each program that wants images holds one entry {pid, cameras bitmask (bit i:
// camera i)}, claimed by compare-and-swap of `pid` from 0 (or from a dead pid); it withdraws by
// writing 0 to both. The producer renders camera i while some entry of a live pid has bit i.
// The entries lie on their own page, so that an observer (whose segment mapping is read-only)
// can map that page alone for writing.

struct ImageSlot {
  uint64_t seq;           // seqlock counter, odd while written (atomic access)
  uint64_t frame;         // frame counter of the camera, 1 for its first frame
  double time;            // simulated (or robot) time of capture [s]
  int32_t width;          // [pixel], <= the header camera's width and kMaxImageWidth
  int32_t height;         // [pixel], <= the header camera's height and kMaxImageHeight
  uint32_t has_depth;     // 1: depth holds width x height values; 0: no depth
  uint32_t pad0;
  alignas(64) uint8_t rgb[kMaxImageWidth * kMaxImageHeight * 3];  // RGB8, row-major, top row
                                                                  // first (width x height x 3)
  alignas(64) float depth[kMaxImageWidth * kMaxImageHeight];  // distance along the optical axis
                                                              // [m], same order; when has_depth
};

struct CameraImages {
  alignas(64) uint64_t latest;  // frame of the last complete slot, 0: none yet (atomic access)
  alignas(64) ImageSlot slot[kImageSlots];
};

struct ImageRequest {
  int32_t pid;        // requesting process, 0: free entry (atomic access)
  uint32_t cameras;   // bitmask of the cameras it wants (atomic access)
};

struct ImageArea {
  alignas(4096) ImageRequest requests[kMaxImageRequesters];  // alone on its page
  alignas(4096) CameraImages camera[kMaxCameras];
};

struct Segment {
  SegmentHeader header;
  alignas(64) SensorBlock sensors;
  alignas(64) CommandBlock commands;
  alignas(64) Sync sync;
  alignas(4096) ImageArea images;
};

// A hash of the layout (sizes and offsets of every block and of the capacities), so that a
// controller built against another layout is refused on attach instead of misreading.
// Deterministic: FNV-1a (64 bit) over kLayoutVersion, the k* capacities and the sizeof and
// offsetof of every struct and field above, each fed as 8 little-endian bytes.
uint64_t LayoutHash();

// FNV-1a (64 bit) of the `n` bytes at `data`, continuing from `h` (the FNV offset basis when
// starting). LayoutHash is built from it; exposed so tests can check it against known vectors.
inline constexpr uint64_t kFnv1aOffsetBasis = 14695981039346656037ull;
inline constexpr uint64_t kFnv1aPrime = 1099511628211ull;
constexpr uint64_t Fnv1a64(const char* data, std::size_t n, uint64_t h = kFnv1aOffsetBasis) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<uint8_t>(data[i]);
    h *= kFnv1aPrime;
  }
  return h;
}

}  // namespace ohrp::shm
