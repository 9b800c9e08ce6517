// posture: attach to a robot segment, ramp to a pose, hold it. See controllers/posture.h.
#include <iostream>

#include "controllers/posture.h"
#include "controllers/cli.h"
#include "controllers/runner.h"
#include "robot_model/model.h"

namespace {

// the joint positions of keyframe `key` of the MJCF `scene`
bool ReadKeyframe(const std::string& scene, const std::string& key,
                  std::vector<std::pair<std::string, double>>* joints,
                  ohrp::controllers::ConfigStatus* status) {
  std::string error;
  auto loaded = ohrp::model::Scene::Load(scene, &error);
  if (loaded && ohrp::model::KeyframeJointPositions(loaded->m(), key, joints, &error)) return true;
  if (loaded) error = scene + ": " + error;  // Load's message names the file already
  *status = ohrp::controllers::ConfigStatus::Fail(ohrp::controllers::ConfigError::kOption,
                                                  "--keyframe " + key + ": " + error);
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  PostureOptions options;
  RunOptions run;
  run.program = "posture";

  CLI::App app{
      "posture: attach to a robot segment (sim_host or hw_driver), read the current joint\n"
      "positions, ramp smoothly (minimum jerk) to a pose over --ramp seconds of the producer's\n"
      "time, then hold it until the producer stops or SIGINT/SIGTERM. Position mode, gains =\n"
      "the producer's default gains times --kp-scale / --kd-scale.",
      "posture"};
  std::string scene, keyframe;
  auto* pose_option = app.add_option("--pose", options.pose_file,
                                     "YAML pose by joint name [rad] (joints not named hold where "
                                     "they are)")
      ->default_val(DefaultPoseFile())->check(CLI::ExistingFile);
  auto* key_option = app.add_option("--keyframe", keyframe,
                                    "take the target from this keyframe of --scene instead of a "
                                    "pose file (e.g. --keyframe home)")
      ->excludes(pose_option);
  app.add_option("--scene", scene, "the MJCF scene (or VRML, robot profile) the producer runs, for --keyframe")
      ->check(CLI::ExistingFile)->needs(key_option);
  key_option->needs("--scene");
  app.add_option("--ramp", options.ramp, "ramp duration [s of producer time], 0 = jump")
      ->default_val(2.0)->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--kp-scale", options.kp_scale, "factor on the producer's default kp")
      ->default_val(1.0)->check(ohrp::cli::Plausible("gain_scale"));
  app.add_option("--kd-scale", options.kd_scale, "factor on the producer's default kd")
      ->default_val(1.0)->check(ohrp::cli::Plausible("gain_scale"));
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;

  ConfigStatus status;
  std::unique_ptr<PostureController> controller;
  if (!keyframe.empty()) {
    // the target from the scene's keyframe (hinge and slide joints by name)
    std::vector<std::pair<std::string, double>> joints;
    if (!ReadKeyframe(scene, keyframe, &joints, &status)) {
      std::cerr << "posture: " << status.message << "\n";
      return kExitUsage;
    }
    controller = PostureController::Create(
        options, FromKeyframe(scene + " keyframe '" + keyframe + "'", joints), &status);
  } else {
    controller = PostureController::Create(options, &status);
  }
  if (!controller) {
    std::cerr << "posture: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
