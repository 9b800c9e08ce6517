// bench_balance: the cost of one `balance` control cycle (base estimator + stabilizer + leg IK,
// controllers/balance.h) beside one `posture` cycle, measured in the same run on the same
// sensor stream: both controllers run closed-loop on an in-process HRP-1S (sim_host's stepping,
// soft soles, 1 ms physics, 5 ms control) and only their update() calls are timed, alternately
// in rounds. Pushes during the measured window keep the stabilizer busy.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "controllers/balance.h"
#include "controllers/posture.h"
#include "sim_host/in_process.h"

namespace {

using ohrp::controllers::Controller;

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

struct Loop {
  std::unique_ptr<ohrp::sim::InProcessRobot> robot;
  Controller* controller = nullptr;
  ohrp::shm::CommandBlock commands{};
  std::vector<double> times;  // update() wall times [s]

  void Cycles(int n, bool timed) {
    for (int i = 0; i < n; ++i) {
      const double t0 = timed ? Now() : 0;
      controller->update(robot->sensors(), &commands);
      if (timed) times.push_back(Now() - t0);
      robot->Cycle(commands);
    }
  }
};

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
  app.add_option("--rounds", rounds, "alternating measurement rounds")->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--cycles", cycles, "control cycles per round and controller")
      ->capture_default_str()->check(CLI::Range(10, 100000));
  app.add_option("--impulse", impulse, "push impulse [N s] (0: no push)")->capture_default_str()
      ->check(CLI::Range(0.0, 60.0));
  CLI11_PARSE(app, argc, argv);
  ohrp::model::InstallMujocoHandlers(nullptr);

  // the measured window starts after the stance (0.5 s ramp + 0.5 s settle + 1 s)
  const double t_measure = 2.0, span = rounds * cycles * 0.005;
  ohrp::sim::InProcessOptions io;
  io.scene = scene;
  io.keyframe = "halfsit";
  if (impulse > 0) {
    ohrp::sim::Perturbation fwd, left;
    fwd.t0 = t_measure + 0.25 * span;
    fwd.t1 = fwd.t0 + 0.1;
    fwd.force[0] = impulse / 0.1;
    left.t0 = t_measure + 0.6 * span;
    left.t1 = left.t0 + 0.1;
    left.force[1] = impulse / 0.1;
    io.pushes = {fwd, left};
  }
  ohrp::controllers::ConfigStatus status;
  ohrp::controllers::BalanceOptions bo;
  bo.ramp = 0.5;
  auto balance = ohrp::controllers::BalanceController::Create(bo, &status);
  if (!balance) Fail(status.message);
  ohrp::controllers::PostureOptions po;
  po.ramp = 0.5;
  auto posture = ohrp::controllers::PostureController::Create(po, &status);
  if (!posture) Fail(status.message);

  Loop loops[2];
  Controller* controllers[2] = {balance.get(), posture.get()};
  for (int k = 0; k < 2; ++k) {
    std::string error;
    loops[k].robot = ohrp::sim::InProcessRobot::Create(io, &error);
    if (!loops[k].robot) Fail(error);
    loops[k].controller = controllers[k];
    status = controllers[k]->configure(loops[k].robot->header());
    if (!status.ok()) Fail(status.message);
    controllers[k]->activate(loops[k].robot->sensors());
    loops[k].Cycles(static_cast<int>(t_measure / 0.005), false);
  }
  if (!balance->standing()) Fail("balance did not reach its stance phase");
  for (int r = 0; r < rounds; ++r) {
    for (Loop& l : loops) l.Cycles(cycles, true);
  }
  const double b = Quantile(loops[0].times, 0.5), p = Quantile(loops[1].times, 0.5);
  std::printf("%-44s %12s %12s\n", "one control cycle (update only)", "median [us]", "p99 [us]");
  std::printf("%-44s %12.2f %12.2f\n", "posture (ramp, then hold)", p * 1e6,
              Quantile(loops[1].times, 0.99) * 1e6);
  std::printf("%-44s %12.2f %12.2f\n", "balance (estimator + stabilizer + 2 leg IK)", b * 1e6,
              Quantile(loops[0].times, 0.99) * 1e6);
  const ohrp::controllers::BalanceStats& st = balance->stats();
  std::printf("balance: %llu stance cycles, %llu leg IK results not converged, base height %.3f m "
              "at the end (truth)\n",
              static_cast<unsigned long long>(st.stand_cycles),
              static_cast<unsigned long long>(st.ik_failures),
              loops[0].robot->sensors().sim_truth.p_WB[2]);
  std::printf("target: balance under 50 us per cycle: %s\n", b < 50e-6 ? "met" : "NOT met");
  std::printf("ratio: %.2f (%.2f us / %.2f us)\n", b / p, b * 1e6, p * 1e6);
  return 0;
}
