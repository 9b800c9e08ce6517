// Fault injection of hw_emulator (see faults.h).
#include "faults.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace ohrp::hw::udp {
namespace {

bool ParseDouble(const std::string& s, double* out) {
  char* end = nullptr;
  *out = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == 0 && std::isfinite(*out);
}

// a double, NaN and infinities included ("nan", "inf", "-inf")
bool ParseAnyDouble(const std::string& s, double* out) {
  char* end = nullptr;
  *out = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == 0;
}

bool ParseBoard(const std::string& s, int nboards, int* out) {
  char* end = nullptr;
  const long b = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != 0 || b < 0 || b >= nboards) return false;
  *out = static_cast<int>(b);
  return true;
}

}  // namespace

int SensorBit(const std::string& name, int nforce, int nimu) {
  int base = 0, count = 0;
  std::string index;
  if (name.rfind("ft", 0) == 0) {
    count = nforce;
    index = name.substr(2);
  } else if (name.rfind("imu", 0) == 0) {
    base = 8;
    count = nimu;
    index = name.substr(3);
  } else {
    return -1;
  }
  int i = 0;
  if (!ParseBoard(index, count, &i)) return -1;
  return base + i;
}

bool ParseEvent(const std::string& option, const std::string& value, int nboards, int nforce,
                int nimu, std::vector<FaultEvent>* events, std::string* error) {
  // split TARGET@TIME+DURATION (TARGET absent for --estop)
  std::string target, when = value, duration;
  const size_t at = value.find('@');
  if (at != std::string::npos) {
    target = value.substr(0, at);
    when = value.substr(at + 1);
  }
  const size_t plus = when.find('+');
  if (plus != std::string::npos) {
    duration = when.substr(plus + 1);
    when = when.substr(0, plus);
  }
  double t = 0, d = 0;
  const bool needs_target = option != "--estop";
  const bool sensor = option == "--stuck" || option == "--saturate";
  const bool joint_value = option == "--value";
  const bool may_last = option == "--silent" || option == "--estop" || joint_value;
  int id = 0;
  double x = 0;
  bool ok = ParseDouble(when, &t) && t >= 0 && (needs_target == !target.empty()) &&
            (duration.empty() || (may_last && ParseDouble(duration, &d) && d > 0));
  if (ok && joint_value) {
    const size_t eq = target.find('=');
    ok = eq != std::string::npos && ParseBoard(target.substr(0, eq), shm::kMaxJoints, &id) &&
         ParseAnyDouble(target.substr(eq + 1), &x);
  } else if (ok && needs_target) {
    if (sensor) {
      id = SensorBit(target, nforce, nimu);
      ok = id >= 0;
    } else {
      ok = ParseBoard(target, nboards, &id);
    }
  }
  if (!ok) {
    std::ostringstream s;
    s << option << " " << value << ": expected ";
    if (option == "--estop") s << "TIME[+DURATION] in robot seconds, e.g. 1.5+0.5";
    else if (joint_value)
      s << "JOINT=VALUE@TIME[+DURATION] with a joint id and any number (nan, inf too), "
           "e.g. 3=1e300@2.0+0.2";
    else if (sensor)
      s << "SENSOR@TIME with SENSOR ft0..ft" << nforce - 1 << " or imu0..imu" << nimu - 1
        << ", e.g. ft0@1.0";
    else
      s << "BOARD@TIME" << (may_last ? "[+DURATION]" : "") << " with BOARD 0.." << nboards - 1
        << " (the sensor board is " << nboards - 1 << "), e.g. 2@1.0";
    *error = s.str();
    return false;
  }
  FaultKind kind = FaultKind::kSilent, end_kind = FaultKind::kTalk;
  if (option == "--reset") kind = FaultKind::kReset;
  else if (option == "--stuck") kind = FaultKind::kStuck;
  else if (option == "--saturate") kind = FaultKind::kSaturate;
  else if (option == "--estop") {
    kind = FaultKind::kEstop;
    end_kind = FaultKind::kEstopOff;
  } else if (joint_value) {
    kind = FaultKind::kValue;
    end_kind = FaultKind::kValueOff;
  }
  events->push_back({t, kind, id, false, x});
  if (d > 0) events->push_back({t + d, end_kind, id, false, 0});
  return true;
}

void ApplyDue(double t, std::vector<FaultEvent>* events, FaultState* s) {
  for (FaultEvent& e : *events) {
    if (e.done || t + 1e-9 < e.time) continue;
    e.done = true;
    switch (e.kind) {
      case FaultKind::kSilent: s->silent |= 1u << e.target; break;
      case FaultKind::kTalk: s->silent &= ~(1u << e.target); break;
      case FaultKind::kReset: s->reset_request |= 1u << e.target; break;
      case FaultKind::kStuck: s->stuck |= 1u << e.target; break;
      case FaultKind::kSaturate: s->saturated |= 1u << e.target; break;
      case FaultKind::kSensorOk:
        s->stuck &= ~(1u << e.target);
        s->saturated &= ~(1u << e.target);
        break;
      case FaultKind::kEstop: s->estop = true; break;
      case FaultKind::kEstopOff: s->estop = false; break;
      case FaultKind::kValue:
        s->value_joint = e.target;
        s->value = e.value;
        break;
      case FaultKind::kValueOff: s->value_joint = -1; break;
    }
  }
}

bool ApplyControlLine(const std::string& line, int nboards, int nforce, int nimu,
                      FaultState* s, std::string* error) {
  std::istringstream in(line);
  std::string cmd, a, b, extra;
  in >> cmd >> a >> b >> extra;
  if (cmd.empty() || cmd[0] == '#') return true;
  double x = 0, y = 0;
  int id = 0;
  bool ok = extra.empty();
  if (cmd == "loss") {
    ok = ok && ParseDouble(a, &x) && x >= 0 && x <= 1 && b.empty();
    if (ok) s->loss = x;
  } else if (cmd == "late") {
    ok = ok && ParseDouble(a, &x) && x >= 0 && x <= 1 && ParseDouble(b, &y) && y >= 0;
    if (ok) {
      s->late_rate = x;
      s->late_s = y * 1e-3;
    }
  } else if (cmd == "silent" || cmd == "talk" || cmd == "reset") {
    ok = ok && b.empty() && ParseBoard(a, nboards, &id);
    if (ok && cmd == "silent") s->silent |= 1u << id;
    if (ok && cmd == "talk") s->silent &= ~(1u << id);
    if (ok && cmd == "reset") s->reset_request |= 1u << id;
  } else if (cmd == "stuck" || cmd == "saturate" || cmd == "sensor-ok") {
    id = SensorBit(a, nforce, nimu);
    ok = ok && b.empty() && id >= 0;
    if (ok && cmd == "stuck") s->stuck |= 1u << id;
    if (ok && cmd == "saturate") s->saturated |= 1u << id;
    if (ok && cmd == "sensor-ok") {
      s->stuck &= ~(1u << id);
      s->saturated &= ~(1u << id);
    }
  } else if (cmd == "estop") {
    ok = ok && b.empty() && (a == "on" || a == "off");
    if (ok) s->estop = a == "on";
  } else if (cmd == "value") {
    ok = ok && ((a == "off" && b.empty()) ||
                (ParseBoard(a, shm::kMaxJoints, &id) && ParseAnyDouble(b, &x)));
    if (ok) {
      s->value_joint = a == "off" ? -1 : id;
      s->value = x;
    }
  } else if (cmd == "clear") {
    ok = ok && a.empty();
    if (ok) {
      const uint32_t reset = s->reset_request;
      *s = FaultState{};
      s->reset_request = reset;
    }
  } else {
    ok = false;
  }
  if (!ok) {
    *error = "control line '" + line +
             "' not understood (loss P | late P MS | silent B | talk B | reset B | stuck S | "
             "saturate S | sensor-ok S | estop on|off | value J X | value off | clear)";
  }
  return ok;
}

std::vector<std::string> ControlFile::NewLines() {
  std::vector<std::string> lines;
  FILE* f = std::fopen(path_.c_str(), "r");
  if (!f) return lines;
  if (std::fseek(f, 0, SEEK_END) == 0) {
    const long size = std::ftell(f);
    if (size < offset_) offset_ = 0;  // the file was truncated: read it again
    if (size > offset_ && std::fseek(f, offset_, SEEK_SET) == 0) {
      std::string text(static_cast<size_t>(size - offset_), '\0');
      const size_t got = std::fread(text.data(), 1, text.size(), f);
      text.resize(got);
      offset_ += static_cast<long>(got);
      partial_ += text;
      size_t start = 0, nl;
      while ((nl = partial_.find('\n', start)) != std::string::npos) {
        lines.push_back(partial_.substr(start, nl - start));
        start = nl + 1;
      }
      partial_.erase(0, start);
    }
  }
  std::fclose(f);
  return lines;
}

}  // namespace ohrp::hw::udp
