// Test helper: HRP-1S in-process on its soft soles, sim_host's servo holding the start pose with
// both ankle pitches leaned forward over one second, the first unless set_lean_start says
// otherwise (the load centre moves under the middle of the soles, as
// controllers/poses/hrp1s_halfsit_lean.yaml does).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/step.h"

namespace ohrp::sim::testing {

class LeaningRobot {
 public:
  // Loads `scene` (a path below the source tree), soft feet, then the keyframe; dt 0 keeps the
  // scene's step. Gains are the servo's defaults, kp times kp_scale and kd times its root.
  void Load(const std::string& scene_file, const std::string& keyframe, double dt,
            double ankle_lean, double kp_scale) {
    model::InstallMujocoHandlers(nullptr);
    std::string error;
    scene_ = model::Scene::Load(std::string(OHRP_SOURCE_DIR) + "/" + scene_file, &error);
    ASSERT_TRUE(scene_) << error;
    if (dt > 0) m()->opt.timestep = dt;
    ASSERT_TRUE(model::MapRobot(m(), &robot_, &error)) << error;
    FeetOptions feet;
    feet.model = ContactModel::kSoft;
    ASSERT_TRUE(SetUpFeet(m(), feet, robot_.total_mass, &soft_, &error)) << error;
    ASSERT_TRUE(scene_->Reset(keyframe, &error)) << error;
    servo_ = std::make_unique<model::Servo>(robot_);
    fold_ = std::make_unique<DampingFold>(m());
    step_ = std::make_unique<PhysicsStep>(m(), d(),
                                          PhysicsStep::Parts{servo_.get(), soft_.get()});
    cmd_.njoint = static_cast<int>(robot_.joints.size());
    start_.assign(cmd_.njoint, 0.0);
    lean_.assign(cmd_.njoint, 0.0);
    for (int i = 0; i < cmd_.njoint; ++i) {
      const model::JointMap& j = robot_.joints[i];
      start_[i] = d()->qpos[j.qpos_adr];
      if (j.name == "RLEG_ANKLE_P" || j.name == "LLEG_ANKLE_P") lean_[i] = ankle_lean;
      cmd_.joint[i].mode = shm::JointMode::kPosition;
      cmd_.joint[i].kp = j.default_kp * kp_scale;
      cmd_.joint[i].kd = j.default_kd * std::sqrt(kp_scale);
    }
  }

  // One physics step, sim_host's own (sim_host/step.h), after the commands (the lean ramped in
  // over one second). Returns false if the servo refused the commands.
  // unsplit: the same parts with mj_step in one piece after the contact's own kinematics (the
  // reference the split step must reproduce); sensors: PhysicsStep::Step's
  bool Step(bool unsplit = false, bool sensors = true) {
    const double s = std::clamp((d()->time - lean_start_) / 1.0, 0.0, 1.0);
    for (int i = 0; i < cmd_.njoint; ++i)
      cmd_.joint[i].q_ref = start_[i] + lean_[i] * 0.5 * (1 - std::cos(M_PI * s));
    if (servo_->Accept(cmd_) != 0) return false;
    if (!unsplit) {
      step_->Step(sensors);
      return true;
    }
    servo_->Apply(m(), d());
    fold_->Begin(m(), d());  // the step's damping fold too: only the split differs
    soft_->ApplyBeforeStep(m(), d());
    mj_step(m(), d());
    fold_->End(m(), d());
    soft_->Commit();
    return true;
  }

  // the lean's ramp starts at `t` [s] of simulated time instead of 0
  void set_lean_start(double t) { lean_start_ = t; }

  mjModel* m() const { return scene_->m(); }
  mjData* d() const { return scene_->d(); }
  const model::RobotMap& robot() const { return robot_; }
  contact::SoftFootContact& soft() const { return *soft_; }

 private:
  std::unique_ptr<model::Scene> scene_;
  model::RobotMap robot_;
  std::unique_ptr<contact::SoftFootContact> soft_;
  std::unique_ptr<PhysicsStep> step_;
  std::unique_ptr<DampingFold> fold_;
  std::unique_ptr<model::Servo> servo_;
  shm::CommandBlock cmd_{};
  std::vector<double> start_, lean_;
  double lean_start_ = 0;  // [s]
};

}  // namespace ohrp::sim::testing
