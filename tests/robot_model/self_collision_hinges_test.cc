// The self-collision checker on bodies with several hinges (MuJoCo's humanoid: a hip of three,
// a shoulder of two) and on slides (a lift, a telescoping arm, a gripper's finger): from_mjcf
// makes each extra joint a joint_only link, and the checker's link poses must still be MuJoCo's
// for any posture, the body's parent and the body must stay one adjacent pair, and the
// self-collision file must keep the chain and the slides. Meshes MuJoCo compiled without a hull
// (visual-only ones: a cube here, every mesh of menagerie's H1) get Qhull's.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>

#include "collision/from_mjcf.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "common/scratch.h"
#include "hull_checks.h"
#include "robot_model/model.h"

namespace ohrp::collision {
namespace {

// a torso with a three-hinge hip (axes and anchors off the body's origin, a turned body frame),
// a one-hinge knee below it and a two-hinge shoulder
constexpr const char* kHinges = R"(<mujoco model="hinges">
  <compiler angle="radian"/>
  <worldbody>
    <body name="torso" pos="0 0 1">
      <freejoint/>
      <geom type="box" size=".1 .15 .2"/>
      <body name="thigh" pos="0 -.1 -.25" quat="0.9659 0 0.2588 0">
        <joint name="hip_x" axis="1 0 0" pos="0 0 .05" limited="true" range="-.5 .5"/>
        <joint name="hip_z" axis="0 .3 1" pos=".02 0 0" limited="true" range="-.7 .4"/>
        <joint name="hip_y" axis="0 1 0" pos="0 .01 .03" limited="true" range="-1.5 .3"/>
        <geom type="capsule" fromto="0 0 0 0 .01 -.34" size=".06"/>
        <body name="shin" pos="0 .01 -.4">
          <joint name="knee" axis="0 -1 0" pos="0 0 .02" limited="true" range="-2 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -.3" size=".05"/>
        </body>
      </body>
      <body name="arm" pos="0 .2 .15">
        <joint name="shoulder_1" axis="2 1 1" limited="true" range="-1.5 1"/>
        <joint name="shoulder_2" axis="0 -1 1" pos=".01 .02 0" limited="true" range="-1.5 1"/>
        <geom type="capsule" fromto="0 0 0 .16 .16 -.16" size=".04"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="hip_x"/> <motor joint="hip_z"/> <motor joint="hip_y"/> <motor joint="knee"/>
    <motor joint="shoulder_1"/> <motor joint="shoulder_2"/>
  </actuator>
</mujoco>
)";

struct Loaded {
  mjModel* m = nullptr;
  model::RobotMap robot;
  RobotGeometry g;
  ~Loaded() { mj_deleteModel(m); }
};

// the model at `path` and its geometry; false (with a failure recorded) when either fails
bool Load(const std::string& path, Loaded* out) {
  char err[512] = "";
  out->m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  EXPECT_TRUE(out->m) << err;
  if (!out->m) return false;
  std::string error;
  const bool ok = model::MapRobot(out->m, &out->robot, &error) &&
                  GeometryFromModel(out->m, out->robot, &out->g, &error);
  EXPECT_TRUE(ok) << error;
  return ok;
}


// writes `xml` to a file named `name` in the tests' temporary folder and returns its path
std::string WriteXml(const std::string& name, const std::string& xml) {
  const std::string path = ohrp::testing::ScratchDir() + "/" + name;
  std::ofstream(path) << xml;
  return path;
}

// the checker's pose of every body's link (the one named as the body) is MuJoCo's, base at the
// origin, in `trials` random postures within the limits; returns the links compared
int ExpectPosesMatchMujoco(const Loaded& l, int trials) {
  std::string error;
  auto c = SelfCollision::Create(l.g, &error);
  EXPECT_TRUE(c) << error;
  if (!c) return 0;
  mjData* d = mj_makeData(l.m);
  std::mt19937 rng(7);
  int compared = 0;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<double> q(l.g.joint_names.size());
    mju_copy(d->qpos, l.m->qpos0, l.m->nq);
    for (size_t j = 0; j < q.size(); ++j) {
      q[j] = std::uniform_real_distribution<double>(l.g.q_min[j], l.g.q_max[j])(rng);
      d->qpos[l.robot.joints[j].qpos_adr] = q[j];
    }
    d->qpos[0] = d->qpos[1] = d->qpos[2] = 0;
    mj_kinematics(l.m, d);
    c->SetPose(q);
    for (size_t k = 0; k < l.g.links.size(); ++k) {
      if (l.g.links[k].joint_only) continue;
      const int b = mj_name2id(l.m, mjOBJ_BODY, l.g.links[k].name.c_str());
      EXPECT_GE(b, 0) << l.g.links[k].name;
      if (b < 0) continue;
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

// writes `g` to a self-collision file (every non-adjacent pair online) and reads it back: the
// links keep their parents, joint_only and slide flags, the pairs stay
SelfCollisionFile RoundTrip(const RobotGeometry& g) {
  SelfCollisionFile f;
  f.robot = g;
  f.online = NonAdjacentPairs(g);
  const std::string path = ohrp::testing::ScratchPath(g.name + "_selfcollision", ".yaml");
  std::string error;
  SelfCollisionFile back;
  EXPECT_TRUE(WriteSelfCollisionFile(path, f, &error)) << error;
  EXPECT_TRUE(ReadSelfCollisionFile(path, &back, &error)) << error;
  EXPECT_EQ(back.online, f.online);
  EXPECT_EQ(back.robot.links.size(), g.links.size());
  for (size_t k = 0; k < std::min(back.robot.links.size(), g.links.size()); ++k) {
    const Link &a = g.links[k], &b = back.robot.links[k];
    EXPECT_EQ(b.parent, a.parent) << a.name;
    EXPECT_EQ(b.joint_only, a.joint_only) << a.name;
    EXPECT_EQ(b.slide, a.slide) << a.name;
  }
  return back;
}

TEST(SelfCollisionHinges, EachExtraHingeIsAJointOnlyLink) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("hinges.xml", kHinges), &l));
  std::vector<std::string> names;
  for (const Link& k : l.g.links) names.push_back(k.name);
  EXPECT_EQ(names, (std::vector<std::string>{"torso", "thigh@hip_x", "thigh@hip_z", "thigh",
                                             "shin", "arm@shoulder_1", "arm"}));
  for (const Link& k : l.g.links) {
    const bool extra = k.name.find('@') != std::string::npos;
    EXPECT_EQ(k.joint_only, extra) << k.name;
    EXPECT_EQ(k.shapes.empty(), extra) << k.name;
    if (k.name != "torso") {
      EXPECT_GE(k.joint, 0) << k.name;
    }
  }
  // the hinges in MuJoCo's order down the chain, the body's shapes on its last link
  const int thigh = FindLink(l.g, "thigh");
  EXPECT_EQ(l.g.joint_names[l.g.links[thigh].joint], "hip_y");
  EXPECT_EQ(l.g.joint_names[l.g.links[thigh - 1].joint], "hip_z");
  EXPECT_EQ(l.g.joint_names[l.g.links[thigh - 2].joint], "hip_x");
  EXPECT_EQ(BodyParent(l.g, thigh), FindLink(l.g, "torso"));
  EXPECT_EQ(BodyParent(l.g, FindLink(l.g, "shin")), thigh);
}

TEST(SelfCollisionHinges, LinkPosesMatchMujoco) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("hinges.xml", kHinges), &l));
  EXPECT_EQ(ExpectPosesMatchMujoco(l, 200), 200 * 4);
}

TEST(SelfCollisionHinges, ABodyAndItsParentStayOneAdjacentPair) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("hinges.xml", kHinges), &l));
  // four links with shapes: C(4, 2) = 6, less torso/thigh, thigh/shin and torso/arm
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const LinkPair& p : NonAdjacentPairs(l.g))
    pairs.emplace_back(l.g.links[p.a].name, l.g.links[p.b].name);
  EXPECT_EQ(pairs, (std::vector<std::pair<std::string, std::string>>{
                       {"torso", "shin"}, {"thigh", "arm"}, {"shin", "arm"}}));
}

TEST(SelfCollisionHinges, TheFileKeepsTheChain) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("hinges.xml", kHinges), &l));
  RoundTrip(l.g);
  // a joint_only link with shapes is refused, naming it
  RobotGeometry bad = l.g;
  bad.links[FindLink(bad, "thigh@hip_z")].shapes = bad.links[FindLink(bad, "thigh")].shapes;
  EXPECT_NE(Validate(bad).find("'thigh@hip_z': a joint_only link needs a joint"), std::string::npos)
      << Validate(bad);
}

// slides: a lift (a slide then a hinge on one turned body, the slide's axis off the body's
// axes), a telescoping arm (a hinge, then a slide below it) and a gripper finger on the lift
constexpr const char* kSlides = R"(<mujoco model="slides">
  <compiler angle="radian"/>
  <worldbody>
    <body name="torso" pos="0 0 1">
      <freejoint/>
      <geom type="box" size=".1 .15 .2"/>
      <body name="lift" pos=".05 0 .25" quat="0.9659 0.2588 0 0">
        <joint name="lift_z" type="slide" axis="0 .2 1" pos=".3 .1 0" limited="true"
               range="-.1 .15"/>
        <joint name="lift_yaw" axis="0 0 1" pos=".02 0 0" limited="true" range="-1 1"/>
        <geom type="box" size=".05 .05 .05"/>
        <body name="finger" pos=".08 0 0">
          <joint name="finger_x" type="slide" axis="1 0 0" limited="true" range="0 .04"/>
          <geom type="box" size=".02 .01 .03"/>
        </body>
      </body>
      <body name="upper_arm" pos="0 .2 .15">
        <joint name="shoulder" axis="0 1 0" pos="0 0 .02" limited="true" range="-1.5 1.5"/>
        <geom type="capsule" fromto="0 0 0 0 0 -.2" size=".04"/>
        <body name="forearm" pos="0 0 -.2">
          <joint name="extend" type="slide" axis="0 0 -1" limited="true" range="0 .12"/>
          <geom type="capsule" fromto="0 0 0 0 0 -.2" size=".03"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="lift_z"/> <motor joint="lift_yaw"/> <motor joint="finger_x"/>
    <motor joint="shoulder"/> <motor joint="extend"/>
  </actuator>
</mujoco>
)";

TEST(SelfCollisionSlides, SlidesAreLinksOfTheirOwn) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("slides.xml", kSlides), &l));
  std::vector<std::string> names;
  std::vector<bool> slides;
  for (const Link& k : l.g.links) {
    names.push_back(k.name);
    slides.push_back(k.slide);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"torso", "lift@lift_z", "lift", "finger", "upper_arm",
                                             "forearm"}));
  EXPECT_EQ(slides, (std::vector<bool>{false, true, false, true, false, true}));
  EXPECT_TRUE(l.g.links[1].joint_only);
  EXPECT_EQ(l.g.q_min[l.g.links[3].joint], 0.0);
  EXPECT_EQ(l.g.q_max[l.g.links[3].joint], 0.04);
}

TEST(SelfCollisionSlides, LinkPosesMatchMujoco) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("slides.xml", kSlides), &l));
  EXPECT_EQ(ExpectPosesMatchMujoco(l, 200), 200 * 5);
}

TEST(SelfCollisionSlides, TheFileKeepsTheSlides) {
  Loaded l;
  ASSERT_TRUE(Load(WriteXml("slides.xml", kSlides), &l));
  // the same postures from the file's geometry
  l.g = RoundTrip(l.g).robot;
  EXPECT_EQ(ExpectPosesMatchMujoco(l, 50), 50 * 5);
}

// a slide's travel bounds how far the links below it move: one without a range is refused,
// naming it and saying what would work
TEST(SelfCollisionSlides, ASlideWithoutARangeIsRefused) {
  std::string xml = kSlides;
  const std::string limited = R"(limited="true" range="0 .04")";
  xml.replace(xml.find(limited), limited.size(), "");
  char err[512] = "";
  mjModel* m = mj_loadXML(WriteXml("slides_unlimited.xml", xml).c_str(), nullptr, err, sizeof(err));
  ASSERT_TRUE(m) << err;
  model::RobotMap robot;
  RobotGeometry g;
  std::string error;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  EXPECT_FALSE(GeometryFromModel(m, robot, &g, &error));
  EXPECT_NE(error.find("joint 'finger_x' is a slide without a range: give it one"),
            std::string::npos)
      << error;
  mj_deleteModel(m);
}

// MuJoCo's own humanoid (../shared/external beside the repository): abdomen, hips and shoulders
// of two and three hinges
TEST(SelfCollisionHinges, MujocosHumanoidPosesMatchMujoco) {
  const std::string path = std::string(OHRP_SOURCE_DIR) +
                           "/../shared/external/mujoco-2.2.2-models/humanoid/humanoid.xml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
  Loaded l;
  ASSERT_TRUE(Load(path, &l));
  int bodies = 0, extra = 0, hinged = 0;
  for (const Link& k : l.g.links) {
    (k.joint_only ? extra : bodies) += 1;
    hinged += k.joint >= 0;
  }
  EXPECT_EQ(bodies, l.m->nbody - 1);  // every body but the world
  EXPECT_GT(extra, 0);
  EXPECT_EQ(hinged, static_cast<int>(l.g.joint_names.size()));  // one hinge a link, all of them
  EXPECT_EQ(ExpectPosesMatchMujoco(l, 100), 100 * bodies);
  // the thighs hang from the pelvis, not from their hips' joint_only links
  const int thigh = FindLink(l.g, "right_thigh"), pelvis = FindLink(l.g, "pelvis");
  ASSERT_GE(thigh, 0);
  EXPECT_EQ(BodyParent(l.g, thigh), pelvis);
}

// a base with a box and, on a hinge, a link whose only geom is a visual cube mesh (5 cm half
// size) 30 cm away along x
constexpr const char* kVisualCube = R"(<mujoco model="visual_cube">
  <asset>
    <mesh name="cube" vertex="-.05 -.05 -.05  .05 -.05 -.05  -.05 .05 -.05  .05 .05 -.05
                              -.05 -.05 .05  .05 -.05 .05  -.05 .05 .05  .05 .05 .05"
          face="0 2 1  1 2 3  4 5 6  5 7 6  0 1 4  1 5 4  2 6 3  3 6 7  0 4 2  2 4 6  1 3 5  3 7 5"/>
  </asset>
  <worldbody>
    <body name="base" pos="0 0 1">
      <freejoint/>
      <geom name="box" type="box" size=".05 .05 .05"/>
      <body name="link" pos=".3 0 0">
        <inertial pos="0 0 0" mass="1" diaginertia=".01 .01 .01"/>
        <joint name="turn" axis="0 0 1"/>
        <geom name="cube" type="mesh" mesh="cube" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="turn"/></actuator>
</mujoco>)";

const Shape* OnlyShape(const RobotGeometry& g, const std::string& link) {
  for (const Link& l : g.links)
    if (l.name == link && l.shapes.size() == 1) return &l.shapes[0];
  return nullptr;
}

TEST(SelfCollisionMeshes, VisualOnlyMeshGetsItsHull) {
  Loaded l;
  ASSERT_TRUE(Load(ohrp::testing::ScratchFile("visual_cube", kVisualCube, ".xml"), &l));
  ASSERT_LT(l.m->mesh_graphadr[0], 0) << "MuJoCo made this mesh's hull itself: the test is moot";
  const Shape* cube = OnlyShape(l.g, "link");
  ASSERT_NE(cube, nullptr);
  EXPECT_EQ(cube->type, ShapeType::kConvex);
  EXPECT_EQ(cube->vertices.size(), 8u);
  EXPECT_EQ(cube->faces.size(), 4u * 12);
  ExpectOutwardTriangles(cube->vertices, cube->faces);
  std::string error;
  auto c = SelfCollision::Create(l.g, &error);
  ASSERT_TRUE(c) << error;
  const int base = 0, link = 1;
  ASSERT_EQ(l.g.links[link].name, "link");
  // face to face: 30 cm between the centres less two half sizes; turned 45 deg about z, the
  // cube's edge comes 5 (sqrt 2 - 1) cm closer
  c->SetPose(std::vector<double>{0.0});
  EXPECT_NEAR(c->Distance(base, link, INFINITY), 0.2, 1e-6);
  c->SetPose(std::vector<double>{M_PI / 4});
  EXPECT_NEAR(c->Distance(base, link, INFINITY), 0.2 - 0.05 * (std::sqrt(2.0) - 1), 1e-6);
}

// menagerie's Unitree H1: every mesh is visual only, the collision geoms are primitives
TEST(SelfCollisionMeshes, MenageriesH1LoadsWithItsMeshes) {
  const std::string path =
      std::string(OHRP_SOURCE_DIR) + "/../shared/external/menagerie/unitree_h1/h1.xml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
  Loaded l;
  ASSERT_TRUE(Load(path, &l));
  // each mesh geom's shape against MuJoCo's vertices of that mesh
  std::mt19937 rng(5);
  int meshes = 0;
  for (int b = 1; b < l.m->nbody; ++b) {
    const std::string body = mj_id2name(l.m, mjOBJ_BODY, b);
    const auto link = std::find_if(l.g.links.begin(), l.g.links.end(),
                                   [&](const Link& k) { return k.name == body; });
    ASSERT_NE(link, l.g.links.end()) << body;
    for (int g = l.m->body_geomadr[b], k = 0; g < l.m->body_geomadr[b] + l.m->body_geomnum[b]; ++g, ++k) {
      if (l.m->geom_type[g] != mjGEOM_MESH) continue;
      ++meshes;
      const int mesh = l.m->geom_dataid[g];
      const float* v = l.m->mesh_vert + 3 * l.m->mesh_vertadr[mesh];
      std::vector<Eigen::Vector3d> raw;
      for (int i = 0; i < l.m->mesh_vertnum[mesh]; ++i) raw.emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      const Shape& s = link->shapes[k];
      ASSERT_EQ(s.type, ShapeType::kConvex) << body;
      EXPECT_LT(s.vertices.size(), raw.size()) << body << ": the hull keeps only its corners";
      // the hull, or its outer polytope within kMeshHullTolerance (outer_hull_test.cc)
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d d = RandomDirection(&rng);
        EXPECT_GE(MaxAlong(s.vertices, d) - MaxAlong(raw, d), -1e-9) << body;
        EXPECT_LE(MaxAlong(s.vertices, d) - MaxAlong(raw, d), kMeshHullTolerance + 1e-9) << body;
      }
    }
  }
  EXPECT_EQ(meshes, l.m->nmesh);  // one visual geom per mesh in H1
  // the checker's link poses are MuJoCo's body poses
  const int links = static_cast<int>(l.g.links.size());
  EXPECT_EQ(ExpectPosesMatchMujoco(l, 50), 50 * links);
}

}  // namespace
}  // namespace ohrp::collision
