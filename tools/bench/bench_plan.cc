// bench_plan: the arm planner (robot_model/planning, issue 34) on HRP-1S's left arm in front of a
// shelf with compartments: planning time (median, p90, failures) over a fixed set of seeded
// goals, beside the cost of one validity check and of the straight-line interpolation check of
// the same paths. Ends with "ratio: X (median planning time / 100 ms target)".
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "collision/pair_file.h"
#include "controllers/pose.h"
#include "planning/arm_planner.h"
#include "quantile.h"

using ohrp::bench::Quantile;
namespace planning = ohrp::planning;

namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// a shelf in front of the robot's left side, in the base (waist) frame: a back panel, two sides
// and three boards, 2 cm thick, making two compartments
std::vector<planning::SceneBox> Shelf(double x0) {
  auto box = [](const char* name, double cx, double cy, double cz, double hx, double hy, double hz) {
    planning::SceneBox b;
    b.name = name;
    b.half_size = {hx, hy, hz};
    b.X_BO.translation() = Eigen::Vector3d(cx, cy, cz);
    return b;
  };
  const double depth = 0.15, y0 = -0.05, y1 = 0.45, z0 = -0.05, z1 = 0.45, t = 0.01;
  const double cx = x0 + depth, cy = 0.5 * (y0 + y1), hy = 0.5 * (y1 - y0), hz = 0.5 * (z1 - z0);
  return {box("back", x0 + 2 * depth, cy, 0.5 * (z0 + z1), t, hy, hz),
          box("side_right", cx, y0, 0.5 * (z0 + z1), depth, t, hz),
          box("side_left", cx, y1, 0.5 * (z0 + z1), depth, t, hz),
          box("board_low", cx, cy, z0, depth, hy, t),
          box("board_mid", cx, cy, 0.5 * (z0 + z1), depth, hy, t),
          box("board_top", cx, cy, z1, depth, hy, t)};
}

}  // namespace

int main(int argc, char** argv) {
  std::string path = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
  std::string pose_file = std::string(OHRP_SOURCE_DIR) + "/controllers/poses/hrp1s_halfsit.yaml";
  int goals = 40;
  unsigned seed = 1;
  double clearance = 0.01, time_limit = 2.0, shelf_x = 0.3;
  CLI::App app{
      "bench_plan: the arm planner on HRP-1S's left arm from half-sitting to seeded random goals "
      "clear of the body and of a shelf in front of it (two compartments): OMPL RRTConnect, "
      "path simplification; planning time median, p90 and failures, beside one validity check "
      "and the straight-line check of the same paths. Ends with 'ratio: X (median planning time "
      "/ 100 ms)', target under 1."};
  app.add_option("--file", path, "self-collision file")->check(CLI::ExistingFile)->capture_default_str();
  app.add_option("--pose", pose_file, "start pose")->check(CLI::ExistingFile)->capture_default_str();
  app.add_option("--goals", goals, "seeded goals")->check(ohrp::cli::InRange(1, 100000))->capture_default_str();
  app.add_option("--seed", seed, "goals' and planner's seed")->check(CLI::Range(1u, 4000000000u))->capture_default_str();
  app.add_option("--clearance", clearance, "[m] beyond the file's margin")
      ->check(ohrp::cli::Plausible("clearance"))->capture_default_str();
  app.add_option("--plan-time", time_limit, "[s] per plan")->check(ohrp::cli::InRange(1e-3, 600.0))->capture_default_str();
  app.add_option("--shelf-x", shelf_x, "[m] the shelf's front in front of the waist")
      ->check(ohrp::cli::InRange(0.1, 2.0))->capture_default_str();
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  ohrp::collision::SelfCollisionFile file;
  std::string error;
  if (!ohrp::collision::ReadSelfCollisionFile(path, &file, &error)) {
    std::fprintf(stderr, "bench_plan: %s\n", error.c_str());
    return 3;
  }
  planning::JointGroup group;
  const std::vector<std::string> arm = {"LARM_SHOULDER_P", "LARM_SHOULDER_R", "LARM_SHOULDER_Y",
                                        "LARM_ELBOW", "LARM_WRIST_Y", "LARM_WRIST_P", "LARM_WRIST_R"};
  if (!planning::MakeJointGroup(file.robot, arm, &group, &error)) {
    std::fprintf(stderr, "bench_plan: %s: %s\n", path.c_str(), error.c_str());
    return 3;
  }
  const std::vector<planning::SceneBox> shelf = Shelf(shelf_x);
  auto check = planning::PostureCheck::Create(file, shelf, group, clearance, &error);
  if (!check) {
    std::fprintf(stderr, "bench_plan: %s\n", error.c_str());
    return 3;
  }
  ohrp::controllers::Pose pose;
  std::vector<double> start;
  if (auto s = ohrp::controllers::LoadPoseFile(pose_file, &pose); !s.ok() ||
      !(s = ohrp::controllers::ResolvePose(pose, file.robot.joint_names, &start)).ok()) {
    std::fprintf(stderr, "bench_plan: %s\n", s.message.c_str());
    return 3;
  }
  start.resize(ohrp::collision::NumJoints(file.robot), 0.0);
  if (const planning::Verdict v = check->Evaluate(start); !v.valid) {
    std::fprintf(stderr, "bench_plan: the start pose is not clear: %s\n", check->Describe(v).c_str());
    return 3;
  }

  // one validity check, on random arm postures
  std::mt19937 rng(seed);
  auto random_arm = [&] {
    std::vector<double> v(group.size());
    for (int j = 0; j < group.size(); ++j)
      v[j] = std::uniform_real_distribution<double>(group.lo[j], group.hi[j])(rng);
    return v;
  };
  std::vector<double> q = start, checks;
  int valid = 0;
  for (int i = 0; i < 5000; ++i) {
    planning::SetGroupValues(group, random_arm(), q);
    const auto t0 = std::chrono::steady_clock::now();
    valid += check->Valid(q);
    checks.push_back(Since(t0));
  }
  // the goals: random arm postures clear of the body and the shelf, a fixed sequence per seed
  std::vector<double> times, straight_times, lengths, clearances;
  int failures = 0, straight_blocked = 0;
  planning::PlanOptions o;
  o.time_limit = time_limit;
  for (int g = 0; g < goals;) {
    const std::vector<double> goal = random_arm();
    planning::SetGroupValues(group, goal, q);
    if (!check->Valid(q)) continue;
    o.seed = seed + g;
    const planning::PlanResult r = planning::PlanJoints(*check, start, goal, o);
    ++g;
    std::vector<double> s(group.size());
    planning::GroupValues(group, start, s);
    straight_blocked += !planning::ClosestAlong(*check, start, {s, goal}, o.resolution).valid;
    if (!r.solved) {
      ++failures;
      continue;
    }
    times.push_back(r.plan_time + r.simplify_time);
    lengths.push_back(r.length);
    clearances.push_back(r.closest.distance);
    const auto t0 = std::chrono::steady_clock::now();
    planning::ClosestAlong(*check, start, r.waypoints, o.resolution);
    straight_times.push_back(Since(t0));
  }
  std::printf("bench_plan: HRP-1S left arm (7 joints) from half-sitting, shelf of %zu boxes %.2f m "
              "in front; self-collision file %s\n", shelf.size(), shelf_x, path.c_str());
  std::printf("planner: OMPL RRTConnect (default range: a fifth of the space's extent), motion "
              "checks every %.3f rad, simplification: reduceVertices x<=5, collapseCloseVertices, "
              "shortcutPath x<=5, reduceVertices; time limit %.1f s; clearance %.1f mm beyond the "
              "margin %.1f mm\n", o.resolution, time_limit, 1e3 * clearance, 1e3 * file.margin);
  std::printf("%-44s %12s %12s\n", "", "median", "p90");
  std::printf("%-44s %9.1f us %9.1f us   (%d of 5000 random arm postures valid)\n",
              "one validity check", 1e6 * Quantile(checks, 0.5), 1e6 * Quantile(checks, 0.9), valid);
  std::printf("%-44s %9.2f ms %9.2f ms   (%d goals, %d failures; the straight line blocked for %d)\n",
              "planning (RRTConnect + simplification)", 1e3 * Quantile(times, 0.5),
              1e3 * Quantile(times, 0.9), goals, failures, straight_blocked);
  std::printf("%-44s %9.2f ms %9.2f ms\n", "the planned path's check at the resolution",
              1e3 * Quantile(straight_times, 0.5), 1e3 * Quantile(straight_times, 0.9));
  std::printf("%-44s %9.3f rad %8.3f rad\n", "path length", Quantile(lengths, 0.5), Quantile(lengths, 0.9));
  std::printf("%-44s %9.1f mm  (smallest %.1f mm)\n", "planned clearance",
              1e3 * Quantile(clearances, 0.5),
              clearances.empty() ? 0.0 : 1e3 * *std::min_element(clearances.begin(), clearances.end()));
  std::printf("ratio: %.2f (median planning time %.2f ms / 100 ms)\n", Quantile(times, 0.5) / 0.1,
              1e3 * Quantile(times, 0.5));
  return failures == 0 ? 0 : 1;
}
