// The live command channel's transport (walk --listen / --socket, reach --listen / --socket):
// lines from a file descriptor (stdin) and from a local stream socket (one client at a time),
// each handed to the owner on the server's own thread with where its one reply line goes. The
// owner's `idle` runs on that thread after each wake-up (at most every 20 ms): where it does
// the work a line asked for (planning allocates, so it is never the control cycle's).
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace ohrp::controllers {

class LineServer {
 public:
  // a line (trimmed, not empty, not a # comment) and the reply's descriptor (-1: stdin's, the
  // reply goes to stderr)
  using OnLine = std::function<void(const std::string& line, int reply_fd)>;
  using OnIdle = std::function<void()>;

  LineServer() = default;
  ~LineServer() { Close(); }
  LineServer(const LineServer&) = delete;
  LineServer& operator=(const LineServer&) = delete;

  // starts reading lines from `fd` (-1: none; e.g. 0 for stdin) and from a local stream socket
  // at `socket_path` ("": none; an existing socket file there is replaced, any other file is
  // not); `program` prefixes the replies to stdin's lines on stderr ("walk: live: ..."). False
  // with `*error` ("--socket PATH: why") when the socket cannot be made.
  bool Open(int fd, const std::string& socket_path, const std::string& program, OnLine on_line,
            OnIdle idle, std::string* error);
  void Close();
  bool open() const { return thread_.joinable(); }

  // one reply line to `fd` (-1: stderr, prefixed "PROGRAM: live: ")
  void Reply(int fd, const std::string& text) const;

 private:
  void Run();

  int fd_ = -1, listen_fd_ = -1, client_fd_ = -1;
  std::string socket_path_, program_;
  OnLine on_line_;
  OnIdle idle_;
  std::thread thread_;
  std::atomic<bool> quit_{false};
};

}  // namespace ohrp::controllers
