// The robot profile (robot_model/profile.h, load.h; reading: profile_read_test.cc): include
// expansion with MuJoCo's semantics; the additions on a small biped written here
// (soles derived from the feet's geoms, F/T sensors, IMU, the stance with its base height, the
// contact switched to the soles or not); assets found beside the model; G1 and H1 through their
// committed profiles and through drafts made by DraftProfile (skipped without ../shared/external).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <string>

#include "../common/scratch.h"
#include "robot_model/ik.h"
#include "robot_model/kinematics.h"
#include "robot_model/load.h"
#include "robot_model/model.h"
#include "robot_model/model_hash.h"
#include "robot_model/profile.h"

namespace ohrp::model {
namespace {

namespace fs = std::filesystem;
using ohrp::testing::ScratchFolder;

void Write(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// a biped: pelvis (free), per leg a hip and a knee hinge, a foot body with a box 0.2 x 0.1 m
// whose bottom is 0.05 m below the foot's origin (x centre 0.03), motors, no sensor, no keyframe
std::string Biped(const std::string& extra = "") {
  auto leg = [](const char* side, double y) {
    char b[1024];
    std::snprintf(b, sizeof b,
                  "<body name='%s_thigh' pos='0 %g -0.1'><joint name='%s_hip' axis='0 1 0'/>"
                  "<geom type='capsule' fromto='0 0 0 0 0 -0.3' size='0.03'/>"
                  "<body name='%s_shin' pos='0 0 -0.3'><joint name='%s_knee' axis='0 1 0'/>"
                  "<geom type='capsule' fromto='0 0 0 0 0 -0.3' size='0.03'/>"
                  "<body name='%s_foot' pos='0 0 -0.3'><joint name='%s_ankle' axis='0 1 0'/>"
                  "<geom name='%s_box' type='box' size='0.1 0.05 0.02' pos='0.03 0 -0.03'/>"
                  "</body></body></body>",
                  side, y, side, side, side, side, side, side);
    return std::string(b);
  };
  return "<mujoco model='biped'><worldbody><geom name='floor' type='plane' size='5 5 0.1'/>"
         "<body name='pelvis' pos='0 0 1'><freejoint/><geom type='box' size='0.1 0.15 0.05'/>" +
         leg("left", 0.1) + leg("right", -0.1) +
         "</body></worldbody><actuator>"
         "<motor joint='left_hip'/><motor joint='left_knee'/><motor joint='left_ankle'/>"
         "<motor joint='right_hip'/><motor joint='right_knee'/><motor joint='right_ankle'/>"
         "</actuator>" + extra + "</mujoco>";
}

const char* kBipedProfile =
    "model: biped.xml\n"
    "feet:\n"
    "  left: {body: left_foot}\n"
    "  right: {body: right_foot}\n"
    "stand:\n"
    "  joints: {left_knee: 0.4, right_knee: 0.4, left_hip: -0.2, right_hip: -0.2, left_ankle: -0.2,\n"
    "           right_ankle: -0.2}\n";

TEST(ProfileApply, IncludesAreExpandedRelativeToTheMainFile) {
  const std::string dir = ScratchFolder("profile_include");
  // robot.xml (in sub/) includes sub/legs.xml: names relative to the MAIN file's folder
  std::string biped = Biped();
  const size_t w = biped.find("<body name='pelvis'");
  const size_t e = biped.find("</worldbody>");
  Write(dir + "/sub/legs.xml", "<mujoco><worldbody>" + biped.substr(w, e - w) + "</worldbody></mujoco>");
  Write(dir + "/sub/robot.xml", "<mujoco model='x'><include file='sub/legs.xml'/>" +
                                    biped.substr(biped.find("<actuator>")));
  Write(dir + "/biped.xml", "<mujoco model='scene'><include file='sub/robot.xml'/>"
                            "<worldbody><geom name='floor' type='plane' size='5 5 0.1'/></worldbody></mujoco>");
  Write(dir + "/p.yaml", kBipedProfile);
  std::string error;
  ModelPtr m(LoadMujocoModel(dir + "/p.yaml", &error));
  ASSERT_TRUE(m) << error;
  EXPECT_GE(mj_name2id(m.get(), mjOBJ_BODY, "left_foot"), 0);
  EXPECT_GE(mj_name2id(m.get(), mjOBJ_GEOM, "LEFT_SOLE"), 0);
  EXPECT_EQ(m->nu, 6);
  // a file included twice is refused, as MuJoCo does
  Write(dir + "/twice.xml", "<mujoco><include file='sub/robot.xml'/><include file='sub/robot.xml'/></mujoco>");
  Write(dir + "/p2.yaml", std::string(kBipedProfile).replace(7, 9, "twice.xml"));
  EXPECT_FALSE(LoadMujocoModel(dir + "/p2.yaml", &error));
  EXPECT_NE(error.find("includes a file a second time"), std::string::npos) << error;
}

class Augmented : public ::testing::Test {
 protected:
  std::unique_ptr<Kinematics> Load(const std::string& profile, const std::string& model = Biped()) {
    dir_ = ScratchFolder("profile_biped");
    Write(dir_ + "/biped.xml", model);
    Write(dir_ + "/p.yaml", profile);
    std::string error;
    auto k = Kinematics::Load(dir_ + "/p.yaml", &error);
    EXPECT_TRUE(k) << error;
    return k;
  }
  std::string dir_;
};

TEST_F(Augmented, SolesSensorsImuAndStanceAreAdded) {
  auto k = Load(kBipedProfile);
  ASSERT_TRUE(k);
  const mjModel* m = k->m();
  ASSERT_GE(k->left_sole(), 0);
  ASSERT_GE(k->right_sole(), 0);
  const SoleMap& left = k->soles()[k->left_sole()];
  EXPECT_EQ(left.name, "LEFT_SOLE");
  EXPECT_EQ(m->body_parentid[left.body_id], mj_name2id(m, mjOBJ_BODY, "left_shin"));
  // derived from the box: 0.2 x 0.1 m, bottom face at z = -0.05, centre x 0.03; 1 cm thick
  EXPECT_NEAR(left.half_size[0], 0.1, 1e-9);
  EXPECT_NEAR(left.half_size[1], 0.05, 1e-9);
  EXPECT_NEAR(left.half_size[2], 0.005, 1e-9);
  EXPECT_NEAR(m->geom_pos[3 * left.geom_id], 0.03, 1e-9);
  EXPECT_NEAR(m->geom_pos[3 * left.geom_id + 2], -0.045, 1e-9);
  for (int side : {k->left_sole(), k->right_sole()}) {
    const int f = k->soles()[side].force_sensor;
    ASSERT_GE(f, 0);
    EXPECT_EQ(m->site_bodyid[k->robot().forces[f].site_id], k->soles()[side].body_id);
  }
  ASSERT_EQ(k->robot().imus.size(), 1u);
  EXPECT_EQ(m->site_bodyid[k->robot().imus[0].site_id], mj_name2id(m, mjOBJ_BODY, "pelvis"));
  EXPECT_GE(k->robot().imus[0].quat_adr, 0);
  // soft contact: the soles collide, the feet's own boxes no longer do; the sole adds no mass
  const int own = mj_name2id(m, mjOBJ_GEOM, "left_box");
  EXPECT_EQ(m->geom_contype[own] | m->geom_conaffinity[own], 0);
  EXPECT_EQ(m->geom_contype[left.geom_id], 1);
  EXPECT_NEAR(k->robot().total_mass, [] {
    std::string e;
    char err[512];
    (void)e;
    mjVFS vfs;
    mj_defaultVFS(&vfs);
    const std::string b = Biped();
    mj_makeEmptyFileVFS(&vfs, "b.xml", static_cast<int>(b.size()));
    std::copy(b.begin(), b.end(), static_cast<char*>(vfs.filedata[0]));
    ModelPtr plain(mj_loadXML("b.xml", &vfs, err, sizeof err));
    mj_deleteVFS(&vfs);
    double mass = 0;
    for (int i = 1; i < plain->nbody; ++i) mass += plain->body_mass[i];
    return mass;
  }(), 1e-9);
  // the stance: the joint values, the base lowered until the lowest sole corner is at z = 0
  const int key = mj_name2id(m, mjOBJ_KEY, "stand");
  ASSERT_GE(key, 0);
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, key);
  mj_kinematics(m, d);
  EXPECT_NEAR(d->qpos[m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, "left_knee")]], 0.4, 1e-12);
  double low = INFINITY;
  for (int side : {k->left_sole(), k->right_sole()}) {
    const int g = k->soles()[side].geom_id;
    for (int c = 0; c < 4; ++c) {
      const mjtNum local[3] = {(c & 1 ? 1 : -1) * m->geom_size[3 * g], (c & 2 ? 1 : -1) * m->geom_size[3 * g + 1],
                               -m->geom_size[3 * g + 2]};
      mjtNum w[3];
      mju_rotVecMat(w, local, d->geom_xmat + 9 * g);
      low = std::min(low, d->geom_xpos[3 * g + 2] + w[2]);
    }
  }
  EXPECT_NEAR(low, 0.0, 1e-9);
  // closed form: pelvis - 0.1 - 0.3 cos(-0.2) - 0.3 cos(0.2) then the foot (net pitch 0) 0.05 down,
  // the sole's heel or toe at z = 0: the lowest corner is at the box's bottom (pitch 0)
  EXPECT_NEAR(d->qpos[2], 0.1 + 0.6 * std::cos(0.2) + 0.05, 1e-9);
  mj_deleteData(d);
  // nothing written beside the model
  std::set<std::string> files;
  for (const auto& f : fs::directory_iterator(dir_)) files.insert(f.path().filename().string());
  EXPECT_EQ(files, (std::set<std::string>{"biped.xml", "p.yaml"}));
}

TEST_F(Augmented, NativeContactKeepsTheAuthorsGeomsAndGivenValuesAreUsed) {
  auto k = Load(std::string(kBipedProfile) +
                "contact: native\nimu: {body: left_thigh, pos: [0, 0, -0.1]}\n"
                "force_torque: {left: {body: left_shin, pos: [0, 0, -0.2]}}\n");
  ASSERT_TRUE(k);
  const mjModel* m = k->m();
  const int own = mj_name2id(m, mjOBJ_GEOM, "left_box");
  const int sole = k->soles()[k->left_sole()].geom_id;
  EXPECT_EQ(m->geom_contype[own], 1);
  EXPECT_EQ(m->geom_contype[sole] | m->geom_conaffinity[sole], 0);
  EXPECT_EQ(m->site_bodyid[k->robot().imus[0].site_id], mj_name2id(m, mjOBJ_BODY, "left_thigh"));
  const int f = k->soles()[k->left_sole()].force_sensor;
  EXPECT_EQ(m->site_bodyid[k->robot().forces[f].site_id], mj_name2id(m, mjOBJ_BODY, "left_shin"));
  EXPECT_NEAR(m->site_pos[3 * k->robot().forces[f].site_id + 2], -0.2, 1e-12);
}

TEST_F(Augmented, ExistingSensorsAreKeptAndEverythingMissingIsListedAtOnce) {
  const std::string sensors =
      "<sensor><gyro site='s'/><accelerometer site='s'/></sensor>";
  std::string model = Biped(sensors);
  model.replace(model.find("<freejoint/>"), 12, "<freejoint/><site name='s'/>");
  auto k = Load(kBipedProfile, model);
  ASSERT_TRUE(k);
  ASSERT_EQ(k->robot().imus.size(), 1u);
  EXPECT_EQ(k->robot().imus[0].name, "s");  // imu: auto adds none
  // three problems, one message
  Write(dir_ + "/bad.yaml", "model: biped.xml\nfeet:\n  left: {body: left_toe}\n  right: {body: right_foot}\n"
                            "stand: {keyframe: crouch}\nchains: {leg: [left_hip, left_heel]}\n");
  std::string error;
  EXPECT_FALSE(LoadMujocoModel(dir_ + "/bad.yaml", &error));
  EXPECT_NE(error.find("3 problems (all listed)"), std::string::npos) << error;
  EXPECT_NE(error.find("feet.left.body: the model has no body 'left_toe'"), std::string::npos) << error;
  EXPECT_NE(error.find("stand.keyframe: the model has no keyframe 'crouch'"), std::string::npos) << error;
  EXPECT_NE(error.find("leg: the model has no joint 'left_heel'"), std::string::npos) << error;
}

TEST_F(Augmented, AFootsOwnSoleBoxIsKept) {
  std::string model = Biped();
  for (const std::string side : {"left", "right"}) {
    const std::string box = "name='" + side + "_box'";
    model.replace(model.find(box), box.size(), "name='" + side + "_OWN_SOLE'");
  }
  auto k = Load(kBipedProfile, model);
  ASSERT_TRUE(k);
  ASSERT_EQ(k->soles().size(), 2u);  // the model's, none added
  EXPECT_EQ(k->soles()[k->left_sole()].name, "left_OWN_SOLE");
  EXPECT_GE(k->soles()[k->left_sole()].force_sensor, 0);
  const int g = k->soles()[k->left_sole()].geom_id;
  EXPECT_EQ(k->m()->geom_contype[g], 1);  // still the contact
  // the stance's height from the model's soles: their bottoms (0.05 below the feet) at z = 0
  const int key = mj_name2id(k->m(), mjOBJ_KEY, "stand");
  ASSERT_GE(key, 0);
  EXPECT_NEAR(k->m()->key_qpos[key * k->m()->nq + 2], 0.1 + 0.6 * std::cos(0.2) + 0.05, 1e-9);
}

// a binary STL tetrahedron
std::string Stl() {
  std::string s(80, '\0');
  const float v[4][3] = {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const uint32_t n = 4;
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : f) {
    const float normal[3] = {0, 0, 0};
    s.append(reinterpret_cast<const char*>(normal), 12);
    for (int i : t) s.append(reinterpret_cast<const char*>(v[i]), 12);
    s.append(2, '\0');
  }
  return s;
}

TEST_F(Augmented, MeshesAreFoundBesideTheModel) {
  std::string model = Biped("<asset><mesh name='tetra' file='tetra.stl'/></asset>");
  model.replace(model.find("<mujoco model='biped'>"), 22,
                "<mujoco model='biped'><compiler meshdir='assets'/>");
  model.replace(model.find("<geom type='box' size='0.1 0.15 0.05'/>"), 39,
                "<geom type='mesh' mesh='tetra' contype='0' conaffinity='0'/>");
  const std::string dir = ScratchFolder("profile_mesh");
  Write(dir + "/assets/tetra.stl", Stl());
  Write(dir + "/biped.xml", model);
  Write(dir + "/p.yaml", kBipedProfile);
  std::string error;
  ModelPtr m(LoadMujocoModel(dir + "/p.yaml", &error));
  ASSERT_TRUE(m) << error;
  EXPECT_EQ(m->nmesh, 1);
  // run from another folder: still found (the VFS name carries the model's folder)
  const fs::path here = fs::current_path();
  fs::current_path("/");
  ModelPtr again(LoadMujocoModel(dir + "/p.yaml", &error));
  fs::current_path(here);
  EXPECT_TRUE(again) << error;
}

// a URDF biped: a pelvis link, per leg a hip and a knee revolute joint and an ankle to a foot
// link with a 0.2 x 0.1 m box; no actuators (URDF has none), its root fixed by MuJoCo
std::string UrdfBiped() {
  auto link = [](const std::string& name, const std::string& geom) {
    return "<link name='" + name + "'><inertial><mass value='1'/><inertia ixx='0.01' ixy='0' ixz='0' "
           "iyy='0.01' iyz='0' izz='0.01'/></inertial><collision><geometry>" + geom +
           "</geometry></collision></link>";
  };
  auto joint = [](const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& xyz) {
    return "<joint name='" + name + "' type='revolute'><parent link='" + parent + "'/><child link='" +
           child + "'/><origin xyz='" + xyz + "'/><axis xyz='0 1 0'/>"
           "<limit lower='-2' upper='2' effort='100' velocity='10'/></joint>";
  };
  std::string u = "<robot name='urdf_biped'>" + link("pelvis", "<box size='0.2 0.3 0.1'/>");
  for (const std::string side : {"left", "right"}) {
    const std::string y = side == "left" ? "0.1" : "-0.1";
    u += link(side + "_thigh", "<cylinder radius='0.03' length='0.3'/>") +
         link(side + "_shin", "<cylinder radius='0.03' length='0.3'/>") +
         link(side + "_foot", "<box size='0.2 0.1 0.04'/>") +
         joint(side + "_hip", "pelvis", side + "_thigh", "0 " + y + " -0.1") +
         joint(side + "_knee", side + "_thigh", side + "_shin", "0 0 -0.3") +
         joint(side + "_ankle", side + "_shin", side + "_foot", "0 0 -0.3");
  }
  return u + "</robot>";
}

TEST(ProfileUrdf, AUrdfRobotGetsAFreeBaseActuatorsAndWhatBalanceNeeds) {
  const std::string dir = ScratchFolder("profile_urdf");
  Write(dir + "/biped.urdf", UrdfBiped());
  Write(dir + "/p.yaml", "model: biped.urdf\nbase: free\nactuators: {type: motor, torque_limit: 80}\n"
                         "feet: {left: {body: left_foot}, right: {body: right_foot}}\n"
                         "stand: {joints: {left_knee: 0.3, right_knee: 0.3}}\n");
  std::string error;
  auto k = Kinematics::Load(dir + "/p.yaml", &error);
  ASSERT_TRUE(k) << error;
  EXPECT_TRUE(k->floating());
  ASSERT_EQ(k->njoint(), 6);
  for (const JointMap& j : k->robot().joints) EXPECT_DOUBLE_EQ(j.tau_max, 80.0) << j.name;
  ASSERT_GE(k->left_sole(), 0);
  ASSERT_GE(k->right_sole(), 0);
  EXPECT_NEAR(k->soles()[k->left_sole()].half_size[0], 0.1, 1e-9);  // the foot box, derived
  for (int side : {k->left_sole(), k->right_sole()}) EXPECT_GE(k->soles()[side].force_sensor, 0);
  EXPECT_EQ(k->robot().imus.size(), 1u);
  EXPECT_GE(mj_name2id(k->m(), mjOBJ_KEY, "stand"), 0);
  // nothing beside the model
  std::set<std::string> files;
  for (const auto& f : fs::directory_iterator(dir)) files.insert(f.path().filename().string());
  EXPECT_EQ(files, (std::set<std::string>{"biped.urdf", "p.yaml"}));
  // a joint the URDF does not have, and a second free joint: both listed
  Write(dir + "/bad.yaml", "model: biped.urdf\nactuators: {type: position, kp: 100, joints: [left_hip, left_toe]}\n"
                           "feet: {left: {body: left_foot}, right: {body: right_foot}}\n");
  EXPECT_FALSE(LoadMujocoModel(dir + "/bad.yaml", &error));
  EXPECT_NE(error.find("actuators.joints: the model has no joint 'left_toe'"), std::string::npos) << error;
}

//---------------- G1 and H1 ----------------

std::string Repo() { return OHRP_SOURCE_DIR; }
bool HaveExternal() { return fs::exists(Repo() + "/../shared/external/menagerie/unitree_g1/scene.xml"); }

// what balance checks (controllers/src/balance_setup.cc MissingRequirements), robot side
void ExpectBalanceRequirements(const std::string& path) {
  std::string error;
  auto k = Kinematics::Load(path, &error);
  ASSERT_TRUE(k) << error;
  EXPECT_TRUE(k->floating());
  ASSERT_GE(k->left_sole(), 0) << path;
  ASSERT_GE(k->right_sole(), 0) << path;
  for (int side : {k->left_sole(), k->right_sole()}) {
    EXPECT_GE(k->soles()[side].force_sensor, 0) << path;
    EXPECT_NO_THROW(LimbIk::ForSole(*k, k->robot().base_body, side)) << path;
  }
  EXPECT_FALSE(k->robot().imus.empty()) << path;
  std::vector<std::pair<std::string, double>> stand;
  ASSERT_TRUE(KeyframeJointPositions(k->m(), "stand", &stand, &error)) << error;
  std::set<std::string> named;
  for (const auto& [n, q] : stand) named.insert(n);
  for (const JointMap& j : k->robot().joints) EXPECT_TRUE(named.count(j.name)) << j.name;
}

TEST(ProfileRobots, G1AndH1MeetBalancesRequirementsThroughTheirProfiles) {
  if (!HaveExternal()) GTEST_SKIP() << "no ../shared/external beside the repository";
  ExpectBalanceRequirements(Repo() + "/robots/g1.yaml");
  ExpectBalanceRequirements(Repo() + "/robots/h1.yaml");
  // H1's stance: h1_free.xml's 'stand' joints, the base height derived (that scene: 0.978 m)
  std::string error;
  ModelPtr m(LoadMujocoModel(Repo() + "/robots/h1.yaml", &error));
  ASSERT_TRUE(m) << error;
  EXPECT_NEAR(m->key_qpos[mj_name2id(m.get(), mjOBJ_KEY, "stand") * m->nq + 2], 0.978, 0.001);
}

TEST(ProfileRobots, EveryLoaderSeesTheSameModel) {
  if (!HaveExternal()) GTEST_SKIP() << "no ../shared/external beside the repository";
  const std::string path = Repo() + "/robots/g1.yaml";
  std::string error;
  auto scene = Scene::Load(path, &error);  // sim_host's
  ASSERT_TRUE(scene) << error;
  auto kin = Kinematics::Load(path, &error);  // a controller's
  ASSERT_TRUE(kin) << error;
  RobotMap robot;
  ASSERT_TRUE(MapRobot(scene->m(), &robot, &error)) << error;
  EXPECT_EQ(ModelHash(scene->m(), robot), ModelHash(kin->m(), kin->robot()));
  // and the profile changes the model: its hash is not the plain scene's
  auto plain = Scene::Load(Repo() + "/../shared/external/menagerie/unitree_g1/scene.xml", &error);
  ASSERT_TRUE(plain) << error;
  RobotMap plain_robot;
  ASSERT_TRUE(MapRobot(plain->m(), &plain_robot, &error)) << error;
  EXPECT_NE(ModelHash(plain->m(), plain_robot), ModelHash(scene->m(), robot));
}

TEST(ProfileDraft, DraftsForG1H1AndTheVrmlSampleLoadAndMeetTheRequirements) {
  if (!HaveExternal()) GTEST_SKIP() << "no ../shared/external beside the repository";
  const std::string dir = ScratchFolder("profile_draft");
  // G1, H1 and OpenHRP's sample robot (VRML, converted in memory, its own soles kept)
  for (const std::string& model : {Repo() + "/../shared/external/menagerie/unitree_g1/scene.xml",
                                   Repo() + "/scenarios/scenes/h1_free.xml",
                                   Repo() + "/../shared/external/openhrp3-sample/sample1.wrl"}) {
    const std::string out = dir + "/" + fs::path(model).stem().string() + ".yaml";
    std::string yaml, error;
    ASSERT_TRUE(DraftProfile(model, out, &yaml, &error)) << error;
    Write(out, yaml);
    ExpectBalanceRequirements(out);
  }
}

TEST(ProfileDraft, WhatCannotBeDerivedIsListedAtOnce) {
  const std::string dir = ScratchFolder("profile_draft_missing");
  Write(dir + "/arm.xml", "<mujoco><worldbody><body name='a'><joint name='j' axis='0 1 0'/>"
                          "<geom type='capsule' fromto='0 0 0 0 0 -0.3' size='0.03'/></body>"
                          "</worldbody></mujoco>");
  std::string yaml, error;
  EXPECT_FALSE(DraftProfile(dir + "/arm.xml", dir + "/p.yaml", &yaml, &error));
  EXPECT_NE(error.find("3 requirements not derivable (all listed)"), std::string::npos) << error;
  EXPECT_NE(error.find("a floating base"), std::string::npos) << error;
  EXPECT_NE(error.find("actuators"), std::string::npos) << error;
  EXPECT_NE(error.find("two feet"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::model
