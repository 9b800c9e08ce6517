// ohrp view --control (view/control.h): the token, the query, the forwarding to the sockets.
#include "view/control.h"

#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>

namespace ohrp::view {

std::string MakeToken() {
  std::random_device rd;  // /dev/urandom
  static const char kHex[] = "0123456789abcdef";
  std::string t;
  for (int i = 0; i < 4; ++i) {
    uint32_t v = rd();
    for (int k = 0; k < 8; ++k, v >>= 4) t += kHex[v & 15];
  }
  return t;
}

std::string QueryValue(const std::string& target, const std::string& key) {
  const size_t q = target.find('?');
  if (q == std::string::npos) return "";
  size_t at = q + 1;
  while (at < target.size()) {
    size_t end = target.find('&', at);
    if (end == std::string::npos) end = target.size();
    const std::string pair = target.substr(at, end - at);
    const size_t eq = pair.find('=');
    if (pair.substr(0, eq) == key) {
      std::string v, raw = eq == std::string::npos ? "" : pair.substr(eq + 1);
      for (size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] == '+') {
          v += ' ';
        } else if (raw[i] == '%' && i + 2 < raw.size() && std::isxdigit(static_cast<unsigned char>(raw[i + 1])) &&
                   std::isxdigit(static_cast<unsigned char>(raw[i + 2]))) {
          v += static_cast<char>(std::stoi(raw.substr(i + 1, 2), nullptr, 16));
          i += 2;
        } else {
          v += raw[i];
        }
      }
      return v;
    }
    at = end + 1;
  }
  return "";
}

bool SendLine(const std::string& path, const std::string& line, double timeout, std::string* reply) {
  sockaddr_un addr{};
  if (path.size() >= sizeof(addr.sun_path)) {
    *reply = "socket path too long: " + path;
    return false;
  }
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  addr.sun_family = AF_UNIX;
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  timeval tv{static_cast<time_t>(timeout), static_cast<suseconds_t>(1e6 * (timeout - static_cast<time_t>(timeout)))};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    *reply = "cannot connect to " + path + ": " + std::strerror(errno);
    if (fd >= 0) close(fd);
    return false;
  }
  const std::string out = line + "\n";
  bool ok = send(fd, out.data(), out.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(out.size());
  reply->clear();
  char c;
  while (ok) {
    const ssize_t n = read(fd, &c, 1);
    if (n <= 0) {
      ok = !reply->empty();
      if (!ok) *reply = "no answer from " + path + (n < 0 ? ": " + std::string(std::strerror(errno)) : "");
      break;
    }
    if (c == '\n') break;
    *reply += c;
  }
  close(fd);
  return ok;
}

void RecordControl(const std::string& path, double sim_time, const std::string& to,
                   const std::string& line, int status, const std::string& reply) {
  static std::mutex mutex;  // pages' threads answer at once
  const std::lock_guard<std::mutex> lock(mutex);
  std::ofstream out(path, std::ios::app);
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  char head[96];
  std::snprintf(head, sizeof head, "{\"wall\": %.3f, \"t\": %.6f, ", now.tv_sec + 1e-9 * now.tv_nsec,
                sim_time);
  const nlohmann::json rest = {{"to", to}, {"line", line}, {"status", status}, {"reply", reply}};
  out << head << rest.dump().substr(1) << "\n";
}

int AnswerControl(const std::string& target, const ControlOptions& o, std::string* body,
                  double sim_time) {
  if (!o.on) {
    *body = "control is off (start ohrp view with --control)\n";
    return 404;
  }
  if (QueryValue(target, "token") != o.token) {
    *body = "refused: the request does not carry this run's token (open the URL ohrp view printed)\n";
    return 403;
  }
  const std::string to = QueryValue(target, "to"), line = QueryValue(target, "line");
  if (to.empty()) {
    *body = std::string("{\"sim\": ") + (o.sim_socket.empty() ? "false" : "true") +
            ", \"walk\": " + (o.walk_socket.empty() ? "false" : "true") + "}";
    return 200;
  }
  const std::string& path = to == "sim" ? o.sim_socket : to == "walk" ? o.walk_socket : "";
  if (to != "sim" && to != "walk") {
    *body = "to=" + to + ": not sim or walk\n";
    return 400;
  }
  if (path.empty()) {
    *body = "error: no " + to + " socket (ohrp view --" + to + "-socket PATH)";
    return 404;
  }
  if (line.empty() || line.find('\n') != std::string::npos) {
    *body = "error: line= must be one command line";
    return 400;
  }
  // a step of many periods may take a while: sim_host answers once they have run
  const int status = SendLine(path, line, 120.0, body) ? 200 : 502;
  if (!o.record.empty()) RecordControl(o.record, sim_time, to, line, status, *body);
  return status;
}

}  // namespace ohrp::view
