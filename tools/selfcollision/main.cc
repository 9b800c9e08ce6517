// ohrp_selfcollision: from a robot's MJCF and its joint limits, the pairs of links a controller
// must check online, the joints' safe ranges and why each pair was pruned (docs/selfcollision.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "cli/command_line.h"
#include "cli/data_dir.h"
#include "collision/from_mjcf.h"
#include "collision/joint_dynamics.h"
#include "collision/prune.h"

namespace {

using ohrp::collision::PruneResult;

// the report: counts, then every pair with the reason it was kept or pruned
std::string Report(const PruneResult& r, double seconds) {
  const auto& f = r.file;
  std::string s = "# self-collision pairs of " + f.robot.name + "\n\n";
  size_t extra = 0;  // the joint_only links of bodies with several joints
  for (const auto& l : f.robot.links) extra += l.joint_only;
  char line[320];
  std::snprintf(line, sizeof(line),
                "links %zu (bodies %zu, extra joints of a body %zu); non-adjacent pairs %zu; "
                "structural %zu; never %zu; pruned by safe ranges %zu; online %zu (%.1f s)\n\n",
                f.robot.links.size(), f.robot.links.size() - extra, extra, r.all,
                f.structural.size(), f.never.size(),
                r.all - f.structural.size() - f.never.size() - f.online.size(), f.online.size(),
                seconds);
  s += line;
  s += "time per step:";
  for (const auto& [name, t] : r.stage_seconds) {
    std::snprintf(line, sizeof(line), " %s %.1f s;", name.c_str(), t);
    s += line;
  }
  s += "\n\n";
  if (!f.robot.passive_names.empty()) {
    s += "passive joints (no actuator: the segment's passive_q, never commanded, moving within "
         "their limits; an unlimited hinge over -pi..pi):";
    for (const auto& n : f.robot.passive_names) s += " " + n;
    s += "\n\n";
  }
  for (const auto& u : f.robot.unchecked) s += "not in the geometry, never checked: " + u + "\n";
  if (!f.robot.unchecked.empty()) s += "\n";
  s += "## safe ranges [rad, m for slides] (the full range in brackets)\n\n";
  for (const auto& g : f.ranges) {
    std::snprintf(line, sizeof(line), "- %s: %.4f .. %.4f  [%.4f .. %.4f], %zu pairs\n",
                  ohrp::collision::JointName(f.robot, g.joint).c_str(), g.lo, g.hi, f.robot.q_min[g.joint],
                  f.robot.q_max[g.joint], g.pairs.size());
    s += line;
  }
  s += "\n## pairs\n\n";
  for (size_t i = 0; i < r.pairs.size(); ++i)
    s += "- " + f.robot.links[r.pairs[i].a].name + " / " + f.robot.links[r.pairs[i].b].name + ": " +
         r.reasons[i] + "\n";
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string model = ohrp::cli::DataPath("mjcf/hrp1s/hrp1s.xml");
  std::string out, report;
  std::vector<std::string> range_joints;
  std::string reference;
  bool quiet = false;
  ohrp::collision::PruneOptions o;
  CLI::App app{
      "ohrp_selfcollision: the offline pre-processing of the self-collision checker (paper "
      "section 4.1). From the model's links and joint limits it finds the pairs that touch at the "
      "zero posture (structural, each with a floor the online check keeps), the pairs proven "
      "never to come within margin + clearance anywhere in the joint limits, and safe ranges "
      "(candidates from sampled cells, a coarse then a fine resolution) over which more pairs are "
      "proven clear: a pair is pruned only on a proof (branch and bound with a certified bound "
      "of the links' motion), never on samples alone; the pairs left are checked online. Writes the YAML file the controllers load "
      "(--self-collision) and a report of every pair and why it was pruned. Passive joints (no "
      "actuator) are taken within their limits (an unlimited hinge over -pi..pi) and listed in "
      "the file; bodies below a ball joint are left out and listed as unchecked.\n"
      "Example: ohrp_selfcollision --out mjcf/hrp1s/selfcollision.yaml --report report.md"};
  app.add_option("--model", model, "the robot's MJCF")->check(CLI::ExistingFile);
  app.add_option("--out", out, "the self-collision file to write (YAML)")->required();
  app.add_option("--report", report, "the report to write (Markdown); default: stdout");
  // every number within its plausible range (cli/plausible.h), then within the tool's own
  // (the scans' cells and samples bounded so that the pre-processing ends within hours)
  using ohrp::cli::InRange;
  using ohrp::cli::Plausible;
  app.add_option("--margin", o.margin, "[m] online stop distance, written to the file")
      ->check(Plausible("clearance"));
  app.add_option("--clearance", o.clearance, "[m] extra distance pruned pairs keep in the samples")
      ->check(Plausible("clearance"));
  app.add_option("--samples", o.samples, "postures sampled within the limits")
      ->check(Plausible("count"))->check(InRange(1, 100000000));
  app.add_option("--coarse", o.coarse, "cells of a joint's range in the coarse scan")
      ->check(Plausible("count"))->check(InRange(2, 1000));
  app.add_option("--fine", o.fine, "sub-cells of a boundary cell in the fine scan")
      ->check(Plausible("count"))->check(InRange(1, 1000));
  app.add_option("--cell-samples", o.cell_samples, "cheap samples per cell of a safe-range scan before its proof")
      ->check(Plausible("count"))->check(InRange(2, 1000000));
  app.add_option("--verify", o.verify,
                 "postures of the independent check of the proofs, within the final ranges (0: "
                 "none)")
      ->check(Plausible("count"))->check(InRange(0, 100000000));
  app.add_option("--proof-budget", o.proof_budget,
                 "boxes one proof may measure (branch and bound); a pair not proven within it "
                 "stays online")
      ->check(Plausible("count"))->check(InRange(1, 100000000));
  app.add_option("--min-range-share", o.min_range_share,
                 "smallest share of a joint's range a safe range may keep")
      ->check(Plausible("fraction"));
  app.add_option("--range-joints", range_joints,
                 "joints that may get a safe range (names, comma-separated); default: all")
      ->delimiter(',');
  app.add_option("--reference", reference,
                 "a keyframe of the model: the posture the safe ranges must contain; default: zero");
  app.add_option("--seed", o.seed, "random seed (the same seed gives the same file)")
      ->check(InRange(0, 18446744073709551615.0));
  app.add_flag("--quiet", quiet, "no progress on stderr");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  // the model and its geometry: any problem is the user's, exit 2 before anything runs
  std::string error;
  auto scene = ohrp::model::Scene::Load(model, &error);
  ohrp::model::RobotMap robot;
  ohrp::collision::RobotGeometry geometry;
  if (!scene || !ohrp::model::MapRobot(scene->m(), &robot, &error) ||
      !ohrp::collision::GeometryFromModel(scene->m(), robot, &geometry, &error)) {
    std::fprintf(stderr, "ohrp_selfcollision: %s: %s\n", model.c_str(), error.c_str());
    return 2;
  }
  // the hinges' limits are numbers of the model: the scans cut them into cells, so a range of
  // 1e300 rad would make every cell absurd
  for (const auto& j : robot.joints) {
    if (scene->m()->jnt_type[j.joint_id] != mjJNT_HINGE) continue;
    const size_t k = static_cast<size_t>(&j - robot.joints.data());
    for (const double q : {geometry.q_min[k], geometry.q_max[k]}) {
      const std::string e = ohrp::cli::CheckPlausible("angle", q, model + ": joint " + j.name + " limit");
      if (!e.empty()) {
        std::fprintf(stderr, "ohrp_selfcollision: %s\n", e.c_str());
        return 2;
      }
    }
  }

  // the joints named for safe ranges
  for (const std::string& name : range_joints) {
    const int id = ohrp::collision::FindJoint(geometry, name);
    if (id < 0) {
      std::fprintf(stderr, "ohrp_selfcollision: --range-joints: no joint '%s' in %s\n",
                   name.c_str(), model.c_str());
      return 2;
    }
    o.range_joints.push_back(id);
  }

  // the reference posture: a keyframe's joint angles
  if (!reference.empty()) {
    const int key = mj_name2id(scene->m(), mjOBJ_KEY, reference.c_str());
    if (key < 0) {
      std::fprintf(stderr, "ohrp_selfcollision: --reference: no keyframe '%s' in %s\n",
                   reference.c_str(), model.c_str());
      return 2;
    }
    // actuated and passive joints
    o.reference.assign(ohrp::collision::NumJoints(geometry), 0.0);
    ohrp::collision::PostureFromQpos(robot, scene->m()->key_qpos + key * scene->m()->nq, o.reference);
    const size_t na = robot.joints.size();
    for (size_t k = 0; k < o.reference.size(); ++k) {
      // a number of the model: the scans find its cell by division
      const int jid = k < na ? robot.joints[k].joint_id : robot.passive[k - na].joint_id;
      if (scene->m()->jnt_type[jid] != mjJNT_HINGE) continue;
      const std::string e = ohrp::cli::CheckPlausible(
          "angle", o.reference[k],
          model + ": keyframe " + reference + ": joint " + ohrp::collision::JointName(geometry, static_cast<int>(k)));
      if (!e.empty()) {
        std::fprintf(stderr, "ohrp_selfcollision: %s\n", e.c_str());
        return 2;
      }
    }
  }

  // the pre-processing, with progress on stderr
  if (!quiet) o.progress = [](const std::string& s) { std::fprintf(stderr, "\r%-78s%s", s.c_str(), s.empty() ? "\r" : ""); };
  const auto t0 = std::chrono::steady_clock::now();
  PruneResult r = ohrp::collision::Prune(geometry, o);
  r.file.dynamics = ohrp::collision::JointDynamicsFromModel(scene->m(), robot);  // the guard's braking
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // the file and the report
  if (!ohrp::collision::WriteSelfCollisionFile(out, r.file, &error)) {
    std::fprintf(stderr, "ohrp_selfcollision: %s\n", error.c_str());
    return 2;
  }
  const std::string text = Report(r, seconds);
  if (report.empty()) {
    std::fputs(text.c_str(), stdout);
  } else if (!(std::ofstream(report) << text)) {
    std::fprintf(stderr, "ohrp_selfcollision: %s: cannot write the report\n", report.c_str());
    return 2;
  }
  return 0;
}
