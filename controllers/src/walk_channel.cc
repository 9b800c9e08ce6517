// Live walk commands: the channel's thread reads and plans, the control cycle takes the plans
// without waiting (see walk_channel.h).
#include "controllers/walk_channel.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>

#include "controllers/walk.h"

namespace ohrp::controllers {
namespace {

constexpr int kPollMs = 20;           // the thread's wake-up period when nothing comes [ms]
constexpr size_t kMaxLine = 4096;     // a longer line is refused

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

}  // namespace

bool WalkChannel::Open(int fd, const std::string& socket_path, const LivePlanning& planning,
                       std::string* error) {
  Close();
  planning_ = planning;
  fd_ = fd;
  if (!socket_path.empty()) {
    sockaddr_un addr{};
    if (socket_path.size() >= sizeof(addr.sun_path)) {
      *error = "--socket " + socket_path + ": longer than " +
               std::to_string(sizeof(addr.sun_path) - 1) + " characters";
      return false;
    }
    struct stat st {};
    if (lstat(socket_path.c_str(), &st) == 0) {
      if (!S_ISSOCK(st.st_mode)) {
        *error = "--socket " + socket_path + ": exists and is not a socket (not replaced)";
        return false;
      }
      unlink(socket_path.c_str());  // a socket left by an earlier run
    }
    listen_fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, socket_path.c_str(), socket_path.size() + 1);
    if (listen_fd_ < 0 || bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        listen(listen_fd_, 1) != 0) {
      *error = "--socket " + socket_path + ": " + std::strerror(errno);
      if (listen_fd_ >= 0) close(listen_fd_);
      listen_fd_ = -1;
      return false;
    }
    socket_path_ = socket_path;
  }
  quit_ = false;
  thread_ = std::thread(&WalkChannel::Run, this);
  return true;
}

void WalkChannel::Close() {
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

//---------------- the control cycle's side ----------------

void WalkChannel::Publish(const walking::FeetPose& feet, uint64_t version) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  stance_ = feet;
  stance_version_ = version;
  have_stance_ = true;
}

WalkChannel::Got WalkChannel::Poll(uint64_t version, std::vector<walking::Footstep>* steps) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return Got::kNothing;
  if (pending_stop_) {
    pending_stop_ = false;
    have_plan_ = false;
    ++applied_;
    return Got::kStop;
  }
  if (!have_plan_) return Got::kNothing;
  have_plan_ = false;
  if (planned_version_ != version) {  // made from a stance that has moved on: again
    replan_ = true;
    return Got::kNothing;
  }
  steps->swap(planned_);
  ++applied_;
  return Got::kSteps;
}

//---------------- the channel's thread ----------------

void WalkChannel::Run() {
  std::string in_buf, client_buf;
  char chunk[512];
  // reads what is there from `fd` into `buf` and hands over its complete lines; false at the end
  auto drain = [&](int fd, std::string* buf, int reply) {
    const ssize_t n = read(fd, chunk, sizeof chunk);
    if (n <= 0) return n < 0 && (errno == EINTR || errno == EAGAIN);
    buf->append(chunk, static_cast<size_t>(n));
    for (size_t eol; (eol = buf->find('\n')) != std::string::npos;) {
      Line(buf->substr(0, eol), reply);
      buf->erase(0, eol + 1);
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
    Plan();
  }
}

void WalkChannel::Reply(int fd, const std::string& text) {
  if (fd < 0) {
    std::cerr << "walk: live: " << text << "\n";
    return;
  }
  const std::string line = text + "\n";
  (void)!send(fd, line.data(), line.size(), MSG_NOSIGNAL);
}

void WalkChannel::Line(const std::string& raw, int reply) {
  const std::string line = Trim(raw);
  if (line.empty() || line[0] == '#') return;
  // a velocity without a duration walks until the next command
  std::istringstream words(line);
  std::string verb, w;
  int count = 0;
  words >> verb;
  while (words >> w) ++count;
  char until[32];
  std::snprintf(until, sizeof until, " %g", planning_.until_stop);
  const std::string text = verb == "velocity" && count == 3 ? line + until : line;
  WalkCommand c;
  std::string error;
  const bool stop = line == "stop";
  const bool ok = stop || (ParseWalkCommand(text, &c, &error) && c.kind != WalkCommand::Kind::kWait);
  if (!ok && error.empty())
    error = "\"" + line + "\": wait is not a live command (send the next one when it is due)";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++received_;
    if (stop) {
      pending_stop_ = true;
      pending_.clear();
      have_plan_ = false;
    } else if (ok) {
      pending_ = text;
      pending_reply_ = reply;
    } else {
      ++refused_;
    }
  }
  if (stop) Reply(reply, "ok: stop");
  if (!ok) Reply(reply, "error: " + error);
}

void WalkChannel::Plan() {
  std::string text;
  int reply = -1;
  bool again = false;
  walking::FeetPose feet;
  uint64_t version = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!have_stance_) return;
    again = pending_.empty() && replan_ && !last_planned_.empty();
    if (pending_.empty() && !again) return;
    text = again ? last_planned_ : pending_;
    reply = again ? -1 : pending_reply_;
    pending_.clear();
    replan_ = false;
    feet = stance_;
    version = stance_version_;
  }
  WalkCommand c;
  std::string note, error;
  std::vector<walking::Footstep> steps;
  bool ok = ParseWalkCommand(text, &c, &error) &&
            PlanWalkCommand(c, feet, planning_.limits, planning_.step_time, &steps, &note, &error);
  const size_t count = steps.size();
  if (ok && count > planning_.max_steps) {
    error = "\"" + text + "\": " + std::to_string(count) + " steps, more than " +
            std::to_string(planning_.max_steps) + " at once";
    ok = false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!ok) {
      ++refused_;
    } else if (pending_.empty() && !pending_stop_) {  // else a newer command came meanwhile
      planned_.swap(steps);
      planned_version_ = version;
      have_plan_ = true;
      last_planned_ = text;
    }
  }
  if (!ok) Reply(reply, "error: " + error);
  else if (!again)
    Reply(reply, "ok: \"" + text + "\": " + std::to_string(count) +
                     " steps planned" + (note.empty() ? "" : "; " + note));
}

}  // namespace ohrp::controllers
