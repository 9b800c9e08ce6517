// The robot profile's reader (robot_model/profile.h ReadProfile): errors with the file, line and
// key (and the plausible range), the servo key balance and walk take their defaults from, and
// the self-collision file controllers load by default.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../common/scratch.h"
#include "robot_model/profile.h"

namespace ohrp::model {
namespace {

using ohrp::testing::ScratchFolder;

void Write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string Error(const std::string& yaml) {
  const std::string dir = ScratchFolder("profile_errors");
  Write(dir + "/p.yaml", yaml);
  RobotProfile p;
  std::string error;
  EXPECT_FALSE(ReadProfile(dir + "/p.yaml", &p, &error)) << yaml;
  return error.substr(error.find("p.yaml"));
}

TEST(ProfileRead, ErrorsNameTheFileLineKeyAndRange) {
  EXPECT_EQ(Error("model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\nhands: 2\n"),
            "p.yaml:5: hands: unknown key (known: actuators, base, chains, contact, contact_file, feet, force_torque, "
            "groups, imu, joint_file, model, self_collision, sensor_file, servo, sole_thickness, stand, walking)");
  // a self-collision file that is not there, with the profile's line
  EXPECT_EQ(Error("model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n"
                  "self_collision: none.yaml\n").substr(0, 40),
            "p.yaml:5: self_collision: no such file: ");
  const std::string size = Error("model: a.xml\nfeet:\n  left: {body: l}\n  right:\n    body: r\n"
                                 "    sole: {size: [0.2, 5], centre: [0, 0, 0]}\n");
  EXPECT_EQ(size.rfind("p.yaml:6: feet.right.sole.size[1]: = 5 is outside the plausible range", 0), 0u) << size;
  EXPECT_NE(size.find("[0.001, 1] m"), std::string::npos) << size;
  EXPECT_EQ(Error("model: a.xml\nfeet:\n  left: {body: l}\n"),
            "p.yaml:3: feet: needs right (its body, and its sole)");
  EXPECT_EQ(Error("feet: {}\n"), "p.yaml:1: model: missing (the robot's MJCF, VRML or URDF file)");
  EXPECT_EQ(Error("model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\ncontact: hard\n"),
            "p.yaml:5: contact: must be soft or native");
  EXPECT_EQ(Error("model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n"
                  "stand: {keyframe: a, joints: {k: 1}}\n"),
            "p.yaml:5: stand: needs either keyframe (a keyframe's name) or joints (name: angle)");
  EXPECT_EQ(Error("model: a.xml\n  - bad: [\n"), "p.yaml:2: not valid YAML: illegal map value");
  const std::string feet = "model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n";
  EXPECT_EQ(Error(feet + "servo: {frequency: 80}\n"),
            "p.yaml:5: servo.frequency: must be at most 50 Hz (balance's --servo-hz)");
  EXPECT_EQ(Error(feet + "servo: {load_feedforward: maybe}\n"),
            "p.yaml:5: servo.load_feedforward: must be true or false");
  EXPECT_EQ(Error(feet + "servo: {kp: 3}\n"),
            "p.yaml:5: servo.kp: unknown key (known: frequency, load_feedforward)");
}

TEST(ProfileRead, TheServoIsRead) {
  const std::string dir = ScratchFolder("profile_servo");
  Write(dir + "/p.yaml", "model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n"
                         "servo: {frequency: 8, load_feedforward: true}\n");
  RobotProfile p;
  std::string error;
  ASSERT_TRUE(ReadProfile(dir + "/p.yaml", &p, &error)) << error;
  EXPECT_EQ(p.servo_frequency, 8.0);
  EXPECT_TRUE(p.load_feedforward);
  Write(dir + "/q.yaml", "model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n");
  ASSERT_TRUE(ReadProfile(dir + "/q.yaml", &p, &error)) << error;
  EXPECT_EQ(p.servo_frequency, 0.0);
  EXPECT_FALSE(p.load_feedforward);
}

// self_collision: a file beside the profile, resolved against its folder
TEST(ProfileRead, TheSelfCollisionFileIsResolvedBesideTheProfile) {
  const std::string dir = ScratchFolder("profile_self_collision");
  Write(dir + "/sc.yaml", "robot: x\n");
  Write(dir + "/p.yaml", "model: a.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n"
                         "self_collision: sc.yaml\n");
  RobotProfile p;
  std::string error;
  ASSERT_TRUE(ReadProfile(dir + "/p.yaml", &p, &error)) << error;
  EXPECT_EQ(p.self_collision_file, dir + "/sc.yaml");
}

}  // namespace
}  // namespace ohrp::model
