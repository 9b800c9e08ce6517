// bench_contact: the cost of one physics step of the standing robot with the soft-foot contact
// beside the same step with MuJoCo's native contact, measured alternately in the same run.
// A step is sim_host's physics step (sim_host/step.h): servo, (soft contact), mj_step, (commit).
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "quantile.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/step.h"
#include "shm_bridge/clock.h"

namespace {

using ohrp::bench::Median;

struct Setup {
  std::unique_ptr<ohrp::model::Scene> scene;
  ohrp::model::RobotMap robot;
  std::unique_ptr<ohrp::model::Servo> servo;
  std::unique_ptr<ohrp::contact::SoftFootContact> soft;
};

Setup Make(const std::string& path, const std::string& key, double dt,
           ohrp::sim::ContactModel model) {
  Setup s;
  std::string error;
  s.scene = ohrp::model::Scene::Load(path, &error);
  if (!s.scene || !ohrp::model::MapRobot(s.scene->m(), &s.robot, &error)) {
    std::fprintf(stderr, "bench_contact: %s\n", error.c_str());
    std::exit(2);
  }
  s.scene->m()->opt.timestep = dt;
  ohrp::sim::FeetOptions feet;
  feet.model = model;
  if (!ohrp::sim::SetUpFeet(s.scene->m(), feet, s.robot.total_mass, &s.soft, &error) ||
      !s.scene->Reset(key, &error)) {
    std::fprintf(stderr, "bench_contact: %s\n", error.c_str());
    std::exit(2);
  }
  s.servo = std::make_unique<ohrp::model::Servo>(s.robot);
  s.servo->HoldCurrent(s.scene->d());
  return s;
}

// wall seconds per step over `steps` steps
double Run(Setup* s, int steps) {
  ohrp::sim::PhysicsStep step(s->scene->m(), s->scene->d(), {s->servo.get(), s->soft.get()});
  const double t0 = ohrp::MonotonicSeconds();
  for (int i = 0; i < steps; ++i) step.Step();  // sim_host's own step (sim_host/step.h)
  return (ohrp::MonotonicSeconds() - t0) / steps;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  std::string key = "halfsit";
  double dt = 0.001;
  int steps = 2000, repeats = 7;
  CLI::App app{
      "bench_contact: one physics step of the standing robot (servo + contact + mj_step) with\n"
      "the soft-foot contact beside MuJoCo's native contact, alternately in the same run.\n"
      "Prints medians and the ratio soft / native."};
  app.add_option("--scene", scene, "MJCF scene")->capture_default_str();
  app.add_option("--keyframe", key, "initial state")->capture_default_str();
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--dt", dt, "physics step [s]")->capture_default_str()
      ->check(ohrp::cli::Plausible("physics_dt"));
  app.add_option("--steps", steps, "steps per measurement")->capture_default_str()
      ->check(ohrp::cli::Plausible("steps"));
  app.add_option("--repeats", repeats, "measurements of each kind")->capture_default_str()
      ->check(ohrp::cli::Plausible("repeats"));
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(nullptr);

  Setup soft = Make(scene, key, dt, ohrp::sim::ContactModel::kSoft);
  Setup native = Make(scene, key, dt, ohrp::sim::ContactModel::kNative);
  Run(&soft, steps);  // settle onto the soles and warm the caches
  Run(&native, steps);
  std::vector<double> ts, tn;
  for (int r = 0; r < repeats; ++r) {
    ts.push_back(Run(&soft, steps));
    tn.push_back(Run(&native, steps));
  }
  const double s = Median(ts), n = Median(tn);
  const auto& st = soft.soft->stats();
  std::printf("%-40s %14s\n", "step of the standing robot", "median [us]");
  std::printf("%-40s %14.1f\n", "native MuJoCo contact", n * 1e6);
  std::printf("%-40s %14.1f\n", "soft-foot contact (FCL, 2 soles)", s * 1e6);
  std::printf("soft-foot: %lld FCL queries, %lld of %lld sole-object pairs stopped by the cheap bound\n",
              st.fcl_queries, st.pairs_bound, st.pairs_considered);
  std::printf("ratio: %.2f (%.1f us / %.1f us)\n", s / n, s * 1e6, n * 1e6);
  return 0;
}
