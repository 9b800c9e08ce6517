// The hardware side of hw_driver: the robot's IO boards behind the paper's four calls
// (open, read, write, close; OpenHRP section 3.1.2). An implementation lives in a shared object
// named on hw_driver's command line and is loaded at start-up, so that a vendor's board support
// drops in without rebuilding the driver. Two ship with the platform: `udp` (the documented UDP
// protocol to the motor and sensor boards, see hw_driver/udp/PROTOCOL.md) and `replay` (a
// recorded data log played back as if it came from the boards).
//
// A plugin exports one C symbol, kRobotIoEntry, returning a new RobotIo (owned by the caller,
// destroyed with `delete` through the virtual destructor; plugin and driver are built by the
// same compiler from this header) and checks kRobotIoAbiVersion.
//
// Units and frames are the segment's (shm_bridge/layout.h): SI, joint-id order, force/torque in
// OpenHRP's sign convention, IMU quaternion (w, x, y, z).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::hw {

inline constexpr uint32_t kRobotIoAbiVersion = 6;  // 2: IoState::nonfinite_boards;
                                                   // 3: cameras (IoConfig::cameras, images);
                                                   // 4: IoState::reports and the boards' masks;
                                                   // 5: passive joints (IoConfig::passive_names,
                                                   //    IoState::passive_q, passive_dq)
                                                   // 6: IoState::applied_q, applied_dq
inline constexpr const char* kRobotIoEntry = "ohrp_create_robot_io";

// What the driver tells the boards at open: the robot (from its model) and the plugin's own
// arguments (--io-arg KEY=VALUE, repeated).
struct IoConfig {
  std::string robot_name;
  std::vector<std::string> joint_names;  // joint-id order
  std::vector<std::string> force_names;
  std::vector<std::string> imu_names;
  std::vector<std::string> passive_names;  // joints no motor drives (measured only), model order
  std::vector<shm::CameraInfo> cameras;  // the robot's cameras, header order (name, size, fovy)
  double period = 0.001;                 // servo cycle of the driver [s]
  std::vector<std::string> args;         // "key=value" strings for the plugin
};

// bits of IoState::faults
namespace io_fault {
inline constexpr uint32_t kBoardSilent = 1u << 0;    // a board did not answer within its timeout
inline constexpr uint32_t kPacketLost = 1u << 1;     // packets lost or corrupted this cycle
inline constexpr uint32_t kSensorStuck = 1u << 2;    // a sensor repeats the same value (board says so)
inline constexpr uint32_t kSensorSaturated = 1u << 3;
inline constexpr uint32_t kBoardReset = 1u << 4;     // a board restarted (its servos are off)
inline constexpr uint32_t kEmergencyStop = 1u << 5;  // the robot's emergency-stop input is pressed
inline constexpr uint32_t kEndOfData = 1u << 6;      // replay: the recording is over
inline constexpr uint32_t kNonFinite = 1u << 7;      // a board sent a NaN or infinite value
                                                     // (IoState::nonfinite_boards says which)
}  // namespace io_fault

// bits of IoState::reports: what a plugin measures, so that the driver checks it (a plugin that
// leaves a bit clear is not held to it)
namespace io_report {
inline constexpr uint32_t kServoState = 1u << 0;      // servo_on[] is what the boards do
inline constexpr uint32_t kFollowsCommands = 1u << 1; // the joints are driven by the commands
                                                      // written (not a replay): tracking checked
inline constexpr uint32_t kBoards = 1u << 2;          // joint_board[] and the board masks below
inline constexpr uint32_t kAppliedReferences = 1u << 3;  // applied_q[], applied_dq[]: the
                                                      // references the boards had when they
                                                      // measured these data
}  // namespace io_report

// The boards' latest measurements, as read once per cycle.
struct IoState {
  uint64_t time_ns = 0;                  // the boards' timestamp of these data [ns]
  uint32_t faults = 0;                   // io_fault:: bits
  uint32_t silent_boards = 0;            // bit i: board i silent this cycle
  uint32_t nonfinite_boards = 0;         // bit i: board i's latest data hold a NaN or inf
  uint64_t packets_lost = 0;             // total since open
  uint32_t reports = 0;                  // io_report:: bits (set by the plugin)
  // with io_report::kBoards, bit b of each mask is board b:
  uint32_t reset_boards = 0;             // reports a reset, not re-armed yet (servos off)
  uint32_t unacked_boards = 0;           // has not acknowledged the commands sent to it for
                                         // the plugin's board timeout (or acknowledges old ones)
  uint32_t refused_boards = 0;           // refused a joint command of the driver (its last one)
  uint32_t foreign_boards = 0;           // refused commands of another sender or session lately
  int8_t joint_board[shm::kMaxJoints] = {};  // the board of each joint (io_report::kBoards)
  double q[shm::kMaxJoints] = {};        // [rad or m]
  double dq[shm::kMaxJoints] = {};       // [rad/s or m/s]
  double tau[shm::kMaxJoints] = {};      // motor torque [N m or N]
  bool servo_on[shm::kMaxJoints] = {};   // what the motor boards report
  shm::ForceTorque force[shm::kMaxForceSensors] = {};
  shm::Imu imu[shm::kMaxImus] = {};
  // the passive joints' encoders (IoConfig::passive_names order), read like the driven ones
  double passive_q[shm::kMaxPassiveJoints] = {};   // [rad or m]
  double passive_dq[shm::kMaxPassiveJoints] = {};  // [rad/s or m/s]
  // with io_report::kAppliedReferences: per joint, the reference position and velocity of the
  // command its board had accepted when it measured these data (the one its state
  // acknowledges), before any delay of the board's own; the driver's data log records it as the
  // reference in the boards' time (--log-time board)
  double applied_q[shm::kMaxJoints] = {};   // [rad or m]
  double applied_dq[shm::kMaxJoints] = {};  // [rad/s or m/s]
};

// What the driver sends the boards once per cycle: servo power and, per joint, the command
// the motor board's own PD runs until the next one (same meaning as shm::JointCommand).
struct IoCommand {
  bool servo_on[shm::kMaxJoints] = {};
  shm::JointCommand joint[shm::kMaxJoints] = {};
};

enum class IoResult {
  kOk,
  kFault,   // the call went through but IoState::faults says what is wrong
  kError,   // the transport itself failed (socket error, file gone)
};

// Where a plugin delivers camera images: the driver's segment (Producer::PublishImage).
class ImageSink {
 public:
  // A frame of IoConfig::cameras[camera] captured at `time` [s, the driver's time base: that of
  // the cycle whose IoState was read at capture]: `rgb` width x height x 3 bytes (RGB8, top row
  // first; at most the camera's size), `depth` width x height distances [m] or null. False
  // when the segment refuses it (camera index or size). Never waits.
  virtual bool Publish(int camera, double time, int width, int height, const uint8_t* rgb,
                       const float* depth) noexcept = 0;

 protected:
  ~ImageSink() = default;
};

// The boards. open/close are set-up calls (they may allocate and report in `*error`); read and
// write run every servo cycle and never allocate, throw or block past the cycle.
class RobotIo {
 public:
  virtual ~RobotIo() = default;
  virtual bool open(const IoConfig& config, std::string* error) = 0;
  // Fills `*state` with the latest data; must return within a small fraction of the period.
  virtual IoResult read(IoState* state) noexcept = 0;
  virtual IoResult write(const IoCommand& command) noexcept = 0;
  virtual void close() noexcept = 0;
  // Camera images: called once per cycle, after read, with the cameras some attached program
  // asks for (bit i: IoConfig::cameras[i]; 0: nobody asks, and a plugin should then do no
  // work) and the driver's time of the cycle [s]. Hands the frames captured since the last
  // call to `sink` (the latest per camera). Runs in the servo cycle: no allocation, no
  // blocking (a real camera's plugin grabs frames on its own thread). The default: no images.
  virtual void images(uint32_t wanted, double time, ImageSink* sink) noexcept {
    (void)wanted;
    (void)time;
    (void)sink;
  }
};

}  // namespace ohrp::hw

// The one symbol a plugin exports (see kRobotIoEntry).
extern "C" ohrp::hw::RobotIo* ohrp_create_robot_io(uint32_t abi_version);
