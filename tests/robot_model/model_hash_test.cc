// Tests the robot model's identity (model_hash.h): the hash is the same for two loads of the
// same robot and for the same robot on another floor, and changes when a mass, an axis, a limit,
// a body position or the joint order changes; CheckModelMatches names each such difference
// against the header a real Producer wrote from MakeProducerConfig.
#include "common/scratch.h"
#include "robot_model/model_hash.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "shm_bridge/bridge.h"

namespace ohrp::model {
namespace {

namespace fs = std::filesystem;

const std::string kRobotDir = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/";

// a loaded scene and its robot map
struct Loaded {
  std::unique_ptr<Scene> scene;
  RobotMap robot;
  uint64_t hash() const { return ModelHash(scene->m(), robot); }
};

using ohrp::testing::ReadFile;

// number of occurrences of `what` in `text`
int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

class ModelHashTest : public ::testing::Test {
 protected:
  void SetUp() override {
    InstallMujocoHandlers(nullptr);
    dir_ = ohrp::testing::ScratchFolder(
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    robot_xml_ = ReadFile(kRobotDir + "hrp1s.xml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  Loaded Load(const std::string& path) {
    Loaded l;
    std::string error;
    l.scene = Scene::Load(path, &error);
    EXPECT_NE(l.scene, nullptr) << error;
    if (l.scene && !MapRobot(l.scene->m(), &l.robot, &error)) ADD_FAILURE() << error;
    return l;
  }
  // hrp1s.xml with each `from` (which must occur exactly once) replaced by its `to`, as a temp
  // file
  std::string Edited(const std::vector<std::pair<std::string, std::string>>& edits) {
    std::string text = robot_xml_;
    for (const auto& [from, to] : edits) {
      EXPECT_EQ(Count(text, from), 1) << "'" << from << "' is not unique in hrp1s.xml";
      const std::size_t at = text.find(from);
      if (at != std::string::npos) text.replace(at, from.size(), to);
    }
    const std::string path = (dir_ / "edited.xml").string();
    std::ofstream(path) << text;
    return path;
  }
  std::string Edited(const std::string& from, const std::string& to) {
    return Edited({{from, to}});
  }
  // the header a real producer publishes for `l` (created, copied, removed)
  shm::SegmentHeader Published(const Loaded& l) {
    const std::string segment = "hashtest_" + std::to_string(getpid());
    shm::ProducerConfig config = MakeProducerConfig(l.robot, l.scene->m(), segment, 0.001, 0.005);
    shm::Status status;
    auto producer = shm::Producer::Create(config, &status);
    EXPECT_NE(producer, nullptr) << status.message;
    return producer ? producer->header() : shm::SegmentHeader{};
  }
  // the index of joint `name` in the segment's order
  static int JointId(const Loaded& l, const std::string& name) {
    for (std::size_t i = 0; i < l.robot.joints.size(); ++i) {
      if (l.robot.joints[i].name == name) return static_cast<int>(i);
    }
    return -1;
  }
  // CheckModelMatches of the model at `path` against the original robot's header
  std::string CheckAgainstOriginal(const std::string& path) {
    const Loaded original = Load(kRobotDir + "hrp1s.xml");
    const Loaded edited = Load(path);
    if (!original.scene || !edited.scene) return "(not loaded)";
    EXPECT_NE(original.hash(), edited.hash());
    return CheckModelMatches(edited.scene->m(), edited.robot, Published(original));
  }

  fs::path dir_;
  std::string robot_xml_;
};

// every refusal ends with both hashes
void ExpectEndsWithHashes(const std::string& message) {
  EXPECT_TRUE(std::regex_search(message, std::regex("; model hash 0x[0-9a-f]{16} in the segment, "
                                                    "0x[0-9a-f]{16} here$")))
      << message;
}

//---------------- same robot, same hash ----------------

TEST_F(ModelHashTest, TwoLoadsOfTheSameFileHashTheSame) {
  const Loaded a = Load(kRobotDir + "scene_flat.xml");
  const Loaded b = Load(kRobotDir + "scene_flat.xml");
  EXPECT_EQ(a.hash(), b.hash());
  EXPECT_NE(a.hash(), 0u);
  EXPECT_NE(a.hash(), shm::kFnv1aOffsetBasis);
  EXPECT_EQ(CheckModelMatches(b.scene->m(), b.robot, Published(a)), "");
}

TEST_F(ModelHashTest, TheSameRobotOnAnotherFloorHashesTheSame) {
  const Loaded flat = Load(kRobotDir + "scene_flat.xml");
  const shm::SegmentHeader header = Published(flat);
  for (const char* scene : {"scene_slope.xml", "scene_rough.xml", "scene_stairs.xml",
                            "scene_uneven.xml", "hrp1s.xml"}) {
    const Loaded other = Load(kRobotDir + scene);
    EXPECT_EQ(other.hash(), flat.hash()) << scene;
    // the scenes name the model differently: a note only, not a refusal
    EXPECT_EQ(CheckModelMatches(other.scene->m(), other.robot, header), "") << scene;
  }
}

TEST_F(ModelHashTest, TheFreeBasesStartingPoseIsNotPartOfTheRobot) {
  const Loaded original = Load(kRobotDir + "hrp1s.xml");
  const Loaded raised = Load(Edited(R"(<body name="WAIST" pos="0 0 0.7235">)",
                                    R"(<body name="WAIST" pos="0.3 0 0.9" euler="0 0 1">)"));
  EXPECT_EQ(raised.hash(), original.hash());
}

TEST_F(ModelHashTest, NegativeZeroHashesAsZero) {
  const Loaded original = Load(kRobotDir + "hrp1s.xml");
  const Loaded negative = Load(Edited(R"(<body name="CHEST" pos="0 0 0.35">)",
                                      R"(<body name="CHEST" pos="-0 -0 0.35">)"));
  EXPECT_EQ(negative.hash(), original.hash());
}

TEST_F(ModelHashTest, MakeProducerConfigCarriesTheIdentity) {
  const Loaded l = Load(kRobotDir + "scene_flat.xml");
  const shm::SegmentHeader h = Published(l);
  EXPECT_EQ(h.model_hash, l.hash());
  // closed forms from hrp1s.xml: 29 motors, 130.8 kg (README), CHEST's axis z, WAIST_R's body 30 kg
  EXPECT_EQ(h.njoint, 29);
  EXPECT_NEAR(h.total_mass, 130.8, 1e-9);
  EXPECT_EQ(h.nbody, l.scene->m()->nbody - 1);  // every body but the world is the robot's
  const int chest = JointId(l, "CHEST");
  ASSERT_GE(chest, 0);
  EXPECT_EQ(h.joint_axis[chest][0], 0.0);
  EXPECT_EQ(h.joint_axis[chest][1], 0.0);
  EXPECT_EQ(h.joint_axis[chest][2], 1.0);
  EXPECT_EQ(h.link_mass[JointId(l, "WAIST_R")], 30.0);
}

//---------------- a different robot, named ----------------

TEST_F(ModelHashTest, AJointCountDifferenceIsNamed) {
  // CHEST loses its motor (and the motor's torque sensor): a passive joint
  const std::string m = CheckAgainstOriginal(Edited(
      {{R"(<motor name="CHEST" joint="CHEST" gear="1" ctrllimited="true" ctrlrange="-300 300" forcelimited="true" forcerange="-300 300"/>)",
        ""},
       {R"(<actuatorfrc name="tau_CHEST" actuator="CHEST"/>)", ""}}));
  EXPECT_NE(m.find("the producer's robot is not this model's robot: the segment has 29 joints, "
                   "this model 28"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, AJointOrderDifferenceNamesTheFirstJoint) {
  const std::string hip_r =
      R"(<motor name="RLEG_HIP_R" joint="RLEG_HIP_R" gear="1" ctrllimited="true" ctrlrange="-400 400" forcelimited="true" forcerange="-400 400"/>)";
  const std::string hip_p =
      R"(<motor name="RLEG_HIP_P" joint="RLEG_HIP_P" gear="1" ctrllimited="true" ctrlrange="-400 400" forcelimited="true" forcerange="-400 400"/>)";
  const std::string m = CheckAgainstOriginal(Edited(hip_r + "  <!-- jointId 0 -->\n    " + hip_p,
                                                    hip_p + "  <!-- jointId 0 -->\n    " + hip_r));
  EXPECT_NE(m.find(": joint 0 is 'RLEG_HIP_R' in the segment, 'RLEG_HIP_P' here;"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, ALimitDifferenceIsNamed) {
  const Loaded original = Load(kRobotDir + "hrp1s.xml");
  const int chest = JointId(original, "CHEST");
  const std::string m = CheckAgainstOriginal(Edited(
      R"(<joint name="CHEST" type="hinge" axis="0 0 1" limited="true" range="-1.5708 1.5708")",
      R"(<joint name="CHEST" type="hinge" axis="0 0 1" limited="true" range="-1.5708 1.2")"));
  EXPECT_NE(m.find(": joint " + std::to_string(chest) +
                   " 'CHEST' limits are [-1.5708, 1.5708] in the segment, [-1.5708, 1.2] here"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, AnAxisDifferenceIsNamed) {
  const Loaded original = Load(kRobotDir + "hrp1s.xml");
  const int chest = JointId(original, "CHEST");
  const std::string m = CheckAgainstOriginal(Edited(
      R"(<joint name="CHEST" type="hinge" axis="0 0 1")",
      R"(<joint name="CHEST" type="hinge" axis="0 0 -1")"));
  EXPECT_NE(m.find(": joint " + std::to_string(chest) +
                   " 'CHEST' axis is (0, 0, 1) in the segment, (0, 0, -1) here"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, ALinkMassDifferenceIsNamed) {
  const Loaded original = Load(kRobotDir + "hrp1s.xml");
  const int waist_r = JointId(original, "WAIST_R");
  const std::string m = CheckAgainstOriginal(
      Edited(R"(<inertial pos="0 0 0.16" mass="30")", R"(<inertial pos="0 0 0.16" mass="31.5")"));
  EXPECT_NE(m.find(": joint " + std::to_string(waist_r) +
                   " 'WAIST_R' moves a body of 30 kg in the segment, 31.5 kg here"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, ABaseMassDifferenceIsNamedAsTheTotalMass) {
  // WAIST carries the free joint, no segment joint: only the total sees it
  const std::string m = CheckAgainstOriginal(Edited(
      R"(<inertial pos="0 0 0.0375" mass="27")", R"(<inertial pos="0 0 0.0375" mass="28")"));
  EXPECT_NE(m.find(": the robot's total mass is 130.8 kg in the segment, 131.8 kg here;"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, ABodyPositionDifferenceIsNamedAsTheTree) {
  const std::string m = CheckAgainstOriginal(Edited(R"(<body name="CHEST" pos="0 0 0.35">)",
                                                    R"(<body name="CHEST" pos="0 0 0.36">)"));
  EXPECT_NE(m.find(": same joints, limits, axes and masses, but the kinematic tree differs "
                   "(body positions, inertias or passive joints); model hash 0x"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, AnInertiaDifferenceIsNamedAsTheTree) {
  const std::string m = CheckAgainstOriginal(
      Edited(R"(mass="30" diaginertia="0.27 0.27 0.0125")", R"(mass="30" diaginertia="0.28 0.27 0.0125")"));
  EXPECT_NE(m.find("but the kinematic tree differs"), std::string::npos) << m;
}

TEST_F(ModelHashTest, ADifferentRobotNameIsANoteBeforeTheDifference) {
  const std::string renamed = (dir_ / "renamed.xml").string();
  {
    std::string text = ReadFile(Edited(R"(<inertial pos="0 0 0.0375" mass="27")",
                                       R"(<inertial pos="0 0 0.0375" mass="28")"));
    text.replace(text.find(R"(<mujoco model="hrp1s">)"), 22, R"(<mujoco model="hrp2">)");
    std::ofstream(renamed) << text;
  }
  const std::string m = CheckAgainstOriginal(renamed);
  EXPECT_NE(m.find("the producer's robot is not this model's robot (model names, not compared: "
                   "'hrp1s' in the segment, 'hrp2' here): the robot's total mass is 130.8 kg"),
            std::string::npos)
      << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, AProducerWithoutAHashIsRefused) {
  const Loaded l = Load(kRobotDir + "hrp1s.xml");
  shm::SegmentHeader h = Published(l);
  h.model_hash = 0;
  const std::string m = CheckModelMatches(l.scene->m(), l.robot, h);
  EXPECT_NE(m.find("the producer publishes no model hash"), std::string::npos) << m;
  ExpectEndsWithHashes(m);
}

TEST_F(ModelHashTest, AnInsaneJointCountInTheHeaderIsClamped) {
  const Loaded l = Load(kRobotDir + "hrp1s.xml");
  shm::SegmentHeader h = Published(l);
  h.model_hash ^= 1;
  h.njoint = 100000;
  const std::string m = CheckModelMatches(l.scene->m(), l.robot, h);
  EXPECT_NE(m.find("the segment has 64 joints, this model 29"), std::string::npos) << m;
}

}  // namespace
}  // namespace ohrp::model
