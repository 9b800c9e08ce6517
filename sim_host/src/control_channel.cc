// sim_host's control channel (sim_host/control_channel.h): the line parser, the slot between
// the channel's thread and the control loop, the replies and the action record.
#include "sim_host/control_channel.h"

#include <time.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "controllers/line_server.h"

namespace ohrp::sim {

namespace {

constexpr const char* kForms =
    "pause | resume | step [N] | reset [KEYFRAME] | push BODY FX FY FZ DURATION | status";

// the names of the model's objects of `type`, for an error ("a, b, c")
std::string Names(const mjModel* m, int type, int count) {
  std::string s;
  for (int i = 0, listed = 0; i < count; ++i) {
    const char* n = mj_id2name(m, type, i);
    if (!n || !*n || (type == mjOBJ_BODY && i == 0)) continue;
    if (++listed > 12) {
      s += ", ... (" + std::to_string(count) + " in all)";
      break;
    }
    if (!s.empty()) s += ", ";
    s += n;
  }
  return s.empty() ? "none" : s;
}

bool Number(std::istringstream& in, double* x) {
  std::string word;
  if (!(in >> word)) return false;
  char* end = nullptr;
  *x = std::strtod(word.c_str(), &end);
  return end != word.c_str() && *end == '\0' && std::isfinite(*x);
}

}  // namespace

bool ParseControlLine(const std::string& line, const mjModel* m, ControlAction* out,
                      std::string* error) {
  std::istringstream in(line);
  std::string verb, extra;
  in >> verb;
  ControlAction a;
  auto fail = [&](const std::string& why) {
    *error = "'" + line + "': " + why;
    return false;
  };
  if (verb == "pause" || verb == "resume" || verb == "status") {
    a.kind = verb == "pause" ? ControlAction::kPause
             : verb == "resume" ? ControlAction::kResume : ControlAction::kStatus;
  } else if (verb == "step") {
    a.kind = ControlAction::kStep;
    double n = 1;
    std::string word;
    if (in >> word) {
      char* end = nullptr;
      n = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end || n < 1 || n > 100000 || n != std::floor(n))
        return fail("step takes a whole number of control periods, 1 to 100000 (step 10)");
    }
    a.steps = static_cast<int>(n);
  } else if (verb == "reset") {
    a.kind = ControlAction::kReset;
    std::string key;
    if (in >> key) {
      a.keyframe = mj_name2id(m, mjOBJ_KEY, key.c_str());
      if (a.keyframe < 0)
        return fail("no keyframe '" + key + "' in the model (its keyframes: " +
                    Names(m, mjOBJ_KEY, m->nkey) + "; 'reset' alone: the run's start state)");
    }
  } else if (verb == "push") {
    a.kind = ControlAction::kPush;
    std::string body;
    if (!(in >> body)) return fail("push BODY FX FY FZ DURATION (e.g. push base_link 100 0 0 0.1)");
    a.body = mj_name2id(m, mjOBJ_BODY, body.c_str());
    if (a.body <= 0)
      return fail("no body '" + body + "' to push (the model's bodies: " +
                  Names(m, mjOBJ_BODY, m->nbody) + ")");
    for (int k = 0; k < 3; ++k)
      if (!Number(in, &a.force[k]))
        return fail("push BODY FX FY FZ DURATION: force " + std::string(1, "xyz"[k]) +
                    " is not a finite number [N]");
    if (std::sqrt(a.force[0] * a.force[0] + a.force[1] * a.force[1] + a.force[2] * a.force[2]) > 1e5)
      return fail("push force above 1e5 N");
    if (!Number(in, &a.duration) || a.duration <= 0 || a.duration > 60)
      return fail("push BODY FX FY FZ DURATION: the duration is seconds of simulated time, "
                  "above 0 and at most 60");
  } else {
    return fail("unknown command '" + verb + "' (commands: " + kForms + ")");
  }
  if (in >> extra) return fail("unexpected '" + extra + "' after the command (" + kForms + ")");
  *out = a;
  return true;
}

struct ControlChannel::Impl {
  controllers::LineServer server;
  const mjModel* m = nullptr;
  int base_body = -1;
  std::string actions_path;
  std::ofstream actions;
  // the slot: 0 empty, 1 an action waiting for the loop, 4 taken by it, 2 done; 3 the loop ended
  std::atomic<int> state{0};
  ControlAction action;
  ControlOutcome outcome;

  void OnLine(const std::string& line, int fd);
  void Record(const std::string& line, const ControlOutcome& o);
};

std::unique_ptr<ControlChannel> ControlChannel::Open(const std::string& socket_path,
                                                     const std::string& actions_path,
                                                     const mjModel* m, int base_body,
                                                     std::string* error) {
  std::unique_ptr<ControlChannel> c(new ControlChannel);
  c->impl_ = std::make_unique<Impl>();
  Impl* p = c->impl_.get();
  p->m = m;
  p->base_body = base_body;
  p->actions_path = actions_path;
  if (!actions_path.empty()) {
    p->actions.open(actions_path, std::ios::trunc);
    if (!p->actions) {
      *error = "--control-socket: cannot write the action record '" + actions_path + "'";
      return nullptr;
    }
  }
  if (!p->server.Open(-1, socket_path, "sim_host",
                      [p](const std::string& line, int fd) { p->OnLine(line, fd); }, nullptr, error)) {
    // LineServer names walk's option: said as sim_host's
    const std::string theirs = "--socket " + socket_path + ": ";
    if (error->rfind(theirs, 0) == 0) error->erase(0, theirs.size());
    *error = "--control-socket " + socket_path + ": " + *error;
    return nullptr;
  }
  return c;
}

ControlChannel::~ControlChannel() {
  Close();
  impl_->server.Close();
}

void ControlChannel::Close() { impl_->state.store(3); }

bool ControlChannel::Take(ControlAction* out) {
  int waiting = 1;
  if (!impl_->state.compare_exchange_strong(waiting, 4, std::memory_order_acquire)) return false;
  *out = impl_->action;
  return true;
}

void ControlChannel::Done(const ControlOutcome& outcome) {
  impl_->outcome = outcome;
  impl_->state.store(2, std::memory_order_release);
}

// the channel's thread: parse, hand over, wait for the loop (at most 10 s of wall time), answer
void ControlChannel::Impl::OnLine(const std::string& line, int fd) {
  ControlAction a;
  std::string error;
  if (!ParseControlLine(line, m, &a, &error)) {
    server.Reply(fd, "error: " + error);
    return;
  }
  int expected = 0;
  action = a;
  // (2: the answer of a step given up on, come late: the slot is free again)
  if (!state.compare_exchange_strong(expected, 1, std::memory_order_release) &&
      !(expected == 2 && state.compare_exchange_strong(expected, 1, std::memory_order_release))) {
    server.Reply(fd, "error: the simulation has ended");
    return;
  }
  // a step is done once its periods have run: up to 100000 of them, at most 10 min
  const int polls = a.kind == ControlAction::kStep ? 600000 : 10000;
  for (int i = 0; i < polls; ++i) {
    const int now = state.load(std::memory_order_acquire);
    if (now != 1 && now != 4) break;
    timespec ms{0, 1000000};
    nanosleep(&ms, nullptr);
  }
  // not taken in time: withdrawn (unless the loop takes it meanwhile)
  int waiting = 1;
  if (state.compare_exchange_strong(waiting, 0)) {
    server.Reply(fd, "error: the control loop did not take the command within 10 s (stalled?)");
    return;
  }
  if (waiting == 4) {
    server.Reply(fd, "error: not done within 10 min; still under way");
    return;
  }
  int done = 2;
  if (!state.compare_exchange_strong(done, 0, std::memory_order_acquire)) {
    server.Reply(fd, "error: the simulation has ended");
    return;
  }
  char text[160];
  std::snprintf(text, sizeof text, "ok: %s: t=%.4f s cycle %llu %s", line.c_str(), outcome.time,
                static_cast<unsigned long long>(outcome.cycle), outcome.paused ? "paused" : "running");
  server.Reply(fd, text);
  if (a.kind != ControlAction::kStatus) Record(line, outcome);
}

// one JSON line per applied action; a push on the base also as the --push that reproduces it
void ControlChannel::Impl::Record(const std::string& line, const ControlOutcome& o) {
  if (!actions) return;
  std::string quoted;
  for (char c : line) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  char head[128];
  std::snprintf(head, sizeof head, "{\"time\": %.6f, \"cycle\": %llu, \"action\": \"", o.time,
                static_cast<unsigned long long>(o.cycle));
  actions << head << quoted << "\"";
  if (action.kind == ControlAction::kPush) {
    char push[200];
    std::snprintf(push, sizeof push, "%.6f,%.6f,%.9g,%.9g,%.9g,0,0,0", o.time, o.push_end,
                  action.force[0], action.force[1], action.force[2]);
    actions << ", \"body\": \"" << mj_id2name(m, mjOBJ_BODY, action.body) << "\"";
    if (action.body == base_body)  // the base: sim_host --push reproduces it
      actions << ", \"sim_host_push\": \"" << push << "\"";
  }
  actions << "}\n";
  actions.flush();
}

}  // namespace ohrp::sim
