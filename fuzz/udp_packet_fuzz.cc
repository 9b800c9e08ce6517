// Fuzzes the boards' UDP packet decoder (hw_driver/udp: DecodeHeader and the payload decoders)
// with arbitrary datagrams: each is decoded as received, then once more with its CRC trailer
// recomputed, so that the fuzzer gets past the checksum into the payloads. A packet that decodes
// must encode again to a packet that decodes to the same header.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "hw_udp/protocol.h"

namespace udp = ohrp::hw::udp;

namespace {

bool SameHeader(const udp::Header& a, const udp::Header& b) {
  return a.type == b.type && a.board == b.board && a.count == b.count && a.first == b.first &&
         a.flags == b.flags && a.seq == b.seq && a.ack == b.ack && a.time_ns == b.time_ns;
}

// re-encodes a decoded packet and decodes that again: same size and header
template <typename Packet, typename Encode, typename Decode>
void RoundTrip(const Packet& p, size_t n, Encode encode, Decode decode) {
  uint8_t out[udp::kMaxPacketSize];
  const size_t m = encode(p, out);
  Packet again;
  if (m != n || decode(out, m, &again) != udp::DecodeError::kOk || !SameHeader(p.h, again.h)) {
    std::abort();
  }
}

// every decoder on one datagram, as the driver and the emulator call them
void DecodeAll(const uint8_t* data, size_t n) {
  if (n > udp::kMaxPacketSize) return;  // the socket reads at most this much
  udp::Header h;
  if (udp::DecodeHeader(data, n, &h) != udp::DecodeError::kOk) return;
  udp::CommandPacket command;
  if (udp::DecodeCommand(data, n, &command) == udp::DecodeError::kOk) {
    RoundTrip(command, n, udp::EncodeCommand, udp::DecodeCommand);
  }
  udp::MotorStatePacket motor;
  if (udp::DecodeMotorState(data, n, &motor) == udp::DecodeError::kOk) {
    RoundTrip(motor, n, udp::EncodeMotorState, udp::DecodeMotorState);
  }
  udp::SensorStatePacket sensor;
  if (udp::DecodeSensorState(data, n, &sensor) == udp::DecodeError::kOk) {
    RoundTrip(sensor, n, udp::EncodeSensorState, udp::DecodeSensorState);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  DecodeAll(data, size);
  // the same bytes with a valid CRC-32 trailer (little-endian, over everything before it)
  if (size < 4) return 0;
  std::vector<uint8_t> fixed(data, data + size);
  const uint32_t crc = udp::Crc32(fixed.data(), size - 4);
  for (int i = 0; i < 4; ++i) fixed[size - 4 + i] = static_cast<uint8_t>(crc >> (8 * i));
  DecodeAll(fixed.data(), size);
  return 0;
}
