// collision::IncrementalCheck against the full check it stands for: on random walks through the
// joint limits of HRP-1S and of random trees of links (hinges about random axes through
// anchors off the link origins, boxes, capsules, cylinders and spheres), with cutoffs of 0 (sim_host's effect) and of a guard's margin, pair subsets that
// change from check to check (the guard's safe ranges) and jumps out and back (the guard's
// posture a period ahead): every pair within the cutoff has exactly the full check's distance,
// the closest pair and its distance are the full check's, every skipped pair's value is a
// lower bound of its true distance above the cutoff, and some pairs are skipped. Also: a
// non-finite angle makes every pair measured again; the reach bound holds for each link.
#include "collision/incremental_check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "collision/from_mjcf.h"
#include "robot_model/model.h"

namespace ohrp::collision {
namespace {

RobotGeometry Hrp1s() {
  RobotGeometry g;
  std::string error;
  mjModel* m = mj_loadXML((std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml").c_str(),
                          nullptr, nullptr, 0);
  EXPECT_TRUE(m);
  if (!m) return g;
  model::RobotMap robot;
  EXPECT_TRUE(model::MapRobot(m, &robot, &error) && GeometryFromModel(m, robot, &g, &error)) << error;
  mj_deleteModel(m);
  return g;
}

// a tree of `n` links hanging from a base, each on a hinge about a random axis through an
// anchor off its origin (with `slides`, every third link on a slide along a random axis, limits
// -0.1..0.15 m), with one or two random shapes
RobotGeometry RandomTree(int n, unsigned seed, bool slides = false) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto vec = [&](double scale) -> Eigen::Vector3d { return Eigen::Vector3d(u(rng), u(rng), u(rng)) * scale; };
  const auto rot = [&]() -> Eigen::Quaterniond { return Eigen::Quaterniond(Eigen::AngleAxisd(3 * u(rng), vec(1).normalized())); };
  RobotGeometry g;
  g.name = "tree" + std::to_string(seed) + (slides ? "_slides" : "");
  Link base;
  base.name = "base";
  Shape s;
  s.type = ShapeType::kBox;
  s.size = {0.1, 0.1, 0.1};
  base.shapes = {s};
  g.links = {base};
  for (int l = 1; l <= n; ++l) {
    Link k;
    k.name = "link" + std::to_string(l);
    k.parent = static_cast<int>((0.5 + 0.5 * u(rng)) * l) % l;  // any earlier link
    k.p_PL = vec(0.15);
    k.q_PL = rot();
    k.joint = l - 1;
    k.slide = slides && l % 3 == 0;
    k.axis_L = vec(1).normalized();
    k.anchor_L = k.slide ? Eigen::Vector3d::Zero() : vec(0.05);
    for (int c = 0; c < 1 + (u(rng) > 0); ++c) {
      Shape t;
      t.type = std::array{ShapeType::kBox, ShapeType::kCapsule, ShapeType::kCylinder,
                          ShapeType::kSphere}[static_cast<int>(2 + 2 * u(rng)) % 4];
      t.size = Eigen::Vector3d(0.02 + 0.03 * (1 + u(rng)), 0.02 + 0.05 * (1 + u(rng)),
                               0.02 + 0.03 * (1 + u(rng)));
      t.p_LS = vec(0.08);
      t.q_LS = rot();
      k.shapes.push_back(t);
    }
    g.links.push_back(k);
    g.joint_names.push_back("j" + std::to_string(l));
    g.q_min.push_back(k.slide ? -0.1 : -2.5);
    g.q_max.push_back(k.slide ? 0.15 : 2.5);
  }
  std::string why = Validate(g);
  EXPECT_TRUE(why.empty()) << why;
  return g;
}

std::vector<RobotGeometry> Robots() {
  return {Hrp1s(), RandomTree(12, 1), RandomTree(20, 2), RandomTree(18, 3, /*slides=*/true)};
}

// the walk: steps from 0.1 mrad to 0.3 rad per joint (some checks move nothing noticeable and
// some jump), every third check a jump a "period" ahead checked in between, subsets of pairs
void Walk(const RobotGeometry& g, double cutoff, unsigned seed) {
  std::string error;
  auto fast = SelfCollision::Create(g, &error);
  auto full = SelfCollision::Create(g, &error);
  ASSERT_TRUE(fast && full) << error;
  const std::vector<LinkPair> pairs = NonAdjacentPairs(g);
  IncrementalCheck check(fast.get(), pairs);
  const size_t nj = g.joint_names.size();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> q(nj), ahead(nj), all(pairs.size());
  for (size_t j = 0; j < nj; ++j) q[j] = 0.5 * (g.q_min[j] + g.q_max[j]);
  std::vector<int> which;
  long within = 0, checks = 0;
  const auto compare = [&](const std::vector<double>& at, const std::vector<int>& subset,
                           const std::string& what) {
    check.MoveTo(at);
    const CheckResult r = check.Check(subset, cutoff);
    full->SetPose(at);
    full->Check(pairs, cutoff, all);
    double min = INFINITY;
    int closest = -1;
    for (int i : subset) {
      if (all[i] <= cutoff) {
        ++within;
        ASSERT_TRUE(check.measured_now(i)) << what;
        ASSERT_EQ(check.distance(i), all[i]) << what << ": pair " << i;
      } else {
        // a lower bound of the true distance (the full check's value is the gap or a lower
        // bound of it above the cutoff, so only the measured value can be compared exactly)
        ASSERT_GT(check.distance(i), cutoff) << what << ": pair " << i;
        if (check.measured_now(i)) {
          ASSERT_EQ(check.distance(i), all[i]) << what;
        }
      }
      if (all[i] < min) min = all[i], closest = all[i] <= cutoff ? i : -1;
    }
    ASSERT_EQ(r.closest, closest) << what;
    if (closest >= 0) {
      ASSERT_EQ(r.min_distance, min) << what;
    } else {
      ASSERT_GT(r.min_distance, cutoff) << what;
    }
    ++checks;
  };
#ifdef OHRP_SANITIZE
  constexpr int kChecks = 300;  // -O1 with ASan: the memory check, Release runs the 1500
#else
  constexpr int kChecks = 1500;
#endif
  for (int k = 0; k < kChecks; ++k) {
    const double step = std::pow(10.0, -4 + 3.5 * (0.5 + 0.5 * u(rng)));  // 1e-4 .. 0.3 rad
    for (size_t j = 0; j < nj; ++j) q[j] = std::clamp(q[j] + step * u(rng), g.q_min[j], g.q_max[j]);
    which.clear();
    for (int i = 0; i < static_cast<int>(pairs.size()); ++i)
      if (k % 4 == 0 || u(rng) > -0.5) which.push_back(i);  // a changing subset, all at times
    compare(q, which, "check " + std::to_string(k));
    if (k % 3 == 0) {
      for (size_t j = 0; j < nj; ++j) ahead[j] = std::clamp(q[j] + 0.05 * u(rng), g.q_min[j], g.q_max[j]);
      compare(ahead, which, "ahead of check " + std::to_string(k));
    }
  }
  const double share = static_cast<double>(check.skipped()) / (check.skipped() + check.measured());
  std::printf("%zu links, cutoff %.3f m: %ld checks, %ld pair distances within the cutoff, %.1f %% "
              "of the pair checks answered by the bound\n",
              g.links.size(), cutoff, checks, within, 100 * share);
  EXPECT_GT(within, 50);        // the walk does come close
  EXPECT_GT(check.skipped(), 0u);  // and the bound does skip
}

TEST(IncrementalCheck, AnswersTheFullCheckWithinTheCutoff) {
  for (const RobotGeometry& g : Robots()) {
    SCOPED_TRACE(g.name);
    Walk(g, 0.0, 3);
    Walk(g, 0.03, 5);
  }
}

TEST(IncrementalCheck, NonFiniteAngleMeasuresEveryPairAgain) {
  const RobotGeometry g = Hrp1s();
  std::string error;
  auto checker = SelfCollision::Create(g, &error);
  IncrementalCheck check(checker.get(), NonAdjacentPairs(g));
  std::vector<double> q(g.joint_names.size(), 0.0);
  check.MoveTo(q);
  check.CheckAll(0.0);
  EXPECT_EQ(check.measured(), check.pairs().size());  // the first check measures everything
  check.MoveTo(q);
  check.CheckAll(0.0);
  const uint64_t still = check.measured() - check.pairs().size();
  EXPECT_LT(still, check.pairs().size() / 4);  // not moved: only pairs near contact again
  q[3] = NAN;
  check.MoveTo(q);
  q[3] = 0.0;
  check.MoveTo(q);  // back from a posture without a bound
  const uint64_t before = check.measured();
  check.CheckAll(0.0);
  EXPECT_EQ(check.measured() - before, check.pairs().size());
}

// every point of a link's shapes moves at most sum_j |dq_j| r_jl: the links' shape centres and
// box corners, moved by random joint steps, against LinkReach
TEST(IncrementalCheck, LinkReachBoundsEveryLinksTravel) {
  for (const RobotGeometry& g : Robots()) {
    const auto reach = LinkReach(g);
    std::string error;
    auto a = SelfCollision::Create(g, &error);
    ASSERT_TRUE(a) << error;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    const size_t nj = g.joint_names.size();
    std::vector<double> q0(nj), q1(nj);
    for (int k = 0; k < 300; ++k) {
      for (size_t j = 0; j < nj; ++j) {
        q0[j] = g.q_min[j] + (0.5 + 0.5 * u(rng)) * (g.q_max[j] - g.q_min[j]);
        q1[j] = std::clamp(q0[j] + 0.2 * u(rng), g.q_min[j], g.q_max[j]);
      }
      std::vector<Eigen::Isometry3d> X0(g.links.size());
      a->SetPose(q0);
      for (size_t l = 0; l < g.links.size(); ++l) X0[l] = a->LinkPose(static_cast<int>(l));
      a->SetPose(q1);
      for (size_t l = 0; l < g.links.size(); ++l) {
        double bound = 0;
        for (const auto& [joint, r] : reach[l]) bound += std::abs(q1[joint] - q0[joint]) * r;
        for (const Shape& s : g.links[l].shapes) {
          std::vector<Eigen::Vector3d> points = {s.p_LS};
          if (s.type == ShapeType::kBox)
            for (int c = 0; c < 8; ++c)
              points.push_back(s.p_LS + s.q_LS * Eigen::Vector3d((c & 1 ? 1 : -1) * s.size[0],
                                                                (c & 2 ? 1 : -1) * s.size[1],
                                                                (c & 4 ? 1 : -1) * s.size[2]));
          for (const auto& p : points) {
            const double moved = (a->LinkPose(static_cast<int>(l)) * p - X0[l] * p).norm();
            ASSERT_LE(moved, bound + 1e-12) << g.name << ": link " << g.links[l].name;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace ohrp::collision
