// Which self-collision file a controller loads when none is given (controllers/src/
// self_collision_choice.h): a robot profile's `self_collision:` file (robots/*.yaml of the data
// folder) whose model hash is the segment's; else the default (HRP-1S's), which for another robot
// means no check with a WARNING naming the profile files that are for this robot's other models.
// A file given on the command line is taken as given. The data folder is a scratch one
// ($OHRP_DATA_DIR, cli/data_dir.h).
#include "self_collision_choice.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "collision/pair_file.h"
#include "common/scratch.h"

namespace ohrp::controllers {
namespace {

namespace fs = std::filesystem;
const std::string kFile = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";

shm::SegmentHeader Header(const collision::SelfCollisionFile& f, uint64_t hash) {
  shm::SegmentHeader h{};
  h.njoint = static_cast<int>(f.robot.joint_names.size());
  h.model_hash = hash;
  std::strncpy(h.robot_name, f.robot.name.c_str(), sizeof(h.robot_name) - 1);
  for (int j = 0; j < h.njoint; ++j)
    std::strncpy(h.joint_names[j], f.robot.joint_names[j].c_str(), shm::kNameLen - 1);
  return h;
}

class ChoiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(collision::ReadSelfCollisionFile(kFile, &file_, &error)) << error;
    // a data folder whose robots/ holds a profile naming a copy of HRP-1S's file beside it,
    // a profile without the key and one that is not YAML
    data_ = ohrp::testing::ScratchDir() + "/choice_data";
    fs::create_directories(data_ + "/robots");
    fs::copy_file(kFile, data_ + "/robots/mine_selfcollision.yaml", fs::copy_options::overwrite_existing);
    std::ofstream(data_ + "/robots/mine.yaml") << "model: x.xml\nself_collision: mine_selfcollision.yaml\n";
    std::ofstream(data_ + "/robots/other.yaml") << "model: y.xml\n";
    std::ofstream(data_ + "/robots/broken.yaml") << "model: [\n";
    setenv("OHRP_DATA_DIR", data_.c_str(), 1);
    options_.self_collision = kFile;  // the default, as AddRunOptions sets it
    options_.self_collision_is_default = true;
  }
  void TearDown() override { unsetenv("OHRP_DATA_DIR"); }

  collision::SelfCollisionFile file_;
  std::string data_;
  RunOptions options_;
  std::ostringstream err_;
};

TEST_F(ChoiceTest, TheProfilesFilesAreListed) {
  const auto files = ProfileSelfCollisionFiles();
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0], data_ + "/robots/mine_selfcollision.yaml");
}

TEST_F(ChoiceTest, AProfilesFileForThisModelIsTheDefault) {
  const auto h = Header(file_, file_.robot.model_hash);
  EXPECT_EQ(SelfCollisionFileFor(options_, h, "prog", err_), data_ + "/robots/mine_selfcollision.yaml");
  EXPECT_EQ(err_.str(), "");
}

TEST_F(ChoiceTest, AGivenFileIsTakenAsGiven) {
  options_.self_collision_is_default = false;
  EXPECT_EQ(SelfCollisionFileFor(options_, Header(file_, file_.robot.model_hash), "prog", err_), kFile);
  options_.self_collision.clear();  // --no-self-collision
  EXPECT_EQ(SelfCollisionFileFor(options_, Header(file_, file_.robot.model_hash), "prog", err_), "");
}

// the same robot with another model: the profile's file does not fit it; the default, for this
// robot too, is returned and the guard refuses it (exit 3), never silently off
TEST_F(ChoiceTest, AnotherModelOfThisRobotGetsTheDefaultForTheGuardToRefuse) {
  const auto h = Header(file_, file_.robot.model_hash ^ 1);
  EXPECT_EQ(SelfCollisionFileFor(options_, h, "prog", err_), kFile);
}

TEST_F(ChoiceTest, AnotherRobotHasNoCheckWithAWarning) {
  auto h = Header(file_, 12345);
  std::strncpy(h.robot_name, "somebot", sizeof(h.robot_name) - 1);
  std::strncpy(h.joint_names[0], "other_joint", shm::kNameLen - 1);
  EXPECT_EQ(SelfCollisionFileFor(options_, h, "prog", err_), "");
  EXPECT_NE(err_.str().find("WARNING: no self-collision check"), std::string::npos) << err_.str();
  EXPECT_NE(err_.str().find("ohrp_selfcollision --model"), std::string::npos) << err_.str();
}

TEST_F(ChoiceTest, AProducerWithoutAModelHashHasNoCheck) {
  EXPECT_EQ(SelfCollisionFileFor(options_, Header(file_, 0), "prog", err_), "");
  EXPECT_NE(err_.str().find("publishes no model hash"), std::string::npos) << err_.str();
}

}  // namespace
}  // namespace ohrp::controllers
