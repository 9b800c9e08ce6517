// The runner: attach, lifecycle, the cycle loop, and how a run ends.
#include "controllers/runner.h"

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <memory>
#include <ostream>
#include <thread>

#include "cli/data_dir.h"
#include "controllers/self_collision_guard.h"
#include "self_collision_choice.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/realtime.h"

namespace ohrp::controllers {
namespace {

volatile std::sig_atomic_t g_stop = 0;

void OnStopSignal(int) { g_stop = 1; }

// how a producer is called in messages
const char* ProducerLabel(shm::ProducerKind kind) {
  switch (kind) {
    case shm::ProducerKind::kSimulation: return "sim_host";
    case shm::ProducerKind::kHardware: return "hw_driver";
    case shm::ProducerKind::kReplay: return "replay";
    case shm::ProducerKind::kUnknown: break;
  }
  return "producer";
}

std::string Fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

bool Retryable(shm::Error e) {
  return e == shm::Error::kNoSegment || e == shm::Error::kProducerNotReady;
}

// Opens the adaptor, retrying a missing or not yet ready segment until the attach timeout.
shm::Status Attach(shm::RobotAdaptor* adaptor, const RunOptions& options, bool* interrupted) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(options.attach_timeout);
  shm::AdaptorOptions adaptor_options;
  adaptor_options.read_timeout = options.read_timeout;
  *interrupted = false;
  while (true) {
    shm::Status status = adaptor->open(options.segment, adaptor_options);
    if (status.ok() || !Retryable(status.code) || Clock::now() >= deadline) return status;
    if (g_stop) {
      *interrupted = true;
      return status;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(options.retry_interval));
  }
}

// the guard's state this cycle into the segment's record (shm::GuardRecord): what a producer
// logs and reports; no allocation
void RecordGuard(const SelfCollisionGuard& guard, shm::GuardRecord* r) {
  *r = shm::GuardRecord{};
  r->holding = guard.holding() ? 1u : 0u;
  r->holds = guard.holds();
  if (!guard.holding()) return;
  r->distance = guard.hold_distance();
  const collision::LinkPair p = guard.hold_pair();
  const auto& links = guard.file().robot.links;
  const auto copy = [&](int link, char* out) {
    if (link < 0 || link >= static_cast<int>(links.size())) return;
    links[link].name.copy(out, shm::kNameLen - 1);
  };
  copy(p.a, r->link_a);
  copy(p.b, r->link_b);
}

}  // namespace

const char* ExitCodeHelp() {
  return "Exit codes:\n"
         "  0  the producer (sim_host / hw_driver) ended its run normally, or SIGINT/SIGTERM\n"
         "  2  bad command line (an unknown option, a bad value, a file that does not exist)\n"
         "  3  a file is malformed or does not fit the robot (joint names/count, limits)\n"
         "  4  could not attach to the segment (not there within --attach-timeout, built\n"
         "     against another layout, another controller attached, ...)\n"
         "  5  the producer's process is gone, or sent no sensors within --read-timeout, or\n"
         "     the segment was corrupted under the run (truncated, overwritten)\n"
         "  6  the producer ended reporting a failure (e.g. the simulation diverged)\n"
         "  7  the producer dropped this controller: it did not answer within the producer's\n"
         "     timeout (e.g. it was stopped, then resumed)\n"
         "  8  the robot fell: its base tilted beyond the limit, its feet stopped carrying its\n"
         "     weight, or its CoM sank below half its stance height (the message says when and\n"
         "     why; the limits come from the robot; --no-fall-watch turns this off)\n"
         "  9  the controller could not do what it was asked, by its own measurements (e.g.\n"
         "     walk: a step that did not land; balance: leg IK failing persistently)\n";
}

std::string DefaultSelfCollisionFile() { return cli::DataPath("mjcf/hrp1s/selfcollision.yaml"); }

void InstallStopSignalHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: blocking waits return with EINTR
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void RequestStop() noexcept { g_stop = 1; }
void ClearStopRequest() noexcept { g_stop = 0; }

int RunController(Controller& controller, const RunOptions& options, std::ostream& out,
                  std::ostream& err, RunReport* report) {
  RunReport local;
  RunReport& rep = report != nullptr ? *report : local;
  rep = RunReport{};
  const std::string& prog = options.program;
  const std::string seg = "'" + options.segment + "'";

  //---------------- attach and configure ----------------
  shm::RobotAdaptor adaptor;
  bool interrupted = false;
  shm::Status attached = Attach(&adaptor, options, &interrupted);
  if (interrupted) {
    out << prog << ": stopped by signal while waiting for segment " << seg << "\n";
    return rep.exit_code = kExitOk;
  }
  if (!attached.ok()) {
    err << prog << ": cannot attach to segment " << seg << " (" << shm::ErrorName(attached.code)
        << "): " << attached.message;
    if (Retryable(attached.code)) {
      err << (options.attach_timeout > 0
                  ? " (gave up after --attach-timeout " + Fixed(options.attach_timeout, 1) + " s)"
                  : " (use --attach-timeout S to wait for the producer)");
    }
    err << "\n";
    return rep.exit_code = kExitAttach;
  }
  const shm::SegmentHeader& header = adaptor.header();
  const std::string producer = std::string(ProducerLabel(header.producer_kind)) + " (pid " +
                               std::to_string(header.producer_pid) + ")";
  ConfigStatus configured = controller.configure(header);
  if (!configured.ok()) {
    err << prog << ": segment " << seg << " (robot " << header.robot_name << ", "
        << header.njoint << " joints): " << configured.message << "\n";
    adaptor.close();
    controller.close();
    return rep.exit_code = kExitConfig;
  }
  // the self-collision check (self_collision_choice.h): a file for this robot with another
  // model hash is refused below, exit 3: protection is never silently off
  SelfCollisionGuard guard;
  const std::string self_collision = SelfCollisionFileFor(options, header, prog, err);
  const bool guarded = !self_collision.empty();
  if (guarded) {
    const std::string problem = guard.Configure(self_collision, header);
    if (!problem.empty()) {
      err << prog << ": --self-collision: " << problem << "\n";
      adaptor.close();
      controller.close();
      return rep.exit_code = kExitConfig;
    }
    guard.set_brake_unloaded_legs(controller.guard_may_brake_legs());
    if (!controller.guard_may_brake()) {
      guard.set_monitor_only(true);
      out << prog << ": self-collision check: monitoring only (a brake mid-motion would topple "
          << "the robot); links measured closer than their limit fail the run\n";
    }
  }
  // the images the controller wants: asked for now, read each cycle into one buffer
  const uint32_t cameras = controller.cameras();
  std::unique_ptr<shm::ImageSlot> image;
  std::array<uint64_t, shm::kMaxCameras> last_frame{};
  if (cameras != 0) {
    if (!adaptor.request_images(cameras)) {
      err << prog << ": segment " << seg << ": cannot ask for the images of cameras (bitmask "
          << cameras << "): the header declares " << header.ncamera
          << " cameras, or 16 programs ask already\n";
      adaptor.close();
      controller.close();
      return rep.exit_code = kExitConfig;
    }
    image = std::make_unique<shm::ImageSlot>();
  }
  // the fall watch: the controller's limits for this robot
  FallWatch watch;
  if (options.fall_watch) {
    FallLimits limits = DefaultFallLimits();
    controller.fall_limits(&limits);
    const std::string off = watch.Configure(header, limits);
    if (!off.empty()) out << prog << ": " << off << "\n";
  }
  out << prog << ": attached to segment " << seg << ": robot " << header.robot_name << ", "
      << header.njoint << " joints, control period " << Fixed(header.control_period * 1e3, 3)
      << " ms, producer " << producer << std::endl;
  if (options.fall_watch) out << prog << ": " << watch.Summary() << std::endl;
  if (options.rt_priority > 0) {
    // the hardware chain's controller: SCHED_FIFO and locked memory where the system permits
    // (shm_bridge/realtime.h); what it refuses is said, and the loop runs without it
    rt::RtSettings rt_settings;
    rt_settings.priority = options.rt_priority;
    const rt::RtReport rt = rt::SetUpRealTime(rt_settings);
    for (const std::string& w : rt.warnings) err << prog << ": " << w << "\n";
    out << prog << ": real time: " << rt.Describe() << std::endl;
  }

  //---------------- the cycle loop: no allocation, throwing or logging ----------------
  shm::SensorBlock sensors{};
  shm::CommandBlock commands{};
  shm::ReadResult result = shm::ReadResult::kOk;
  bool stopped_by_signal = false;
  bool fell = false;
  bool active = false;
  uint32_t last_status = 0;
  uint64_t late = 0, rejected = 0;
  while (true) {
    if (g_stop) {
      stopped_by_signal = true;
      break;
    }
    result = adaptor.read(&sensors);
    if (result != shm::ReadResult::kOk) break;
    if (!active) {
      active = controller.activate(sensors);
      rep.first_time = sensors.time;
      if (guarded) guard.Activate(sensors);
    }
    rep.last_time = sensors.time;
    last_status = sensors.status;
    late = sensors.late_commands;
    rejected = sensors.rejected_commands;
    for (int c = 0; cameras >> c != 0 && c < shm::kMaxCameras; ++c) {
      if ((cameras & (1u << c)) != 0 &&
          adaptor.read_image(c, last_frame[c], image.get()) == shm::ImageResult::kOk) {
        last_frame[c] = image->frame;
        controller.on_image(c, *image);
      }
    }
    controller.update(sensors, &commands);
    if (guarded) {
      guard.Filter(sensors, &commands);
      RecordGuard(guard, &commands.guard);
    }
    if (options.fall_watch && watch.Update(sensors, controller.base_tilt(), controller.com_height())) {
      fell = true;  // the producer holds the last commands
      break;
    }
    result = adaptor.write(commands);
    if (result != shm::ReadResult::kOk) break;
    ++rep.cycles;
  }
  if (g_stop && !fell) stopped_by_signal = true;
  // the producer's own verdict in its final block, which may have come with the end of the run
  if (result == shm::ReadResult::kProducerStopped) last_status |= adaptor.published_status();

  //---------------- end of the run ----------------
  controller.deactivate();
  // a producer that fails (sim_host diverging) sets the segment's state to failed before it
  // can publish another block, so the last status seen may not carry kDiverged
  const bool producer_failed = adaptor.producer_state() == shm::ProducerState::kFailed;
  adaptor.close();  // frees the controller slot
  controller.close();
  if (fell) {
    rep.fall = watch.event();
    controller.NoteFall(rep.fall);
  }

  std::string why;
  if (fell) {
    why = watch.Describe();
    rep.exit_code = kExitFell;
  } else if (stopped_by_signal) {
    why = "stopped by signal";
    rep.exit_code = kExitOk;
  } else if (result == shm::ReadResult::kProducerStopped) {
    if ((last_status & shm::status::kDiverged) || producer_failed) {
      why = producer + " ended its run reporting a failure" +
            (header.producer_kind == shm::ProducerKind::kSimulation ||
                     (last_status & shm::status::kDiverged)
                 ? std::string(" (the simulation diverged: the producer's diagnostic says where "
                               "and why)")
                 : std::string(" (see the producer's output)"));
      rep.exit_code = kExitProducerFailed;
    } else if (last_status & shm::status::kFallen) {
      // judged on the robot by the producer (sim_host's fall watch), though this program's own
      // watch did not fire (off, or the robot lacks the sensors it needs)
      why = producer + " ended its run: the robot fell (the producer's fall watch: its output "
            "says when and why)";
      rep.exit_code = kExitFell;
    } else {
      why = producer + " ended its run";
      rep.exit_code = kExitOk;
    }
  } else if (result == shm::ReadResult::kDropped) {
    why = producer + " dropped this controller: it did not answer within the producer's "
          "timeout (was it stopped or stalled?); the robot was held without it";
    rep.exit_code = kExitDropped;
  } else if (result == shm::ReadResult::kProducerGone) {
    why = producer + " is gone (its process exited without ending the run)";
    rep.exit_code = kExitProducerLost;
  } else if (result == shm::ReadResult::kTimeout) {
    why = "no sensors from " + producer + " for " + Fixed(options.read_timeout, 2) +
          " s (--read-timeout): the producer is alive but not cycling";
    rep.exit_code = kExitProducerLost;
  } else {
    why = std::string("the adaptor reported ") + shm::ReadResultName(result);
    rep.exit_code = kExitProducerLost;
  }
  std::ostream& sink = rep.exit_code == kExitOk ? out : err;
  sink << prog << ": " << why << "; stopped after " << rep.cycles << " cycles (producer time "
       << Fixed(rep.first_time, 3) << " .. " << Fixed(rep.last_time, 3) << " s), segment "
       << seg << " released\n";
  controller.report(out);
  if (guarded) guard.Report(prog, out);
  // the controller's own verdict, unless the run already failed for a reason of its own; a
  // motion the self-collision guard still held at the end was not completed
  if (rep.exit_code == kExitOk || rep.exit_code == kExitFell) {
    rep.failure = controller.failure();
    // a hold is a result: the motion the controller was asked for was stopped; where its own
    // verification does not confirm its goal (or its motion is the trajectory, playback), or
    // the guard still held at the end, the run failed, naming the pair
    // judged on the robot: links measured closer than their limit fail the run
    if (guarded && guard.violations() > 0) {
      const std::string v = guard.ViolationSummary();
      rep.failure += (rep.failure.empty() ? "" : "; ") + v;
    }
    if (guarded && guard.holds() > 0) {
      if (!rep.failure.empty()) {
        rep.failure += "; " + guard.HoldSummary();
      } else if (controller.hold_is_failure()) {
        rep.failure = "the motion was not completed: " + guard.HoldSummary();
      } else if (guard.holding()) {
        shm::GuardRecord g;
        RecordGuard(guard, &g);
        rep.failure = std::string("the self-collision guard was still holding the motion at the "
                                  "end of the run (") + g.link_a + "/" + g.link_b + " at " +
                      Fixed(1e3 * g.distance, 1) + " mm): the commanded motion was not completed";
      }
    }
    if (!rep.failure.empty()) {
      err << prog << ": FAILED: " << rep.failure << "\n";
      if (rep.exit_code == kExitOk) rep.exit_code = kExitFailed;
    }
  }
  const CycleCounters& c = controller.counters();
  if (c.non_finite_fixed || c.clamped || c.diverged_sensors || late || rejected) {
    err << prog << ": problems counted: " << c.non_finite_fixed
        << " non-finite joint commands replaced by a hold, " << c.clamped
        << " references clamped to joint limits, " << c.diverged_sensors
        << " diverged sensor blocks; the producer counted " << late << " late command blocks and "
        << rejected << " rejected joint commands\n";
  }
  return rep.exit_code;
}

}  // namespace ohrp::controllers
