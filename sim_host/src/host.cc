// The sim_host run loop (see host.h).
#include "sim_host/host.h"

#include <signal.h>
#include <time.h>

#include <atomic>
#include <boost/interprocess/shared_memory_object.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "cli/plausible.h"
#include "shm_bridge/bridge.h"
#include "sim_host/divergence.h"
#include "sim_host/host_text.h"
#include "sim_host/model.h"
#include "sim_host/period.h"
#include "sim_host/recorder.h"
#include "sim_host/report.h"
#include "sim_host/self_collision_watch.h"
#include "sim_host/step.h"
#include "shm_bridge/clock.h"

namespace ohrp::sim {
namespace {

std::atomic<int> g_signal{0};
char g_segment_object[128] = "";  // removed by the fatal-error path

void OnSignal(int sig) { g_signal.store(sig); }

void OnFatal(const char*) {
  if (g_segment_object[0]) boost::interprocess::shared_memory_object::remove(g_segment_object);
}

bool ApplyOverrides(const HostOptions& o, mjModel* m, std::string* error) {
  if (o.physics_dt > 0) m->opt.timestep = o.physics_dt;
  // the step, the scene's or ours, is plausible (cli/plausible.h): 1e308 or 1e-300 never runs
  *error = cli::CheckPlausible("physics_dt", m->opt.timestep,
                               o.physics_dt > 0 ? "--physics-dt" : o.scene + ": <option timestep>");
  if (!error->empty()) return false;
  if (!o.integrator.empty()) {
    if (o.integrator == "euler") m->opt.integrator = mjINT_EULER;
    else if (o.integrator == "rk4") m->opt.integrator = mjINT_RK4;
    else if (o.integrator == "implicit") m->opt.integrator = mjINT_IMPLICIT;
    else {
      *error = "unknown integrator '" + o.integrator + "' (use euler, rk4 or implicit)";
      return false;
    }
  }
  return true;
}


}  // namespace

int RunHost(const HostOptions& options) {
  HostOptions o = options;  // the control period is resolved below
  InstallMujocoHandlers(OnFatal);
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
  signal(SIGXFSZ, SIG_IGN);  // a file size limit fails the log's write (reported), never kills

  //---------------- set-up: scene, robot, segment ----------------
  std::string error;
  auto scene = Scene::Load(o.scene, &error);
  if (!scene) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  mjModel* m = scene->m();
  mjData* d = scene->d();
  RobotMap robot;
  if (!MapRobot(m, &robot, &error)) {
    std::fprintf(stderr, "sim_host: %s: %s\n", o.scene.c_str(), error.c_str());
    return kExitUsage;
  }
  if (!o.pushes.empty() && robot.base_body < 0) {
    std::fprintf(stderr, "sim_host: %s: --push acts on the robot's free-floating base, and this model "
                         "has none (no free joint)\n", o.scene.c_str());
    return kExitUsage;
  }
  std::unique_ptr<contact::SoftFootContact> soft;
  ContactModel contact_model = o.feet.model;
  EffectsPlan effects;  // decided on the scene as loaded, applied once the soles are set up
  if (!ApplyOverrides(o, m, &error) ||
      !ResolveEffects(m, robot, o.feet, !o.log_path.empty(), o.effects, &effects, &error) ||
      !SetUpFeet(m, o.feet, robot.total_mass, &soft, &error, &contact_model)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  ApplyEffects(effects, robot, m);
  struct FilterGuard {
    ~FilterGuard() { ClearContactFilter(); }
  } filter_guard;
  if (!scene->Reset(o.keyframe, &error)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  // the fall watch, on the initial state (fall.h)
  auto fall = FallWatch::Create(m, d, robot, o.feet.soles, o.fall, &error);
  if (!fall) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  // the control period: the scene's step times n (period.h)
  const double dt = m->opt.timestep;
  int steps_per_cycle = 1;
  if (!ChooseControlPeriod(dt, options.control_period, &o.control_period, &steps_per_cycle, &error)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  // the self_collision effect: the controllers' checker on the robot's links, once a cycle
  std::unique_ptr<SelfCollisionWatch> self_collision;
  if (effects.on(Effect::kSelfCollision)) {
    self_collision = SelfCollisionWatch::Create(m, robot, o.self_collision_file, &error);
    if (!self_collision) {
      std::fprintf(stderr, "sim_host: %s\n", error.c_str());
      return kExitUsage;
    }
    self_collision->Start(d);
  }
  const HostText text{o, robot, effects, self_collision.get(), soft.get(), m, steps_per_cycle,
                      options.control_period <= 0, contact_model};
  if (o.explain) {
    PrintExplain(text);
    std::printf("%s\n", fall->Describe().c_str());
    return kExitOk;
  }
  // the data log, before anything runs (its header written: a file that takes none is refused)
  std::unique_ptr<Recorder> recorder;
  if (effects.on(Effect::kLog)) {
    RecorderChannels channels;
    channels.base = effects.on(Effect::kLogBase);
    channels.joints = effects.on(Effect::kLogJoints);
    channels.force_torque = effects.on(Effect::kLogForceTorque);
    channels.imu = effects.on(Effect::kLogImu);
    recorder = Recorder::Open(o.log_path, robot, &error, 8192, channels, o.log_max);
    if (!recorder) {
      std::fprintf(stderr, "sim_host: --log: %s\n", error.c_str());
      return kExitUsage;
    }
  }
  const SensorSelection selection = SelectSensors(effects);
  std::unique_ptr<SensorNoise> noise;
  if (effects.on(Effect::kNoise)) noise = std::make_unique<SensorNoise>(effects.noise, selection);

  shm::Status status;
  shm::ProducerConfig pc = MakeProducerConfig(robot, m, o.segment, dt, o.control_period);
  pc.read_timeout_hint = o.controller_timeout;
  for (shm::CameraInfo& c : pc.cameras) {
    c.width = o.cameras.width;
    c.height = o.cameras.height;
  }
  auto producer = shm::Producer::Create(pc, &status);
  if (!producer) {
    std::fprintf(stderr, "sim_host: %s\n", status.message.c_str());
    return kExitUsage;
  }
  if (!status.message.empty()) std::fprintf(stderr, "sim_host: %s\n", status.message.c_str());
  std::snprintf(g_segment_object, sizeof(g_segment_object), "%s",
                producer->object_name().c_str());

  // the summary, before the run: a provisional one (outcome "running") until the end
  if (!o.summary_path.empty() &&
      !model::PrepareOutputFile(o.summary_path, ProvisionalSummary(o), &error)) {
    std::fprintf(stderr, "sim_host: --summary: %s\n", error.c_str());
    return kExitUsage;  // the segment is removed on the way out
  }
  Cameras cameras(robot, o.cameras, effects.on(Effect::kCameras));
  Servo servo(robot);
  servo.HoldCurrent(d);
  if (!o.quiet) PrintStart(text);
  if (!o.quiet) std::fprintf(stderr, "sim_host: %s\n", fall->Describe().c_str());

  //---------------- the loop ----------------
  RunStats st;
  st.wall_start = MonotonicSeconds();
  double next_progress = st.wall_start + o.progress;
  double wait_since = st.wall_start;
  bool had_controller = false;
  bool waiting = o.wait_controller > 0;  // waiting for a (new) controller, time frozen
  uint32_t extra_status = 0;
  long warnings_at_start = WarningCount();
  DivergenceWatch watch(m);  // non-finite state, MuJoCo's resets, energy blow-up (divergence.h)
  if (soft) {
    std::vector<int> sole_bodies;
    for (int g : soft->sole_geoms()) sole_bodies.push_back(m->geom_bodyid[g]);
    watch.SetPassiveBodies(sole_bodies);
  }
  watch.Start(m, d);
  shm::CommandBlock cmd{};
  GuardWatch guard;  // the hold episodes of the controller's self-collision guard
  int exit_code = kExitOk;

  bool republish = false;
  auto publish = [&](uint32_t flags, bool record = true) {
    shm::SensorBlock& s = producer->BeginSensors();
    FillSensors(robot, m, d, selection, &s);
    if (noise) noise->Apply(robot, &s);
    s.cycle = st.cycles;
    s.time = d->time;
    s.status = shm::status::kRunning | shm::status::kSimulated | extra_status | flags |
               (producer->controller_pid() ? 0u : shm::status::kNoController);
    s.late_commands = st.late;
    s.rejected_commands = servo.rejected_total();
    std::memcpy(s.rejected_per_joint, servo.rejected_per_joint(),
                robot.joints.size() * sizeof(uint32_t));
    producer->PublishSensors();
    if (record && recorder && st.cycles % static_cast<uint64_t>(o.log_every) == 0)
      recorder->Push(s, &servo.reference(0), cmd.guard.holding);
  };
  publish(0);

  auto lose_controller = [&](const char* why, const char* event, pid_t pid) {
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
  };

  // the physics step (sim_host/step.h): pushes, servo, soft soles, mj_step, commit, watch
  PhysicsStep stepper(m, d, {&servo, soft.get(), &o.pushes, robot.base_body, &watch});
  pid_t last_controller = 0;  // the pid of the last controller that attached
  bool rejecting = false;     // its last command block had rejected joints
  double deadline = st.wall_start;  // real time: the wall time at which cycle k is due
  // another process wrote into the segment's wake-up words: the handshake cannot be trusted
  auto segment_corrupted = [&] {
    if (!producer->sync_corrupted()) return false;
    st.outcome = "segment_corrupted";
    st.detail = shm::SegmentFaultText(producer->fault());
    std::fprintf(stderr, "sim_host: segment '%s': %s at t=%.3f s; ending the run\n",
                 o.segment.c_str(), st.detail.c_str(), d->time);
    exit_code = kExitControllerLost;
    return true;
  };
  while (!g_signal.load()) {
    if (o.duration > 0 && d->time >= o.duration - 0.5 * dt) break;
    if (recorder && recorder->failed()) break;  // the log is incomplete: a failed run (below)

    // commands for the cycle just published; the segment checked after this first read of it
    // (a truncated file reads as zeros: "detached" would be no answer)
    const bool attached = producer->controller_pid() != 0;
    if (segment_corrupted()) break;
    if (republish) {
      republish = false;
      publish(0, false);
    }
    if (waiting && !attached) {
      if (o.on_loss != ControllerLoss::kWait || !had_controller) {
        if (MonotonicSeconds() - wait_since > o.wait_controller) {
          std::fprintf(stderr,
                       "sim_host: no controller attached to segment '%s' within %g s; start one "
                       "(e.g. 'posture --segment %s') or pass --wait-controller 0 to run without\n",
                       o.segment.c_str(), o.wait_controller, o.segment.c_str());
          st.outcome = "no_controller";
          exit_code = kExitControllerLost;
          break;
        }
      }
      const double slept_from = MonotonicSeconds();
      timespec pause{0, 2000000};
      nanosleep(&pause, nullptr);
      st.wall_waiting += MonotonicSeconds() - slept_from;
      continue;
    }
    if (attached) {
      // a controller just attached may still be setting up: its first answer gets the
      // attach wait, not the per-cycle timeout
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
      double timeout = first_answer ? std::fmax(o.controller_timeout, o.wait_controller)
                                    : o.controller_timeout;
      if (first_answer) deadline = MonotonicSeconds();  // real time starts when the controller is there
      if (o.realtime) timeout = std::fmax(0.0, deadline + 0.9 * o.control_period - MonotonicSeconds());
      const double wait_from = first_answer ? MonotonicSeconds() : 0.0;
      const pid_t answering = producer->controller_pid();
      const shm::WaitResult answer = producer->WaitCommands(timeout, &cmd);
      if (first_answer) st.wall_waiting += MonotonicSeconds() - wait_from;  // a new controller setting up
      if (segment_corrupted()) break;
      switch (answer) {
        case shm::WaitResult::kCommands:
          if (st.commands++ == 0) {
            st.wall_first_command = MonotonicSeconds();
            st.cycles_at_first_command = st.cycles;
          }
          extra_status &= ~(shm::status::kHolding | shm::status::kCommandLate |
                            shm::status::kCommandRejected);
          // the controller's self-collision guard: a hold's begin and end are events
          if (int64_t hold = 0; const int change = guard.Update(cmd.guard, d->time, st.cycles, &hold))
            st.Record(d->time, change > 0 ? "guard_hold_begin" : "guard_hold_end", hold);
          if (const int rejected = servo.Accept(cmd); rejected > 0) {
            extra_status |= shm::status::kCommandRejected;
            if (!rejecting) st.Record(d->time, "commands_rejected", rejected);
            rejecting = true;
          } else {
            rejecting = false;
          }
          break;
        case shm::WaitResult::kTimeout:
          ++st.late;
          extra_status |= shm::status::kCommandLate;
          if (!o.realtime) {
            // a hung controller is let go: a new one may attach, and this one, should it run
            // again, learns that it was dropped (shm_bridge/controller_loss.h)
            producer->DropController(answering);
            if (lose_controller("did not answer within the timeout", "controller_silent", answering))
              exit_code = kExitControllerLost;
          }
          break;
        case shm::WaitResult::kControllerDied:
          if (lose_controller("died", "controller_died", answering)) exit_code = kExitControllerLost;
          break;
        case shm::WaitResult::kNoController:
          break;
      }
      if (exit_code != kExitOk) break;
      if (waiting) continue;
    } else if (had_controller && !(extra_status & shm::status::kHolding)) {
      // the controller detached cleanly (closed its adaptor)
      if (lose_controller("detached", "controller_detached", last_controller)) {
        exit_code = kExitControllerLost;
        break;
      }
      if (waiting) continue;
    }

    // physics: the servo runs at every step; the sensors on the cycle's last (published)
    for (int s = 0; s < steps_per_cycle; ++s) {
      const double t = d->time;
      const bool held = stepper.Step(s == steps_per_cycle - 1);
      ++st.steps;
      // each push's start and end, as events at the step's start
      for (size_t i = 0; i < o.pushes.size(); ++i) {
        if (stepper.push_changed(i))
          st.Record(t, stepper.push_on(i) ? "push_start" : "push_end", i);
      }
      if (!held) break;
    }
    if (watch.diverged()) {
      DiagnosisContext why{soft.get(), 0.5 * robot.total_mass, {}};
      for (size_t i = 0; i < robot.joints.size(); ++i) {
        const shm::JointCommand& c = servo.reference(i);
        const bool pos = c.mode == shm::JointMode::kPosition;
        if (pos || c.mode == shm::JointMode::kVelocity)
          why.gains.push_back({robot.joints[i].dof_adr, pos ? c.kp : 0.0, c.kd});
      }
      st.divergence = watch.Diagnose(m, d, why);
      st.outcome = "diverged";
      st.detail = st.divergence.Text();
      std::fprintf(stderr, "sim_host: simulation diverged: %s\n", st.detail.c_str());
      extra_status |= shm::status::kDiverged;
      producer->SetState(shm::ProducerState::kFailed);
      exit_code = kExitDiverged;
      break;
    }
    ++st.cycles;
    // once a cycle, after its physics steps (allocation-free)
    if (self_collision) self_collision->Check(d, d->time, st.cycles);
    // the fall watch, once a cycle (allocation-free): the first fall is an event
    if (fall->Check(m, d, d->time, st.cycles)) {
      st.Record(d->time, "fall", fall->fall().body);
      if (o.fall.on_fall == OnFall::kEnd) {
        exit_code = kExitFell;
        publish(shm::status::kShuttingDown);
        break;
      }
    }

    if (o.realtime) {
      deadline += o.control_period;
      if (MonotonicSeconds() < deadline) SleepUntil(deadline, &g_signal);
    }
    const bool last = o.duration > 0 && d->time >= o.duration - 0.5 * dt;
    // the images of this cycle's end, before its sensors (cameras.h: only while asked)
    if (!cameras.Tick(m, d, producer.get(), &error))
      std::fprintf(stderr, "sim_host: cameras off: %s\n", error.c_str());
    publish(last ? shm::status::kShuttingDown : 0);

    // progress on long runs (one line every few wall seconds, not per cycle)
    if (o.progress > 0 && !o.quiet) {
      const double now = MonotonicSeconds();
      if (now >= next_progress) {
        next_progress = now + o.progress;
        char end[32] = "until stopped";  // --duration 0
        if (o.duration > 0) std::snprintf(end, sizeof(end), "of %.2f s", o.duration);
        std::fprintf(stderr, "sim_host: t=%.2f s simulated (%s), %.2fx real time while simulating, "
                     "%lu cycles, late %lu, rejected %lu\n",
                     d->time, end, RealTimeFactor(d->time, st, now),
                     static_cast<unsigned long>(st.cycles), static_cast<unsigned long>(st.late),
                     static_cast<unsigned long>(servo.rejected_total()));
      }
    }
  }

  //---------------- shutdown ----------------
  st.wall_end = MonotonicSeconds();
  st.sim_time = d->time;
  if (g_signal.load() && exit_code == kExitOk) {
    st.outcome = "interrupted";
    exit_code = kExitInterrupted;
    std::fprintf(stderr, "sim_host: interrupted (signal %d) at t=%.3f s; shutting down\n",
                 g_signal.load(), d->time);
  }
  // a fall is the run's outcome unless the run ended for a worse reason (fall.h)
  st.fall = fall->Summary(m);
  if (st.fall.fell && (exit_code == kExitOk || exit_code == kExitInterrupted || exit_code == kExitFell)) {
    char at[96];
    std::snprintf(at, sizeof(at), "the robot fell at t=%.3f s (cycle %lu): ", st.fall.record.time,
                  static_cast<unsigned long>(st.fall.record.cycle));
    st.outcome = "fell";
    st.detail = at + st.fall.cause;
    exit_code = kExitFell;
  }
  if (exit_code != kExitDiverged) producer->SetState(shm::ProducerState::kStopped);
  if (recorder) EndLog(recorder.get(), &st, &exit_code);
  st.rejected = servo.rejected_total();
  st.clamped = servo.clamped_total();
  for (size_t i = 0; i < robot.joints.size(); ++i) {
    if (servo.clamped(static_cast<int>(i)) > 0) st.clamped_joints.emplace_back(robot.joints[i].name, servo.clamped(static_cast<int>(i)));
  }
  st.warnings = WarningCount() - warnings_at_start;
  if (self_collision) st.self_collision = self_collision->Summary();
  st.guard = guard.Summary();
  if (!o.quiet) PrintReport(st);
  if (!o.quiet && cameras.frames() > 0)
    std::fprintf(stderr, "sim_host: cameras: %lu images rendered, %.2f ms each\n",
                 static_cast<unsigned long>(cameras.frames()),
                 1e3 * cameras.render_seconds() / static_cast<double>(cameras.frames()));
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
  g_segment_object[0] = 0;
  return exit_code;
}

}  // namespace ohrp::sim
