// The self-collision checker (robot_model/collision): distances and penetrations against closed
// forms, a link inside another, the links' poses against MuJoCo's, the pair list of HRP-1S, the
// broad phase, validation messages, the shipped file (current, read back, its mistakes).
#include "collision/self_collision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <random>

#include "collision/from_mjcf.h"
#include "collision/pair_file.h"
#include "common/scratch.h"
#include "robot_model/model.h"

namespace ohrp::collision {
namespace {

constexpr double kTol = 1e-6;  // [m] GJK's tolerance is 1e-6 of the shapes' scale

Shape Box(double hx, double hy, double hz) { Shape s; s.type = ShapeType::kBox; s.size = {hx, hy, hz}; return s; }
Shape Sphere(double r) { Shape s; s.type = ShapeType::kSphere; s.size = {r, 0, 0}; return s; }
Shape Cylinder(double r, double h) { Shape s; s.type = ShapeType::kCylinder; s.size = {r, h, 0}; return s; }
Shape Capsule(double r, double h) { Shape s; s.type = ShapeType::kCapsule; s.size = {r, h, 0}; return s; }

// two free-standing links, one shape each, at poses (p, q) in the base frame
std::unique_ptr<SelfCollision> TwoLinks(Shape a, const Eigen::Vector3d& p_a, Shape b,
                                        const Eigen::Vector3d& p_b,
                                        const Eigen::Quaterniond& q_a = Eigen::Quaterniond::Identity(),
                                        const Eigen::Quaterniond& q_b = Eigen::Quaterniond::Identity()) {
  RobotGeometry r;
  Link la, lb;
  la.name = "a";
  la.p_PL = p_a;
  la.q_PL = q_a;
  la.shapes = {a};
  lb.name = "b";
  lb.p_PL = p_b;
  lb.q_PL = q_b;
  lb.shapes = {b};
  r.links = {la, lb};
  std::string error;
  auto c = SelfCollision::Create(r, &error);
  EXPECT_TRUE(c) << error;
  return c;
}

// their distance
double Pair(Shape a, const Eigen::Vector3d& p_a, Shape b, const Eigen::Vector3d& p_b,
            const Eigen::Quaterniond& q_b = Eigen::Quaterniond::Identity()) {
  auto c = TwoLinks(a, p_a, b, p_b, Eigen::Quaterniond::Identity(), q_b);
  return c ? c->Distance(0, 1, INFINITY) : NAN;
}

Eigen::Quaterniond About(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

TEST(SelfCollisionDistance, GapsMatchClosedForms) {
  // boxes face to face, a sphere beside a cylinder's side and beyond its cap, crossed cylinders,
  // parallel capsules, a box turned 45 deg showing its edge to a cylinder
  EXPECT_NEAR(Pair(Box(0.1, 0.1, 0.1), {0, 0, 0}, Box(0.1, 0.2, 0.3), {0.35, 0.05, 0}), 0.15, kTol);
  EXPECT_NEAR(Pair(Cylinder(0.05, 0.1), {0, 0, 0}, Sphere(0.02), {0.2, 0, 0}), 0.13, kTol);
  EXPECT_NEAR(Pair(Cylinder(0.05, 0.1), {0, 0, 0}, Sphere(0.02), {0, 0, 0.25}), 0.13, kTol);
  EXPECT_NEAR(Pair(Cylinder(0.05, 0.1), {0, 0, 0}, Cylinder(0.05, 0.1), {0, 0.3, 0},
                   About(M_PI / 2, Eigen::Vector3d::UnitY())),
              0.2, kTol);
  EXPECT_NEAR(Pair(Capsule(0.03, 0.2), {0, 0, 0}, Capsule(0.02, 0.1), {0.1, 0, 0.05}), 0.05, kTol);
  EXPECT_NEAR(Pair(Cylinder(0.05, 0.1), {0.3, 0, 0}, Box(0.1, 0.1, 0.1), {0, 0, 0},
                   About(M_PI / 4, Eigen::Vector3d::UnitZ())),
              0.3 - 0.1 * std::sqrt(2.0) - 0.05, kTol);
  // a cylinder's rim against a box face: its axis tilted 30 deg from the vertical, its lowest
  // point h cos t + r sin t below its centre
  const double t = M_PI / 6, rim = 0.1 * std::cos(t) + 0.05 * std::sin(t);
  EXPECT_NEAR(Pair(Box(0.2, 0.2, 0.1), {0, 0, 0}, Cylinder(0.05, 0.1), {0, 0, 0.1 + rim + 0.02},
                   About(t, Eigen::Vector3d::UnitY())),
              0.02, kTol);
}

TEST(SelfCollisionDistance, PenetrationDepthIsExactForBoxesAndSpheres) {
  // overlapping boxes: the smallest push-out is along x, 3 cm
  EXPECT_NEAR(Pair(Box(0.1, 0.1, 0.1), {0, 0, 0}, Box(0.1, 0.1, 0.1), {0.17, 0.05, 0.01}), -0.03, kTol);
  // a turned box: the separating-axis depth
  const double d = Pair(Box(0.1, 0.1, 0.1), {0, 0, 0}, Box(0.1, 0.1, 0.1), {0.2, 0, 0},
                        About(M_PI / 4, Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(d, -(0.1 + 0.1 * std::sqrt(2.0) - 0.2), kTol);
  // spheres: radius sum minus the distance of the centres
  EXPECT_NEAR(Pair(Sphere(0.1), {0, 0, 0}, Sphere(0.1), {0.15, 0, 0}), -0.05, 1e-5);
  // a sphere in a cylinder's side: radius sum minus the distance from the axis
  EXPECT_NEAR(Pair(Cylinder(0.05, 0.2), {0, 0, 0}, Sphere(0.02), {0.06, 0, 0}), -0.01, 1e-5);
}

TEST(SelfCollisionDistance, LinkFullyInsideAnotherIsCaught) {
  // GJK sees the overlap; the depth is what pushes the small box out through the near face
  EXPECT_NEAR(Pair(Box(0.2, 0.2, 0.2), {0, 0, 0}, Box(0.01, 0.01, 0.01), {0.05, 0, 0}), -0.16, kTol);
  // curved shapes: a sphere at a cylinder's centre, a cylinder inside a capsule
  EXPECT_LT(Pair(Cylinder(0.1, 0.2), {0, 0, 0}, Sphere(0.01), {0, 0, 0}), -0.09);
  EXPECT_LT(Pair(Capsule(0.1, 0.3), {0, 0, 0}, Cylinder(0.02, 0.05), {0, 0, 0.1}), -0.09);
}

// HRP-1S's geometry from its MJCF
RobotGeometry Hrp1s(mjModel** m_out = nullptr) {
  std::string error;
  mjModel* m = mj_loadXML((std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml").c_str(),
                          nullptr, nullptr, 0);
  EXPECT_TRUE(m);
  model::RobotMap robot;
  RobotGeometry g;
  EXPECT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  EXPECT_TRUE(GeometryFromModel(m, robot, &g, &error)) << error;
  if (m_out) *m_out = m;
  else mj_deleteModel(m);
  return g;
}

TEST(SelfCollisionModel, Hrp1sHas30LinksAnd406NonAdjacentPairs) {
  const RobotGeometry g = Hrp1s();
  // 30 bodies (the paper's N = 29 counts the waist's two small joint links as one);
  // C(30, 2) - 29 parent-child pairs
  EXPECT_EQ(g.links.size(), 30u);
  EXPECT_EQ(NonAdjacentPairs(g).size(), 30u * 29 / 2 - 29);
}

TEST(SelfCollisionModel, LinkPosesMatchMujoco) {
  mjModel* m = nullptr;
  const RobotGeometry g = Hrp1s(&m);
  mjData* d = mj_makeData(m);
  std::string error;
  auto c = SelfCollision::Create(g, &error);
  ASSERT_TRUE(c) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error));
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    // a random posture, the base at the origin
    std::vector<double> q(g.joint_names.size());
    mju_copy(d->qpos, m->qpos0, m->nq);
    for (size_t j = 0; j < q.size(); ++j) {
      q[j] = std::uniform_real_distribution<double>(g.q_min[j], g.q_max[j])(rng);
      d->qpos[robot.joints[j].qpos_adr] = q[j];
    }
    d->qpos[0] = d->qpos[1] = d->qpos[2] = 0;
    mj_kinematics(m, d);
    c->SetPose(q);
    for (size_t l = 0; l < g.links.size(); ++l) {
      const int b = mj_name2id(m, mjOBJ_BODY, g.links[l].name.c_str());
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->xmat + 9 * b);
      EXPECT_LT((c->LinkPose(l).translation() - Eigen::Vector3d(d->xpos + 3 * b)).norm(), 1e-9);
      EXPECT_LT((c->LinkPose(l).linear() - R).norm(), 1e-9) << g.links[l].name;
    }
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}

// SetPoseOf (the guard's conservative advancement: one pair at many postures) places the
// pair's links exactly as SetPose does, whatever posture the other links were left in
TEST(SelfCollisionModel, SetPoseOfPlacesThePairAsSetPose) {
  const RobotGeometry g = Hrp1s();
  std::string error;
  auto full = SelfCollision::Create(g, &error), part = SelfCollision::Create(g, &error);
  ASSERT_TRUE(full && part) << error;
  const std::vector<LinkPair> pairs = NonAdjacentPairs(g);
  std::mt19937 rng(29);
  const auto posture = [&] {
    std::vector<double> q(g.joint_names.size());
    for (size_t j = 0; j < q.size(); ++j)
      q[j] = std::uniform_real_distribution<double>(g.q_min[j], g.q_max[j])(rng);
    return q;
  };
  int moved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const LinkPair p = pairs[rng() % pairs.size()];
    part->SetPose(posture());  // the other links somewhere else
    const std::vector<double> q = posture();
    full->SetPose(q);
    const Eigen::Vector3d before = part->LinkPose(p.a).translation();
    part->SetPoseOf(q, p.a, p.b);
    moved += (part->LinkPose(p.a).translation() - before).norm() > 1e-6;
    for (int l : {p.a, p.b}) {
      EXPECT_EQ((part->LinkPose(l).matrix() - full->LinkPose(l).matrix()).norm(), 0.0)
          << g.links[l].name;
    }
    EXPECT_EQ(part->Distance(p.a, p.b, 1.0), full->Distance(p.a, p.b, 1.0))
        << g.links[p.a].name << " / " << g.links[p.b].name;
  }
  EXPECT_GT(moved, 100);  // the postures differed: the test compared moved links
}

TEST(SelfCollisionCheck, FarPairsNeverReachGjk) {
  const RobotGeometry g = Hrp1s();
  std::string error;
  auto c = SelfCollision::Create(g, &error);
  ASSERT_TRUE(c);
  // the two hands hanging far apart at the zero posture: the broad phase answers
  const LinkPair hands{FindLink(g, "LARM_WRIST_R"), FindLink(g, "RARM_WRIST_R")};
  const CheckResult r = c->Check(std::span(&hands, 1), 0.01, {});
  EXPECT_EQ(r.narrow_queries, 0);
  EXPECT_EQ(r.closest, -1);
  EXPECT_GT(r.min_distance, 0.2);
  // the knees side by side (10 cm apart less their widths): GJK measures them
  const LinkPair knees{FindLink(g, "LLEG_KNEE"), FindLink(g, "RLEG_KNEE")};
  const CheckResult k = c->Check(std::span(&knees, 1), 0.1, {});
  EXPECT_GT(k.narrow_queries, 0);
  EXPECT_EQ(k.closest, 0);
  EXPECT_NEAR(k.min_distance, 0.18 - 0.1, kTol);
}

// Above the cutoff the broad phase may answer with any lower bound of the gap: the bounding
// spheres, or the gap of the shapes' projections on the line of their centres, which is tight
// for limbs side by side where the spheres of long shapes overlap.
TEST(SelfCollisionCheck, BroadPhaseBoundsAreLowerBounds) {
  // two parallel upright capsules (radius 3 cm, half-length 20 cm) 20 cm apart: their spheres
  // (23 cm) overlap, the gap is 14 cm, and the line of centres finds it without GJK
  auto limbs = TwoLinks(Capsule(0.03, 0.2), {0, 0, 0}, Capsule(0.03, 0.2), {0.2, 0, 0});
  ASSERT_TRUE(limbs);
  const LinkPair both{0, 1};
  const CheckResult r = limbs->Check(std::span(&both, 1), 0.05, {});
  EXPECT_EQ(r.narrow_queries, 0);
  EXPECT_EQ(r.closest, -1);
  EXPECT_NEAR(r.min_distance, 0.14, 1e-12);
  // random shapes, sizes, poses: whatever the broad phase answers above a cutoff is at most the
  // gap GJK measures (no cutoff), and within the cutoff it is the measured gap itself
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  auto shape = [&](int kind) {
    const double r = 0.01 + 0.05 * u(rng), h = 0.01 + 0.2 * u(rng);
    switch (kind) {
      case 0: return Box(r, h, 0.01 + 0.1 * u(rng));
      case 1: return Capsule(r, h);
      case 2: return Cylinder(r, h);
      default: return Sphere(r);
    }
  };
  auto rotation = [&] {
    return Eigen::Quaterniond(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
  };
  int bounded = 0;
  for (int i = 0; i < 4000; ++i) {
    const Shape a = shape(i % 4), b = shape((i / 4) % 4);
    const Eigen::Vector3d p(0.6 * u(rng) - 0.3, 0.6 * u(rng) - 0.3, 0.6 * u(rng) - 0.3);
    auto c = TwoLinks(a, {0, 0, 0}, b, p, rotation(), rotation());
    ASSERT_TRUE(c);
    const double exact = c->ShapeDistance(0, 0, 1, 0, INFINITY);
    for (double cutoff : {0.0, 0.02, 0.1}) {
      const double d = c->ShapeDistance(0, 0, 1, 0, cutoff);
      if (d > cutoff) {
        EXPECT_LE(d, exact + 1e-9) << "pair " << i << ", cutoff " << cutoff;
        ++bounded;
      } else {
        EXPECT_NEAR(d, exact, 1e-12) << "pair " << i << ", cutoff " << cutoff;
      }
    }
  }
  EXPECT_GT(bounded, 1000);
}

TEST(SelfCollisionModel, ValidateNamesWhatIsWrong) {
  RobotGeometry g = Hrp1s();
  std::string error;
  RobotGeometry bad = g;
  bad.links[1].parent = 5;
  EXPECT_FALSE(SelfCollision::Create(bad, &error));
  EXPECT_NE(error.find("parent 5 is not an earlier link"), std::string::npos) << error;
  bad = g;
  bad.links[2].shapes[0].size.x() = 0;
  EXPECT_FALSE(SelfCollision::Create(bad, &error));
  EXPECT_NE(error.find("size that is not positive"), std::string::npos) << error;
  bad = g;
  bad.links[3].joint = 99;
  EXPECT_FALSE(SelfCollision::Create(bad, &error));
  EXPECT_NE(error.find("joint id 99 is outside"), std::string::npos) << error;
}

// the shipped file is current: the geometry, joints and model hash it carries are what the
// MJCF gives now (regenerate: docs/selfcollision.md), and it reads back as written
TEST(SelfCollisionFile, TheShippedHrp1sFileMatchesTheModel) {
  const RobotGeometry g = Hrp1s();
  SelfCollisionFile f;
  std::string error;
  const std::string path = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
  ASSERT_TRUE(ReadSelfCollisionFile(path, &f, &error)) << error;
  EXPECT_EQ(f.robot.model_hash, g.model_hash) << "regenerate " << path;
  EXPECT_EQ(f.robot.joint_names, g.joint_names);
  ASSERT_EQ(f.robot.links.size(), g.links.size());
  for (size_t l = 0; l < g.links.size(); ++l) {
    EXPECT_EQ(f.robot.links[l].name, g.links[l].name);
    EXPECT_EQ(f.robot.links[l].parent, g.links[l].parent);
    EXPECT_EQ(f.robot.links[l].joint, g.links[l].joint);
    EXPECT_TRUE(f.robot.links[l].p_PL.isApprox(g.links[l].p_PL, 1e-12) ||
                (f.robot.links[l].p_PL - g.links[l].p_PL).norm() < 1e-12);
    ASSERT_EQ(f.robot.links[l].shapes.size(), g.links[l].shapes.size());
    for (size_t s = 0; s < g.links[l].shapes.size(); ++s) {
      EXPECT_EQ(f.robot.links[l].shapes[s].type, g.links[l].shapes[s].type);
      EXPECT_LT((f.robot.links[l].shapes[s].size - g.links[l].shapes[s].size).norm(), 1e-12);
      EXPECT_LT((f.robot.links[l].shapes[s].p_LS - g.links[l].shapes[s].p_LS).norm(), 1e-12);
    }
  }
  // every non-adjacent pair is in exactly one of the lists (a range's pairs may repeat)
  size_t listed = f.online.size() + f.structural.size() + f.never.size();
  std::vector<LinkPair> ranged;
  for (const auto& r : f.ranges)
    for (const auto& p : r.pairs)
      if (std::find(ranged.begin(), ranged.end(), p) == ranged.end()) ranged.push_back(p);
  EXPECT_EQ(listed + ranged.size(), NonAdjacentPairs(g).size());
  // written again, it is the same text
  EXPECT_EQ(SelfCollisionYaml(f), [&] {
    std::ifstream in(path);
    std::stringstream t;
    t << in.rdbuf();
    return t.str();
  }());
}

TEST(SelfCollisionFile, MistakesNameTheFileLineAndKey) {
  const std::string dir = ohrp::testing::ScratchDir() + "/";
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + name) << text;
    return dir + name;
  };
  SelfCollisionFile f;
  std::string error;
  EXPECT_FALSE(ReadSelfCollisionFile(write("sc_a.yaml", "robot: x\n"), &f, &error));
  EXPECT_NE(error.find("sc_a.yaml:1: model_hash: missing"), std::string::npos) << error;
  EXPECT_FALSE(ReadSelfCollisionFile(write("sc_b.yaml", "robot: [\n"), &f, &error));
  EXPECT_NE(error.find("not valid YAML"), std::string::npos) << error;
  EXPECT_FALSE(ReadSelfCollisionFile(dir + "none.yaml", &f, &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  // an unknown link in a pair: its line
  const std::string shipped = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
  std::ifstream in(shipped);
  std::stringstream t;
  t << in.rdbuf();
  std::string text = t.str();
  const size_t at = text.find("online: [[") + 10;
  text.replace(at, text.find(',', at) - at, "NOSUCH");
  const int line = static_cast<int>(std::count(text.begin(), text.begin() + at, '\n')) + 1;
  EXPECT_FALSE(ReadSelfCollisionFile(write("sc_c.yaml", text), &f, &error));
  EXPECT_NE(error.find("sc_c.yaml:" + std::to_string(line) + ": online: no link 'NOSUCH'"),
            std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::collision
