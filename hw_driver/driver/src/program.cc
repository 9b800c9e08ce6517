// The hw_driver program: set-up, the reporter thread, the end-of-run report (see program.h).
#include "hw_driver/program.h"

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <boost/interprocess/shared_memory_object.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <thread>

#include "hw_driver/plugin.h"
#include "robot_model/model.h"
#include "robot_model/output_file.h"
#include "datalog/recorder.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::hw {
namespace {

char g_segment_object[128] = "";  // removed by MuJoCo's fatal-error path

void OnMujocoFatal(const char*) {
  if (g_segment_object[0]) boost::interprocess::shared_memory_object::remove(g_segment_object);
  _exit(kExitUsage);
}

void PrintEvent(const Event& e, const shm::ProducerConfig& robot) {
  char what[160] = "";
  switch (e.kind) {
    case EventKind::kControllerAttached:
    case EventKind::kControllerDied:
    case EventKind::kControllerDetached:
      std::snprintf(what, sizeof(what), " (pid %ld)", static_cast<long>(e.value));
      break;
    case EventKind::kControllerSilent:
      std::snprintf(what, sizeof(what), " (%ld cycles without an answer)",
                    static_cast<long>(e.value));
      break;
    case EventKind::kBoardSilent:
    case EventKind::kBoardReset:
      std::snprintf(what, sizeof(what), " (board mask 0x%lx)", static_cast<long>(e.value));
      break;
    case EventKind::kBoardNonFinite:
      if (e.value != 0) {
        std::snprintf(what, sizeof(what), " (NaN or inf from board mask 0x%lx)",
                      static_cast<long>(e.value));
      } else {
        std::snprintf(what, sizeof(what), " (NaN or inf in the joint positions read)");
      }
      break;
    case EventKind::kBoardBack:
      std::snprintf(what, sizeof(what), " (after %ld silent cycles)", static_cast<long>(e.value));
      break;
    case EventKind::kSafeMode: {
      static const char* kWhy[] = {"", "board silent", "board reset", "controller silent",
                                   "controller died", "controller detached",
                                   "NaN or inf from a board", "implausible values from a board",
                                   "a board disobeyed", "the robot fell"};
      const long v = static_cast<long>(e.value);
      std::snprintf(what, sizeof(what), " (%s): damped hold, then servo-off",
                    v >= 1 && v <= kSafeFall ? kWhy[v] : "?");
      break;
    }
    case EventKind::kImplausibleReading:
    case EventKind::kServoMismatch:
    case EventKind::kTrackingError:
      std::snprintf(what, sizeof(what), " (board %d, joint %d %s, read %.6g)", e.board, e.joint,
                    e.joint >= 0 && e.joint < static_cast<int>(robot.joint_names.size())
                        ? robot.joint_names[e.joint].c_str() : "?",
                    e.reading);
      break;
    case EventKind::kCommandsUnacknowledged:
    case EventKind::kCommandRefused:
    case EventKind::kForeignCommand:
    case EventKind::kSafeModeRefused:
    case EventKind::kResetHold:
    case EventKind::kResetRamped:
      std::snprintf(what, sizeof(what), " (board %d, board mask 0x%lx)", e.board,
                    static_cast<long>(e.value));
      break;
    case EventKind::kFall:
      std::snprintf(what, sizeof(what), " (IMU tilt %.1f deg)", e.reading * 180.0 / M_PI);
      break;
    case EventKind::kServoOn:
      if (e.value > 0) std::snprintf(what, sizeof(what), " (recovery %ld)", static_cast<long>(e.value));
      break;
    case EventKind::kWaitingForController:
      std::snprintf(what, sizeof(what), ": servos off until a new controller attaches");
      break;
    case EventKind::kBoardRearm:
      std::snprintf(what, sizeof(what), ": boards re-armed, servo-on after clean reads");
      break;
    case EventKind::kEmergencyStop:
      std::snprintf(what, sizeof(what), " (%s): servos off", e.value == 1 ? "board input" : "SIGUSR2");
      break;
    default:
      break;
  }
  std::fprintf(stderr, "hw_driver:   cycle %lu, t=%.3f s: %s%s\n",
               static_cast<unsigned long>(e.cycle), e.time, EventName(e.kind), what);
}

// The end-of-run report: the outcome with the counts, its detail, the lateness table (when
// `lateness`) and the events.
void PrintReport(const DriverResult& r, const LiveStats& live, const DriverOptions& o,
                 const shm::ProducerConfig& robot, bool lateness) {
  std::fprintf(stderr,
               "hw_driver: %s after %.3f s: %lu cycles, %lu deadline misses, %lu slots skipped, "
               "%lu commands, %lu late, %lu rejected, %lu clamped, %lu silent reads, %lu packets "
               "lost (%s)\n",
               r.outcome.c_str(), r.duration, static_cast<unsigned long>(live.cycles.load()),
               static_cast<unsigned long>(live.deadline_misses.load()),
               static_cast<unsigned long>(live.skipped.load()),
               static_cast<unsigned long>(live.commands.load()),
               static_cast<unsigned long>(live.late_commands.load()),
               static_cast<unsigned long>(live.rejected.load()),
               static_cast<unsigned long>(live.clamped.load()),
               static_cast<unsigned long>(live.silent_reads.load()),
               static_cast<unsigned long>(live.packets_lost.load()), r.rt.Describe().c_str());
  if (!r.detail.empty()) std::fprintf(stderr, "hw_driver: %s\n", r.detail.c_str());
  if (lateness) {
    std::fprintf(stderr, "hw_driver: wake-up lateness (--wake %s%s):\n%s",
                 WakeModeName(o.wake.mode), WakeCost(live, o).c_str(),
                 LatenessTable(live.lateness).c_str());
  }
  std::fprintf(stderr, "hw_driver: events:\n");
  for (const Event& e : r.events) PrintEvent(e, robot);
  if (r.events_dropped > 0) {
    std::fprintf(stderr, "hw_driver:   (%lu more events not kept)\n",
                 static_cast<unsigned long>(r.events_dropped));
  }
}

}  // namespace

bool LoadRobotDescription(const std::string& model_path, const std::string& segment,
                          double period, shm::ProducerConfig* out, std::string* error) {
  auto scene = model::Scene::Load(model_path, error);
  if (!scene) return false;
  model::RobotMap robot;
  if (!model::MapRobot(scene->m(), &robot, error)) {
    *error = model_path + ": " + *error;
    return false;
  }
  *out = model::MakeProducerConfig(robot, scene->m(), segment, 0.0, period);
  out->kind = shm::ProducerKind::kHardware;
  out->read_timeout_hint = 10 * period;
  return true;
}

bool CheckHoldGains(const shm::ProducerConfig& robot, const DriverOptions& o, std::string* error) {
  for (size_t j = 0; j < robot.joint_names.size(); ++j) {
    const double kp = robot.default_kp[j] * o.safe_kp_scale, kd = robot.default_kd[j] * o.safe_kd_scale;
    const char* which = nullptr;
    if (!(kp <= model::kMaxGain)) which = "--safe-kp-scale";
    else if (!(kd <= model::kMaxGain)) which = "--safe-kd-scale";
    else if (!(kp > 0) && robot.default_kp[j] > 0) which = "--safe-kp-scale";
    if (which) {
      char buf[320];
      std::snprintf(buf, sizeof(buf),
                    "%s: joint %s's hold gains kp %.6g, kd %.6g would be refused by its servo "
                    "(gains in (0, %.6g]): the safe mode would not hold",
                    which, robot.joint_names[j].c_str(), kp, kd, model::kMaxGain);
      *error = buf;
      return false;
    }
  }
  return true;
}

int RunProgram(const ProgramOptions& o) {
  model::InstallMujocoHandlers(OnMujocoFatal);
  InstallSignalHandlers();
  signal(SIGXFSZ, SIG_IGN);  // a file size limit fails the log's write (reported), never kills
  // SIGUSR1 stays blocked in every thread but is taken by the reporter (sigtimedwait), so that
  // it never kills the driver, even during set-up
  sigset_t usr1;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &usr1, nullptr);

  //---------------- configure: robot, plugin, boards, segment ----------------
  std::string error;
  shm::ProducerConfig robot;
  if (!LoadRobotDescription(o.model, o.segment, o.driver.period, &robot, &error)) {
    std::fprintf(stderr, "hw_driver: %s\n", error.c_str());
    return kExitUsage;
  }
  // the outputs, before anything runs (robot_model/output_file.h)
  for (const auto& [option, path] : {std::pair{"--summary", &o.summary_path}, {"--stats", &o.stats_path}}) {
    if (!path->empty() && !model::PrepareOutputFile(*path, "{}\n", &error)) {
      std::fprintf(stderr, "hw_driver: %s: %s\n", option, error.c_str());
      return kExitUsage;
    }
    if (!path->empty()) std::remove(path->c_str());  // written whole once there is something to say
  }
  // the safe mode's hold must be one the boards take (robot_model/servo.h: gains up to kMaxGain)
  if (!CheckHoldGains(robot, o.driver, &error)) {
    std::fprintf(stderr, "hw_driver: %s\n", error.c_str());
    return kExitUsage;
  }
  // the data log: sim_host's columns without the ground truth (no base_* on the robot)
  std::unique_ptr<datalog::Recorder> log;
  if (!o.log_path.empty()) {
    datalog::RecorderChannels channels;
    channels.base = false;
    channels.joint_velocities = o.log_dq;
    channels.reference_velocities = o.log_dq;  // dqref_: the servos' (the boards' on their time)
    log = datalog::Recorder::Open(o.log_path,
                                  {robot.joint_names, robot.force_names, robot.imu_names,
                                   robot.passive_names},
                                  &error, 16384, channels, o.log_max);
    if (!log) {
      std::fprintf(stderr, "hw_driver: %s (--log)\n", error.c_str());
      return kExitUsage;
    }
  }
  auto plugin = IoPlugin::Load(o.io_plugin, &error);
  if (!plugin) {
    std::fprintf(stderr, "hw_driver: %s\n", error.c_str());
    return kExitUsage;
  }
  IoConfig io_config;
  io_config.robot_name = robot.robot_name;
  io_config.joint_names = robot.joint_names;
  io_config.force_names = robot.force_names;
  io_config.imu_names = robot.imu_names;
  io_config.passive_names = robot.passive_names;
  io_config.cameras = robot.cameras;
  io_config.period = o.driver.period;
  io_config.args = o.io_args;
  if (!plugin->io().open(io_config, &error)) {
    std::fprintf(stderr, "hw_driver: IO plugin '%s' could not open the boards: %s\n",
                 o.io_plugin.c_str(), error.c_str());
    return kExitIo;
  }
  shm::Status status;
  auto producer = shm::Producer::Create(robot, &status);
  if (!producer) {
    plugin->io().close();
    std::fprintf(stderr, "hw_driver: %s\n", status.message.c_str());
    return kExitUsage;
  }
  if (!status.message.empty()) std::fprintf(stderr, "hw_driver: %s\n", status.message.c_str());
  std::snprintf(g_segment_object, sizeof(g_segment_object), "%s",
                producer->object_name().c_str());
  if (!o.quiet) {
    std::fprintf(stderr,
                 "hw_driver: robot '%s' (%zu joints, %zu F/T, %zu IMU) from %s; boards: %s\n"
                 "hw_driver: segment '%s', servo cycle %g s, watchdog %d cycles, board timeout "
                 "%d cycles, safe mode %g s, controller loss: %s\n",
                 robot.robot_name.c_str(), robot.joint_names.size(), robot.force_names.size(),
                 robot.imu_names.size(), o.model.c_str(), o.io_plugin.c_str(), o.segment.c_str(),
                 o.driver.period, o.driver.watchdog_cycles, o.driver.board_timeout_cycles,
                 o.driver.safe_time, shm::ControllerLossName(o.driver.on_controller_loss));
  }

  //---------------- the reporter: SIGUSR1 and the stats file, off the loop's thread ----------
  Driver driver(o.driver, robot, &plugin->io(), producer.get());
  driver.SetLog(log.get());
  std::atomic<bool> reporter_stop{false};
  std::thread reporter([&] {
    using Clock = std::chrono::steady_clock;
    auto next_stats = Clock::now();
    while (!reporter_stop.load()) {
      timespec slice{0, 50000000};
      if (sigtimedwait(&usr1, nullptr, &slice) == SIGUSR1) {
        std::fprintf(stderr, "hw_driver: %lu cycles, %lu deadline misses, state %s; lateness:\n%s",
                     static_cast<unsigned long>(driver.live().cycles.load()),
                     static_cast<unsigned long>(driver.live().deadline_misses.load()),
                     DriverStateName(static_cast<DriverState>(driver.live().state.load())),
                     LatenessTable(driver.live().lateness).c_str());
      }
      if (!o.stats_path.empty() && Clock::now() >= next_stats) {
        next_stats += std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(o.stats_interval));
        WriteStats(o.stats_path, o, robot, driver.live(), nullptr);
      }
    }
  });

  //---------------- run ----------------
  const rt::RtReport& rt = driver.PrepareRealTime();  // after the reporter: it stays SCHED_OTHER
  for (const std::string& w : rt.warnings) std::fprintf(stderr, "hw_driver: warning: %s\n", w.c_str());
  const int exit_code = driver.Run();
  reporter_stop.store(true);
  reporter.join();
  plugin->io().close();

  //---------------- report, then close: the segment is removed ----------------
  const DriverResult& r = driver.result();
  // --quiet: a failure only (a stop by SIGINT/SIGTERM is none), without the lateness table
  if (!o.quiet) {
    PrintReport(r, driver.live(), o.driver, robot, true);
  } else if (exit_code != kExitOk && exit_code != kExitInterrupted) {
    PrintReport(r, driver.live(), o.driver, robot, false);
  }
  int code = exit_code;  // an output not written whole (below) fails a run that was ok
  if (!o.summary_path.empty() && !WriteStats(o.summary_path, o, robot, driver.live(), &r)) {
    std::fprintf(stderr, "hw_driver: cannot write the summary '%s'\n", o.summary_path.c_str());
    if (code == kExitOk) code = model::kExitOutputFailed;
  }
  if (!o.stats_path.empty()) WriteStats(o.stats_path, o, robot, driver.live(), &r);
  if (log) {
    // everything the loop pushed, SIGINT or not, written and synced: the rows ON DISK counted
    const bool complete = log->Close();
    if (!complete || log->limit_reached() || log->dropped() > 0 || !o.quiet)
      std::fprintf(stderr, "hw_driver: %s\n", log->Describe().c_str());
    if (!complete && code == kExitOk) code = model::kExitOutputFailed;
    log.reset();
  }
  producer.reset();
  g_segment_object[0] = 0;
  return code;
}

}  // namespace ohrp::hw
