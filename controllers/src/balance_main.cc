// balance: attach to a robot segment, stand, and keep standing against pushes. See
// controllers/balance.h.

#include <iostream>

#include "cli/command_line.h"
#include "controllers/balance.h"
#include "controllers/cli.h"
#include "controllers/posture.h"
#include "controllers/runner.h"
#include "robot_model/model.h"

namespace {
[[noreturn]] void OnMujocoFatal(const char*) { std::_Exit(ohrp::controllers::kExitConfig); }
}  // namespace

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  BalanceOptions o;
  RunOptions run;
  run.program = "balance";
  StabilizerGains& g = o.gains;

  CLI::App app{
      "balance: attach to a robot segment (sim_host or hw_driver), ramp to the stance pose,\n"
      "then keep the robot standing against pushes with its own sensors only: the base\n"
      "estimator (IMU, leg kinematics, ankle force/torque sensors) gives the centre of mass; the\n"
      "stabilizer turns its divergent component (capture point) into a desired ZMP, carried by\n"
      "the feet (ankle strategy: damping control of the foot rotations and of the soles' height\n"
      "difference against the ankle sensors) and, beyond the soles, by the torso (hip\n"
      "strategy). Leg joints by inverse kinematics on the robot's own model (--model), which\n"
      "must be the producer's robot (checked by the model hash in the segment header).",
      "balance"};
  app.add_option("--model", o.model, "MJCF, OpenHRP VRML .wrl or robot profile .yaml of the robot (must match the producer's robot)")
      ->default_val(DefaultModelFile())
      ->check(CLI::ExistingFile);
  auto* pose_option = app.add_option("--pose", o.pose_file, "stance pose, YAML by joint name [rad]")
      ->default_val(DefaultPoseFile())
      ->check(CLI::ExistingFile);
  app.add_option("--keyframe", o.keyframe,
                 "take the stance pose from this keyframe of --model instead of a pose file "
                 "(e.g. --keyframe stand)")
      ->excludes(pose_option);
  app.add_option("--ramp", o.ramp, "[s] ramp from the measured pose to the stance pose")
      ->default_val(o.ramp)->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--settle", o.settle, "[s] of quiet standing before the CoM reference is taken")
      ->default_val(o.settle)->check(ohrp::cli::Plausible("wait"));
  app.add_option("--centre-time", o.centre_time,
                 "[s] to move the CoM over the middle of the soles once standing")
      ->default_val(o.centre_time)->check(ohrp::cli::Plausible("ramp_time"));
  bool no_centre = false;
  app.add_flag("--no-centre-com", no_centre, "keep the CoM where the stance pose puts it");
  std::vector<std::string> one_leg;
  app.add_option("--one-leg", one_leg,
                 "once centred, stand on these feet in turn: left, right (e.g. --one-leg left,right)")
      ->delimiter(',')
      ->check(CLI::IsMember({"left", "right"}));
  app.add_option("--lift", o.one_leg.lift, "[m] swing foot height when on one leg")
      ->default_val(o.one_leg.lift)
      ->check(ohrp::cli::InRange(0.0, 0.3));
  app.add_option("--hold", o.one_leg.hold, "[s] on one leg")->default_val(o.one_leg.hold)
      ->check(ohrp::cli::InRange(0.0, 3600.0));
  app.add_option("--shift-time", o.one_leg.shift_time,
                 "[s] to move the CoM over the stance foot (and back)")
      ->default_val(o.one_leg.shift_time)
      ->check(ohrp::cli::InRange(0.1, 60.0));
  AddLoadFeedforwardFlags(&app, &o.load_feedforward);
  app.add_option("--servo-hz", o.servo_frequency,
                 "[Hz] closing frequency of the joints' servo (the producer suggests 6 Hz on each "
                 "joint's own inertia; a robot of <motor>s such as H1 needs a stiffer one); 0: the "
                 "robot profile's servo.frequency, else the suggested gains")
      ->default_val(o.servo_frequency)
      ->check(ohrp::cli::InRange(0.0, 50.0));
  app.add_option("--k-dcm", g.k_dcm, "[1/s] convergence rate of the capture point")
      ->default_val(g.k_dcm)->check(ohrp::cli::Plausible("rate"));
  app.add_option("--ankle-damping", g.ankle_damping, "[N m s/rad] foot rotation damping D")
      ->default_val(g.ankle_damping)->check(ohrp::cli::Plausible("kd"));
  app.add_option("--ankle-recovery", g.ankle_recovery, "[s] foot offsets return time constant")
      ->default_val(g.ankle_recovery)->check(ohrp::cli::Plausible("time_constant"));
  app.add_option("--z-damping", g.z_damping, "[N s/m] sole height difference damping")
      ->default_val(g.z_damping)->check(ohrp::cli::Plausible("linear_damping"));
  app.add_option("--hip-gain", g.hip_gain, "share of the moment beyond the soles asked of the torso")
      ->default_val(g.hip_gain)->check(ohrp::cli::Plausible("gain_scale"));
  app.add_option("--support-margin", g.support_margin, "[m] desired ZMP kept this far inside the soles")
      ->default_val(g.support_margin)->check(ohrp::cli::Plausible("support_margin"));
  bool no_ankle = false, no_hip = false;
  app.add_flag("--no-ankle", no_ankle, "feet held as commanded (no foot damping control)");
  app.add_flag("--no-hip", no_hip, "no torso motion (ankle strategy only)");
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;
  o.centre_com = !no_centre;
  for (const std::string& side : one_leg) o.one_leg.sides.push_back(side == "left" ? 0 : 1);
  g.ankle_strategy = !no_ankle;
  g.hip_strategy = !no_hip;

  ohrp::model::InstallMujocoHandlers(OnMujocoFatal);
  ConfigStatus status;
  auto controller = BalanceController::Create(o, &status);
  if (!controller) {
    std::cerr << "balance: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
