// The control channel's actions in sim_host's loop (host_run.h, sim_host/control_channel.h):
// applied at the cycle's boundary, after the controller's commands are taken and before the
// physics steps; allocation-free and silent (the channel's thread answers and records).
#include <time.h>

#include <cmath>
#include <filesystem>

#include "host_run.h"
#include "shm_bridge/clock.h"

namespace ohrp::sim {

bool HostRun::OpenControl(std::string* why) {
  // the actions are recorded beside the summary (the run folder); without --summary they are not
  std::string actions;
  if (!o.summary_path.empty())
    actions = (std::filesystem::path(o.summary_path).parent_path() / "actions.jsonl").string();
  start_keyframe = o.keyframe.empty() ? -1 : mj_name2id(m, mjOBJ_KEY, o.keyframe.c_str());
  saved_xfrc.assign(6 * static_cast<size_t>(m->nbody), 0.0);
  control = ControlChannel::Open(o.control_socket, actions, m, robot.base_body, why);
  if (control && !o.quiet)
    std::fprintf(stderr, "sim_host: control channel on %s%s%s\n", o.control_socket.c_str(),
                 actions.empty() ? " (actions not recorded: no --summary)" : ", actions in ",
                 actions.c_str());
  return control != nullptr;
}

// the channel's action, if one waits; paused: the cycle waits here (a heartbeat block every
// 0.25 s keeps the controller's read alive) until resumed, stepped or signalled
bool HostRun::ControlGate() {
  EndControlPush();
  ControlAction a;
  if (control->Take(&a)) ApplyAction(a);
  if (paused && steps_left == 0) {
    if (step_owed) ControlDone(ControlAction::kStep);  // the steps are done: answered now
    const double from = MonotonicSeconds();
    while (paused && steps_left == 0 && !signal->load()) {
      const double now = MonotonicSeconds();
      if (now - heartbeat > 0.25) {
        Publish(shm::status::kPaused, false);
        heartbeat = now;
      }
      timespec ms{0, 2000000};
      nanosleep(&ms, nullptr);
      if (control->Take(&a)) ApplyAction(a);
    }
    st.wall_waiting += MonotonicSeconds() - from;  // the real-time factor leaves pauses out
    if (o.realtime) deadline = MonotonicSeconds();  // real time starts again from now
    if (signal->load()) return false;
  }
  if (steps_left > 0) --steps_left;
  return true;
}

void HostRun::ApplyAction(const ControlAction& a) {
  switch (a.kind) {
    case ControlAction::kPause:
      paused = true;
      heartbeat = 0;
      break;
    case ControlAction::kResume:
      paused = false;
      steps_left = 0;
      break;
    case ControlAction::kStep:
      paused = true;
      steps_left = a.steps;
      break;
    case ControlAction::kReset: {
      // the keyframe's state (alone: the run's start, --keyframe or qpos0) at the same simulated time; the wrenches on the
      // bodies kept (the --push windows and the channel's push go on); the watches re-armed
      const double t = d->time;
      for (int i = 0; i < 6 * m->nbody; ++i) saved_xfrc[i] = d->xfrc_applied[i];
      const int key = a.keyframe >= 0 ? a.keyframe : start_keyframe;  // "reset": the start's
      if (key >= 0)
        mj_resetDataKeyframe(m, d, key);
      else
        mj_resetData(m, d);
      d->time = t;
      for (int i = 0; i < 6 * m->nbody; ++i) d->xfrc_applied[i] = saved_xfrc[i];
      watch->Start(m, d);  // mj_forward, and the energy's new baseline
      break;
    }
    case ControlAction::kPush: {
      if (push_body >= 0) {  // a new push replaces the one under way
        push_end = -1;
        EndControlPush();
      }
      push_body = a.body;
      double* row = d->xfrc_applied + 6 * push_body;
      for (int k = 0; k < 3; ++k) {
        push_force[k] = a.force[k];
        row[k] += a.force[k];
      }
      const double periods = std::ceil(a.duration / o.control_period - 1e-9);
      push_end = d->time + std::fmax(1.0, periods) * o.control_period;
      break;
    }
    case ControlAction::kStatus:
    case ControlAction::kNone:
      break;
  }
  // a step is answered once its periods have run (ControlGate), the others now
  if (a.kind == ControlAction::kStep)
    step_owed = true;
  else
    ControlDone(a.kind);
}

void HostRun::ControlDone(int kind) {
  ControlOutcome out;
  out.time = d->time;
  out.cycle = st.cycles;
  out.paused = paused;
  out.push_end = kind == ControlAction::kPush ? push_end : 0;
  step_owed = false;
  control->Done(out);
}

// the channel's push ends at the first cycle boundary at or past its end time
void HostRun::EndControlPush() {
  if (push_body < 0 || d->time < push_end - 0.5 * dt) return;
  double* row = d->xfrc_applied + 6 * push_body;
  for (int k = 0; k < 3; ++k) row[k] -= push_force[k];
  push_body = -1;
}

}  // namespace ohrp::sim
