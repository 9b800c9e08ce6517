// Non-blocking UDP socket (see socket.h).
#include "hw_udp/socket.h"

#include <arpa/inet.h>
#include <errno.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <cstring>

namespace ohrp::hw::udp {
namespace {

constexpr int kSocketBuffer = 1 << 20;  // receive/send buffer asked of the kernel [byte]

}  // namespace

bool MakeAddress(const std::string& host, int port, sockaddr_in* out) {
  if (port < 0 || port > 65535) return false;
  std::memset(out, 0, sizeof(*out));
  out->sin_family = AF_INET;
  out->sin_port = htons(static_cast<uint16_t>(port));
  return inet_pton(AF_INET, host.c_str(), &out->sin_addr) == 1;
}

UdpSocket::~UdpSocket() { Close(); }

bool UdpSocket::Open(const std::string& host, int port, std::string* error) {
  Close();
  sockaddr_in addr;
  if (!MakeAddress(host, port, &addr)) {
    *error = "bad address '" + host + ":" + std::to_string(port) +
             "' (expected a dotted IPv4 address such as 127.0.0.1 and a port 0..65535)";
    return false;
  }
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    *error = std::string("cannot create a UDP socket: ") + std::strerror(errno);
    return false;
  }
  int size = kSocketBuffer;
  setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &size, sizeof(size));
  setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &size, sizeof(size));
  const int on = 1;
  setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on));  // best effort: counts if it can
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) {
    *error = "cannot bind UDP " + host + ":" + std::to_string(port) + ": " + std::strerror(errno) +
             (errno == EADDRINUSE ? " (another program uses this port: pick another one)" : "");
    Close();
    return false;
  }
  sockaddr_in bound{};
  socklen_t len = sizeof(bound);
  getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &len);
  port_ = ntohs(bound.sin_port);
  return true;
}

void UdpSocket::Close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  port_ = 0;
}

bool UdpSocket::Connect(const sockaddr_in& peer, std::string* error) {
  if (connect(fd_, reinterpret_cast<const sockaddr*>(&peer), sizeof(peer)) == 0) return true;
  *error = std::string("cannot connect the UDP socket to its peer: ") + std::strerror(errno);
  return false;
}

bool UdpSocket::SendTo(const sockaddr_in& to, const uint8_t* data, size_t n) {
  // a connected socket reports an earlier send's ICMP error on this one: consumed, sent again
  for (int attempt = 0; attempt < 2; ++attempt) {
    const ssize_t r = sendto(fd_, data, n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof(to));
    if (r == static_cast<ssize_t>(n)) return true;
    if (r >= 0 || errno != ECONNREFUSED) return false;
  }
  return false;
}

long UdpSocket::Receive(uint8_t* buf, size_t cap, sockaddr_in* from) {
  for (;;) {
    sockaddr_in src{};
    iovec iov{buf, cap};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(uint32_t))];
    msghdr msg{};
    msg.msg_name = &src;
    msg.msg_namelen = sizeof(src);
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof(control);
    const ssize_t r = recvmsg(fd_, &msg, 0);
    if (r >= 0) {
      if (from) *from = src;
      for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL)
          std::memcpy(&kernel_drops_, CMSG_DATA(c), sizeof(kernel_drops_));
      }
      // a datagram larger than the buffer is not one of ours: report it as 1 byte (too short)
      return (msg.msg_flags & MSG_TRUNC) ? 1 : static_cast<long>(r);
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return kNoDatagram;
    if (errno == ECONNREFUSED) continue;  // an ICMP error of an earlier send: not fatal
    return kReceiveFailed;
  }
}

bool UdpSocket::WaitReadable(double timeout) {
  pollfd p{fd_, POLLIN, 0};
  const int ms = static_cast<int>(std::ceil(std::fmax(0.0, timeout) * 1e3));
  return poll(&p, 1, ms) > 0 && (p.revents & POLLIN);
}

}  // namespace ohrp::hw::udp
