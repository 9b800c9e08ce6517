// The hw_emulator loop: set-up, real-time cycle, report (see emulator.h).
#include <signal.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "emulator_impl.h"
#include "robot_model/sensors.h"
#include "shm_bridge/clock.h"

namespace ohrp::hw::udp {
namespace {

std::atomic<int> g_signal{0};
void OnSignal(int sig) { g_signal.store(sig); }
void OnFatal(const char*) {}

}  // namespace

namespace emu {

double Emulator::BaseTiltDeg() const {
  if (robot_.base_qpos < 0) return 0;
  const double* q = d_->qpos + robot_.base_qpos + 3;  // w x y z
  const double c = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);  // z of the base's z axis in the world
  return std::acos(std::fmax(-1.0, std::fmin(1.0, c))) * 180.0 / M_PI;
}

//---------------- set-up ----------------

bool Emulator::SetUp(int* exit_code) {
  *exit_code = kEmuExitUsage;
  std::string error;
  scene_ = model::Scene::Load(o_.model, &error);
  if (!scene_) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  m_ = scene_->m();
  d_ = scene_->d();
  if (o_.timestep > 0) m_->opt.timestep = o_.timestep;
  const double ratio = o_.period / m_->opt.timestep;
  steps_per_cycle_ = static_cast<int>(std::lround(ratio));
  if (steps_per_cycle_ < 1 || std::fabs(ratio - steps_per_cycle_) > 1e-6) {
    std::fprintf(stderr,
                 "hw_emulator: --period %g s must be a whole multiple of the model's timestep "
                 "(%g s)\n", o_.period, m_->opt.timestep);
    return false;
  }
  if (!model::MapRobot(m_, &robot_, &error)) {
    std::fprintf(stderr, "hw_emulator: %s: %s\n", o_.model.c_str(), error.c_str());
    return false;
  }
  // the contact under the soles, as sim_host sets it up (sim_host/feet.h), before the state
  // is first computed
  // (sim_host/contact_choice.h: the same choice as sim_host's, a profile's contact_file too)
  sim::FeetOptions feet;
  sim::ContactChoice choice{o_.contact, o_.contact_file, {}};
  if (o_.contact_stiffness > 0) choice.given.insert("stiffness");
  if (o_.contact_damping >= 0) choice.given.insert("damping");
  if (!sim::ChooseContact(o_.model, choice, &feet, nullptr, &error)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  if (o_.contact_stiffness > 0) feet.params.stiffness = o_.contact_stiffness;
  if (o_.contact_damping >= 0) feet.params.damping = o_.contact_damping;
  if (!sim::SetUpFeet(m_, feet, robot_.total_mass, &soft_, &error, &contact_)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  for (const std::string& spec : o_.pushes) {
    sim::Perturbation p;
    if (!sim::ParsePerturbation(spec, &p, &error)) {
      std::fprintf(stderr, "hw_emulator: --push %s: %s\n", spec.c_str(), error.c_str());
      return false;
    }
    pushes_.push_back(p);
  }
  if (!pushes_.empty() && robot_.base_body < 0) {
    std::fprintf(stderr, "hw_emulator: --push needs a floating base; %s has none\n", o_.model.c_str());
    return false;
  }
  // the robot's differences from the model, on the model before the state is first computed
  std::vector<std::string> joint_names;
  std::vector<int> dofs;
  for (const model::JointMap& j : robot_.joints) {
    joint_names.push_back(j.name);
    dofs.push_back(j.dof_adr);
    q_min_.push_back(j.q_min);
    q_max_.push_back(j.q_max);
  }
  if (!ParseGap(o_.gap, joint_names, o_.period, &gap_, &error)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  ApplyGapToModel(gap_, dofs, m_, d_);
  model::SensorParams file;  // --sensor-file's, in the robot's order
  if (!o_.gap.sensor_file.empty()) {
    model::SensorParams read;
    if (!model::ReadSensorParamsFile(o_.gap.sensor_file, &read, &error) ||
        !model::BindSensorParams(read, robot_, &file, &error)) {
      std::fprintf(stderr, "hw_emulator: --sensor-file %s: %s\n", o_.gap.sensor_file.c_str(),
                   error.c_str());
      return false;
    }
  }
  sensor_gap_ = std::make_unique<SensorGap>(gap_, robot_.imus.size(), robot_.forces.size(), file,
                                            o_.seed + 0x5eed);
  if (!scene_->Reset(o_.keyframe, &error)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  std::vector<std::string> names;
  for (const model::JointMap& j : robot_.joints) names.push_back(j.name);
  if (o_.boards.empty()) {
    layout_ = DefaultLayout(names);
  } else if (!ParseLayout(o_.boards, static_cast<int>(names.size()), &layout_, &error)) {
    std::fprintf(stderr, "hw_emulator: --boards: %s\n", error.c_str());
    return false;
  }
  if (layout_.nboards() > kMaxBoards) {
    std::fprintf(stderr, "hw_emulator: the robot needs %d boards, more than the protocol's %d; "
                 "give a layout with --boards\n", layout_.nboards(), kMaxBoards);
    return false;
  }
  const int nf = static_cast<int>(robot_.forces.size()), ni = static_cast<int>(robot_.imus.size());
  auto plan = [&](const char* option, const std::vector<std::string>& values) {
    for (const std::string& v : values) {
      if (!ParseEvent(option, v, layout_.nboards(), nf, ni, &events_, &error)) {
        std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
        return false;
      }
    }
    return true;
  };
  if (!plan("--silent", o_.silent) || !plan("--reset", o_.reset) || !plan("--stuck", o_.stuck) ||
      !plan("--saturate", o_.saturate) || !plan("--estop", o_.estop) ||
      !plan("--value", o_.values))
    return false;
  faults_.loss = o_.loss;
  faults_.late_rate = o_.late_rate;
  faults_.late_s = o_.late_ms * 1e-3;
  if (!o_.control_file.empty()) control_ = std::make_unique<ControlFile>(o_.control_file);
  late_.resize(kLateQueue);

  // the boards: servos off
  for (const BoardLayout::Range& r : layout_.motor) {
    MotorBoard b;
    b.first = r.first;
    b.count = r.count;
    motor_.push_back(b);
  }
  servo_ = std::make_unique<model::Servo>(robot_);
  step_ = std::make_unique<sim::PhysicsStep>(
      m_, d_, sim::PhysicsStep::Parts{servo_.get(), soft_.get(), &pushes_, robot_.base_body, nullptr});
  block_.njoint = static_cast<int>(robot_.joints.size());
  for (int i = 0; i < block_.njoint; ++i) block_.joint[i] = shm::JointCommand{};  // kOff
  servo_->Accept(block_);
  wanted_ = block_;
  delay_.SetUp(std::vector<int>(robot_.joints.size(), gap_.delay_cycles), block_);
  mj_forward(m_, d_);
  z0_ = BaseZ();

  if (!o_.log_path.empty()) {
    log_ = std::fopen(o_.log_path.c_str(), "w");
    if (!log_) {
      std::fprintf(stderr, "hw_emulator: cannot write the log '%s': %s\n", o_.log_path.c_str(),
                   std::strerror(errno));
      return false;
    }
    std::fprintf(log_, "time,base_z,tilt_deg,servos_on,silent,stuck,saturated,estop,base_x,base_y,"
                 "yaw_deg\n");
  }
  if (!socket_.Open(o_.host, o_.port, &error)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  if (!o_.port_file.empty()) {
    const std::string tmp = o_.port_file + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f || std::fprintf(f, "%d\n", socket_.port()) < 0 || std::fclose(f) != 0 ||
        std::rename(tmp.c_str(), o_.port_file.c_str()) != 0) {
      std::fprintf(stderr, "hw_emulator: cannot write the port file '%s'\n", o_.port_file.c_str());
      return false;
    }
  }
  if (!o_.quiet) {
    std::fprintf(stderr,
                 "hw_emulator: robot '%s' (%zu joints, %d F/T, %d IMU) from %s; boards %s + "
                 "sensor board %d on udp %s:%d; period %g s (%d physics steps); contact %s; loss %g, "
                 "late %g x %g ms; robot unlike the model: %s; robot time starts with the first "
                 "command\n",
                 robot_.name.c_str(), robot_.joints.size(), nf, ni, o_.model.c_str(),
                 LayoutString(layout_).c_str(), layout_.sensor_board(), o_.host.c_str(),
                 socket_.port(), o_.period, steps_per_cycle_, sim::ContactModelName(contact_), o_.loss, o_.late_rate, o_.late_ms,
                 DescribeGap(gap_).c_str());
    if (!o_.gap.sensor_file.empty())
      std::fprintf(stderr, "hw_emulator: --sensor-file %s: %s\n", o_.gap.sensor_file.c_str(),
                   model::DescribeSensorParams(sensor_gap_->params()).c_str());
  }
  *exit_code = kEmuExitOk;
  return true;
}

//---------------- faults at run time, log, report ----------------

void Emulator::PollControl() {
  std::string error;
  for (const std::string& line : control_->NewLines()) {
    if (!ApplyControlLine(line, layout_.nboards(), static_cast<int>(robot_.forces.size()),
                          static_cast<int>(robot_.imus.size()), &faults_, &error)) {
      std::fprintf(stderr, "hw_emulator: %s: %s\n", control_->path().c_str(), error.c_str());
    } else if (!o_.quiet && !line.empty() && line[0] != '#') {
      std::fprintf(stderr, "hw_emulator: t=%.3f s: control '%s'\n", d_->time, line.c_str());
    }
  }
}

void Emulator::Log() {
  int on = 0;
  for (int i = 0; i < block_.njoint; ++i) on += servo_on_[i] ? 1 : 0;
  // the base's horizontal position and heading last (columns added after the first eight)
  double x = 0, y = 0, yaw = 0;
  if (robot_.base_qpos >= 0) {
    const double* p = d_->qpos + robot_.base_qpos;  // x y z, then w x y z
    x = p[0];
    y = p[1];
    yaw = std::atan2(2 * (p[3] * p[6] + p[4] * p[5]), 1 - 2 * (p[5] * p[5] + p[6] * p[6]));
  }
  std::fprintf(log_, "%.4f,%.5f,%.3f,%d,%u,%u,%u,%d,%.5f,%.5f,%.3f\n", d_->time, BaseZ(),
               BaseTiltDeg(), on, faults_.silent, faults_.stuck, faults_.saturated,
               faults_.estop ? 1 : 0, x, y, yaw * 180.0 / M_PI);
}

void Emulator::Report(double wall, int exit_code) {
  uint64_t cmds = 0, cmd_lost = 0, cmd_dropped = 0, sent = sensor_sent_, dropped = sensor_dropped_,
           resets = 0, holds = 0, jumps = 0;
  for (const MotorBoard& b : motor_) {
    cmds += b.commands;
    cmd_lost += b.rx.lost();
    cmd_dropped += b.commands_dropped;
    sent += b.states_sent;
    dropped += b.states_dropped;
    resets += b.resets;
    holds += b.holds;
    jumps += b.jumps;
  }
  if (!o_.quiet)
    std::fprintf(stderr,
               "hw_emulator: robot time %.3f s in %.3f s wall, %llu cycles, %llu overruns, %llu "
               "resyncs; base height %.4f m at start, %.4f m at end, %.4f m lowest; tilt %.2f deg "
               "at most\n"
               "hw_emulator: commands applied %llu, lost on the way %llu (%llu injected), refused "
               "joints %llu; states sent %llu, dropped %llu (injected), late %llu; corrupted %llu; "
               "board resets %llu\n",
               d_->time, wall, static_cast<unsigned long long>(cycles_),
               static_cast<unsigned long long>(overruns_), static_cast<unsigned long long>(resyncs_),
               z0_, BaseZ(), z_min_ > 1e8 ? BaseZ() : z_min_, tilt_max_,
               static_cast<unsigned long long>(cmds), static_cast<unsigned long long>(cmd_lost),
               static_cast<unsigned long long>(cmd_dropped),
               static_cast<unsigned long long>(refused_joints_), static_cast<unsigned long long>(sent),
               static_cast<unsigned long long>(dropped), static_cast<unsigned long long>(late_sent_),
               static_cast<unsigned long long>(corrupted_), static_cast<unsigned long long>(resets));
  // one machine-readable line (always printed, also with --quiet)
  std::fprintf(stderr,
               "hw_emulator: result exit=%d time=%.4f base_z_start=%.5f base_z_end=%.5f "
               "base_z_min=%.5f tilt_max_deg=%.3f commands=%llu commands_lost=%llu "
               "commands_dropped=%llu states_sent=%llu states_dropped=%llu late=%llu "
               "send_failed=%llu overruns=%llu foreign=%llu jumps=%llu holds=%llu\n",
               exit_code, d_->time, z0_, BaseZ(), z_min_ > 1e8 ? BaseZ() : z_min_, tilt_max_,
               static_cast<unsigned long long>(cmds), static_cast<unsigned long long>(cmd_lost),
               static_cast<unsigned long long>(cmd_dropped),
               static_cast<unsigned long long>(sent), static_cast<unsigned long long>(dropped),
               static_cast<unsigned long long>(late_sent_),
               static_cast<unsigned long long>(send_failed_),
               static_cast<unsigned long long>(overruns_),
               static_cast<unsigned long long>(foreign_), static_cast<unsigned long long>(jumps),
               static_cast<unsigned long long>(holds));
}

//---------------- the loop ----------------

int Emulator::Run() {
  int exit_code = kEmuExitOk;
  if (!SetUp(&exit_code)) return exit_code;
  const double wall_start = MonotonicSeconds();
  double deadline = wall_start;
  double next_control = wall_start;
  const int badqacc = d_->warning[mjWARN_BADQACC].number;
  while (!g_signal.load()) {
    if (o_.duration > 0 && d_->time >= o_.duration - 0.5 * m_->opt.timestep) break;
    const double now = MonotonicSeconds();
    if (control_ && now >= next_control) {
      next_control = now + kControlPollPeriod;
      PollControl();
    }
    ApplyDue(d_->time, &events_, &faults_);
    if (faults_.reset_request) {
      for (int b = 0; b < layout_.nboards(); ++b)
        if (faults_.reset_request & (1u << b)) ResetBoard(b);
      faults_.reset_request = 0;
    }
    if (faults_.estop != estop_) {
      estop_ = faults_.estop;
      EstopChanged();
    }

    Receive(now);
    HoldIdleBoards(now);
    if (!started_ && o_.wait_driver > 0 && now - wall_start > o_.wait_driver) {
      std::fprintf(stderr,
                   "hw_emulator: no command packet within %g s on udp %s:%d; start the driver "
                   "(e.g. hw_driver --io lib/libohrp_io_udp.so --io-arg port=%d) or raise "
                   "--wait-driver\n", o_.wait_driver, o_.host.c_str(), socket_.port(), socket_.port());
      exit_code = kEmuExitNoDriver;
      break;
    }

    // physics, the motor boards' PD at every step
    if (started_) {
      if (delay_.cycles() > 0) ApplyDelayed();  // the commands of --delay-ms ago reach the PD
      // sim_host's physics step: pushes, the servo, the soft soles (when --contact soft), mj_step
      for (int s = 0; s < steps_per_cycle_; ++s) step_->Step(s == steps_per_cycle_ - 1);
      bool finite = true;
      for (int i = 0; i < m_->nq; ++i) finite &= std::isfinite(d_->qpos[i]);
      if (!finite || d_->warning[mjWARN_BADQACC].number != badqacc) {
        std::fprintf(stderr, "hw_emulator: the simulation diverged at t=%.3f s\n", d_->time);
        exit_code = kEmuExitDiverged;
        break;
      }
      z_min_ = std::fmin(z_min_, BaseZ());
      tilt_max_ = std::fmax(tilt_max_, BaseTiltDeg());
    }
    model::FillSensors(robot_, m_, d_, &sensors_);
    ++cycles_;

    const double sent_at = MonotonicSeconds();
    if (have_peer_) SendStates(sent_at);
    FlushLate(sent_at);
    if (log_ && cycles_ % static_cast<uint64_t>(o_.log_every) == 0) Log();

    // absolute deadlines; far behind (a stalled machine), real time starts again
    deadline += o_.period;
    const double after = MonotonicSeconds();
    if (after > deadline + o_.period) ++overruns_;
    if (after > deadline + kMaxBehind) {
      deadline = after;
      ++resyncs_;
    }
    SleepUntil(deadline, &g_signal);
  }
  const double wall = MonotonicSeconds() - wall_start;
  if (g_signal.load() && exit_code == kEmuExitOk) {
    exit_code = kEmuExitInterrupted;
    if (!o_.quiet)
      std::fprintf(stderr, "hw_emulator: interrupted (signal %d); shutting down\n", g_signal.load());
  }
  if (log_) std::fclose(log_);
  log_ = nullptr;
  Report(wall, exit_code);
  return exit_code;
}

}  // namespace emu

int RunEmulator(const EmulatorOptions& options) {
  model::InstallMujocoHandlers(OnFatal);
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  emu::Emulator e(options);
  return e.Run();
}

}  // namespace ohrp::hw::udp
