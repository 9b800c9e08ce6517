// Tests ValidateConfig and Producer::Create's refusal of bad configurations: each mistake is
// reported as kInvalidConfig with a message naming the field, and no segment is created.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/checks.h"
#include "test_util.h"

namespace ohrp::shm {
namespace {

using testing::DevShmPath;
using testing::SmallConfig;

// the message of ValidateConfig after `edit` is applied to a valid config
template <class Edit>
Status ValidateEdited(Edit edit) {
  ProducerConfig c = SmallConfig("cfg");
  edit(c);
  return ValidateConfig(c);
}

void ExpectInvalid(const Status& s, const std::string& fragment) {
  EXPECT_EQ(s.code, Error::kInvalidConfig) << s.message;
  EXPECT_NE(s.message.find(fragment), std::string::npos)
      << "message '" << s.message << "' should mention '" << fragment << "'";
}

TEST(ValidateConfig, AcceptsTheSmallConfig) {
  const Status s = ValidateConfig(SmallConfig("cfg"));
  EXPECT_TRUE(s.ok()) << s.message;
}

TEST(ValidateConfig, AcceptsHardwareWithoutPhysicsPeriodAndEmptyGains) {
  const Status s = ValidateEdited([](ProducerConfig& c) {
    c.kind = ProducerKind::kHardware;
    c.physics_period = 0.0;
    c.default_kp.clear();
    c.default_kd.clear();
  });
  EXPECT_TRUE(s.ok()) << s.message;
}

TEST(ValidateConfig, NamesTheSegmentName) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.segment_name = ""; }), "segment_name");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.segment_name = "a/b"; }),
                "segment_name 'a/b'");
}

TEST(ValidateConfig, NamesTooManyJoints) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) {
                  c.joint_names.clear();
                  for (int i = 0; i <= kMaxJoints; ++i)
                    c.joint_names.push_back(std::string("j").append(std::to_string(i)));
                  c.q_min.clear();
                  c.q_max.clear();
                  c.tau_max.clear();
                  c.default_kp.clear();
                  c.default_kd.clear();
                }),
                "joint_names has 65 entries, the layout holds at most 64");
}

TEST(ValidateConfig, NamesTooManySensors) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) {
                  c.force_names = {"a", "b", "c", "d", "e"};
                }),
                "force_names has 5 entries");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) {
                  c.imu_names = {"a", "b", "c"};
                }),
                "imu_names has 3 entries");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.cameras.resize(kMaxCameras + 1); }),
                "cameras has 5 entries");
}

TEST(ValidateConfig, NamesTheLongName) {
  ExpectInvalid(
      ValidateEdited([](ProducerConfig& c) { c.joint_names[1] = std::string(kNameLen, 'k'); }),
      "joint_names[1]");
  ExpectInvalid(
      ValidateEdited([](ProducerConfig& c) { c.robot_name = std::string(kNameLen, 'r'); }),
      "robot_name");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.imu_names[0] = ""; }),
                "imu_names[0] is empty");
}

TEST(ValidateConfig, NamesARepeatedJoint) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.joint_names[2] = "hip"; }),
                "joint_names[2] 'hip' repeats joint_names[0]");
}

TEST(ValidateConfig, NamesAnInconsistentVector) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.q_max.pop_back(); }),
                "q_max has 2 entries, expected 0 or njoint = 3");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.default_kd.push_back(1.0); }),
                "default_kd has 4 entries");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.tau_max[1] = NAN; }), "tau_max[1] is NaN");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.q_min[2] = 1.0; }),
                "q_min[2] > q_max[2] (joint 'ankle')");
}

TEST(ValidateConfig, NamesNegativeOrInfiniteDefaultGains) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.default_kp[1] = -1.0; }),
                "default_kp[1] must be finite and >= 0");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.default_kd[0] = HUGE_VAL; }),
                "default_kd[0] must be finite and >= 0");
}

TEST(ValidateConfig, NamesABadModelIdentity) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.link_mass = {1.0, 2.0}; }),
                "link_mass has 2 entries, expected 0 or njoint = 3");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.link_mass = {1.0, -2.0, 1.0}; }),
                "link_mass[1] is negative");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.joint_axis = {{0, 0, 1}}; }),
                "joint_axis has 1 entries, expected 0 or njoint = 3");
  ExpectInvalid(
      ValidateEdited([](ProducerConfig& c) { c.joint_axis = {{0, 0, 1}, {0, NAN, 1}, {1, 0, 0}}; }),
      "joint_axis[1] is not finite");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.total_mass = -1.0; }),
                "total_mass must be >= 0 [kg]");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.nbody = -1; }), "nbody must be >= 0");
}

TEST(ValidateConfig, NamesABadPeriod) {
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.control_period = 0.0; }),
                "control_period must be > 0");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.physics_period = -0.001; }),
                "physics_period must be >= 0");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.physics_period = 0.01; }),
                "physics_period 0.010000 s is longer than control_period 0.005000 s");
  ExpectInvalid(ValidateEdited([](ProducerConfig& c) { c.read_timeout_hint = 0.0; }),
                "read_timeout_hint");
}

TEST(ValidateConfig, NamesABadCamera) {
  CameraInfo cam{};
  std::strcpy(cam.name, "head");
  cam.width = 640;
  cam.height = 0;
  cam.fovy = 45.0;
  ExpectInvalid(ValidateEdited([&](ProducerConfig& c) { c.cameras = {cam}; }),
                "cameras[0] 'head' has size 640x0");
}

TEST(ProducerCreate, RefusesAnInvalidConfigWithoutCreatingASegment) {
  const std::string name = testing::UniqueSegment("badcfg");
  testing::RemoveSegment(name);
  ProducerConfig c = SmallConfig(name);
  c.control_period = -1.0;
  Status status;
  auto producer = Producer::Create(c, &status);
  EXPECT_EQ(producer, nullptr);
  ExpectInvalid(status, "control_period");
  struct stat st {};
  EXPECT_NE(stat(DevShmPath(name).c_str(), &st), 0);
}

}  // namespace
}  // namespace ohrp::shm
