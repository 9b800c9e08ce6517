// bench_balance: the cost of one `balance` control cycle (base estimator + stabilizer + leg IK,
// controllers/balance.h) beside one `posture` cycle, measured in the same run on the same
// sensor stream: both controllers run closed-loop on an in-process HRP-1S (sim_host's stepping,
// soft soles, 1 ms physics, 5 ms control) and only their update() calls are timed, alternately
// in rounds. Pushes during the measured window keep the stabilizer busy. Issue 31: balance on a
// second robot through its profile (--beside, Unitree G1 by default) is timed in the same
// rounds and printed beside them.
//
// Each update() is timed twice, wall and thread CPU time (cycle_timing.h). Median, p90 and
// p99 of both are printed. A fingerprint of all the commands balance sent (joint references,
// bit for bit) tells whether a change to the libraries changed its results.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "controllers/balance.h"
#include "controllers/posture.h"
#include "cycle_timing.h"
#include "robot_model/kinematics.h"
#include "robot_model/profile.h"
#include "sim_host/in_process.h"

namespace {

using ohrp::controllers::Controller;

struct Loop {
  std::unique_ptr<ohrp::sim::InProcessRobot> robot;
  Controller* controller = nullptr;
  ohrp::shm::CommandBlock commands{};
  ohrp::bench::CycleTimes times;  // update() wall and thread CPU times [s]
  uint64_t fingerprint = 1469598103934665603ull;

  void Cycles(int n, bool timed) {
    const int nj = robot->header().njoint;
    for (int i = 0; i < n; ++i) {
      auto update = [&] { controller->update(robot->sensors(), &commands); };
      if (timed)
        times.Time(update);
      else
        update();
      ohrp::bench::Fingerprint(commands, nj, &fingerprint);
      robot->Cycle(commands);
    }
  }
};

// pushes of `impulse` [N s] over 0.1 s in the measured window: forward at a quarter, to the left
// at six tenths of it
std::vector<ohrp::sim::Perturbation> Pushes(double impulse, double t_measure, double span) {
  if (!(impulse > 0)) return {};
  ohrp::sim::Perturbation fwd, left;
  fwd.t0 = t_measure + 0.25 * span;
  fwd.t1 = fwd.t0 + 0.1;
  fwd.force[0] = impulse / 0.1;
  left.t0 = t_measure + 0.6 * span;
  left.t1 = left.t0 + 0.1;
  left.force[1] = impulse / 0.1;
  return {fwd, left};
}

ohrp::sim::InProcessOptions Robot(const std::string& scene, const std::string& keyframe,
                                  std::vector<ohrp::sim::Perturbation> pushes) {
  ohrp::sim::InProcessOptions io;
  io.scene = scene;
  io.keyframe = keyframe;
  io.pushes = std::move(pushes);
  return io;
}

[[noreturn]] void Fail(const std::string& what) {
  std::fprintf(stderr, "bench_balance: %s\n", what.c_str());
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  int rounds = 10, cycles = 200;
  double impulse = 15.0;
  CLI::App app{
      "bench_balance: one control cycle of `balance` (estimator + stabilizer + leg IK) beside\n"
      "one of `posture`, each closed-loop on an in-process HRP-1S (soft soles, 1 ms physics,\n"
      "5 ms control); only update() is timed, alternately in rounds, with pushes of --impulse\n"
      "N s over 0.1 s (forward, then to the left) in the measured window. Prints medians and\n"
      "the ratio balance / posture."};
  app.add_option("--scene", scene, "MJCF scene with the halfsit keyframe")->capture_default_str();
  // every number within its plausible range (cli/plausible.h), then within the bench's own
  // (a push above 60 N s topples the robot; the rounds' cycles fit the measured window)
  app.add_option("--rounds", rounds, "alternating measurement rounds")->capture_default_str()
      ->check(ohrp::cli::Plausible("repeats"))->check(ohrp::cli::InRange(1, 1000));
  app.add_option("--cycles", cycles, "control cycles per round and controller")
      ->capture_default_str()->check(ohrp::cli::Plausible("cycles"))
      ->check(ohrp::cli::InRange(10, 100000));
  app.add_option("--impulse", impulse, "push impulse [N s] (0: no push)")->capture_default_str()
      ->check(ohrp::cli::Plausible("impulse"))->check(ohrp::cli::InRange(0.0, 60.0));
  std::string beside = std::string(OHRP_SOURCE_DIR) + "/robots/g1.yaml";
  app.add_option("--beside", beside,
                 "a robot profile with a 'stand' stance whose balance is timed in the same rounds, "
                 "pushed by --impulse scaled by its mass over HRP-1S's (\"\": none; skipped, "
                 "said, when its model is not there)")
      ->capture_default_str();
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(nullptr);

  // the measured window starts after the stance (0.5 s ramp + 0.5 s settle + 1 s)
  const double t_measure = 2.0, span = rounds * cycles * 0.005;
  const ohrp::sim::InProcessOptions io = Robot(scene, "halfsit", Pushes(impulse, t_measure, span));
  ohrp::controllers::ConfigStatus status;
  ohrp::controllers::BalanceOptions bo;
  bo.ramp = 0.5;
  auto balance = ohrp::controllers::BalanceController::Create(bo, &status);
  if (!balance) Fail(status.message);
  ohrp::controllers::PostureOptions po;
  po.ramp = 0.5;
  auto posture = ohrp::controllers::PostureController::Create(po, &status);
  if (!posture) Fail(status.message);
  std::vector<Controller*> controllers = {balance.get(), posture.get()};
  std::vector<ohrp::sim::InProcessOptions> robots = {io, io};

  // the second robot's balance, through its profile, when its model is there
  std::unique_ptr<ohrp::controllers::BalanceController> other;
  std::string other_name;
  if (!beside.empty()) {
    ohrp::model::RobotProfile profile;
    std::string error;
    if (!ohrp::model::ReadProfile(beside, &profile, &error)) Fail("--beside " + error);
    if (!std::filesystem::exists(profile.model)) {
      std::printf("(--beside %s: its model %s is not there; HRP-1S alone)\n", beside.c_str(),
                  profile.model.c_str());
    } else {
      ohrp::controllers::BalanceOptions ob = bo;
      ob.model = beside;
      ob.keyframe = "stand";
      other = ohrp::controllers::BalanceController::Create(ob, &status);
      if (!other) Fail(beside + ": " + status.message);
      auto hrp = ohrp::model::Kinematics::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml", &error);
      auto them = ohrp::model::Kinematics::Load(beside, &error);
      if (!hrp || !them) Fail(error);
      other_name = std::filesystem::path(beside).stem().string();
      controllers.push_back(other.get());
      robots.push_back(Robot(beside, "stand",
                             Pushes(impulse * them->mass() / hrp->mass(), t_measure, span)));
    }
  }

  std::vector<Loop> loops(controllers.size());
  for (size_t k = 0; k < loops.size(); ++k) {
    std::string error;
    loops[k].robot = ohrp::sim::InProcessRobot::Create(robots[k], &error);
    if (!loops[k].robot) Fail(error);
    loops[k].controller = controllers[k];
    status = controllers[k]->configure(loops[k].robot->header());
    if (!status.ok()) Fail(status.message);
    controllers[k]->activate(loops[k].robot->sensors());
    loops[k].Cycles(static_cast<int>(t_measure / 0.005), false);
  }
  if (!balance->standing()) Fail("balance did not reach its stance phase");
  if (other && !other->standing()) Fail(other_name + ": balance did not reach its stance phase");
  for (int r = 0; r < rounds; ++r) {
    for (Loop& l : loops) l.Cycles(cycles, true);
  }
  const double overhead = ohrp::bench::ThreadCpuOverhead();
  const double b = ohrp::bench::Quantile(loops[0].times.wall, 0.5),
               p = ohrp::bench::Quantile(loops[1].times.wall, 0.5);
  std::printf("%-44s %26s   %26s\n", "one control cycle (update only) [us]",
              "wall: median  p90  p99", "thread CPU: median  p90  p99");
  ohrp::bench::PrintRow("posture (ramp, then hold)", loops[1].times, overhead);
  ohrp::bench::PrintRow("balance (estimator + stabilizer + 2 leg IK)", loops[0].times, overhead);
  if (other) ohrp::bench::PrintRow((other_name + ": balance").c_str(), loops[2].times, overhead);
  std::printf("(%zu cycles each; thread CPU clock read cost %.2f us subtracted)\n",
              loops[0].times.wall.size(), overhead * 1e6);
  auto figures = [&](const std::string& who, const ohrp::controllers::BalanceController& c,
                     const Loop& l) {
    const ohrp::controllers::BalanceStats& st = c.stats();
    std::printf("%s: %llu stance cycles, %llu leg IK results not converged, base height %.3f m "
                "at the end (truth)\n",
                who.c_str(), static_cast<unsigned long long>(st.stand_cycles),
                static_cast<unsigned long long>(st.ik_failures), l.robot->sensors().sim_truth.p_WB[2]);
    std::printf("%s: commands fingerprint %016llx over all %d cycles\n", who.c_str(),
                static_cast<unsigned long long>(l.fingerprint),
                static_cast<int>(t_measure / 0.005) + rounds * cycles);
  };
  figures("balance", *balance, loops[0]);
  if (other) figures(other_name + " balance", *other, loops[2]);
  std::printf("target: balance under 50 us per cycle: %s\n", b < 50e-6 ? "met" : "NOT met");
  std::printf("ratio: %.2f (%.2f us / %.2f us)\n", b / p, b * 1e6, p * 1e6);
  return 0;
}
