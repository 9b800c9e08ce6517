// bench_selfcollision: the online self-collision check of HRP-1S per posture (issue 15): forward
// kinematics and every non-adjacent pair of links, then the reduced list a controller checks
// (the file's online pairs plus the pairs of each safe range the posture leaves), beside the
// 5 ms control period. Postures are random within the joint limits, the safe ranges kept (the
// regime the reduced list is for). The paper's figures are printed for reference.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "collision/incremental_check.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "controllers/self_collision_guard.h"
#include "controllers/trajectory.h"
#include "robot_model/model.h"
#include "cycle_timing.h"
#include "quantile.h"
#include "shm_bridge/clock.h"

using ohrp::bench::Quantile;

namespace {

using namespace ohrp::collision;

struct Options {
  std::string path = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
  std::string walk = std::string(OHRP_SOURCE_DIR) + "/../shared/external/openhrp3-sample/SamplePD/angle.dat";
  std::string model = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml";
  int postures = 20000;
  double period = 0.005;
};

void AddOptions(CLI::App& app, Options& o) {
  app.add_option("--file", o.path, "self-collision file (ohrp_selfcollision)")
      ->check(CLI::ExistingFile)->capture_default_str();
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--postures", o.postures, "random postures")->check(ohrp::cli::Plausible("count"))
      ->check(ohrp::cli::InRange(100, 10000000))->capture_default_str();
  app.add_option("--control-period", o.period, "[s]")->check(ohrp::cli::Plausible("control_period"))
      ->capture_default_str();
  app.add_option("--walk", o.walk,
                 "joint angles along a walk (OpenHRP's angle.dat format; its rows are the control "
                 "cycles): the guard's two checks a cycle (the posture and the next), in full and "
                 "incrementally; '' to skip")
      ->capture_default_str();
  app.add_option("--model", o.model, "the file's robot (MJCF): the torque limits and gains of the "
                 "segment header the guard checks against")
      ->check(CLI::ExistingFile)->capture_default_str();
}

// the walk, read before anything runs (the default file is OpenHRP's sample beside the
// repository: skipped when it is not there); 2 on a bad one, else -1
int LoadWalk(const CLI::App& app, const RobotGeometry& g, std::string* walk_path,
             ohrp::controllers::Trajectory* traj) {
  std::string& walk = *walk_path;
  if (!walk.empty() && app.count("--walk") == 0 && !std::filesystem::exists(walk)) {
    std::fprintf(stderr, "bench_selfcollision: no walk rows: %s not found\n", walk.c_str());
    walk.clear();
  }
  if (!walk.empty()) {
    const auto status = ohrp::controllers::LoadTrajectory(walk, traj);
    if (!status.ok() || traj->njoint != static_cast<int>(g.joint_names.size())) {
      std::fprintf(stderr, "bench_selfcollision: --walk %s: %s\n", walk.c_str(),
                   status.ok() ? "not one column per joint of the file's robot" : status.message.c_str());
      return 2;
    }
  }
  return -1;
}

// the postures, the safe ranges kept
std::vector<std::vector<double>> RandomPostures(const SelfCollisionFile& file, int postures) {
  const RobotGeometry& g = file.robot;
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> qs(postures, std::vector<double>(g.joint_names.size()));
  for (auto& q : qs) {
    for (size_t j = 0; j < q.size(); ++j) q[j] = g.q_min[j] + u(rng) * (g.q_max[j] - g.q_min[j]);
    for (const SafeRange& s : file.ranges) q[s.joint] = s.lo + u(rng) * (s.hi - s.lo);
  }
  return qs;
}

struct PairFigures {
  double med_all, p99_all, med_red;  // [s]
};

// all pairs, then the reduced list, each with its forward kinematics (the table's first rows)
PairFigures TimeAllAndReduced(SelfCollision* checker, const SelfCollisionFile& file,
                              const std::vector<std::vector<double>>& qs) {
  const std::vector<LinkPair> all = NonAdjacentPairs(file.robot);
  std::vector<double> t_all, t_reduced;
  long close_all = 0, close_reduced = 0;
  for (const auto& q : qs) {
    const double t0 = ohrp::MonotonicSeconds();
    checker->SetPose(q);
    close_all += checker->Check(all, file.margin, {}).closest >= 0;
    const double t1 = ohrp::MonotonicSeconds();
    checker->SetPose(q);
    close_reduced += checker->Check(file.online, file.margin, {}).closest >= 0;
    const double t2 = ohrp::MonotonicSeconds();
    t_all.push_back(t1 - t0);
    t_reduced.push_back(t2 - t1);
  }
  const double med_all = Quantile(t_all, 0.5), p99_all = Quantile(t_all, 0.99);
  const double med_red = Quantile(t_reduced, 0.5), p99_red = Quantile(t_reduced, 0.99);
  std::printf("| check | pairs | median [us] | p99 [us] | postures within the margin |\n");
  std::printf("|---|---:|---:|---:|---:|\n");
  std::printf("| all non-adjacent pairs | %zu | %.1f | %.1f | %ld |\n", all.size(), med_all * 1e6,
              p99_all * 1e6, close_all);
  std::printf("| reduced list (safe ranges kept) | %zu | %.1f | %.1f | %ld |\n", file.online.size(),
              med_red * 1e6, p99_red * 1e6, close_reduced);
  return {med_all, p99_all, med_red};
}

// what the guard checks every cycle: the posture and the one a cycle ahead
void TimeWalkChecks(SelfCollision* checker, const SelfCollisionFile& file,
                    const ohrp::controllers::Trajectory& traj) {
  IncrementalCheck incremental(checker, file.online);
  std::vector<int> every(file.online.size());
  for (size_t i = 0; i < every.size(); ++i) every[i] = static_cast<int>(i);
  std::vector<double> t_full, t_inc;
  std::vector<double> q(traj.row(0), traj.row(0) + traj.njoint), ahead = q;
  long differ = 0;
  for (size_t r = 0; r + 1 < traj.rows(); ++r) {
    std::copy_n(traj.row(r), traj.njoint, q.begin());
    std::copy_n(traj.row(r + 1), traj.njoint, ahead.begin());
    const double t0 = ohrp::MonotonicSeconds();
    checker->SetPose(q);
    const CheckResult a = checker->Check(file.online, file.margin, {});
    checker->SetPose(ahead);
    const CheckResult b = checker->Check(file.online, file.margin, {});
    const double t1 = ohrp::MonotonicSeconds();
    incremental.MoveTo(q);
    const CheckResult c = incremental.Check(every, file.margin);
    incremental.MoveTo(ahead);
    const CheckResult d = incremental.Check(every, file.margin);
    const double t2 = ohrp::MonotonicSeconds();
    t_full.push_back(t1 - t0);
    t_inc.push_back(t2 - t1);
    differ += a.closest != c.closest || b.closest != d.closest ||
              (a.closest >= 0 && a.min_distance != c.min_distance) ||
              (b.closest >= 0 && b.min_distance != d.min_distance);
  }
  std::printf("| reduced list along the walk, 2 postures a cycle, full | %zu | %.1f | %.1f | - |\n",
              file.online.size(), Quantile(t_full, 0.5) * 1e6, Quantile(t_full, 0.99) * 1e6);
  std::printf("| the same, incremental (what the guard runs) | %zu | %.1f | %.1f | %ld answers differ |\n",
              file.online.size(), Quantile(t_inc, 0.5) * 1e6, Quantile(t_inc, 0.99) * 1e6, differ);
}

// the guard's whole cycle: sensors moving along the rows (velocities from their differences,
// the torque zero: the load is what accelerates the joints), the next row commanded
std::vector<std::vector<double>> GuardRows(const std::string& walk,
                                           const ohrp::controllers::Trajectory& traj,
                                           const std::vector<std::vector<double>>& qs, double period) {
  std::vector<std::vector<double>> rows;
  if (!walk.empty()) {
    for (size_t r = 0; r < traj.rows(); ++r) rows.emplace_back(traj.row(r), traj.row(r) + traj.njoint);
  } else {
    // ramps at up to 1 rad/s between 20 random postures
    for (int k = 0; k + 1 < 20; ++k) {
      const auto& a = qs[k];
      const auto& b = qs[k + 1];
      double far = 0;
      for (size_t j = 0; j < a.size(); ++j) far = std::max(far, std::abs(b[j] - a[j]));
      const int n = std::max(1, static_cast<int>(far / (1.0 * period)));
      for (int i = 0; i < n; ++i) {
        rows.push_back(a);
        for (size_t j = 0; j < a.size(); ++j) rows.back()[j] += (b[j] - a[j]) * i / n;
      }
    }
  }
  return rows;
}

// the segment header the guard checks against, from the file's robot and --model's limits and
// gains; 2 when --model is not that robot, else -1
int HeaderFromModel(const Options& o, const RobotGeometry& g, ohrp::shm::SegmentHeader* out) {
  const std::string& model = o.model;
  const double period = o.period;
  std::string merror;
  auto scene = ohrp::model::Scene::Load(model, &merror);
  ohrp::model::RobotMap robot;
  if (!scene || !ohrp::model::MapRobot(scene->m(), &robot, &merror) ||
      robot.joints.size() != g.joint_names.size()) {
    std::fprintf(stderr, "bench_selfcollision: --model %s: %s\n", model.c_str(),
                 merror.empty() ? "not the file's robot" : merror.c_str());
    return 2;
  }
  ohrp::shm::SegmentHeader& header = *out;
  header.njoint = static_cast<int>(g.joint_names.size());
  header.model_hash = g.model_hash;
  header.control_period = period;
  for (int j = 0; j < header.njoint; ++j) {
    std::snprintf(header.joint_names[j], ohrp::shm::kNameLen, "%s", g.joint_names[j].c_str());
    header.tau_max[j] = robot.joints[j].tau_max;
    header.default_kp[j] = robot.joints[j].default_kp;
    header.default_kd[j] = robot.joints[j].default_kd;
  }
  return -1;
}

// the guard's Filter timed along the rows (its two table rows); returns its p99 cycle [s]
double TimeGuard(ohrp::controllers::SelfCollisionGuard& guard, const ohrp::shm::SegmentHeader& header,
                 const std::vector<std::vector<double>>& rows, double period, const char* along) {
  ohrp::shm::SensorBlock sensors{};
  ohrp::shm::CommandBlock commands{};
  ohrp::bench::CycleTimes t_guard;
  std::vector<double> evaluations;  // the certification's distance evaluations per cycle
  const double cpu_overhead = ohrp::bench::ThreadCpuOverhead();
  long braked = 0;
  for (size_t r = 0; r + 1 < rows.size(); ++r) {
    for (int j = 0; j < header.njoint; ++j) {
      sensors.q[j] = rows[r][j];
      sensors.dq[j] = r > 0 ? (rows[r][j] - rows[r - 1][j]) / period : 0.0;
      sensors.tau[j] = 0.0;
      commands.joint[j] = {ohrp::shm::JointMode::kPosition, 0, rows[r + 1][j],
                           (rows[r + 1][j] - rows[r][j]) / period, 0.0, header.default_kp[j],
                           header.default_kd[j]};
    }
    if (r == 0) guard.Activate(sensors);
    t_guard.Time([&] { braked += guard.Filter(sensors, &commands); });
    evaluations.push_back(guard.last_evaluations());
  }
  const double med_guard = Quantile(t_guard.wall, 0.5), p99_guard = Quantile(t_guard.wall, 0.99);
  const double max_guard = *std::max_element(t_guard.wall.begin(), t_guard.wall.end());
  const double p99_cpu = Quantile(t_guard.cpu, 0.99) - cpu_overhead;
  std::printf("| the guard's cycle (Filter: braking check, certification, brake) along the %s | %zu | %.1f | %.1f (max %.1f) | %ld of %zu cycles braked, %ld not certified |\n",
              along, guard.file().online.size(), med_guard * 1e6,
              p99_guard * 1e6, max_guard * 1e6, braked, t_guard.wall.size(), guard.uncertified_cycles());
  std::printf("| the same, the thread's CPU time (without preemption) | %zu | %.1f | %.1f | distance evaluations a cycle: median %.0f, p99 %.0f, max %.0f (bound %d) |\n",
              guard.file().online.size(), (Quantile(t_guard.cpu, 0.5) - cpu_overhead) * 1e6,
              p99_cpu * 1e6, Quantile(evaluations, 0.5), Quantile(evaluations, 0.99),
              *std::max_element(evaluations.begin(), evaluations.end()),
              ohrp::controllers::SelfCollisionGuard::kWorkBound);
  return p99_guard;
}

// the paper's figures, the control period, the targets and the ratio
void PrintSummary(const PairFigures& f, double p99_guard, double period) {
  const double med_all = f.med_all, p99_all = f.p99_all, med_red = f.med_red;
  std::printf("| paper: HRP-1S, 933 MHz Pentium III, ~10,000 polygons | 350 | ~10000 (mean) | - | - |\n");
  std::printf("| paper: reduced list while walking | 36 | ~1000 (35 pairs/ms) | - | - |\n");
  std::printf("| control period | - | %.0f | - | - |\n", period * 1e6);
  std::printf("targets: all pairs median < 50 us (%s), p99 < 150 us (%s); reduced median < 10 us (%s); the guard's p99 cycle < 20 %% of the period (%s)\n",
              med_all < 50e-6 ? "met" : "missed", p99_all < 150e-6 ? "met" : "missed",
              med_red < 10e-6 ? "met" : "missed", p99_guard < 0.2 * period ? "met" : "missed");
  std::printf("ratio: %.4f (%.2f us / %.0f us: the guard's p99 cycle / control period)\n",
              p99_guard / period, p99_guard * 1e6, period * 1e6);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "bench_selfcollision: the self-collision check per posture of HRP-1S: all non-adjacent "
      "pairs, and the reduced list of the self-collision file, median and p99, beside the "
      "control period (targets: all pairs under 50 us median and 150 us p99, the reduced list "
      "under 10 us median); then the online guard's whole cycle (SelfCollisionGuard::Filter: the "
      "braking check, its certification and the brake) along the walk, or along ramps between "
      "random postures without it. Ends with 'ratio: X (the guard's p99 cycle / control "
      "period)', target under 0.2."};
  AddOptions(app, o);
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  SelfCollisionFile file;
  std::string error;
  if (!ReadSelfCollisionFile(o.path, &file, &error)) {
    std::fprintf(stderr, "bench_selfcollision: %s\n", error.c_str());
    return 2;
  }
  auto checker = SelfCollision::Create(file.robot, &error);
  ohrp::controllers::Trajectory traj;
  if (const int code = LoadWalk(app, file.robot, &o.walk, &traj); code >= 0) return code;
  const std::vector<std::vector<double>> qs = RandomPostures(file, o.postures);
  const PairFigures figures = TimeAllAndReduced(checker.get(), file, qs);
  if (!o.walk.empty()) TimeWalkChecks(checker.get(), file, traj);
  const std::vector<std::vector<double>> rows = GuardRows(o.walk, traj, qs, o.period);
  ohrp::shm::SegmentHeader header{};
  if (const int code = HeaderFromModel(o, file.robot, &header); code >= 0) return code;
  ohrp::controllers::SelfCollisionGuard guard;
  if (const std::string problem = guard.Configure(o.path, header); !problem.empty()) {
    std::fprintf(stderr, "bench_selfcollision: %s\n", problem.c_str());
    return 2;
  }
  const double p99_guard = TimeGuard(guard, header, rows, o.period, o.walk.empty() ? "ramps" : "walk");
  PrintSummary(figures, p99_guard, o.period);
  return 0;
}
