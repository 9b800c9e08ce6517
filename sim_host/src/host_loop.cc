// sim_host's control cycle (host_run.h): the controller's commands for the cycle just
// published, the physics steps, the watches, the pace and the next publication; then the
// shutdown that reports the run.
#include <time.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "host_run.h"
#include "shm_bridge/clock.h"

namespace ohrp::sim {

int HostRun::Run() {
  StartLoop();
  while (!signal->load()) {
    if (o.duration > 0 && d->time >= o.duration - 0.5 * dt) break;
    if (recorder && recorder->failed()) break;  // the log is incomplete: a failed run (Shutdown)
    const Next next = Commands();
    if (next == Next::kEnd) break;
    if (next == Next::kAgain) {
      // waiting for a controller: an action is applied now (a pause holds from the first cycle)
      if (ControlAction a; control && control->Take(&a)) ApplyAction(a);
      continue;
    }
    if (control && !ControlGate()) break;  // the channel's actions; paused here
    if (!Physics()) break;
    ++st.cycles;
    if (!Watches()) break;
    PaceAndPublish();
    Progress();
  }
  return Shutdown();
}

void HostRun::StartLoop() {
  st.wall_start = MonotonicSeconds();
  next_progress = st.wall_start + o.progress;
  wait_since = st.wall_start;
  deadline = st.wall_start;
  waiting = o.wait_controller > 0;
  warnings_at_start = model::WarningCount();
  // non-finite state, MuJoCo's resets, energy blow-up (divergence.h)
  watch = std::make_unique<DivergenceWatch>(m);
  if (soft) {
    std::vector<int> sole_bodies;
    for (int g : soft->sole_geoms()) sole_bodies.push_back(m->geom_bodyid[g]);
    watch->SetPassiveBodies(sole_bodies);
  }
  watch->Start(m, d);
  Publish(0);
  // the physics step (sim_host/step.h): pushes, servo, soft soles, mj_step, commit, watch
  stepper = std::make_unique<PhysicsStep>(
      m, d, PhysicsStep::Parts{servo.get(), soft.get(), &o.pushes, robot.base_body, watch.get()});
}

void HostRun::Publish(uint32_t flags, bool record) noexcept {
  shm::SensorBlock& s = producer->BeginSensors();
  model::FillSensors(robot, m, d, selection, &s);
  if (sensors) ApplySensorModel(robot, selection, sensors.get(), &s);
  s.cycle = st.cycles;
  s.time = d->time;
  s.status = shm::status::kRunning | shm::status::kSimulated | extra_status | flags |
             (producer->controller_pid() ? 0u : shm::status::kNoController);
  s.late_commands = st.late;
  s.rejected_commands = servo->rejected_total();
  std::memcpy(s.rejected_per_joint, servo->rejected_per_joint(),
              robot.joints.size() * sizeof(uint32_t));
  producer->PublishSensors();
  if (record && recorder && st.cycles % static_cast<uint64_t>(o.log_every) == 0)
    recorder->Push(s, &servo->reference(0), cmd.guard.holding);
}

// another process wrote into the segment's wake-up words: the handshake cannot be trusted
bool HostRun::SegmentCorrupted() {
  if (!producer->sync_corrupted()) return false;
  st.outcome = "segment_corrupted";
  st.detail = shm::SegmentFaultText(producer->fault());
  std::fprintf(stderr, "sim_host: segment '%s': %s at t=%.3f s; ending the run\n",
               o.segment.c_str(), st.detail.c_str(), d->time);
  exit_code = kExitControllerLost;
  return true;
}

// the commands for the cycle just published; the segment checked after this first read of it
// (a truncated file reads as zeros: "detached" would be no answer)
HostRun::Next HostRun::Commands() {
  const bool attached = producer->controller_pid() != 0;
  if (SegmentCorrupted()) return Next::kEnd;
  if (republish) {
    republish = false;
    Publish(0, false);
  }
  if (waiting && !attached) return WaitForController();
  if (attached) return TakeCommands();
  if (had_controller && !(extra_status & shm::status::kHolding)) {
    // the controller detached cleanly (closed its adaptor)
    if (LoseController("detached", "controller_detached", last_controller)) {
      exit_code = kExitControllerLost;
      return Next::kEnd;
    }
    if (waiting) return Next::kAgain;
  }
  return Next::kStep;
}

// time frozen until a controller attaches, or the wait's end
HostRun::Next HostRun::WaitForController() {
  if ((o.on_loss != ControllerLoss::kWait || !had_controller) &&
      MonotonicSeconds() - wait_since > o.wait_controller) {
    std::fprintf(stderr,
                 "sim_host: no controller attached to segment '%s' within %g s; start one "
                 "(e.g. 'posture --segment %s') or pass --wait-controller 0 to run without\n",
                 o.segment.c_str(), o.wait_controller, o.segment.c_str());
    st.outcome = "no_controller";
    exit_code = kExitControllerLost;
    return Next::kEnd;
  }
  const double slept_from = MonotonicSeconds();
  timespec pause{0, 2000000};
  nanosleep(&pause, nullptr);
  st.wall_waiting += MonotonicSeconds() - slept_from;
  return Next::kAgain;
}

HostRun::Next HostRun::TakeCommands() {
  // a controller just attached may still be setting up: its first answer gets the attach
  // wait, not the per-cycle timeout
  const bool first_answer = !had_controller || waiting;
  if (first_answer) {
    ++st.controllers_seen;
    last_controller = producer->controller_pid();
    rejecting = false;
    st.Record(d->time, "controller_attached", last_controller);
    if (!o.quiet)
      std::fprintf(stderr, "sim_host: controller pid %d attached\n", producer->controller_pid());
  }
  had_controller = true;
  waiting = false;
  double timeout =
      first_answer ? std::fmax(o.controller_timeout, o.wait_controller) : o.controller_timeout;
  if (first_answer) deadline = MonotonicSeconds();  // real time starts when the controller is there
  if (o.realtime) timeout = std::fmax(0.0, deadline + 0.9 * o.control_period - MonotonicSeconds());
  const double wait_from = first_answer ? MonotonicSeconds() : 0.0;
  const pid_t answering = producer->controller_pid();
  const shm::WaitResult answer = producer->WaitCommands(timeout, &cmd);
  if (first_answer) st.wall_waiting += MonotonicSeconds() - wait_from;  // a new controller setting up
  if (SegmentCorrupted()) return Next::kEnd;
  switch (answer) {
    case shm::WaitResult::kCommands:
      Accept();
      break;
    case shm::WaitResult::kTimeout:
      ++st.late;
      extra_status |= shm::status::kCommandLate;
      if (!o.realtime) {
        // a hung controller is let go: a new one may attach, and this one, should it run
        // again, learns that it was dropped (shm_bridge/controller_loss.h)
        producer->DropController(answering);
        if (LoseController("did not answer within the timeout", "controller_silent", answering))
          exit_code = kExitControllerLost;
      }
      break;
    case shm::WaitResult::kControllerDied:
      if (LoseController("died", "controller_died", answering)) exit_code = kExitControllerLost;
      break;
    case shm::WaitResult::kNoController:
      break;
  }
  if (exit_code != kExitOk) return Next::kEnd;
  return waiting ? Next::kAgain : Next::kStep;
}

// a command block: the guard's holds as events, the servo's references, the rejections
void HostRun::Accept() {
  if (st.commands++ == 0) {
    st.wall_first_command = MonotonicSeconds();
    st.cycles_at_first_command = st.cycles;
  }
  extra_status &=
      ~(shm::status::kHolding | shm::status::kCommandLate | shm::status::kCommandRejected);
  // the controller's self-collision guard: a hold's begin and end are events
  if (int64_t hold = 0; const int change = guard.Update(cmd.guard, d->time, st.cycles, &hold))
    st.Record(d->time, change > 0 ? "guard_hold_begin" : "guard_hold_end", hold);
  // the controller's references are in its (biased) encoders' frame, the servo's in the joints'
  if (sensors) sensors->ToJointFrame(q_min.data(), q_max.data(), &cmd);
  // the actuators' delay (the joint file's delay:): each joint's command of that many cycles ago
  if (const int rejected = servo->Accept(delay.Shift(cmd)); rejected > 0) {
    extra_status |= shm::status::kCommandRejected;
    if (!rejecting) st.Record(d->time, "commands_rejected", rejected);
    rejecting = true;
  } else {
    rejecting = false;
  }
}

// the controller is gone (why, as an event): true when the run ends (--on-controller-loss)
bool HostRun::LoseController(const char* why, const char* event, pid_t pid) {
  ++st.controller_losses;
  st.Record(d->time, event, pid);
  extra_status |= shm::status::kHolding;
  std::fprintf(stderr, "sim_host: controller %s at t=%.3f s (cycle %lu); holding its last references\n",
               why, d->time, static_cast<unsigned long>(st.cycles));
  switch (o.on_loss) {
    case ControllerLoss::kEnd:
      st.outcome = "controller_lost";
      st.detail = std::string("controller ") + why;
      return true;
    case ControllerLoss::kWait:
      std::fprintf(stderr, "sim_host: waiting for a new controller on segment '%s'\n", o.segment.c_str());
      waiting = true;
      wait_since = MonotonicSeconds();
      republish = true;  // the next controller reads this cycle again, marked as holding
      return false;
    case ControllerLoss::kContinue:
      return false;
  }
  return false;
}

// the servo runs at every step; the sensors on the cycle's last (published); false when the
// simulation diverged
bool HostRun::Physics() {
  for (int s = 0; s < steps_per_cycle; ++s) {
    const double t = d->time;
    const bool held = stepper->Step(s == steps_per_cycle - 1);
    ++st.steps;
    // each push's start and end, as events at the step's start
    for (size_t i = 0; i < o.pushes.size(); ++i) {
      if (stepper->push_changed(i)) st.Record(t, stepper->push_on(i) ? "push_start" : "push_end", i);
    }
    if (!held) break;
  }
  if (!watch->diverged()) return true;
  RecordDivergence();
  return false;
}

void HostRun::RecordDivergence() {
  DiagnosisContext why{soft.get(), 0.5 * robot.total_mass, {}};
  for (size_t i = 0; i < robot.joints.size(); ++i) {
    const shm::JointCommand& c = servo->reference(i);
    const bool pos = c.mode == shm::JointMode::kPosition;
    if (pos || c.mode == shm::JointMode::kVelocity)
      why.gains.push_back({robot.joints[i].dof_adr, pos ? c.kp : 0.0, c.kd});
  }
  st.divergence = watch->Diagnose(m, d, why);
  st.outcome = "diverged";
  st.detail = st.divergence.Text();
  std::fprintf(stderr, "sim_host: simulation diverged: %s\n", st.detail.c_str());
  extra_status |= shm::status::kDiverged;
  producer->SetState(shm::ProducerState::kFailed);
  exit_code = kExitDiverged;
}

// once a cycle, after its physics steps (allocation-free): the self-collision watch, the fall
// watch (the first fall is an event); false when a fall ends the run (--on-fall end)
bool HostRun::Watches() {
  if (self_collision) self_collision->Check(d, d->time, st.cycles);
  if (!fall->Check(m, d, d->time, st.cycles)) return true;
  st.Record(d->time, "fall", fall->fall().body);
  extra_status |= shm::status::kFallen;  // every block from now on says it
  if (o.fall.on_fall != OnFall::kEnd) return true;
  exit_code = kExitFell;
  Publish(shm::status::kShuttingDown);
  return false;
}

// real time: sleep to the cycle's due time; the images of the cycle's end, before its sensors
// (cameras.h: only while asked); then the sensors
void HostRun::PaceAndPublish() {
  if (o.realtime) {
    deadline += o.control_period;
    if (MonotonicSeconds() < deadline) SleepUntil(deadline, signal);
  }
  const bool last = o.duration > 0 && d->time >= o.duration - 0.5 * dt;
  if (!cameras->Tick(m, d, producer.get(), &error))
    std::fprintf(stderr, "sim_host: cameras off: %s\n", error.c_str());
  Publish(last ? shm::status::kShuttingDown : 0);
}

// progress on long runs (one line every few wall seconds, not per cycle)
void HostRun::Progress() {
  if (o.progress <= 0 || o.quiet) return;
  const double now = MonotonicSeconds();
  if (now < next_progress) return;
  next_progress = now + o.progress;
  char end[32] = "until stopped";  // --duration 0
  if (o.duration > 0) std::snprintf(end, sizeof(end), "of %.2f s", o.duration);
  std::fprintf(stderr, "sim_host: t=%.2f s simulated (%s), %.2fx real time while simulating, "
               "%lu cycles, late %lu, rejected %lu\n",
               d->time, end, RealTimeFactor(d->time, st, now),
               static_cast<unsigned long>(st.cycles), static_cast<unsigned long>(st.late),
               static_cast<unsigned long>(servo->rejected_total()));
}

// --record-images: the writer drained; images not written whole are a failed run, as the log's
void HostRun::EndImages() {
  cameras->Record(nullptr);
  const bool ok = images->Close(&st.images_error);
  st.images_recorded = images->frames();
  st.images_waited = images->waited_seconds();
  if (!o.quiet)
    std::fprintf(stderr, "sim_host: images: %lu written to %s%s%s\n",
                 static_cast<unsigned long>(st.images_recorded), images->dir().c_str(),
                 ok ? "" : "; INCOMPLETE: ", st.images_error.c_str());
  if (!ok && exit_code == kExitOk) {
    st.outcome = "images_failed";
    st.detail = "the recorded images in '" + images->dir() + "' are incomplete: " + st.images_error;
    exit_code = kExitOutputFailed;
  }
}

// the run's outcome (a signal, a fall), the log's end, the report and the summary
int HostRun::Shutdown() {
  if (control) control->Close();
  st.wall_end = MonotonicSeconds();
  st.sim_time = d->time;
  if (signal->load() && exit_code == kExitOk) {
    st.outcome = "interrupted";
    exit_code = kExitInterrupted;
    std::fprintf(stderr, "sim_host: interrupted (signal %d) at t=%.3f s; shutting down\n",
                 signal->load(), d->time);
  }
  // a fall is the run's outcome unless the run ended for a worse reason (fall.h)
  st.fall = fall->Summary(m);
  if (st.fall.fell &&
      (exit_code == kExitOk || exit_code == kExitInterrupted || exit_code == kExitFell)) {
    char at[96];
    std::snprintf(at, sizeof(at), "the robot fell at t=%.3f s (cycle %lu): ", st.fall.record.time,
                  static_cast<unsigned long>(st.fall.record.cycle));
    st.outcome = "fell";
    st.detail = at + st.fall.cause;
    exit_code = kExitFell;
  }
  if (exit_code != kExitDiverged) producer->SetState(shm::ProducerState::kStopped);
  if (recorder) EndLog(recorder.get(), &st, &exit_code);
  if (images) EndImages();
  st.rejected = servo->rejected_total();
  st.clamped = servo->clamped_total();
  for (size_t i = 0; i < robot.joints.size(); ++i) {
    const int j = static_cast<int>(i);
    if (servo->clamped(j) > 0) st.clamped_joints.emplace_back(robot.joints[i].name, servo->clamped(j));
  }
  st.warnings = model::WarningCount() - warnings_at_start;
  if (self_collision) st.self_collision = self_collision->Summary();
  st.guard = guard.Summary();
  if (!o.quiet) PrintReport(st);
  if (!o.quiet && cameras->frames() > 0)
    std::fprintf(stderr, "sim_host: cameras: %lu images rendered, %.2f ms each\n",
                 static_cast<unsigned long>(cameras->frames()),
                 1e3 * cameras->render_seconds() / static_cast<double>(cameras->frames()));
  if (soft) {
    st.fcl_queries = soft->stats().fcl_queries;
    st.contact_pairs = soft->stats().pairs_considered;
    st.contact_pairs_bounded = soft->stats().pairs_bound;
  }
  st.contact = ContactModelName(contact_model);
  if (!o.summary_path.empty() &&
      !WriteSummary(o.summary_path, o, robot, m, st, exit_code, &effects) && exit_code == kExitOk)
    exit_code = kExitOutputFailed;
  recorder.reset();
  producer.reset();  // removes the segment
  segment_object[0] = 0;
  return exit_code;
}

}  // namespace ohrp::sim
