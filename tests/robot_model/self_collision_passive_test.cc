// Passive joints (no actuator: the segment publishes them read-only) in the self-collision
// geometry: joint ids after the actuated ones, postures njoint + npassive long, limits that bound
// them (an unlimited hinge over -pi..pi), joint reference positions (ref) folded into the body
// poses, bodies below a ball joint left out and named. Closed forms on a small model, then
// menagerie's Cassie (../shared/external beside the repository).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <random>

#include "collision/from_mjcf.h"
#include "collision/incremental_check.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "common/scratch.h"
#include "robot_model/model.h"
#include "test_models.h"

namespace ohrp::collision {
namespace {

// a torso with a sphere beside it on an actuated hinge, and an arm on a passive hinge (about z
// through the torso's origin, ref 0.3 rad) carrying a sphere at 0.4 m; a passive unlimited
// hinge below it (a spring); a ball-jointed rod that the segment cannot place
constexpr char kXml[] = R"(<mujoco model="passive">
  <compiler angle="radian"/>
  <worldbody>
    <body name="torso"><freejoint/>
      <geom type="box" size=".02 .02 .02"/>
      <body name="post" pos=".5 0 0">
        <joint name="lift" axis="0 1 0" limited="true" range="-1 1"/>
        <geom type="sphere" size=".05"/>
      </body>
      <body name="arm" axisangle="0 0 1 0.3">
        <joint name="swing" axis="0 0 1" ref="0.3" limited="true" range="-1.2 1.2"/>
        <geom type="sphere" size=".06" pos=".4 0 0"/>
        <body name="spring" pos=".4 0 .2">
          <joint name="coil" axis="1 0 0" stiffness="100"/>
          <geom type="capsule" fromto="0 0 0 0 .1 0" size=".01"/>
        </body>
      </body>
      <body name="rod" pos="0 0 -.3">
        <joint name="rod_ball" type="ball"/>
        <geom type="capsule" fromto="0 0 0 .3 0 0" size=".01"/>
        <body name="rod_tip" pos=".3 0 0"><geom type="sphere" size=".02"/></body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="lift"/></actuator>
</mujoco>)";

struct Loaded {
  mjModel* m = nullptr;
  model::RobotMap robot;
  RobotGeometry g;
  ~Loaded() { mj_deleteModel(m); }
};

bool LoadXml(const char* xml, Loaded* out) {
  std::string error;
  out->m = model::testing::LoadString(xml, &error);
  EXPECT_TRUE(out->m) << error;
  const bool ok = out->m && model::MapRobot(out->m, &out->robot, &error) &&
                  GeometryFromModel(out->m, out->robot, &out->g, &error);
  EXPECT_TRUE(ok) << error;
  return ok;
}

bool LoadFile(const std::string& path, Loaded* out) {
  char err[512] = "";
  out->m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  EXPECT_TRUE(out->m) << path << ": " << err;
  std::string error;
  const bool ok = out->m && model::MapRobot(out->m, &out->robot, &error) &&
                  GeometryFromModel(out->m, out->robot, &out->g, &error);
  EXPECT_TRUE(ok) << error;
  return ok;
}

// the checker's pose of every body's link is MuJoCo's (base at the origin) in `trials` random
// postures within the limits, passive joints included; returns the links compared
int ExpectPosesMatchMujoco(const Loaded& l, int trials) {
  std::string error;
  auto c = SelfCollision::Create(l.g, &error);
  EXPECT_TRUE(c) << error;
  if (!c) return 0;
  mjData* d = mj_makeData(l.m);
  std::mt19937 rng(3);
  std::vector<double> q(NumJoints(l.g));
  int compared = 0;
  for (int trial = 0; trial < trials; ++trial) {
    mju_copy(d->qpos, l.m->qpos0, l.m->nq);
    for (int j = 0; j < NumJoints(l.g); ++j)
      q[j] = std::uniform_real_distribution<double>(l.g.q_min[j], l.g.q_max[j])(rng);
    // the posture into MuJoCo's qpos: actuated, then passive
    for (size_t j = 0; j < l.robot.joints.size(); ++j) d->qpos[l.robot.joints[j].qpos_adr] = q[j];
    for (size_t k = 0; k < l.robot.passive.size(); ++k)
      d->qpos[l.robot.passive[k].qpos_adr] = q[l.robot.joints.size() + k];
    d->qpos[0] = d->qpos[1] = d->qpos[2] = 0;
    d->qpos[3] = 1, d->qpos[4] = d->qpos[5] = d->qpos[6] = 0;
    mj_kinematics(l.m, d);
    std::vector<double> back(q.size());
    PostureFromQpos(l.robot, d->qpos, back);
    EXPECT_EQ(back, q);
    c->SetPose(q);
    for (size_t k = 0; k < l.g.links.size(); ++k) {
      if (l.g.links[k].joint_only) continue;
      const int b = mj_name2id(l.m, mjOBJ_BODY, l.g.links[k].name.c_str());
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->xmat + 9 * b);
      EXPECT_LT((c->LinkPose(k).translation() - Eigen::Vector3d(d->xpos + 3 * b)).norm(), 1e-9)
          << l.g.links[k].name << ", trial " << trial;
      EXPECT_LT((c->LinkPose(k).linear() - R).norm(), 1e-9) << l.g.links[k].name;
      ++compared;
    }
  }
  mj_deleteData(d);
  return compared;
}

TEST(SelfCollisionPassive, JointIdsLimitsRefAndTheBallJointLeftOut) {
  Loaded l;
  ASSERT_TRUE(LoadXml(kXml, &l));
  ASSERT_EQ(l.g.joint_names, std::vector<std::string>{"lift"});
  ASSERT_EQ(l.g.passive_names, (std::vector<std::string>{"swing", "coil"}));
  EXPECT_EQ(NumJoints(l.g), 3);
  EXPECT_EQ(FindJoint(l.g, "swing"), 1);
  EXPECT_EQ(JointName(l.g, 2), "coil");
  // swing's range; coil is unlimited: a hinge turns all the way round
  EXPECT_EQ(l.g.q_min[1], -1.2);
  EXPECT_EQ(l.g.q_max[1], 1.2);
  EXPECT_EQ(l.g.q_min[2], -M_PI);
  EXPECT_EQ(l.g.q_max[2], M_PI);
  // the rod and its tip are not in the geometry, and the geometry says so
  EXPECT_EQ(FindLink(l.g, "rod"), -1);
  EXPECT_EQ(FindLink(l.g, "rod_tip"), -1);
  ASSERT_EQ(l.g.unchecked.size(), 2u);
  EXPECT_NE(l.g.unchecked[0].find("rod: a ball joint"), std::string::npos) << l.g.unchecked[0];
  EXPECT_NE(l.g.unchecked[1].find("rod_tip"), std::string::npos) << l.g.unchecked[1];
  EXPECT_GT(ExpectPosesMatchMujoco(l, 100), 0);
}

// the passive swing turns the arm's sphere (0.4 m out, radius 0.06) about z; the post's sphere
// (radius 0.05) is at x = 0.5 when lift is 0: the gap is |c_post - c_arm| - 0.11, the arm's
// centre at 0.4 (cos(a0 + q - ref), sin(...)) with the body's own turn a0 = 0.3 (its quat) and
// ref = 0.3: at q = 0.3 the arm points at the post's side by 0.3 rad
TEST(SelfCollisionPassive, APassiveJointMovesItsLinkAsTheClosedFormSays) {
  Loaded l;
  ASSERT_TRUE(LoadXml(kXml, &l));
  std::string error;
  auto c = SelfCollision::Create(l.g, &error);
  ASSERT_TRUE(c) << error;
  const int post = FindLink(l.g, "post"), arm = FindLink(l.g, "arm");
  IncrementalCheck inc(c.get(), {{std::min(post, arm), std::max(post, arm)}});
  for (double q = -1.2; q <= 1.2; q += 0.05) {
    const double angle = 0.3 + q - 0.3;
    const Eigen::Vector3d arm_c(0.4 * std::cos(angle), 0.4 * std::sin(angle), 0);
    const double want = (Eigen::Vector3d(0.5, 0, 0) - arm_c).norm() - 0.11;
    const std::vector<double> posture = {0.0, q, 0.0};
    c->SetPose(posture);
    EXPECT_NEAR(c->Distance(post, arm, 1.0), want, 1e-6) << "swing " << q;
    // the incremental check counts the passive joint's motion: within the cutoff it measures
    inc.MoveTo(posture);
    const CheckResult r = inc.CheckAll(0.2);
    if (want <= 0.2) EXPECT_NEAR(r.min_distance, want, 1e-6) << "swing " << q;
    else EXPECT_GT(inc.distance(0), 0.2 - 1e-6);
  }
  // the spring's reach is counted for the passive swing and coil above it
  const auto reach = LinkReach(l.g);
  const int spring = FindLink(l.g, "spring");
  std::vector<int> joints;
  for (const auto& [j, r] : reach[spring]) joints.push_back(j);
  EXPECT_EQ(joints, (std::vector<int>{2, 1}));
}

TEST(SelfCollisionPassive, TheFileListsThePassiveJointsAndWhatIsLeftOut) {
  Loaded l;
  ASSERT_TRUE(LoadXml(kXml, &l));
  SelfCollisionFile f, back;
  f.robot = l.g;
  f.online = NonAdjacentPairs(l.g);
  // the first pair pruned by swing's range instead of online (a file lists each pair once)
  f.ranges.push_back({FindJoint(l.g, "swing"), -0.5, 0.5, {f.online[0]}});
  f.online.erase(f.online.begin());
  f.robot.unchecked.push_back("a \"quoted\" body: a back\\slash");  // escaped in the YAML
  const std::string path = ohrp::testing::ScratchPath("passive", ".yaml");
  std::string error;
  ASSERT_TRUE(WriteSelfCollisionFile(path, f, &error)) << error;
  ASSERT_TRUE(ReadSelfCollisionFile(path, &back, &error)) << error;
  EXPECT_EQ(back.robot.passive_names, l.g.passive_names);
  EXPECT_EQ(back.robot.q_min, l.g.q_min);
  EXPECT_EQ(back.robot.q_max, l.g.q_max);
  EXPECT_EQ(back.robot.unchecked, f.robot.unchecked);
  ASSERT_EQ(back.ranges.size(), 1u);
  EXPECT_EQ(back.ranges[0].joint, 1);
  EXPECT_EQ(back.robot.links[FindLink(back.robot, "arm")].joint, 1);
  // a file whose links name a passive joint it does not list is refused, naming it
  std::string text = SelfCollisionYaml(f);
  const size_t from = text.find("passive_joints:"), to = text.find("unchecked:");
  ASSERT_NE(from, std::string::npos);
  text.erase(from, to - from);
  const std::string cut = ohrp::testing::ScratchFile("no_passive", text, ".yaml");
  EXPECT_FALSE(ReadSelfCollisionFile(cut, &back, &error));
  EXPECT_NE(error.find("no joint 'swing'"), std::string::npos) << error;
}

TEST(SelfCollisionPassive, AnUnlimitedPassiveSlideIsRefused) {
  constexpr char kSlide[] = R"(<mujoco model="slide">
  <worldbody>
    <body name="base"><freejoint/><geom type="sphere" size=".05"/>
      <body name="a" pos=".3 0 0"><joint name="hinge" axis="0 0 1" limited="true" range="-1 1"/>
        <geom type="sphere" size=".05"/></body>
      <body name="b" pos="0 .3 0"><joint name="free_slide" type="slide" axis="0 1 0"/>
        <geom type="sphere" size=".05"/></body>
    </body>
  </worldbody>
  <actuator><motor joint="hinge"/></actuator>
</mujoco>)";
  std::string error;
  mjModel* m = model::testing::LoadString(kSlide, &error);
  ASSERT_TRUE(m) << error;
  model::RobotMap robot;
  RobotGeometry g;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  EXPECT_FALSE(GeometryFromModel(m, robot, &g, &error));
  EXPECT_NE(error.find("'free_slide' is a slide without a range"), std::string::npos) << error;
  mj_deleteModel(m);
}

// menagerie's Cassie: 10 motors, 10 passive joints (shin, tarsus, heel spring, foot crank,
// plantar rod of each leg; the knee and tarsus have a ref), an ellipsoid pelvis, the achilles
// rods on ball joints left out
TEST(SelfCollisionPassive, CassieLoadsWithItsPassiveJoints) {
  const std::string path =
      std::string(OHRP_SOURCE_DIR) + "/../shared/external/menagerie/agility_cassie/cassie.xml";
  Loaded l;
  ASSERT_TRUE(LoadFile(path, &l));
  EXPECT_EQ(l.g.joint_names.size(), 10u);
  EXPECT_EQ(l.g.passive_names.size(), 10u);
  EXPECT_GE(FindJoint(l.g, "left-heel-spring"), 10);
  EXPECT_EQ(l.g.links.size(), 23u);  // the pelvis and 11 bodies a leg (the achilles rod out)
  ASSERT_EQ(l.g.unchecked.size(), 2u);
  EXPECT_NE(l.g.unchecked[0].find("left-achilles-rod"), std::string::npos);
  int ellipsoids = 0;
  for (const auto& s : l.g.links[0].shapes) ellipsoids += s.type == ShapeType::kEllipsoid;
  EXPECT_EQ(ellipsoids, 1);
  EXPECT_EQ(ExpectPosesMatchMujoco(l, 50), 50 * 23);
  // the home keyframe: the knees' link poses from qpos (ref folded in) and no NaN distance
  std::string error;
  auto c = SelfCollision::Create(l.g, &error);
  ASSERT_TRUE(c) << error;
  const int key = mj_name2id(l.m, mjOBJ_KEY, "home");
  ASSERT_GE(key, 0);
  std::vector<double> q(NumJoints(l.g));
  PostureFromQpos(l.robot, l.m->key_qpos + key * l.m->nq, q);
  c->SetPose(q);
  for (const LinkPair& p : NonAdjacentPairs(l.g)) EXPECT_TRUE(std::isfinite(c->Distance(p.a, p.b, 0.01)));
}

}  // namespace
}  // namespace ohrp::collision
