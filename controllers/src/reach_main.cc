// reach: attach to a robot segment, stand as balance does, plan a collision-free motion of a
// joint group to goal joint values and execute it. See controllers/reach.h, docs/planning.md.

#include <cmath>
#include <iostream>
#include <sstream>

#include "cli/command_line.h"
#include "controllers/cli.h"
#include "controllers/posture.h"
#include "controllers/reach.h"
#include "controllers/reach_goals.h"
#include "controllers/runner.h"
#include "robot_model/model.h"
#include "robot_model/profile.h"
#include "robot_model/scene_obstacles.h"

namespace {
using ohrp::controllers::ParseHandPoses;
using ohrp::controllers::ParseJointsGoal;

[[noreturn]] void OnMujocoFatal(const char*) { std::_Exit(ohrp::controllers::kExitConfig); }

// "NAME,CX,CY,CZ,HX,HY,HZ": a box in the base frame; false with `*error`
bool ParseBox(const std::string& text, ohrp::planning::SceneBox* box, std::string* error) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  if (items.size() != 7 || items[0].empty()) {
    *error = "--box '" + text + "': give NAME,CX,CY,CZ,HX,HY,HZ (metres, base frame)";
    return false;
  }
  double v[6];
  for (int i = 0; i < 6; ++i) {
    std::istringstream number(items[i + 1]);
    std::string rest;
    if (!(number >> v[i]) || (number >> rest) || !std::isfinite(v[i]) || (i >= 3 && !(v[i] > 0))) {
      *error = "--box '" + text + "': '" + items[i + 1] + "' is not a " +
               (i < 3 ? "finite number" : "positive half size");
      return false;
    }
    if (const std::string why = ohrp::cli::CheckPlausible(i < 3 ? "height" : "distance", v[i], "--box");
        !why.empty()) {
      *error = why;
      return false;
    }
  }
  box->name = items[0];
  box->X_BO.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  box->half_size = Eigen::Vector3d(v[3], v[4], v[5]);
  return true;
}
// --group NAME: with a robot profile as --model, one of its chains or groups (docs/robots.md)
// stands for its joints; false with `*error` for a single name that is neither a joint the
// profile lists nor a chain or group of it
bool GroupFromProfile(const std::string& model, std::vector<std::string>* group, std::string* error) {
  if (group->size() != 1 || !ohrp::model::IsProfilePath(model)) return true;
  ohrp::model::RobotProfile p;
  if (!ohrp::model::ReadProfile(model, &p, error)) return false;
  for (const auto* named : {&p.chains, &p.groups}) {
    if (const auto it = named->find(group->front()); it != named->end()) {
      *group = it->second;
      return true;
    }
  }
  return true;  // a joint's name: the controller checks it against the robot
}
}  // namespace

int main(int argc, char** argv) {
  using namespace ohrp::controllers;
  ReachOptions o;
  RunOptions run;
  run.program = "reach";

  CLI::App app{
      "reach: attach to a robot segment (sim_host or hw_driver), stand as balance does, then\n"
      "move a joint group (the joints named in --goal-joints, or --group with a hand pose\n"
      "--goal-pose solved by the shared limb IK) from its measured posture to the goal along a\n"
      "path planned clear of the robot's own links (the self-collision file's online pairs,\n"
      "margin and safe ranges, plus --clearance) and of --box and --scene obstacles by OMPL's\n"
      "RRTConnect with path simplification (--goals FILE: several goals in sequence), timed within --max-speed and --max-accel; hold it, and report the\n"
      "planning time, the path length, the smallest clearance of the executed motion (from the\n"
      "measured joint angles) and the final tracking error. Exit 9 when no path is found, the\n"
      "run ends before the hold is over, or the final error exceeds --tolerance.",
      "reach"};
  app.add_option("--model", o.balance.model, "MJCF, OpenHRP VRML .wrl or robot profile .yaml of the robot")
      ->default_val(DefaultModelFile())
      ->check(CLI::ExistingFile);
  auto* pose = app.add_option("--pose", o.balance.pose_file, "stance pose, YAML by joint name [rad]")
      ->default_val(DefaultPoseFile())
      ->check(CLI::ExistingFile);
  app.add_option("--keyframe", o.balance.keyframe,
                 "take the stance pose from this keyframe of --model instead of --pose (as "
                 "balance's --keyframe; a robot profile's stance is its keyframe 'stand')")
      ->excludes(pose);
  app.add_option("--ramp", o.balance.ramp, "[s] ramp from the measured pose to the stance pose")
      ->default_val(o.balance.ramp)->check(ohrp::cli::Plausible("ramp_time"));
  app.add_option("--settle", o.balance.settle, "[s] of quiet standing before the CoM reference is taken")
      ->default_val(o.balance.settle)->check(ohrp::cli::Plausible("wait"));
  app.add_option("--collision-file", o.collision_file,
                 "the robot's self-collision file (ohrp_selfcollision): geometry, pairs, margin")
      ->default_val(DefaultSelfCollisionFile())
      ->check(CLI::ExistingFile);
  std::vector<std::string> goal_items;
  app.add_option("--goal-joints", goal_items,
                 "the goal: NAME=VALUE,... [rad]; the named joints are the group the plan moves")
      ->delimiter(',');
  app.add_option("--group", o.group,
                 "with --goal-pose: the joints the plan moves, the chain to the site, root outwards; with a "
                 "robot profile as --model, a chain or group of it by name (e.g. left_arm)")
      ->delimiter(',');
  std::vector<std::string> pose_items;
  app.add_option("--goal-pose", pose_items,
                 "the goal as a hand pose: SITE,X,Y,Z[,ROLL,PITCH,YAW] in the base frame [m, rad] "
                 "(the group's joints by the shared limb IK from the stance pose); repeat for a "
                 "second hand (both arms in --group, one site each)")
      ->delimiter(',')
      ->excludes("--goal-joints");
  std::string goals_file;
  app.add_option("--goals", goals_file,
                 "a goals file (YAML: group, goals: joints or a hand pose each, optional hold) "
                 "reached in sequence, each planned from where the previous one left the arm")
      ->check(CLI::ExistingFile)
      ->excludes("--goal-joints")
      ->excludes("--goal-pose");
  std::vector<std::string> box_items;
  app.add_option("--box", box_items,
                 "a static box to keep clear of: NAME,CX,CY,CZ,HX,HY,HZ (centre and half sizes in "
                 "the base frame, as the robot stands) [m]; repeat for more")
      ->take_all()->allow_extra_args(false);
  app.add_option("--scene", o.scene_file,
                 "an MJCF scene (normally the one sim_host simulates): its static geoms (boxes; "
                 "spheres, capsules, cylinders as their bounding boxes; not the floor) are kept "
                 "clear of, placed in the base frame from the estimated base pose when the plan is "
                 "made (the scene's world: the estimator's, soles centred on x = y = 0, facing +x)")
      ->check(CLI::ExistingFile);
  app.add_option("--scene-keyframe", o.scene_keyframe,
                 "with --scene: the keyframe the scene starts the robot in (where its soles stand)")
      ->default_val(o.scene_keyframe);
  app.add_option("--clearance", o.clearance, "[m] kept between links beyond the file's margin")
      ->default_val(o.clearance)->check(ohrp::cli::Plausible("clearance"));
  app.add_option("--start", o.start, "[s] after the stance begins, when the plan is made")
      ->default_val(o.start)->check(ohrp::cli::Plausible("wait"));
  app.add_option("--hold", o.hold, "[s] at the goal before the tracking error is measured")
      ->default_val(o.hold)->check(ohrp::cli::Plausible("wait"));
  app.add_option("--max-speed", o.max_speed, "[rad/s] per joint")
      ->default_val(o.max_speed)->check(ohrp::cli::InRange(1e-3, 20.0));
  app.add_option("--max-accel", o.max_accel, "[rad/s^2] per joint (lower where the torque allows less)")
      ->default_val(o.max_accel)->check(ohrp::cli::InRange(1e-3, 200.0));
  app.add_option("--tolerance", o.tolerance, "[rad] largest final tracking error accepted")
      ->default_val(o.tolerance)->check(ohrp::cli::InRange(1e-4, 1.0));
  app.add_flag("--stop-at-waypoints", o.stop_at_waypoints,
               "time the path rest to rest at every waypoint (default: blended, not stopping at "
               "them, where the blended path, checked again, keeps the clearance)");
  app.add_option("--plan-log", o.plan_log,
                 "CSV written after the run: the plan's waypoints, the timed path every 10 ms and "
                 "the measured group joints every cycle (kind,t,JOINT...)");
  app.add_option("--plan-time", o.plan.time_limit, "[s] the planner's time limit")
      ->default_val(o.plan.time_limit)->check(ohrp::cli::InRange(1e-3, 600.0));
  app.add_option("--seed", o.plan.seed, "the planner's random seed (the same seed, the same path)")
      ->default_val(o.plan.seed)->check(CLI::Range(1u, 4000000000u));
  app.add_flag("--listen", o.listen,
               "live goals on stdin while it stands, one a line: 'joints NAME=VALUE,...' or 'pose "
               "SITE,X,Y,Z[,ROLL,PITCH,YAW] [SITE,...]' (reach_live.h; docs/planning.md), each "
               "reached after the ones before it; replies on stderr");
  app.add_option("--socket", o.socket,
                 "live goals on a local stream socket at this path, as --listen (one client at a "
                 "time, one reply line per goal: 'ok: goal N queued' or 'error: why')");
  AddRunOptions(&app, &run);
  if (const int code = ParseCommandLine(&app, argc, argv); code >= 0) return code;
  std::string error;
  if (!ParseJointsGoal(goal_items, "--goal-joints", &o.goal_joints, &error) ||
      !ParseHandPoses(pose_items, "--goal-pose", &o.hands, &error)) {
    std::cerr << "reach: " << error << "\n";
    return kExitUsage;
  }
  if (!GroupFromProfile(o.balance.model, &o.group, &error)) {
    std::cerr << "reach: --group: " << error << "\n";
    return kExitUsage;
  }
  if (!goals_file.empty() && !ReadGoalsFile(goals_file, &o.goals, &error)) {
    std::cerr << "reach: --goals: " << error << "\n";
    return kExitUsage;
  }
  for (const std::string& b : box_items) {
    ohrp::planning::SceneBox box;
    if (!ParseBox(b, &box, &error)) {
      std::cerr << "reach: " << error << "\n";
      return kExitUsage;
    }
    o.boxes.push_back(box);
  }

  ohrp::model::InstallMujocoHandlers(OnMujocoFatal);
  if (!o.scene_file.empty()) {
    ohrp::model::SceneObstacles scene;
    if (!ohrp::model::ReadSceneObstacles(o.scene_file, &scene, &error)) {
      std::cerr << "reach: " << error << "\n";
      return kExitUsage;
    }
    o.scene = scene.boxes;
  }
  ConfigStatus status;
  auto controller = ReachController::Create(o, &status);
  if (!controller) {
    std::cerr << "reach: " << status.message << "\n";
    return status.code == ConfigError::kOption ? kExitUsage : kExitConfig;
  }
  InstallStopSignalHandlers();
  return RunController(*controller, run, std::cout, std::cerr);
}
