// Tests that a self-collision file cannot lie (collision/pair_file.h, issue 29): each damaged copy
// of the shipped HRP-1S file is refused with its file, line and key (lists that lose or
// contradict pairs, a range over the whole joint, a shape edited by hand: the checksum), and a
// hand made bigger in the MJCF changes the model hash the file is checked against.
#include <gtest/gtest.h>

#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>

#include "collision/from_mjcf.h"
#include "collision/pair_file.h"
#include "common/scratch.h"
#include "robot_model/model.h"
#include "robot_model/model_hash.h"

namespace ohrp::collision {
namespace {

const std::string kShipped = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";

std::string Text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream t;
  t << in.rdbuf();
  return t.str();
}

std::string V(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << std::setprecision(17) << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

class DamagedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    text_ = Text(kShipped);
    std::string error;
    ASSERT_TRUE(ReadSelfCollisionFile(kShipped, &file_, &error)) << error;
    ASSERT_FALSE(file_.online.empty());
    ASSERT_FALSE(file_.ranges.empty());
  }
  // `text` written to a scratch file and read: the error (empty when accepted)
  std::string Read(const std::string& text) {
    const std::string path = ohrp::testing::ScratchPath("damaged", ".yaml");
    std::ofstream(path) << text;
    SelfCollisionFile f;
    std::string error;
    if (ReadSelfCollisionFile(path, &f, &error)) return "";
    EXPECT_EQ(error.rfind(path + ":", 0), 0u) << "not 'path:line: ...': " << error;
    return error;
  }
  // the line of the file that starts with `prefix`, replaced by `to`
  std::string ReplaceLine(const std::string& prefix, const std::string& to) {
    std::string t = text_;
    const size_t at = t.find("\n" + prefix) + 1;
    EXPECT_NE(at, 0u) << prefix;
    t.replace(at, t.find('\n', at) - at, to);
    return t;
  }
  std::string Pair(LinkPair p) const {
    return "[" + file_.robot.links[p.a].name + ", " + file_.robot.links[p.b].name + "]";
  }
  std::string text_;
  SelfCollisionFile file_;
};

TEST_F(DamagedFile, TheShippedFileIsAcceptedAndWritesBackTheSame) {
  EXPECT_EQ(Read(text_), "");
  EXPECT_EQ(SelfCollisionYaml(file_), text_);
  EXPECT_EQ(file_.structural_floor.size(), file_.structural.size());
}

TEST_F(DamagedFile, AnEmptyOnlineListIsRefused) {
  const std::string e = Read(ReplaceLine("online:", "online: []"));
  EXPECT_NE(e.find("online: pair"), std::string::npos) << e;
  EXPECT_NE(e.find("is in no list"), std::string::npos) << e;
}

TEST_F(DamagedFile, ADeletedOnlinePairIsRefused) {
  std::string t = text_;
  const std::string first = Pair(file_.online[0]) + ", ";
  const size_t at = t.find("online: [") + 9;
  ASSERT_EQ(t.compare(at, first.size(), first), 0) << t.substr(at, 60);
  t.erase(at, first.size());
  const std::string e = Read(t);
  EXPECT_NE(e.find("pair " + Pair(file_.online[0]) + " is in no list"), std::string::npos) << e;
}

TEST_F(DamagedFile, APairBothOnlineAndNeverIsRefused) {
  std::string t = text_;
  const size_t at = t.find("\nnever: [") + 9;
  t.insert(at, Pair(file_.online[0]) + (file_.never.empty() ? "" : ", "));
  const std::string e = Read(t);
  EXPECT_NE(e.find("never: pair " + Pair(file_.online[0]) + " is also in online"), std::string::npos) << e;
}

TEST_F(DamagedFile, ARangeWidenedToTheWholeJointIsRefused) {
  const SafeRange& r = file_.ranges[0];
  const std::string joint = file_.robot.joint_names[r.joint];
  std::ostringstream limits;
  limits << std::setprecision(17) << "min: " << file_.robot.q_min[r.joint]
         << ", max: " << file_.robot.q_max[r.joint] << ",";
  const std::string t = std::regex_replace(
      text_, std::regex("(\\{joint: " + joint + ", )min: [^,]+, max: [^,]+,"), "$1" + limits.str());
  ASSERT_NE(t, text_);
  const std::string e = Read(t);
  EXPECT_NE(e.find("safe_ranges: the range of " + joint + " covers its whole range"), std::string::npos) << e;
}

TEST_F(DamagedFile, AHandShrunkTenTimesFailsTheChecksum) {
  const int hand = FindLink(file_.robot, "RARM_WRIST_R");
  ASSERT_GE(hand, 0);
  const Eigen::Vector3d size = file_.robot.links[hand].shapes[0].size;
  std::string t = text_;
  const size_t link = t.find("- name: RARM_WRIST_R\n");
  const size_t at = t.find("size: " + V(size), link);
  ASSERT_NE(at, std::string::npos);
  t.replace(at, 6 + V(size).size(), "size: " + V(size / 10));
  const std::string e = Read(t);
  EXPECT_NE(e.find("checksum: the text does not hash to it: edited by hand"), std::string::npos) << e;
  // a file without its checksum line
  const std::string cut = text_.substr(0, text_.rfind("checksum:"));
  EXPECT_NE(Read(cut).find("checksum: missing"), std::string::npos);
}

TEST_F(DamagedFile, FloorsForEveryStructuralPair) {
  ASSERT_FALSE(file_.structural_floor.empty());
  const std::string e = Read(ReplaceLine("structural_floor:", "structural_floor: [0.001]"));
  EXPECT_NE(e.find("structural_floor: has 1 floors for"), std::string::npos) << e;
}

// a 6 cm block added to the right hand: the model hash (which the file carries and every reader
// compares with the model's) differs; so does the geometry's
TEST(StaleFile, ABlockAddedToAHandChangesTheModelHash) {
  const std::string xml = Text(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml");
  const std::string anchor = "<inertial pos=\"0 0.03 -0.1\" mass=\"0.4\"";
  const size_t body = xml.find("<body name=\"RARM_WRIST_R\">");
  ASSERT_NE(body, std::string::npos);
  std::string edited = xml;
  edited.insert(edited.find(anchor, body),
                "<geom type=\"box\" size=\"0.03 0.03 0.03\" pos=\"0 0.03 -0.2\" mass=\"0\"/>\n");
  const std::string path = ohrp::testing::ScratchPath("hrp1s_block", ".xml");
  std::ofstream(path) << edited;
  auto hash = [](const std::string& p, RobotGeometry* g) {
    std::string error;
    mjModel* m = mj_loadXML(p.c_str(), nullptr, nullptr, 0);
    EXPECT_TRUE(m) << p;
    if (!m) return uint64_t{0};
    model::RobotMap robot;
    EXPECT_TRUE(model::MapRobot(m, &robot, &error)) << error;
    EXPECT_TRUE(GeometryFromModel(m, robot, g, &error)) << error;
    const uint64_t h = model::ModelHash(m, robot);
    mj_deleteModel(m);
    return h;
  };
  RobotGeometry original, blocked;
  const uint64_t h0 = hash(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml", &original);
  const uint64_t h1 = hash(path, &blocked);
  EXPECT_NE(h0, h1);
  EXPECT_EQ(blocked.model_hash, h1);
  SelfCollisionFile f;
  std::string error;
  ASSERT_TRUE(ReadSelfCollisionFile(kShipped, &f, &error)) << error;
  EXPECT_EQ(f.robot.model_hash, h0) << "regenerate " << kShipped;
  EXPECT_NE(f.robot.model_hash, h1);
  // the block is in the geometry too
  const int hand = FindLink(blocked, "RARM_WRIST_R");
  ASSERT_GE(hand, 0);
  EXPECT_EQ(blocked.links[hand].shapes.size(), original.links[hand].shapes.size() + 1);
}

}  // namespace
}  // namespace ohrp::collision
