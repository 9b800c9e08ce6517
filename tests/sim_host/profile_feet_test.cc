// sim_host's contact choice on a model loaded through a robot profile (robot_model/profile.h):
// `contact: soft` soles are taken by the soft-foot contact under --contact auto; `contact:
// native` soles (contype = conaffinity = 0, markers of the support polygon) leave the author's
// foot geoms as MuJoCo's contact, so auto resolves to native; an explicit --contact soft still
// takes them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include "../common/scratch.h"
#include "robot_model/load.h"
#include "sim_host/feet.h"

namespace ohrp::sim {
namespace {

// a free box with two feet (boxes) and a motor, under a profile
std::string LoadedProfile(const std::string& contact) {
  const std::string dir = testing::ScratchFolder("profile_feet");
  std::ofstream(dir + "/m.xml")
      << "<mujoco><worldbody><geom name='floor' type='plane' size='5 5 0.1'/>"
         "<body name='base' pos='0 0 0.5'><freejoint/><geom type='box' size='0.1 0.2 0.1'/>"
         "<body name='lf' pos='0 0.1 -0.2'><joint name='l' axis='0 1 0'/>"
         "<geom name='lbox' type='box' size='0.1 0.05 0.02'/></body>"
         "<body name='rf' pos='0 -0.1 -0.2'><joint name='r' axis='0 1 0'/>"
         "<geom name='rbox' type='box' size='0.1 0.05 0.02'/></body></body></worldbody>"
         "<actuator><motor joint='l'/><motor joint='r'/></actuator></mujoco>";
  std::ofstream(dir + "/p.yaml") << "model: m.xml\nfeet: {left: {body: lf}, right: {body: rf}}\n"
                                    "contact: " << contact << "\n";
  return dir + "/p.yaml";
}

ContactModel Resolve(const std::string& profile, ContactModel asked, std::string* error) {
  std::unique_ptr<mjModel, void (*)(mjModel*)> m(model::LoadMujocoModel(profile, error), mj_deleteModel);
  EXPECT_TRUE(m) << *error;
  if (!m) return ContactModel::kAuto;
  FeetOptions o;
  o.model = asked;
  std::unique_ptr<contact::SoftFootContact> soft;
  ContactModel resolved = ContactModel::kAuto;
  EXPECT_TRUE(SetUpFeet(m.get(), o, 10.0, &soft, error, &resolved)) << *error;
  EXPECT_EQ(soft != nullptr, resolved == ContactModel::kSoft);
  return resolved;
}

TEST(ProfileFeet, AutoTakesSoftSolesAndLeavesNativeMarkers) {
  std::string error;
  EXPECT_EQ(Resolve(LoadedProfile("soft"), ContactModel::kAuto, &error), ContactModel::kSoft);
  EXPECT_EQ(Resolve(LoadedProfile("native"), ContactModel::kAuto, &error), ContactModel::kNative);
  EXPECT_EQ(Resolve(LoadedProfile("native"), ContactModel::kSoft, &error), ContactModel::kSoft);
}

}  // namespace
}  // namespace ohrp::sim
