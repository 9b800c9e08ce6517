// The arm planner (robot_model/planning) against closed forms: a point (a small sphere on two
// slides) in a square with a wall, whose shortest path around the wall's end is known; starts
// and goals refused with the reason; the same seed, the same path; the validity check against
// the closed-form point-box distance on random postures; the timing within its limits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "planning/arm_planner.h"
#include "planning/timed_path.h"

namespace ohrp::planning {
namespace {

constexpr double kRadius = 0.03;     // the point's sphere [m]
constexpr double kClearance = 0.02;  // the planner's clearance [m] (margin 0)
constexpr double kWallHalfWidth = 0.05, kWallTop = 0.5;  // the wall: x in [-w, w], y in [-1, top]

// a sphere on an X slide then a Y slide, in the square [-1, 1]^2
collision::SelfCollisionFile PointRobot() {
  collision::SelfCollisionFile f;
  f.margin = 0;
  collision::RobotGeometry& r = f.robot;
  r.name = "point";
  r.joint_names = {"X", "Y"};
  r.q_min = {-1, -1};
  r.q_max = {1, 1};
  collision::Link base;
  base.name = "base";
  collision::Link x;
  x.name = "point@X";
  x.parent = 0;
  x.joint = 0;
  x.slide = true;
  x.joint_only = true;
  x.axis_L = Eigen::Vector3d::UnitX();
  collision::Link y;
  y.name = "point";
  y.parent = 1;
  y.joint = 1;
  y.slide = true;
  y.axis_L = Eigen::Vector3d::UnitY();
  collision::Shape s;
  s.type = collision::ShapeType::kSphere;
  s.size = {kRadius, 0, 0};
  y.shapes.push_back(s);
  r.links = {base, x, y};
  return f;
}

std::vector<SceneBox> Wall() {
  SceneBox wall;
  wall.name = "wall";
  wall.half_size = {kWallHalfWidth, 0.5 * (kWallTop + 1), 0.2};
  wall.X_BO.translation() = Eigen::Vector3d(0, 0.5 * (kWallTop - 1), 0);
  return {wall};
}

std::unique_ptr<PostureCheck> Check() {
  const collision::SelfCollisionFile f = PointRobot();
  JointGroup g;
  std::string error;
  EXPECT_TRUE(MakeJointGroup(f.robot, {"X", "Y"}, &g, &error)) << error;
  auto c = PostureCheck::Create(f, Wall(), g, kClearance, &error);
  EXPECT_TRUE(c) << error;
  return c;
}

// the shortest path from (-a, 0) to (a, 0) around the wall's top, kept r = radius + clearance
// away: tangent to the circle of radius r about the corner (-w, top), the arc round it, the
// wall's width, and the same on the other side
double ShortestAroundWall(double a) {
  const double r = kRadius + kClearance;
  const double dx = a - kWallHalfWidth, dy = kWallTop, d = std::hypot(dx, dy);
  const double tangent = std::sqrt(d * d - r * r);
  const double phi = std::atan2(dy, dx) + std::asin(r / d);  // the tangent's heading
  return 2 * (tangent + r * phi) + 2 * kWallHalfWidth;
}

TEST(PlannerTest, PathAroundWallWithinTenPercentOfTheShortest) {
  auto check = Check();
  const std::vector<double> start = {-0.6, 0}, goal = {0.6, 0};
  PlanOptions o;
  o.seed = 3;
  const PlanResult r = PlanJoints(*check, start, goal, o);
  ASSERT_TRUE(r.solved) << r.reason;
  const double shortest = ShortestAroundWall(0.6);  // 1.664 m
  // no valid path is shorter (less what the 1 cm checks may cut off a corner), simplification
  // brings it within 10 %
  EXPECT_GT(r.length, 0.995 * shortest);
  EXPECT_LT(r.length, 1.10 * shortest) << "raw " << r.raw_length;
  EXPECT_LE(r.length, r.raw_length + 1e-12);
  EXPECT_TRUE(r.closest.valid);
  EXPECT_GE(r.closest.distance, kClearance);
  EXPECT_EQ(r.waypoints.front(), start);
  EXPECT_EQ(r.waypoints.back(), goal);
  std::printf("wall: shortest %.4f, raw %.4f, simplified %.4f, clearance %.4f m, %zu waypoints, "
              "plan %.1f ms, simplify %.1f ms, %ld checks\n",
              shortest, r.raw_length, r.length, r.closest.distance, r.waypoints.size(),
              1e3 * r.plan_time, 1e3 * r.simplify_time, r.evaluations);
}

TEST(PlannerTest, SameSeedSamePath) {
  auto check = Check();
  const std::vector<double> start = {-0.6, 0}, goal = {0.6, -0.2};
  PlanOptions o;
  o.seed = 11;
  const PlanResult a = PlanJoints(*check, start, goal, o);
  const PlanResult b = PlanJoints(*check, start, goal, o);
  ASSERT_TRUE(a.solved && b.solved);
  EXPECT_EQ(a.waypoints, b.waypoints);
  EXPECT_EQ(a.raw_length, b.raw_length);
  o.seed = 12;
  const PlanResult c = PlanJoints(*check, start, goal, o);
  ASSERT_TRUE(c.solved);
  EXPECT_NE(a.raw_length, c.raw_length) << "another seed, another tree";
}

TEST(PlannerTest, GoalInsideTheWallRefusedWithTheReason) {
  auto check = Check();
  const PlanResult r = PlanJoints(*check, std::vector<double>{-0.6, 0}, std::vector<double>{0.0, 0}, {});
  EXPECT_FALSE(r.solved);
  EXPECT_NE(r.reason.find("goal in collision"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("scene:wall"), std::string::npos) << r.reason;
  // beside the wall, closer than the clearance: refused too
  const double x = kWallHalfWidth + kRadius + 0.5 * kClearance;
  const PlanResult near = PlanJoints(*check, std::vector<double>{-0.6, 0}, std::vector<double>{x, 0}, {});
  EXPECT_FALSE(near.solved);
  EXPECT_NE(near.reason.find("goal in collision"), std::string::npos) << near.reason;
}

TEST(PlannerTest, StartInCollisionRefused) {
  auto check = Check();
  const PlanResult r = PlanJoints(*check, std::vector<double>{0.02, -0.5}, std::vector<double>{0.6, 0}, {});
  EXPECT_FALSE(r.solved);
  EXPECT_NE(r.reason.find("start in collision"), std::string::npos) << r.reason;
}

TEST(PlannerTest, GoalOutsideTheLimitsRefused) {
  auto check = Check();
  const PlanResult r = PlanJoints(*check, std::vector<double>{-0.6, 0}, std::vector<double>{0.6, 1.5}, {});
  EXPECT_FALSE(r.solved);
  EXPECT_NE(r.reason.find("Y = 1.5000 is outside its limits [-1.0000, 1.0000] by 0.5000"),
            std::string::npos) << r.reason;
}

TEST(PlannerTest, NoPathWhenTheWallClosesTheSquare) {
  const collision::SelfCollisionFile f = PointRobot();
  JointGroup g;
  std::string error;
  ASSERT_TRUE(MakeJointGroup(f.robot, {"X", "Y"}, &g, &error));
  std::vector<SceneBox> wall = Wall();
  wall[0].half_size.y() = 1.2;  // y from -1.2 to 1.2: the square is cut in two
  wall[0].X_BO.translation().y() = 0;
  auto check = PostureCheck::Create(f, wall, g, kClearance, &error);
  ASSERT_TRUE(check);
  PlanOptions o;
  o.time_limit = 0.2;
  const PlanResult r = PlanJoints(*check, std::vector<double>{-0.6, 0}, std::vector<double>{0.6, 0}, o);
  EXPECT_FALSE(r.solved);
  EXPECT_NE(r.reason.find("no collision-free path"), std::string::npos) << r.reason;
}

// the distance of the sphere to the wall in closed form (the point to the box, less the radius)
double BruteDistance(double x, double y) {
  const double cy = 0.5 * (kWallTop - 1), hy = 0.5 * (kWallTop + 1);
  const double ex = std::max(0.0, std::abs(x) - kWallHalfWidth), ey = std::max(0.0, std::abs(y - cy) - hy);
  if (ex > 0 || ey > 0) return std::hypot(ex, ey) - kRadius;
  return -std::min(kWallHalfWidth - std::abs(x), hy - std::abs(y - cy)) - kRadius;
}

TEST(PlannerTest, ValidityAgreesWithTheClosedFormOnRandomPostures) {
  auto check = Check();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int valid = 0, invalid = 0;
  for (int i = 0; i < 2000; ++i) {
    const std::vector<double> q = {u(rng), u(rng)};
    const double brute = BruteDistance(q[0], q[1]);
    if (std::abs(brute - check->required()) < 1e-6) continue;  // on the boundary
    const bool expected = brute >= check->required();
    ASSERT_EQ(check->Valid(q), expected) << q[0] << ", " << q[1] << ": " << brute;
    const Verdict v = check->Evaluate(q);
    ASSERT_EQ(v.valid, expected);
    if (brute > 0 && brute < check->required() + 0.05) {
      ASSERT_NEAR(v.distance, brute, 1e-6);
    }
    if (brute < 0) {
      ASSERT_LT(v.distance, 0);
    }
    (expected ? valid : invalid)++;
  }
  EXPECT_GT(valid, 500);
  EXPECT_GT(invalid, 50);
}

TEST(TimedPathTest, OneSegmentHasTheTrapezoidsClosedFormDuration) {
  TimedPath p;
  std::string error;
  // 2 rad at 1 rad/s and 2 rad/s^2: 0.5 s up, 1.5 s cruising, 0.5 s down: 2.5 s
  ASSERT_TRUE(p.Build({{0.0}, {2.0}}, std::vector<double>{1.0}, std::vector<double>{2.0}, &error));
  EXPECT_NEAR(p.duration(), 2.0 / 1.0 + 1.0 / 2.0, 1e-12);
  // 0.2 rad: a triangle, 2 sqrt(0.2 / 2) s
  ASSERT_TRUE(p.Build({{0.0}, {0.2}}, std::vector<double>{1.0}, std::vector<double>{2.0}, &error));
  EXPECT_NEAR(p.duration(), 2 * std::sqrt(0.1), 1e-12);
  EXPECT_FALSE(p.Build({{0.0}, {0.2}}, std::vector<double>{0.0}, std::vector<double>{2.0}, &error));
}

// a right-angle corner for one joint pair, blended: 1 rad along x then 1 rad along y at 1 rad/s
// and 2 rad/s^2: the segments take 1 s each at full speed, the blends 0.5 s (start and end: 1
// rad/s from rest; the corner: 1 rad/s off in x and on in y), so 0.25 + 1 + 1 + 0.25 = 2.5 s;
// the corner is cut by |dV| b / 8 = 1 * 0.5 / 8 per joint, and passed at full speed
TEST(TimedPathTest, ABlendedCornerHasTheClosedFormsTimingAndCut) {
  TimedPath p;
  std::string error;
  const std::vector<double> v{1.0, 1.0}, a{2.0, 2.0};
  ASSERT_TRUE(p.Build({{0, 0}, {1, 0}, {1, 1}}, v, a, &error, true)) << error;
  ASSERT_TRUE(p.blended());
  EXPECT_NEAR(p.duration(), 2.5, 1e-12);
  EXPECT_NEAR(p.CornerCut(1), 0.5 / 8, 1e-12);
  double q[2], dq[2], ddq[2];
  p.Sample(1.25, q, dq, ddq);  // the corner's time: the parabola's middle
  EXPECT_NEAR(q[0], 1 - 0.5 / 8, 1e-12);
  EXPECT_NEAR(q[1], 0.5 / 8, 1e-12);
  EXPECT_NEAR(dq[0], 0.5, 1e-12);  // half way from (1, 0) to (0, 1) rad/s: never stopping
  EXPECT_NEAR(dq[1], 0.5, 1e-12);
  EXPECT_NEAR(ddq[0], -2, 1e-12);
  EXPECT_NEAR(ddq[1], 2, 1e-12);
  // rest to rest stops there: two 1 rad trapezoids of 1.5 s
  ASSERT_TRUE(p.Build({{0, 0}, {1, 0}, {1, 1}}, v, a, &error, false));
  EXPECT_FALSE(p.blended());
  EXPECT_NEAR(p.duration(), 3.0, 1e-12);
}

// random blended paths: within the limits (sampled and by finite differences), the velocity
// continuous, from rest at the first waypoint to rest at the last, each inner waypoint passed
// within its corner cut, and never slower than rest to rest
TEST(TimedPathTest, BlendedNeverExceedsTheLimitsAndPassesNearTheWaypoints) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2), lim(0.3, 3);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 1 + trial % 7;
    std::vector<std::vector<double>> w(3 + trial % 5, std::vector<double>(n));
    for (auto& p : w)
      for (double& x : p) x = u(rng);
    std::vector<double> v(n), a(n);
    for (int j = 0; j < n; ++j) v[j] = lim(rng), a[j] = lim(rng);
    TimedPath p, stops;
    std::string error;
    ASSERT_TRUE(p.Build(w, v, a, &error, true)) << error;
    ASSERT_TRUE(stops.Build(w, v, a, &error, false)) << error;
    EXPECT_LE(p.duration(), stops.duration() * (1 + 1e-9)) << "trial " << trial;
    std::vector<double> q(n), dq(n), ddq(n), q_prev(n), dq_prev(n);
    std::vector<double> closest(w.size(), 1e9);  // each waypoint's nearest approach (max norm)
    const double dt = 1e-4;
    for (double t = 0; t <= p.duration() + dt; t += dt) {
      p.Sample(t, q.data(), dq.data(), ddq.data());
      for (int j = 0; j < n; ++j) {
        ASSERT_LE(std::abs(dq[j]), v[j] * (1 + 1e-9));
        ASSERT_LE(std::abs(ddq[j]), a[j] * (1 + 1e-9));
        if (t > 0) {
          ASSERT_LE(std::abs(q[j] - q_prev[j]) / dt, v[j] * (1 + 1e-6));
          ASSERT_LE(std::abs(dq[j] - dq_prev[j]) / dt, a[j] * (1 + 1e-6));
        }
      }
      for (size_t k = 0; k < w.size(); ++k) {
        double d = 0;
        for (int j = 0; j < n; ++j) d = std::max(d, std::abs(q[j] - w[k][j]));
        closest[k] = std::min(closest[k], d);
      }
      q_prev = q, dq_prev = dq;
    }
    for (size_t k = 1; k + 1 < w.size(); ++k)
      EXPECT_LE(closest[k], p.CornerCut(static_cast<int>(k)) + 1e-3) << "trial " << trial << ", waypoint " << k;
    p.Sample(p.duration(), q.data(), dq.data(), nullptr);
    for (int j = 0; j < n; ++j) {
      EXPECT_NEAR(q[j], w.back()[j], 1e-12);
      EXPECT_EQ(dq[j], 0);
    }
    p.Sample(0, q.data(), dq.data(), nullptr);
    for (int j = 0; j < n; ++j) {
      EXPECT_NEAR(q[j], w.front()[j], 1e-12);
      EXPECT_EQ(dq[j], 0);
    }
  }
}

TEST(TimedPathTest, NeverExceedsTheLimitsAndPassesTheWaypoints) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2, 2), lim(0.3, 3);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 1 + trial % 7;
    std::vector<std::vector<double>> w(2 + trial % 5, std::vector<double>(n));
    for (auto& p : w)
      for (double& x : p) x = u(rng);
    std::vector<double> v(n), a(n);
    for (int j = 0; j < n; ++j) v[j] = lim(rng), a[j] = lim(rng);
    TimedPath p;
    std::string error;
    ASSERT_TRUE(p.Build(w, v, a, &error)) << error;
    std::vector<double> q(n), dq(n), ddq(n), q_prev(n), dq_prev(n);
    const double dt = 1e-4;
    for (double t = 0; t <= p.duration() + dt; t += dt) {
      p.Sample(t, q.data(), dq.data(), ddq.data());
      for (int j = 0; j < n; ++j) {
        ASSERT_LE(std::abs(dq[j]), v[j] * (1 + 1e-9));
        ASSERT_LE(std::abs(ddq[j]), a[j] * (1 + 1e-9));
        if (t > 0) {  // the velocity is the position's derivative, within a step's acceleration
          ASSERT_LE(std::abs(q[j] - q_prev[j]) / dt, v[j] * (1 + 1e-6));
          ASSERT_LE(std::abs(dq[j] - dq_prev[j]) / dt, a[j] * (1 + 1e-6));
        }
      }
      q_prev = q, dq_prev = dq;
    }
    p.Sample(p.duration(), q.data(), dq.data(), nullptr);
    for (int j = 0; j < n; ++j) {
      EXPECT_DOUBLE_EQ(q[j], w.back()[j]);
      EXPECT_EQ(dq[j], 0);
    }
    p.Sample(0, q.data(), nullptr, nullptr);
    EXPECT_EQ(q, w.front());
  }
}

}  // namespace
}  // namespace ohrp::planning
