// The live command channel's transport (controllers/line_server.h).
#include "controllers/line_server.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>

namespace ohrp::controllers {
namespace {

constexpr int kPollMs = 20;        // the thread's wake-up period when nothing comes [ms]
constexpr size_t kMaxLine = 4096;  // a longer line is refused

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

// a listening local stream socket at `path` (a socket file left there is replaced); -1 with
// `*error`
int Listen(const std::string& path, std::string* error) {
  sockaddr_un addr{};
  if (path.size() >= sizeof(addr.sun_path)) {
    *error = "--socket " + path + ": longer than " + std::to_string(sizeof(addr.sun_path) - 1) +
             " characters";
    return -1;
  }
  struct stat st {};
  if (lstat(path.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode)) {
      *error = "--socket " + path + ": exists and is not a socket (not replaced)";
      return -1;
    }
    unlink(path.c_str());  // a socket left by an earlier run
  }
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || listen(fd, 1) != 0) {
    *error = "--socket " + path + ": " + std::strerror(errno);
    if (fd >= 0) close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

bool LineServer::Open(int fd, const std::string& socket_path, const std::string& program,
                      OnLine on_line, OnIdle idle, std::string* error) {
  Close();
  program_ = program;
  on_line_ = std::move(on_line);
  idle_ = std::move(idle);
  fd_ = fd;
  if (!socket_path.empty()) {
    listen_fd_ = Listen(socket_path, error);
    if (listen_fd_ < 0) return false;
    socket_path_ = socket_path;
  }
  quit_ = false;
  thread_ = std::thread(&LineServer::Run, this);
  return true;
}

void LineServer::Close() {
  if (thread_.joinable()) {
    quit_ = true;
    thread_.join();
  }
  if (client_fd_ >= 0) close(client_fd_);
  if (listen_fd_ >= 0) close(listen_fd_);
  client_fd_ = listen_fd_ = -1;
  if (!socket_path_.empty()) unlink(socket_path_.c_str());
  socket_path_.clear();
}

void LineServer::Reply(int fd, const std::string& text) const {
  if (fd < 0) {
    std::cerr << program_ << ": live: " << text << "\n";
    return;
  }
  const std::string line = text + "\n";
  (void)!send(fd, line.data(), line.size(), MSG_NOSIGNAL);
}

void LineServer::Run() {
  std::string in_buf, client_buf;
  char chunk[512];
  // reads what is there from `fd` into `buf` and hands over its complete lines; false at the end
  auto drain = [&](int fd, std::string* buf, int reply) {
    const ssize_t n = read(fd, chunk, sizeof chunk);
    if (n <= 0) return n < 0 && (errno == EINTR || errno == EAGAIN);
    buf->append(chunk, static_cast<size_t>(n));
    for (size_t eol; (eol = buf->find('\n')) != std::string::npos;) {
      const std::string line = Trim(buf->substr(0, eol));
      buf->erase(0, eol + 1);
      if (!line.empty() && line[0] != '#') on_line_(line, reply);
    }
    if (buf->size() > kMaxLine) {
      Reply(reply, "error: a line longer than " + std::to_string(kMaxLine) + " characters");
      buf->clear();
    }
    return true;
  };
  while (!quit_) {
    pollfd fds[3];
    int n = 0, in = -1, listening = -1, client = -1;
    if (fd_ >= 0) fds[in = n++] = {fd_, POLLIN, 0};
    if (listen_fd_ >= 0) fds[listening = n++] = {listen_fd_, POLLIN, 0};
    if (client_fd_ >= 0) fds[client = n++] = {client_fd_, POLLIN, 0};
    if (poll(fds, n, kPollMs) > 0) {
      if (in >= 0 && fds[in].revents && !drain(fd_, &in_buf, -1)) fd_ = -1;  // stdin ended
      if (client >= 0 && fds[client].revents && !drain(client_fd_, &client_buf, client_fd_)) {
        close(client_fd_);
        client_fd_ = -1;
        client_buf.clear();
      }
      if (listening >= 0 && fds[listening].revents) {
        const int c = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
        if (c >= 0 && client_fd_ >= 0) {
          Reply(c, "error: one client at a time");
          close(c);
        } else if (c >= 0) {
          client_fd_ = c;
        }
      }
    }
    if (idle_) idle_();
  }
}

}  // namespace ohrp::controllers
