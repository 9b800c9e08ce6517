// Tests sim_host/effects.h: which effects a scene calls for, each resolution rule and
// dependency. That an effect switched off is really off, and the noise, are in
// effects_off_test.cc; `sim_host --explain` and the scenario key in effects_process_test.cc.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "effects_scenes.h"

namespace ohrp::sim {
namespace {

using testing::Apply;
using testing::kBoxes;
using testing::kFlat;
using testing::kPendulum;
using testing::Load;
using testing::Loaded;
using testing::LoadText;
using testing::Refused;
using testing::Resolve;

class EffectsFlat : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model::InstallMujocoHandlers(nullptr);
    flat_ = new Loaded(Load(kFlat));
  }
  static void TearDownTestSuite() { delete flat_; }
  static Loaded* flat_;
};
Loaded* EffectsFlat::flat_ = nullptr;

//---------------- resolution ----------------

TEST_F(EffectsFlat, DefaultsOfTheStandingScene) {
  const EffectsPlan p = Resolve(*flat_, "");
  EXPECT_TRUE(p.on(Effect::kGravity));
  EXPECT_TRUE(p.on(Effect::kJointLimits));
  EXPECT_TRUE(p.on(Effect::kPassive));  // damping 0.1 on every joint
  EXPECT_TRUE(p.on(Effect::kSoftContact));
  EXPECT_FALSE(p.on(Effect::kNativeContact)) << p[Effect::kNativeContact].reason;
  EXPECT_FALSE(p.on(Effect::kSelfContact));
  EXPECT_FALSE(p.on(Effect::kSelfCollision));  // declared (the robot has geometry), not asked for
  EXPECT_TRUE(p[Effect::kSelfCollision].declared);
  EXPECT_NE(p[Effect::kSelfCollision].reason.find("30 links have 406 non-adjacent pairs"), std::string::npos)
      << p[Effect::kSelfCollision].reason;
  EXPECT_TRUE(p.on(Effect::kForceTorque));
  EXPECT_TRUE(p.on(Effect::kAccelerometer));
  EXPECT_TRUE(p.on(Effect::kRnePost));
  EXPECT_EQ(p[Effect::kRnePost].reason, "needed by force_torque, accelerometer");
  EXPECT_FALSE(p.on(Effect::kOtherSensors));
  EXPECT_NE(p[Effect::kOtherSensors].reason.find("87 MuJoCo sensors"), std::string::npos);
  EXPECT_FALSE(p.on(Effect::kNoise));
  // on, but rendered only while a program asks (sim_host/cameras.h)
  EXPECT_TRUE(p.on(Effect::kCameras));
  EXPECT_NE(p[Effect::kCameras].reason.find("rendered only while an attached program asks"),
            std::string::npos);
  EXPECT_FALSE(p.on(Effect::kLog));
  EXPECT_FALSE(p.on(Effect::kLogForceTorque));
  // the soles' pairs with the floor exist, handed to the soft-foot contact; the ankles are
  // excluded from each other by the model
  ASSERT_EQ(p.pairs.size(), 2u);
  for (const auto& cp : p.pairs) {
    EXPECT_FALSE(cp.on);
    EXPECT_TRUE(cp.soles);
  }
}

TEST_F(EffectsFlat, NativeContactTakesTheSolePairs) {
  const EffectsPlan p = Resolve(*flat_, "", false, ContactModel::kNative);
  EXPECT_FALSE(p.on(Effect::kSoftContact));
  EXPECT_TRUE(p.on(Effect::kNativeContact));
  for (const auto& cp : p.pairs) EXPECT_TRUE(cp.on) << cp.name;
}

TEST_F(EffectsFlat, RnePostIsNeededByForceTorqueAndAccelerometer) {
  EffectsPlan p = Resolve(*flat_, "accelerometer=off");
  EXPECT_TRUE(p.on(Effect::kRnePost));
  EXPECT_EQ(p[Effect::kRnePost].reason, "needed by force_torque");
  p = Resolve(*flat_, "accelerometer=off,force_torque=off");
  EXPECT_FALSE(p.on(Effect::kRnePost));
  // switching the shared need off takes both (they were on by default)
  p = Resolve(*flat_, "rne_post=off");
  EXPECT_FALSE(p.on(Effect::kForceTorque));
  EXPECT_FALSE(p.on(Effect::kAccelerometer));
  EXPECT_EQ(p[Effect::kForceTorque].reason, "needs rne_post, which is off");
  EXPECT_TRUE(p.on(Effect::kGyro));  // a velocity-stage sensor: no need of it
  // asking for both is a conflict
  EXPECT_NE(Refused(*flat_, "rne_post=off,force_torque=on").find("force_torque=on needs rne_post"),
            std::string::npos);
}

TEST_F(EffectsFlat, LogChannelsNeedTheirSensors) {
  EffectsPlan p = Resolve(*flat_, "", true);
  EXPECT_TRUE(p.on(Effect::kLog));
  EXPECT_TRUE(p.on(Effect::kLogForceTorque));
  EXPECT_TRUE(p.on(Effect::kLogImu));
  p = Resolve(*flat_, "force_torque=off", true);
  EXPECT_FALSE(p.on(Effect::kLogForceTorque));
  EXPECT_EQ(p[Effect::kLogForceTorque].reason, "needs force_torque, which is off");
  EXPECT_TRUE(p.on(Effect::kRnePost));  // the accelerometer still needs it
  // a requested channel switches its sensor back on, and its sensor's needs
  p = Resolve(*flat_, "log_force_torque=on,accelerometer=off", true);
  EXPECT_TRUE(p.on(Effect::kForceTorque));
  EXPECT_TRUE(p.on(Effect::kRnePost));
  EXPECT_NE(Refused(*flat_, "log_force_torque=on,force_torque=off", true).find("needs force_torque"),
            std::string::npos);
  EXPECT_NE(Refused(*flat_, "log_imu=on").find("log_imu=on"), std::string::npos);  // no --log
  p = Resolve(*flat_, "log=off", true);
  EXPECT_FALSE(p.on(Effect::kLogJoints));
}

TEST_F(EffectsFlat, SelfCollisionIsOnWhenAsked) {
  const EffectsPlan p = Resolve(*flat_, "self_collision=on");
  EXPECT_TRUE(p.on(Effect::kSelfCollision));
  EXPECT_EQ(p[Effect::kSelfCollision].reason, "switched on by request");
  // no physics changes with it: MuJoCo's contact stays off, the pairs as without it
  EXPECT_FALSE(p.on(Effect::kNativeContact));
  EXPECT_FALSE(p.on(Effect::kSelfContact));
  EXPECT_EQ(p.pairs.size(), Resolve(*flat_, "").pairs.size());
}

TEST_F(EffectsFlat, WhatCannotBeSwitchedOnIsRefused) {
  EXPECT_NE(Refused(LoadText(kPendulum), "cameras=on").find("the scene declares no camera"),
            std::string::npos);
  EXPECT_FALSE(Resolve(*flat_, "cameras=off").on(Effect::kCameras));
  EXPECT_NE(Refused(*flat_, "soft_contact=off").find("--contact"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "self_contact=on").find("cannot be switched on"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "native_contact=on").find("cannot be switched on"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "contact:WAIST/world=off").find("no such colliding body pair"),
            std::string::npos);
  EXPECT_NE(Refused(*flat_, "grav=off").find("unknown effect 'grav'"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "gravity=maybe").find("on or off"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "noise.force=-1").find("standard deviation"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "noise.color=1").find("unknown noise kind"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "contact:LLEG_ANKLE_R=off").find("two bodies"), std::string::npos);
}

TEST(Effects, ModelWithoutSolesOrSensors) {
  model::InstallMujocoHandlers(nullptr);
  const Loaded l = LoadText(kPendulum);
  const EffectsPlan p = Resolve(l, "");
  EXPECT_TRUE(p.on(Effect::kGravity));
  EXPECT_FALSE(p.on(Effect::kJointLimits));
  EXPECT_EQ(p[Effect::kJointLimits].reason, "no limited joint or tendon in the scene");
  EXPECT_FALSE(p.on(Effect::kPassive));
  EXPECT_FALSE(p.on(Effect::kSoftContact));
  EXPECT_EQ(p[Effect::kSoftContact].reason, "--contact native (the model has no *_SOLE geoms)");
  EXPECT_FALSE(p.on(Effect::kNativeContact));
  EXPECT_FALSE(p.on(Effect::kForceTorque));
  EXPECT_FALSE(p.on(Effect::kGyro));
  EXPECT_FALSE(p.on(Effect::kRnePost));
  EXPECT_TRUE(p.on(Effect::kEncoders));
  EXPECT_EQ(p[Effect::kCameras].reason, "the scene declares no camera");
  const std::string table = p.Table();
  EXPECT_NE(table.find("force_torque       off    the scene declares no F/T sensor"), std::string::npos)
      << table;
  EXPECT_EQ(table.find("contact pairs"), std::string::npos);  // none
  EXPECT_NE(Refused(l, "force_torque=on").find("the scene declares no F/T sensor"), std::string::npos);
  // one link: nothing for the self-collision check
  EXPECT_NE(Refused(l, "self_collision=on").find("no two non-adjacent links"), std::string::npos);
}

TEST(Effects, SelfContactNeedsNativeContact) {
  model::InstallMujocoHandlers(nullptr);
  // the hand's sphere overlaps the arm's (its grandparent: not filtered as parent-child); the
  // forearm's overlaps both but is the child of one and the parent of the other (filtered)
  Loaded l = LoadText(kBoxes);
  EffectsPlan p = Resolve(l, "");
  EXPECT_TRUE(p.on(Effect::kNativeContact));
  EXPECT_TRUE(p.on(Effect::kSelfContact)) << p[Effect::kSelfContact].reason;
  std::vector<std::string> self;
  for (const auto& cp : p.pairs)
    if (cp.self) self.push_back(cp.name);
  EXPECT_EQ(self, std::vector<std::string>{"arm/hand"});
  // contacts between two bodies after Reset's mj_forward
  auto contacts = [](const Loaded& x, const char* b1, const char* b2) {
    const mjModel* m = x.scene->m();
    const int i1 = mj_name2id(m, mjOBJ_BODY, b1), i2 = mj_name2id(m, mjOBJ_BODY, b2);
    int n = 0;
    for (int c = 0; c < x.scene->d()->ncon; ++c) {
      const int g1 = m->geom_bodyid[x.scene->d()->contact[c].geom1];
      const int g2 = m->geom_bodyid[x.scene->d()->contact[c].geom2];
      n += (g1 == i1 && g2 == i2) || (g1 == i2 && g2 == i1);
    }
    return n;
  };
  Apply(l, p);
  EXPECT_EQ(contacts(l, "arm", "hand"), 1);
  p = Resolve(l, "native_contact=off");
  EXPECT_FALSE(p.on(Effect::kSelfContact));
  EXPECT_EQ(p[Effect::kSelfContact].reason, "needs native_contact, which is off");
  for (const auto& cp : p.pairs) EXPECT_FALSE(cp.on);
  // switched off: the contact filter drops the pair
  Loaded l2 = LoadText(kBoxes);
  p = Resolve(l2, "self_contact=off");
  for (const auto& cp : p.pairs) EXPECT_EQ(cp.on, !cp.self) << cp.name << ": " << cp.reason;
  Apply(l2, p);
  EXPECT_EQ(contacts(l2, "arm", "hand"), 0);
  EXPECT_EQ(contacts(l2, "box1", "world"), 4);  // the other pairs are untouched
  ClearContactFilter();
  p = Resolve(l2, "contact:box1/world=off");
  for (const auto& cp : p.pairs)
    EXPECT_EQ(cp.on, cp.name != "world/box1") << cp.name << ": " << cp.reason;
}

}  // namespace
}  // namespace ohrp::sim
