// A non-blocking UDP socket on IPv4, as the udp plugin, hw_emulator and the tests use it.
// Open is a set-up call (reports errors in text); SendTo and Receive never block or allocate.
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace ohrp::hw::udp {

// Resolves a dotted IPv4 address (e.g. "127.0.0.1") and a port. Returns false on a malformed
// address or a port outside 0..65535.
bool MakeAddress(const std::string& host, int port, sockaddr_in* out);

// what Receive returns besides a datagram's size (a datagram may have 0 bytes)
inline constexpr long kNoDatagram = -1;     // nothing is waiting
inline constexpr long kReceiveFailed = -2;  // the socket failed

class UdpSocket {
 public:
  UdpSocket() = default;
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  // Binds to host:port (port 0: the system picks one, see port()). Non-blocking, close-on-exec.
  bool Open(const std::string& host, int port, std::string* error);
  void Close();
  bool is_open() const { return fd_ >= 0; }
  int port() const { return port_; }  // the bound port
  int fd() const { return fd_; }

  // Accepts datagrams from `peer` only (connect): the kernel drops those of any other address
  // or port before they reach this socket's queue, so a flood from elsewhere cannot delay or
  // crowd out the peer's. Sending to other addresses stays possible. A set-up call.
  bool Connect(const sockaddr_in& peer, std::string* error);
  // Sends one datagram. Returns false when the system refused it (full buffer, no route).
  // An error the kernel kept from an earlier send (ICMP port unreachable, reported on a
  // connected socket) is consumed and the send tried once more.
  bool SendTo(const sockaddr_in& to, const uint8_t* data, size_t n);
  // Receives one datagram if one is waiting: returns its size (0 for an empty datagram: it is
  // one), kNoDatagram when none is waiting, kReceiveFailed on a socket error. `from` may be
  // null. A datagram larger than `cap` is reported as 1 byte (too short for any packet).
  long Receive(uint8_t* buf, size_t cap, sockaddr_in* from);
  // Waits up to `timeout` [s] for a datagram to arrive (poll). Returns true when one is there.
  bool WaitReadable(double timeout);
  // Datagrams the kernel dropped because this socket's receive buffer was full (SO_RXQ_OVFL),
  // as of the last datagram received: loss on this machine, not on the network.
  uint32_t kernel_drops() const { return kernel_drops_; }

 private:
  int fd_ = -1;
  int port_ = 0;
  uint32_t kernel_drops_ = 0;
};

}  // namespace ohrp::hw::udp
