// Packet encoding and decoding, CRC-32 and sequence numbers (see protocol.h, PROTOCOL.md).
#include "hw_udp/protocol.h"

#include <array>
#include <bit>
#include <cstring>

namespace ohrp::hw::udp {
namespace {

//---------------- little-endian primitives ----------------

// explicit byte order, so that the wire format does not depend on the host's
class Writer {
 public:
  explicit Writer(uint8_t* p) : p_(p) {}
  void U8(uint8_t v) { *p_++ = v; }
  void U16(uint16_t v) {
    for (int i = 0; i < 2; ++i) *p_++ = static_cast<uint8_t>(v >> (8 * i));
  }
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) *p_++ = static_cast<uint8_t>(v >> (8 * i));
  }
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) *p_++ = static_cast<uint8_t>(v >> (8 * i));
  }
  void F64(double v) { U64(std::bit_cast<uint64_t>(v)); }
  uint8_t* pos() const { return p_; }

 private:
  uint8_t* p_;
};

class Reader {
 public:
  explicit Reader(const uint8_t* p) : p_(p) {}
  uint8_t U8() { return *p_++; }
  uint16_t U16() {
    uint16_t v = 0;
    for (int i = 0; i < 2; ++i) v |= static_cast<uint16_t>(*p_++) << (8 * i);
    return v;
  }
  uint32_t U32() {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(*p_++) << (8 * i);
    return v;
  }
  uint64_t U64() {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(*p_++) << (8 * i);
    return v;
  }
  double F64() { return std::bit_cast<double>(U64()); }

 private:
  const uint8_t* p_;
};

constexpr std::array<uint32_t, 256> MakeCrcTable() {
  std::array<uint32_t, 256> t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}
constexpr std::array<uint32_t, 256> kCrcTable = MakeCrcTable();

void PutHeader(const Header& h, Writer* w) {
  w->U16(kMagic);
  w->U8(kVersion);
  w->U8(h.type);
  w->U8(h.board);
  w->U8(h.count);
  w->U8(h.first);
  w->U8(h.flags);
  w->U32(h.seq);
  w->U32(h.ack);
  w->U64(h.time_ns);
}

// appends the CRC of everything written so far; returns the packet size
size_t Finish(uint8_t* start, Writer* w) {
  const size_t n = static_cast<size_t>(w->pos() - start);
  w->U32(Crc32(start, n));
  return n + kCrcSize;
}

size_t ExpectedSize(const Header& h) {
  switch (static_cast<PacketType>(h.type)) {
    case PacketType::kHello: return kHeaderSize + kCrcSize;
    case PacketType::kCommand: return kHeaderSize + h.count * kCommandJointSize + kCrcSize;
    case PacketType::kMotorState: return kHeaderSize + h.count * kStateJointSize + kCrcSize;
    case PacketType::kSensorState:
      return kHeaderSize + h.count * kForceSize + h.first * kImuSize +
             static_cast<size_t>(h.ack) * kPassiveSize + kCrcSize;
  }
  return 0;
}

DecodeError CheckPayload(const uint8_t* data, size_t n, PacketType type, Header* h) {
  const DecodeError e = DecodeHeader(data, n, h);
  if (e != DecodeError::kOk) return e;
  if (h->type != static_cast<uint8_t>(type)) return DecodeError::kBadType;
  return DecodeError::kOk;
}

}  // namespace

uint32_t Crc32(const uint8_t* data, size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; ++i) c = kCrcTable[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

const char* DecodeErrorName(DecodeError e) {
  switch (e) {
    case DecodeError::kOk: return "ok";
    case DecodeError::kTooShort: return "too short";
    case DecodeError::kBadMagic: return "bad magic";
    case DecodeError::kBadVersion: return "bad version";
    case DecodeError::kBadChecksum: return "bad checksum";
    case DecodeError::kBadLength: return "bad length";
    case DecodeError::kBadType: return "bad type";
  }
  return "?";
}

//---------------- encoding ----------------

size_t EncodeHello(Header h, uint8_t* out) {
  h.type = static_cast<uint8_t>(PacketType::kHello);
  h.count = h.first = 0;
  Writer w(out);
  PutHeader(h, &w);
  return Finish(out, &w);
}

size_t EncodeCommand(const CommandPacket& p, uint8_t* out) {
  if (p.h.count > kMaxBoardJoints) return 0;
  Header h = p.h;
  h.type = static_cast<uint8_t>(PacketType::kCommand);
  Writer w(out);
  PutHeader(h, &w);
  for (int i = 0; i < h.count; ++i) {
    const JointCommandWire& j = p.joint[i];
    w.U8(j.servo_on ? 1 : 0);
    w.U8(static_cast<uint8_t>(j.cmd.mode));
    w.F64(j.cmd.q_ref);
    w.F64(j.cmd.dq_ref);
    w.F64(j.cmd.tau_ff);
    w.F64(j.cmd.kp);
    w.F64(j.cmd.kd);
  }
  return Finish(out, &w);
}

size_t EncodeMotorState(const MotorStatePacket& p, uint8_t* out) {
  if (p.h.count > kMaxBoardJoints) return 0;
  Header h = p.h;
  h.type = static_cast<uint8_t>(PacketType::kMotorState);
  Writer w(out);
  PutHeader(h, &w);
  for (int i = 0; i < h.count; ++i) {
    const JointStateWire& j = p.joint[i];
    w.U8(j.servo_on ? 1 : 0);
    w.U8(j.fault);
    w.F64(j.q);
    w.F64(j.dq);
    w.F64(j.tau);
  }
  return Finish(out, &w);
}

size_t EncodeSensorState(const SensorStatePacket& p, uint8_t* out) {
  if (p.h.count > shm::kMaxForceSensors || p.h.first > shm::kMaxImus ||
      p.h.ack > static_cast<uint32_t>(shm::kMaxPassiveJoints))
    return 0;
  Header h = p.h;
  h.type = static_cast<uint8_t>(PacketType::kSensorState);
  Writer w(out);
  PutHeader(h, &w);
  for (int i = 0; i < h.count; ++i) {
    for (double v : p.force[i].force) w.F64(v);
    for (double v : p.force[i].torque) w.F64(v);
  }
  for (int i = 0; i < h.first; ++i) {
    for (double v : p.imu[i].gyro) w.F64(v);
    for (double v : p.imu[i].accel) w.F64(v);
    for (double v : p.imu[i].quat_WI) w.F64(v);
  }
  for (uint32_t i = 0; i < h.ack; ++i) {
    w.F64(p.passive_q[i]);
    w.F64(p.passive_dq[i]);
  }
  return Finish(out, &w);
}

//---------------- decoding ----------------

DecodeError DecodeHeader(const uint8_t* data, size_t n, Header* h) {
  if (n < kHeaderSize + kCrcSize) return DecodeError::kTooShort;
  Reader r(data);
  if (r.U16() != kMagic) return DecodeError::kBadMagic;
  if (r.U8() != kVersion) return DecodeError::kBadVersion;
  Reader crc(data + n - kCrcSize);
  if (crc.U32() != Crc32(data, n - kCrcSize)) return DecodeError::kBadChecksum;
  h->type = r.U8();
  h->board = r.U8();
  h->count = r.U8();
  h->first = r.U8();
  h->flags = r.U8();
  h->seq = r.U32();
  h->ack = r.U32();
  h->time_ns = r.U64();
  const size_t expected = ExpectedSize(*h);
  if (expected == 0) return DecodeError::kBadType;
  if (expected != n) return DecodeError::kBadLength;
  return DecodeError::kOk;
}

DecodeError DecodeCommand(const uint8_t* data, size_t n, CommandPacket* p) {
  const DecodeError e = CheckPayload(data, n, PacketType::kCommand, &p->h);
  if (e != DecodeError::kOk) return e;
  if (p->h.count > kMaxBoardJoints) return DecodeError::kBadLength;
  Reader r(data + kHeaderSize);
  for (int i = 0; i < p->h.count; ++i) {
    JointCommandWire& j = p->joint[i];
    j.servo_on = r.U8() != 0;
    j.cmd.mode = static_cast<shm::JointMode>(r.U8());  // checked by the board's servo
    j.cmd.pad0 = 0;
    j.cmd.q_ref = r.F64();
    j.cmd.dq_ref = r.F64();
    j.cmd.tau_ff = r.F64();
    j.cmd.kp = r.F64();
    j.cmd.kd = r.F64();
  }
  return DecodeError::kOk;
}

DecodeError DecodeMotorState(const uint8_t* data, size_t n, MotorStatePacket* p) {
  const DecodeError e = CheckPayload(data, n, PacketType::kMotorState, &p->h);
  if (e != DecodeError::kOk) return e;
  if (p->h.count > kMaxBoardJoints) return DecodeError::kBadLength;
  Reader r(data + kHeaderSize);
  for (int i = 0; i < p->h.count; ++i) {
    JointStateWire& j = p->joint[i];
    j.servo_on = r.U8() != 0;
    j.fault = r.U8();
    j.q = r.F64();
    j.dq = r.F64();
    j.tau = r.F64();
  }
  return DecodeError::kOk;
}

DecodeError DecodeSensorState(const uint8_t* data, size_t n, SensorStatePacket* p) {
  const DecodeError e = CheckPayload(data, n, PacketType::kSensorState, &p->h);
  if (e != DecodeError::kOk) return e;
  if (p->h.count > shm::kMaxForceSensors || p->h.first > shm::kMaxImus ||
      p->h.ack > static_cast<uint32_t>(shm::kMaxPassiveJoints))
    return DecodeError::kBadLength;
  Reader r(data + kHeaderSize);
  for (int i = 0; i < p->h.count; ++i) {
    for (double& v : p->force[i].force) v = r.F64();
    for (double& v : p->force[i].torque) v = r.F64();
  }
  for (int i = 0; i < p->h.first; ++i) {
    for (double& v : p->imu[i].gyro) v = r.F64();
    for (double& v : p->imu[i].accel) v = r.F64();
    for (double& v : p->imu[i].quat_WI) v = r.F64();
  }
  for (uint32_t i = 0; i < p->h.ack; ++i) {
    p->passive_q[i] = r.F64();
    p->passive_dq[i] = r.F64();
  }
  return DecodeError::kOk;
}

//---------------- sequence numbers ----------------

bool SeqTracker::Accept(uint32_t seq, bool restart) {
  if (!started_) {
    started_ = true;
    last_ = seq;
    ++received_;
    return true;
  }
  const uint32_t ahead = seq - last_;  // modulo 2^32
  if (ahead == 0 || (ahead >= 0x80000000u && !restart)) {
    ++stale_;
    return false;
  }
  if (ahead > kMaxSeqJump && ahead < 0x80000000u && !restart) {
    ++jumps_;  // no sender this receiver knows is that far ahead: forged or corrupted
    return false;
  }
  if (ahead <= kMaxSeqJump) lost_ += ahead - 1;  // else: the sender restarted its numbering
  last_ = seq;
  ++received_;
  return true;
}

}  // namespace ohrp::hw::udp
