// The UDP protocol between hw_driver (through the `udp` RobotIo plugin) and the robot's boards:
// packet layout, encoding and decoding, checksums, and the sequence-number bookkeeping.
// The byte-level specification is hw_driver/udp/PROTOCOL.md; this header implements it.
//
// In short: every datagram is one packet = a 24-byte header | payload | CRC-32 (4 bytes), all
// little-endian, floating-point values as IEEE-754 binary64. The driver sends one command packet
// per motor board per cycle; every board answers one state packet per cycle (motor boards: joint
// states; the sensor board: force/torque sensors and IMUs). Each sender numbers its packets per
// board (seq, +1 per packet, wrapping at 2^32); the receiver counts gaps as lost packets.
//
// Units are the segment's (shm_bridge/layout.h): SI, joint-id order, F/T in OpenHRP's sign
// convention, IMU quaternion (w, x, y, z). Nothing here allocates except the layout helpers
// (set-up only); Encode*/Decode* run every cycle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::hw::udp {

//---------------- constants ----------------

inline constexpr uint16_t kMagic = 0x4855;        // bytes 'U','H' on the wire
inline constexpr uint8_t kVersion = 3;            // bump on any incompatible change (2: the
                                                  // driver's session id in its packets' ack field;
                                                  // 3: passive joints in the sensor state)
inline constexpr size_t kHeaderSize = 24;         // [byte]
inline constexpr size_t kCrcSize = 4;             // [byte]
inline constexpr int kMaxBoardJoints = 8;         // joints per motor board
inline constexpr int kMaxBoards = 16;             // motor boards + the sensor board
inline constexpr size_t kCommandJointSize = 42;   // bytes per joint in a command packet
inline constexpr size_t kStateJointSize = 26;     // bytes per joint in a motor state packet
inline constexpr size_t kForceSize = 48;          // bytes per F/T sensor (6 doubles)
inline constexpr size_t kImuSize = 80;            // bytes per IMU (10 doubles)
inline constexpr size_t kPassiveSize = 16;        // bytes per passive joint (q, dq)
inline constexpr size_t kMaxPacketSize = 1024;    // every packet of this protocol fits [byte]
inline constexpr int kDefaultPort = 7700;         // the boards' UDP port (emulator default)
// the largest forward jump of a sequence number a receiver accepts: further ahead is no gap of
// a sender it knows (65 s of packets at 1 kHz) but a forged or corrupted number, refused
inline constexpr uint32_t kMaxSeqJump = 1u << 16;

// packet types (header byte 3)
enum class PacketType : uint8_t {
  kHello = 1,        // driver -> board: "send your states to me" (no payload)
  kCommand = 2,      // driver -> motor board
  kMotorState = 3,   // motor board -> driver
  kSensorState = 4,  // sensor board -> driver
};

// header flags of state packets (board -> driver)
namespace board_flag {
inline constexpr uint8_t kReset = 1u << 0;           // the board restarted; its servos stay off
                                                      // until a command turns all of them off
inline constexpr uint8_t kSensorStuck = 1u << 1;     // a sensor repeats the same value
inline constexpr uint8_t kSensorSaturated = 1u << 2; // a sensor reads at the end of its range
inline constexpr uint8_t kEmergencyStop = 1u << 3;   // the e-stop input is pressed (sensor board)
inline constexpr uint8_t kJointFault = 1u << 4;      // a joint of the board refused its command
inline constexpr uint8_t kForeign = 1u << 5;         // the board refused a hello or command of
                                                      // another sender or session lately
inline constexpr uint8_t kHolding = 1u << 6;         // no valid command for the board's hold time:
                                                      // it holds its joints where they are
}  // namespace board_flag

//---------------- packets (decoded form) ----------------

// The fixed header every packet starts with.
struct Header {
  uint8_t type = 0;      // PacketType
  uint8_t board = 0;     // board id, 0 .. nboards-1 (motor boards first, then the sensor board)
  uint8_t count = 0;     // joints carried (command / motor state), F/T sensors (sensor state)
  uint8_t first = 0;     // first joint id carried (motor packets), IMUs (sensor state)
  uint8_t flags = 0;     // board_flag:: bits (state packets); 0 in driver packets
  uint32_t seq = 0;      // sender's packet number for this board, +1 per packet
  uint32_t ack = 0;      // motor state: seq of the last command the board applied; hello and
                         // command: the driver's session id (non-zero, chosen at its open);
                         // sensor state: the passive joints carried
  uint64_t time_ns = 0;  // sender's clock: driver's monotonic time / board time [ns]
};

struct JointCommandWire {
  bool servo_on = false;
  shm::JointCommand cmd{};  // mode, q_ref, dq_ref, tau_ff, kp, kd
};

struct CommandPacket {
  Header h;  // type kCommand; first/count: the board's joint range
  JointCommandWire joint[kMaxBoardJoints];
};

struct JointStateWire {
  bool servo_on = false;
  uint8_t fault = 0;  // non-zero: the joint's last command was refused (it holds)
  double q = 0, dq = 0, tau = 0;  // [rad or m], [rad/s or m/s], [N m or N]
};

struct MotorStatePacket {
  Header h;  // type kMotorState
  JointStateWire joint[kMaxBoardJoints];
};

struct SensorStatePacket {
  Header h;  // type kSensorState; count = F/T sensors, first = IMUs, ack = passive joints
  shm::ForceTorque force[shm::kMaxForceSensors];
  shm::Imu imu[shm::kMaxImus];
  double passive_q[shm::kMaxPassiveJoints];   // [rad or m]
  double passive_dq[shm::kMaxPassiveJoints];  // [rad/s or m/s]
};

//---------------- encoding and decoding ----------------

// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320, init and final xor 0xFFFFFFFF) of `n`
// bytes: the check value of "123456789" is 0xCBF43926.
uint32_t Crc32(const uint8_t* data, size_t n);

// Each Encode writes the whole packet (header, payload, CRC) into `out` (at least
// kMaxPacketSize bytes) and returns its size, or 0 when the packet's counts are out of range.
// The header's type is set by the function.
size_t EncodeHello(Header h, uint8_t* out);
size_t EncodeCommand(const CommandPacket& p, uint8_t* out);
size_t EncodeMotorState(const MotorStatePacket& p, uint8_t* out);
size_t EncodeSensorState(const SensorStatePacket& p, uint8_t* out);

enum class DecodeError {
  kOk,
  kTooShort,     // shorter than a header + CRC
  kBadMagic,     // not this protocol
  kBadVersion,   // another version of it
  kBadChecksum,  // corrupted
  kBadLength,    // the size does not match the type and counts
  kBadType,
};
const char* DecodeErrorName(DecodeError e);

// Checks magic, version and CRC of a received datagram and decodes its header.
DecodeError DecodeHeader(const uint8_t* data, size_t n, Header* h);
// Decode the payload of a datagram whose header DecodeHeader accepted (they check its size).
DecodeError DecodeCommand(const uint8_t* data, size_t n, CommandPacket* p);
DecodeError DecodeMotorState(const uint8_t* data, size_t n, MotorStatePacket* p);
DecodeError DecodeSensorState(const uint8_t* data, size_t n, SensorStatePacket* p);

//---------------- sequence numbers ----------------

// Receiver-side bookkeeping of one board's sequence numbers.
//   seq == last + 1            in order: accepted
//   last + 1 < seq <= last + kMaxSeqJump
//                              a gap: accepted, seq - last - 1 packets counted lost
//   last + kMaxSeqJump < seq < last + 2^31
//                              a jump: refused (counted in `jumps`), unless `restart`
//   seq == last                duplicate: refused (counted in `stale`)
//   otherwise (behind)         old: refused (counted in `stale`), unless `restart` (the sender
//                              says it restarted, its numbering began again), which resyncs.
class SeqTracker {
 public:
  // Returns true when the packet is new and should be used.
  bool Accept(uint32_t seq, bool restart);
  bool started() const { return started_; }
  uint32_t last() const { return last_; }
  uint64_t lost() const { return lost_; }
  uint64_t stale() const { return stale_; }
  uint64_t jumps() const { return jumps_; }
  uint64_t received() const { return received_; }

 private:
  bool started_ = false;
  uint32_t last_ = 0;
  uint64_t lost_ = 0, stale_ = 0, jumps_ = 0, received_ = 0;
};

//---------------- board layout ----------------

// Which joints each motor board carries; the sensor board comes after the motor boards.
struct BoardLayout {
  struct Range {
    int first = 0;  // joint id
    int count = 0;  // <= kMaxBoardJoints
  };
  std::vector<Range> motor;  // motor board i carries joints motor[i].first ...
  int sensor_board() const { return static_cast<int>(motor.size()); }
  int nboards() const { return static_cast<int>(motor.size()) + 1; }
};

// The default layout from the joint names: consecutive joints whose names share the text before
// the first '_' (RLEG, RARM, ...) form a limb group; adjacent groups of fewer than 3 joints are
// merged (WAIST_P, WAIST_R, CHEST: the trunk) while they fit a board; groups above
// kMaxBoardJoints are split. For HRP-1S: 0-5, 6-12, 13-18, 19-25, 26-28.
BoardLayout DefaultLayout(const std::vector<std::string>& joint_names);

// Parses "0-5,6-12,13-18,19-25,26-28" (inclusive joint ranges, one per motor board, which must
// cover joints 0..njoint-1 in order). Returns false with `*error` set on a malformed spec.
bool ParseLayout(const std::string& spec, int njoint, BoardLayout* layout, std::string* error);
std::string LayoutString(const BoardLayout& layout);

}  // namespace ohrp::hw::udp
