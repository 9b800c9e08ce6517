// RunController's stages (see controller_run.h).
#include "controller_run.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include "self_collision_choice.h"
#include "shm_bridge/realtime.h"

namespace ohrp::controllers {
namespace {

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
shm::Status OpenRetrying(shm::RobotAdaptor* adaptor, const RunOptions& options, bool* interrupted) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(options.attach_timeout);
  shm::AdaptorOptions adaptor_options;
  adaptor_options.read_timeout = options.read_timeout;
  *interrupted = false;
  while (true) {
    shm::Status status = adaptor->open(options.segment, adaptor_options);
    if (status.ok() || !Retryable(status.code) || Clock::now() >= deadline) return status;
    if (StopRequested()) {
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

ControllerRun::ControllerRun(Controller& controller, const RunOptions& options, std::ostream& out,
                             std::ostream& err, RunReport* report)
    : controller_(controller),
      options_(options),
      out_(out),
      err_(err),
      rep_(report != nullptr ? *report : local_),
      prog_(options.program),
      seg_("'" + options.segment + "'") {
  rep_ = RunReport{};
}

//---------------- attach and configure ----------------

bool ControllerRun::Attach() {
  bool interrupted = false;
  const shm::Status attached = OpenRetrying(&adaptor_, options_, &interrupted);
  if (interrupted) {
    out_ << prog_ << ": stopped by signal while waiting for segment " << seg_ << "\n";
    rep_.exit_code = kExitOk;
    return false;
  }
  if (!attached.ok()) {
    err_ << prog_ << ": cannot attach to segment " << seg_ << " ("
         << shm::ErrorName(attached.code) << "): " << attached.message;
    if (Retryable(attached.code)) {
      err_ << (options_.attach_timeout > 0
                   ? " (gave up after --attach-timeout " + Fixed(options_.attach_timeout, 1) + " s)"
                   : " (use --attach-timeout S to wait for the producer)");
    }
    err_ << "\n";
    rep_.exit_code = kExitAttach;
    return false;
  }
  const shm::SegmentHeader& header = adaptor_.header();
  producer_ = std::string(ProducerLabel(header.producer_kind)) + " (pid " +
              std::to_string(header.producer_pid) + ")";
  return true;
}

bool ControllerRun::Configure() {
  const shm::SegmentHeader& header = adaptor_.header();
  const ConfigStatus configured = controller_.configure(header);
  if (!configured.ok()) {
    err_ << prog_ << ": segment " << seg_ << " (robot " << header.robot_name << ", "
         << header.njoint << " joints): " << configured.message << "\n";
    return Refuse(kExitConfig);
  }
  if (!ConfigureGuard() || !RequestImages()) return Refuse(kExitConfig);
  ConfigureFallWatch();
  out_ << prog_ << ": attached to segment " << seg_ << ": robot " << header.robot_name << ", "
       << header.njoint << " joints, control period " << Fixed(header.control_period * 1e3, 3)
       << " ms, producer " << producer_ << std::endl;
  if (options_.fall_watch) out_ << prog_ << ": " << watch_.Summary() << std::endl;
  SetUpRealTime();
  return true;
}

bool ControllerRun::Refuse(ExitCode code) {
  adaptor_.close();
  controller_.close();
  rep_.exit_code = code;
  return false;
}

// the self-collision check (self_collision_choice.h): a file for this robot with another model
// hash is refused, exit 3: protection is never silently off
bool ControllerRun::ConfigureGuard() {
  const std::string self_collision = SelfCollisionFileFor(options_, adaptor_.header(), prog_, err_);
  guarded_ = !self_collision.empty();
  if (!guarded_) return true;
  const std::string problem = guard_.Configure(self_collision, adaptor_.header());
  if (!problem.empty()) {
    err_ << prog_ << ": --self-collision: " << problem << "\n";
    return false;
  }
  guard_.set_brake_unloaded_legs(controller_.guard_may_brake_legs());
  if (!controller_.guard_may_brake()) {
    guard_.set_monitor_only(true);
    out_ << prog_ << ": self-collision check: monitoring only (a brake mid-motion would topple "
         << "the robot); links measured closer than their limit fail the run\n";
  }
  return true;
}

// the images the controller wants: asked for now, read each cycle into one buffer
bool ControllerRun::RequestImages() {
  cameras_ = controller_.cameras();
  if (cameras_ == 0) return true;
  if (!adaptor_.request_images(cameras_)) {
    err_ << prog_ << ": segment " << seg_ << ": cannot ask for the images of cameras (bitmask "
         << cameras_ << "): the header declares " << adaptor_.header().ncamera
         << " cameras, or 16 programs ask already\n";
    return false;
  }
  image_ = std::make_unique<shm::ImageSlot>();
  return true;
}

// the fall watch: the controller's limits for this robot
void ControllerRun::ConfigureFallWatch() {
  if (!options_.fall_watch) return;
  FallLimits limits = DefaultFallLimits();
  controller_.fall_limits(&limits);
  const std::string off = watch_.Configure(adaptor_.header(), limits);
  if (!off.empty()) out_ << prog_ << ": " << off << "\n";
}

// the hardware chain's controller: SCHED_FIFO and locked memory where the system permits
// (shm_bridge/realtime.h); what it refuses is said, and the loop runs without it
void ControllerRun::SetUpRealTime() {
  if (options_.rt_priority <= 0) return;
  rt::RtSettings rt_settings;
  rt_settings.priority = options_.rt_priority;
  const rt::RtReport rt = rt::SetUpRealTime(rt_settings);
  for (const std::string& w : rt.warnings) err_ << prog_ << ": " << w << "\n";
  out_ << prog_ << ": real time: " << rt.Describe() << std::endl;
}

//---------------- the cycle loop: no allocation, throwing or logging ----------------

void ControllerRun::Loop() {
  while (Cycle()) ++rep_.cycles;
  if (StopRequested() && !fell_) stopped_by_signal_ = true;
  // the producer's own verdict in its final block, which may have come with the end of the run
  if (result_ == shm::ReadResult::kProducerStopped) last_status_ |= adaptor_.published_status();
}

bool ControllerRun::Cycle() {
  if (StopRequested()) {
    stopped_by_signal_ = true;
    return false;
  }
  result_ = adaptor_.read(&sensors_);
  if (result_ != shm::ReadResult::kOk) return false;
  if (!active_) {
    active_ = controller_.activate(sensors_);
    rep_.first_time = sensors_.time;
    if (guarded_) guard_.Activate(sensors_);
  }
  rep_.last_time = sensors_.time;
  last_status_ = sensors_.status;
  late_ = sensors_.late_commands;
  rejected_ = sensors_.rejected_commands;
  ReadImages();
  controller_.update(sensors_, &commands_);
  if (guarded_) {
    guard_.Filter(sensors_, &commands_);
    RecordGuard(guard_, &commands_.guard);
  }
  if (options_.fall_watch &&
      watch_.Update(sensors_, controller_.base_tilt(), controller_.com_height())) {
    fell_ = true;  // the producer holds the last commands
    return false;
  }
  result_ = adaptor_.write(commands_);
  return result_ == shm::ReadResult::kOk;
}

void ControllerRun::ReadImages() {
  for (int c = 0; cameras_ >> c != 0 && c < shm::kMaxCameras; ++c) {
    if ((cameras_ & (1u << c)) != 0 &&
        adaptor_.read_image(c, last_frame_[c], image_.get()) == shm::ImageResult::kOk) {
      last_frame_[c] = image_->frame;
      controller_.on_image(c, *image_);
    }
  }
}

//---------------- end of the run ----------------

void ControllerRun::End() {
  Release();
  const std::string why = WhyItEnded();
  std::ostream& sink = rep_.exit_code == kExitOk ? out_ : err_;
  sink << prog_ << ": " << why << "; stopped after " << rep_.cycles << " cycles (producer time "
       << Fixed(rep_.first_time, 3) << " .. " << Fixed(rep_.last_time, 3) << " s), segment "
       << seg_ << " released\n";
  controller_.report(out_);
  if (guarded_) guard_.Report(prog_, out_);
  // the controller's own verdict, unless the run already failed for a reason of its own
  if (rep_.exit_code == kExitOk || rep_.exit_code == kExitFell) JudgeController();
  ReportCounters();
}

void ControllerRun::Release() {
  controller_.deactivate();
  // a producer that fails (sim_host diverging) sets the segment's state to failed before it
  // can publish another block, so the last status seen may not carry kDiverged
  producer_failed_ = adaptor_.producer_state() == shm::ProducerState::kFailed;
  adaptor_.close();  // frees the controller slot
  controller_.close();
  if (fell_) {
    rep_.fall = watch_.event();
    controller_.NoteFall(rep_.fall);
  }
}

// why the loop ended, with the exit code it means
std::string ControllerRun::WhyItEnded() {
  if (fell_) {
    rep_.exit_code = kExitFell;
    return watch_.Describe(controller_.tilt_reference());
  }
  if (stopped_by_signal_) {
    rep_.exit_code = kExitOk;
    return "stopped by signal";
  }
  switch (result_) {
    case shm::ReadResult::kProducerStopped:
      return EndOfProducerRun();
    case shm::ReadResult::kDropped:
      rep_.exit_code = kExitDropped;
      return producer_ + " dropped this controller: it did not answer within the producer's "
             "timeout (was it stopped or stalled?); the robot was held without it";
    case shm::ReadResult::kProducerGone:
      rep_.exit_code = kExitProducerLost;
      return producer_ + " is gone (its process exited without ending the run)";
    case shm::ReadResult::kTimeout:
      rep_.exit_code = kExitProducerLost;
      return "no sensors from " + producer_ + " for " + Fixed(options_.read_timeout, 2) +
             " s (--read-timeout): the producer is alive but not cycling";
    default:
      rep_.exit_code = kExitProducerLost;
      return std::string("the adaptor reported ") + shm::ReadResultName(result_);
  }
}

// the producer ended the run: with a failure, a fall it judged, or normally
std::string ControllerRun::EndOfProducerRun() {
  const bool diverged = (last_status_ & shm::status::kDiverged) != 0;
  if (diverged || producer_failed_) {
    rep_.exit_code = kExitProducerFailed;
    return producer_ + " ended its run reporting a failure" +
           (adaptor_.header().producer_kind == shm::ProducerKind::kSimulation || diverged
                ? std::string(" (the simulation diverged: the producer's diagnostic says where "
                              "and why)")
                : std::string(" (see the producer's output)"));
  }
  if (last_status_ & shm::status::kFallen) {
    // judged on the robot by the producer (sim_host's fall watch), though this program's own
    // watch did not fire (off, or the robot lacks the sensors it needs)
    rep_.exit_code = kExitFell;
    return producer_ + " ended its run: the robot fell (the producer's fall watch: its output "
           "says when and why)";
  }
  rep_.exit_code = kExitOk;
  return producer_ + " ended its run";
}

// The controller's verdict and the guard's: a hold is a result (the motion the controller was
// asked for was stopped): where the controller's own verification does not confirm its goal (or
// its motion is the trajectory, playback), or the guard still held at the end, the run failed,
// naming the pair; links measured closer than their limit fail the run.
void ControllerRun::JudgeController() {
  rep_.failure = controller_.failure();
  if (guarded_ && guard_.violations() > 0)
    rep_.failure += (rep_.failure.empty() ? "" : "; ") + guard_.ViolationSummary();
  if (guarded_ && guard_.holds() > 0) {
    if (!rep_.failure.empty())
      rep_.failure += "; " + guard_.HoldSummary();
    else
      rep_.failure = GuardFailure();
  }
  if (!rep_.failure.empty()) {
    err_ << prog_ << ": FAILED: " << rep_.failure << "\n";
    if (rep_.exit_code == kExitOk) rep_.exit_code = kExitFailed;
  }
}

// the guard's holds when the controller itself reports no failure ("" when they do not fail it)
std::string ControllerRun::GuardFailure() const {
  if (controller_.hold_is_failure()) return "the motion was not completed: " + guard_.HoldSummary();
  if (!guard_.holding()) return "";
  shm::GuardRecord g;
  RecordGuard(guard_, &g);
  return std::string("the self-collision guard was still holding the motion at the end of the "
                     "run (") + g.link_a + "/" + g.link_b + " at " + Fixed(1e3 * g.distance, 1) +
         " mm): the commanded motion was not completed";
}

void ControllerRun::ReportCounters() {
  const CycleCounters& c = controller_.counters();
  if (c.non_finite_fixed || c.clamped || c.diverged_sensors || late_ || rejected_) {
    err_ << prog_ << ": problems counted: " << c.non_finite_fixed
         << " non-finite joint commands replaced by a hold, " << c.clamped
         << " references clamped to joint limits, " << c.diverged_sensors
         << " diverged sensor blocks; the producer counted " << late_ << " late command blocks and "
         << rejected_ << " rejected joint commands\n";
  }
}

}  // namespace ohrp::controllers
