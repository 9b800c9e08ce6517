// bench_effects: what each effect of sim_host costs (sim_host/effects.h, docs/effects.md).
//
// The default standing scene (HRP-1S on the flat floor from the half-sitting keyframe, the
// servos holding, soft feet) is stepped as sim_host steps it: per physics step the servo, the
// soft-foot contact and mj_step; per control cycle (5 steps) the segment's sensor block
// (FillSensors with the sensor kinds that are on, the noise when on) and the log's row when
// the log is on. Each configuration is the default with one effect toggled; every measurement
// starts from the keyframe and runs the same number of steps; the configurations are measured
// in turn, `--repeats` rounds, and each gets the median of its rounds. Times are the CPU time
// of the stepping thread (CLOCK_THREAD_CPUTIME_ID), so that other processes on a shared
// machine do not count; the log's background writer thread is not in them (its Push is).
//
// The baseline ("bare") is the same loop written without the effects module: the same
// physics and the same MuJoCo sensors computed as the default, but no effect switches, no
// noise object, no log branch. The default configuration must cost the same: switched-off
// effects cost nothing measurable. "before" is the loop as it was before the effects module
// (MuJoCo's collision detection and every sensor of the scene computed), for the saving.
// Criterion: the median over rounds of the paired ratio
// default / bare (measured next to each other) lies within 3 % of 1.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "sim_host/effects.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "datalog/recorder.h"
#include "robot_model/log_names.h"
#include "sim_host/self_collision_watch.h"
#include "sim_host/step.h"
#include "shm_bridge/clock.h"

namespace {

using namespace ohrp::sim;

constexpr int kStepsPerCycle = 5;       // 1 ms physics, 5 ms control as on HRP-1S
constexpr double kSameWithin = 0.03;    // criterion of "costs nothing measurable" [-]

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1) + 0.5)];
}

struct Config {
  std::string label;    // the table's row
  std::string effects;  // --effects spec ("" = defaults); "bare" for the baseline
  ContactModel contact = ContactModel::kAuto;
  bool log = false;
  std::string self_collision_file = "";  // the self_collision effect's pair list ("": all pairs)
};

struct Setup {
  std::unique_ptr<ohrp::model::Scene> scene;
  ohrp::model::RobotMap robot;
  EffectsPlan plan;
  std::unique_ptr<ohrp::model::Servo> servo;
  std::unique_ptr<ohrp::contact::SoftFootContact> soft;
  ohrp::model::SensorSelection selection;
  std::unique_ptr<ohrp::model::SensorModel> noise;
  std::unique_ptr<ohrp::datalog::Recorder> recorder;
  std::unique_ptr<SelfCollisionWatch> watch;
  bool bare = false;
};

[[noreturn]] void Fail(const std::string& what) {
  std::fprintf(stderr, "bench_effects: %s\n", what.c_str());
  std::exit(2);
}

std::unique_ptr<Setup> Make(const std::string& path, const std::string& key, const Config& c,
                            const std::string& log_path) {
  auto s = std::make_unique<Setup>();
  std::string error;
  s->scene = ohrp::model::Scene::Load(path, &error);
  if (!s->scene || !ohrp::model::MapRobot(s->scene->m(), &s->robot, &error)) Fail(error);
  mjModel* m = s->scene->m();
  m->opt.timestep = 0.001;
  FeetOptions feet;
  feet.model = c.contact;
  s->bare = c.effects == "bare" || c.effects == "before";
  if (s->bare) {
    if (!SetUpFeet(m, feet, s->robot.total_mass, &s->soft, &error)) Fail(error);
    if (c.effects == "bare") {
      // what the default resolves to, written by hand: MuJoCo's collision detection off (the
      // soles are on the soft-foot contact, nothing else collides), MuJoCo computes only the
      // F/T and IMU sensors (sim_host reads q, dq, tau from the state)
      m->opt.disableflags |= mjDSBL_CONTACT;
      for (int i = 0; i < m->nsensor; ++i) {
        const int t = m->sensor_type[i];
        if (t == mjSENS_JOINTPOS || t == mjSENS_JOINTVEL || t == mjSENS_ACTUATORFRC)
          m->sensor_needstage[i] = mjSTAGE_NONE;
      }
    }
    // "before": the loop as it was before the effects module, everything the scene declares
  } else {
    EffectRequests req;
    if (!ParseEffectRequests(c.effects, &req, &error) ||
        !ResolveEffects(m, s->robot, feet, c.log, req, &s->plan, &error) ||
        !SetUpFeet(m, feet, s->robot.total_mass, &s->soft, &error))
      Fail(c.label + ": " + error);
    ApplyEffects(s->plan, s->robot, m);
    s->selection = SelectSensors(s->plan);
    if (s->plan.on(Effect::kNoise))
      s->noise = std::make_unique<ohrp::model::SensorModel>(NoiseAsSensorParams(s->plan.noise, s->robot),
                                                            s->plan.noise.seed);
    if (s->plan.on(Effect::kLog)) {
      ohrp::datalog::RecorderChannels ch;
      ch.base = s->plan.on(Effect::kLogBase);
      ch.joints = s->plan.on(Effect::kLogJoints);
      ch.force_torque = s->plan.on(Effect::kLogForceTorque);
      ch.imu = s->plan.on(Effect::kLogImu);
      s->recorder = ohrp::datalog::Recorder::Open(log_path, ohrp::model::LogNamesOf(s->robot), &error, 8192, ch);
      if (!s->recorder) Fail(error);
    }
  }
  if (!s->scene->Reset(key, &error)) Fail(error);
  if (!s->bare && s->plan.on(Effect::kSelfCollision)) {
    s->watch = SelfCollisionWatch::Create(m, s->robot, c.self_collision_file, &error);
    if (!s->watch) Fail(c.label + ": " + error);
    s->watch->Start(s->scene->d());
  }
  s->servo = std::make_unique<ohrp::model::Servo>(s->robot);
  s->servo->HoldCurrent(s->scene->d());
  return s;
}

// wall seconds per physics step over `cycles` control cycles
double Run(Setup* s, int cycles, int warmup) {
  mjModel* m = s->scene->m();
  mjData* d = s->scene->d();
  static ohrp::shm::SensorBlock block;
  // sim_host's physics step (sim_host/step.h): servo, soft soles, mj_step, commit
  ohrp::sim::PhysicsStep step(m, d, {s->servo.get(), s->soft.get()});
  double t0 = ohrp::ThreadCpuSeconds();
  if (s->bare) {
    for (int c = 0; c < warmup + cycles; ++c) {
      if (c == warmup) t0 = ohrp::ThreadCpuSeconds();
      for (int k = 0; k < kStepsPerCycle; ++k) step.Step(k == kStepsPerCycle - 1);
      ohrp::model::FillSensors(s->robot, m, d, &block);
    }
  } else {
    for (int c = 0; c < warmup + cycles; ++c) {
      if (c == warmup) t0 = ohrp::ThreadCpuSeconds();
      for (int k = 0; k < kStepsPerCycle; ++k) step.Step(k == kStepsPerCycle - 1);
      ohrp::model::FillSensors(s->robot, m, d, s->selection, &block);
      if (s->noise) ApplySensorModel(s->robot, s->selection, s->noise.get(), &block);
      if (s->recorder) s->recorder->Push(block, &s->servo->reference(0));
      if (s->watch) s->watch->Check(d, d->time, c);
    }
  }
  return (ohrp::ThreadCpuSeconds() - t0) / (cycles * kStepsPerCycle);
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  std::string key = "halfsit";
  int cycles = 400, repeats = 15;
  CLI::App app{
      "bench_effects: the step time of the standing robot (servo holding, soft feet) with every\n"
      "effect at its default and with each effect toggled, measured in turn in one run; the\n"
      "default beside the same loop without the effects module (switched-off effects must cost\n"
      "nothing measurable). Prints medians per physics step and the ratio default / bare."};
  app.add_option("--scene", scene, "MJCF scene")->capture_default_str();
  app.add_option("--keyframe", key, "initial state")->capture_default_str();
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--cycles", cycles, "control cycles (5 physics steps each) per measurement")
      ->capture_default_str()->check(ohrp::cli::Plausible("cycles"));
  app.add_option("--repeats", repeats, "rounds over all configurations")
      ->capture_default_str()->check(ohrp::cli::Plausible("repeats"));
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(nullptr);
  const std::string log_path =
      (std::filesystem::temp_directory_path() / ("bench_effects_" + std::to_string(getpid()) + ".csv")).string();

  // configurations: the default, each effect toggled, the baseline
  const std::vector<Config> configs = {
      {"default", ""},
      {"bare", "bare"},
      {"before", "before"},
      {"gravity", "gravity=off"},
      {"joint_limits", "joint_limits=off"},
      {"passive", "passive=off"},
      {"force_torque", "force_torque=off"},
      {"accelerometer", "accelerometer=off"},
      {"rne_post (F/T + accelerometer)", "rne_post=off"},
      {"gyro", "gyro=off"},
      {"orientation", "orientation=off"},
      {"joint sensors (q, dq, tau)", "encoders=off,joint_velocities=off,joint_torques=off"},
      {"other_sensors (87 unread)", "other_sensors=on"},
      {"noise", "noise=on"},
      {"log (all channels)", "", ContactModel::kAuto, true},
      {"soft_contact -> native_contact", "", ContactModel::kNative},
      {"self_collision (all pairs)", "self_collision=on"},
      {"self_collision (file's pairs)", "self_collision=on", ContactModel::kAuto, false,
       std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml"},
  };
  // the watch's own clock: CPU time per check, per configuration (the last round's)
  std::vector<double> per_check(configs.size(), 0.0);
  std::vector<int> pairs_checked(configs.size(), 0);
  const size_t n = configs.size();
  std::vector<std::vector<double>> t(n);
  std::vector<double> paired;  // default / bare, per round
  {
    // warm-up: one of each
    for (const auto& c : configs) {
      auto s = Make(scene, key, c, log_path);
      Run(s.get(), cycles / 4, 0);
    }
  }
  // each round starts at another configuration (no configuration always follows the same
  // one); each measurement runs 50 untimed cycles first (caches, the soles settling)
  const int warmup = 50;
  for (int r = 0; r < repeats; ++r) {
    double t_default = 0, t_bare = 0;
    for (size_t k = 0; k < n; ++k) {
      const size_t i = (k + r) % n;
      auto s = Make(scene, key, configs[i], log_path);
      t[i].push_back(Run(s.get(), cycles, warmup));
      if (s->watch) {
        const SelfCollisionSummary sc = s->watch->Summary();
        per_check[i] = sc.check_seconds / std::max<uint64_t>(1, sc.checks);
        pairs_checked[i] = sc.pairs_checked;
      }
      if (i == 0) t_default = t[i].back();
      if (i == 1) t_bare = t[i].back();
    }
    paired.push_back(t_default / t_bare);
  }
  std::filesystem::remove(log_path);

  const double t_def = Quantile(t[0], 0.5), t_bare = Quantile(t[1], 0.5);
  std::printf("step of the standing robot (HRP-1S, flat floor, %s, servo holding, soft feet): "
              "%d rounds x %d steps, medians of the stepping thread's CPU time per step [us]\n\n",
              key.c_str(), repeats, cycles * kStepsPerCycle);
  std::printf("%-32s %-8s %9s %9s %9s %8s %10s\n", "effect", "default", "on", "off", "delta",
              "delta%", "noise +-");
  // delta: the median over rounds of (on - off) measured in the same round; noise: half the
  // interquartile range of those paired differences
  auto row = [&](size_t i, bool default_on) {
    std::vector<double> diff;
    for (int r = 0; r < repeats; ++r)
      diff.push_back(default_on ? t[0][r] - t[i][r] : t[i][r] - t[0][r]);
    const double ti = Quantile(t[i], 0.5);
    const double on = default_on ? t_def : ti, off = default_on ? ti : t_def;
    const double delta = Quantile(diff, 0.5);
    const double noise = 0.5 * (Quantile(diff, 0.75) - Quantile(diff, 0.25));
    std::printf("%-32s %-8s %9.2f %9.2f %+9.2f %+7.1f%% %10.2f%s\n", configs[i].label.c_str(),
                default_on ? "on" : "off", on * 1e6, off * 1e6, delta * 1e6, 100 * delta / t_def,
                noise * 1e6, std::fabs(delta) <= noise ? "  (within noise)" : "");
  };
  for (size_t i = 3; i < n; ++i) {
    const Config& c = configs[i];
    const bool default_on = !(c.effects == "other_sensors=on" || c.effects == "noise=on" ||
                              c.effects == "self_collision=on" || c.log);
    row(i, default_on);
  }
  std::printf("%-32s %-8s %9s   (cannot be on: the scene declares no self-colliding pair)\n",
              "self_contact", "off", "-");
  std::printf("%-32s %-8s %9s   (rendered only while a program asks: ./ohrp bench cameras)\n",
              "cameras", "on", "-");
  std::printf("\n%-32s %9.2f us  (IQR %.2f-%.2f)\n", "default configuration", t_def * 1e6,
              Quantile(t[0], 0.25) * 1e6, Quantile(t[0], 0.75) * 1e6);
  std::printf("%-32s %9.2f us  (IQR %.2f-%.2f)\n", "bare loop, no effects module", t_bare * 1e6,
              Quantile(t[1], 0.25) * 1e6, Quantile(t[1], 0.75) * 1e6);
  const double t_before = Quantile(t[2], 0.5);
  std::printf("%-32s %9.2f us  (IQR %.2f-%.2f): collision detection and every MuJoCo sensor\n",
              "before the effects module", t_before * 1e6, Quantile(t[2], 0.25) * 1e6,
              Quantile(t[2], 0.75) * 1e6);
  // the self_collision effect per check (once per control cycle of 5 steps): the paired delta
  // per step times 5, and the watch's own wall clock around each check
  for (size_t i = 0; i < n; ++i) {
    if (configs[i].effects != "self_collision=on") continue;
    std::vector<double> diff;
    for (int r = 0; r < repeats; ++r) diff.push_back(t[i][r] - t[0][r]);
    std::printf("%-32s %9.2f us per check (paired delta x %d steps), %.2f us by its own clock; "
                "%d pairs\n", configs[i].label.c_str(), Quantile(diff, 0.5) * kStepsPerCycle * 1e6,
                kStepsPerCycle, per_check[i] * 1e6, pairs_checked[i]);
  }
  const double pr = Quantile(paired, 0.5);
  std::printf("paired default / bare: median %.3f, IQR %.3f-%.3f\n", pr, Quantile(paired, 0.25),
              Quantile(paired, 0.75));
  std::printf("switched-off effects cost nothing measurable (|default/bare - 1| < %.0f %%): %s\n",
              100 * kSameWithin, std::fabs(pr - 1) < kSameWithin ? "yes" : "NO");
  std::printf("ratio: %.2f (%.2f us default step / %.2f us bare step)\n", t_def / t_bare,
              t_def * 1e6, t_bare * 1e6);
  return 0;
}
