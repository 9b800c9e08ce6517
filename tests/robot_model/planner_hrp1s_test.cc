// The arm planner on HRP-1S with the shipped self-collision file (the online guard's pairs,
// margin and safe ranges): seeded random goals of the left arm planned, every planned path
// re-checked by a plain checker (collision::SelfCollision, no planner code) at four times the
// planner's resolution; a goal in self-collision refused naming the pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "collision/pair_file.h"
#include "planning/arm_planner.h"

namespace ohrp::planning {
namespace {

const std::vector<std::string> kLeftArm = {"LARM_SHOULDER_P", "LARM_SHOULDER_R", "LARM_SHOULDER_Y",
                                           "LARM_ELBOW", "LARM_WRIST_Y", "LARM_WRIST_P",
                                           "LARM_WRIST_R"};
constexpr double kClearance = 0.01;  // [m]

struct Hrp1s {
  collision::SelfCollisionFile file;
  JointGroup group;
  std::unique_ptr<PostureCheck> check;
  std::unique_ptr<collision::SelfCollision> plain;
  std::vector<double> zero;
};

Hrp1s Load() {
  Hrp1s h;
  std::string error;
  EXPECT_TRUE(collision::ReadSelfCollisionFile(OHRP_SOURCE_DIR "/mjcf/hrp1s/selfcollision.yaml",
                                               &h.file, &error)) << error;
  EXPECT_TRUE(MakeJointGroup(h.file.robot, kLeftArm, &h.group, &error)) << error;
  h.check = PostureCheck::Create(h.file, {}, h.group, kClearance, &error);
  EXPECT_TRUE(h.check) << error;
  h.plain = collision::SelfCollision::Create(h.file.robot, &error);
  h.zero.assign(collision::NumJoints(h.file.robot), 0.0);
  return h;
}

// the smallest distance of the guard's pairs with a left-arm link at posture q, by the plain
// checker: online, and the pairs of each safe range q leaves (exact below 5 cm)
double GuardDistance(Hrp1s& h, const std::vector<double>& q, collision::LinkPair* closest) {
  h.plain->SetPose(q);
  double d = INFINITY;
  auto visit = [&](const collision::LinkPair& p) {
    const auto& links = h.file.robot.links;
    if (links[p.a].name.rfind("LARM", 0) != 0 && links[p.b].name.rfind("LARM", 0) != 0) return;
    const double x = h.plain->Distance(p.a, p.b, 0.05);
    if (x < d) d = x, *closest = p;
  };
  for (const auto& p : h.file.online) visit(p);
  for (const auto& r : h.file.ranges)
    if (q[r.joint] < r.lo || q[r.joint] > r.hi)
      for (const auto& p : r.pairs) visit(p);
  return d;
}

std::vector<double> RandomArm(const JointGroup& g, std::mt19937& rng) {
  std::vector<double> v(g.size());
  for (int j = 0; j < g.size(); ++j) v[j] = std::uniform_real_distribution<double>(g.lo[j], g.hi[j])(rng);
  return v;
}

TEST(PlannerHrp1sTest, RandomLeftArmGoalsPlannedAndIndependentlyClear) {
  Hrp1s h = Load();
  ASSERT_TRUE(h.check->Evaluate(h.zero).valid) << h.check->Describe(h.check->Evaluate(h.zero));
  std::mt19937 rng(21);
  std::vector<double> q = h.zero;
  int planned = 0;
  std::vector<double> times;
  while (planned < 6) {
    const std::vector<double> goal = RandomArm(h.group, rng);
    SetGroupValues(h.group, goal, q);
    if (!h.check->Valid(q)) continue;
    PlanOptions o;
    o.seed = 1 + planned;
    const PlanResult r = PlanJoints(*h.check, h.zero, goal, o);
    ASSERT_TRUE(r.solved) << r.reason;
    times.push_back(r.plan_time + r.simplify_time);
    // the path at a quarter of the resolution, by the plain checker: never below the margin
    // (the planner kept margin + clearance at its own resolution)
    double closest = INFINITY;
    std::vector<double> p = h.zero, v(h.group.size());
    for (size_t k = 0; k + 1 < r.waypoints.size(); ++k) {
      const double len = PathLength({r.waypoints[k], r.waypoints[k + 1]});
      const int steps = std::max(1, static_cast<int>(std::ceil(4 * len / o.resolution)));
      for (int i = 0; i <= steps; ++i) {
        for (int j = 0; j < h.group.size(); ++j)
          v[j] = r.waypoints[k][j] + (r.waypoints[k + 1][j] - r.waypoints[k][j]) * i / steps;
        SetGroupValues(h.group, v, p);
        collision::LinkPair pair;
        closest = std::min(closest, GuardDistance(h, p, &pair));
      }
    }
    EXPECT_GE(closest, h.file.margin) << "goal " << planned;
    // the planner's closest pair, at its coarser resolution, within a millimetre of it
    EXPECT_NEAR(r.closest.distance, std::min(closest, 0.05), 1e-3);
    std::printf("goal %d: plan %.1f ms + simplify %.1f ms, length %.3f rad (raw %.3f), "
                "%zu waypoints, clearance %.1f mm (plain check %.1f mm, %s / %s), %ld checks\n",
                planned, 1e3 * r.plan_time, 1e3 * r.simplify_time, r.length, r.raw_length,
                r.waypoints.size(), 1e3 * r.closest.distance, 1e3 * closest, r.closest.a.c_str(),
                r.closest.b.c_str(), r.evaluations);
    ++planned;
  }
  std::sort(times.begin(), times.end());
  std::printf("median planning time %.1f ms\n", 1e3 * times[times.size() / 2]);
}

TEST(PlannerHrp1sTest, GoalInSelfCollisionRefusedNamingThePair) {
  Hrp1s h = Load();
  std::mt19937 rng(4);
  std::vector<double> q = h.zero, goal;
  collision::LinkPair pair;
  // a random arm posture the plain checker finds touching the body (an arm link inside another)
  for (int i = 0; i < 100000; ++i) {
    goal = RandomArm(h.group, rng);
    SetGroupValues(h.group, goal, q);
    if (GuardDistance(h, q, &pair) < -0.005) break;
  }
  ASSERT_LT(GuardDistance(h, q, &pair), -0.005);
  const PlanResult r = PlanJoints(*h.check, h.zero, goal, {});
  EXPECT_FALSE(r.solved);
  EXPECT_NE(r.reason.find("goal in collision: "), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find(" / "), std::string::npos) << r.reason;
  const Verdict v = h.check->Evaluate(q);
  EXPECT_LT(v.distance, -0.005);
  std::printf("%s\n", r.reason.c_str());
}

TEST(PlannerHrp1sTest, SceneBoxKeptClearOfTheArm) {
  Hrp1s h = Load();
  // a box in front of the robot at the height of the hand's sweep: the arm, lifted forward to
  // the other side, must go round it; the box against the arm's links by the plain checker
  SceneBox box;
  box.name = "box";
  box.half_size = {0.05, 0.05, 0.05};
  std::string error;
  // the zero posture's left hand, and a box placed where the straight line to a raised arm passes
  std::vector<double> goal(h.group.size(), 0.0);
  goal[0] = -1.5;  // shoulder pitch: the arm forward
  std::vector<double> q = h.zero;
  SetGroupValues(h.group, std::vector<double>(h.group.size(), 0.0), q);
  // half way along the straight motion, the wrist's position
  std::vector<double> mid = goal;
  mid[0] = -0.75;
  SetGroupValues(h.group, mid, q);
  h.plain->SetPose(q);
  const int wrist = collision::FindLink(h.file.robot, "LARM_WRIST_R");
  ASSERT_GE(wrist, 0);
  box.X_BO.translation() = h.plain->LinkPose(wrist).translation();
  auto check = PostureCheck::Create(h.file, {box}, h.group, kClearance, &error);
  ASSERT_TRUE(check) << error;
  // the straight line is blocked by the box
  const Verdict straight = ClosestAlong(*check, h.zero, {std::vector<double>(7, 0.0), goal}, 0.01);
  ASSERT_FALSE(straight.valid);
  EXPECT_EQ(straight.b, "scene:box");
  PlanOptions o;
  o.seed = 2;
  const PlanResult r = PlanJoints(*check, h.zero, goal, o);
  ASSERT_TRUE(r.solved) << r.reason;
  EXPECT_GE(r.closest.distance, check->required());
  std::printf("round the box at (%.3f, %.3f, %.3f): plan %.1f ms + %.1f ms, length %.3f rad "
              "(straight 1.500), clearance %.1f mm (%s / %s)\n", box.X_BO.translation().x(),
              box.X_BO.translation().y(), box.X_BO.translation().z(), 1e3 * r.plan_time,
              1e3 * r.simplify_time, r.length, 1e3 * r.closest.distance, r.closest.a.c_str(),
              r.closest.b.c_str());
}

}  // namespace
}  // namespace ohrp::planning
