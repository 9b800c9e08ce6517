// reach's scene: the estimator's frame placed in the scene's world, the scene's obstacles placed
// in the base frame when a plan is asked (reach --scene, docs/planning.md).
#include <cmath>

#include "controllers/reach.h"

namespace ohrp::controllers {

// The estimator's world frame in the scene's: at reset it puts the base's yaw at 0 and the origin
// midway between the soles, on the floor (robot_model/estimator.h); the soles stand where the
// scene's keyframe `key` puts them (standing does not move them; the base's pose over them is
// the estimator's, measured).
ConfigStatus EstimatorFrameInScene(model::Kinematics& kin, const std::string& key,
                                   Eigen::Isometry3d* X_WE) {
  const mjModel* m = kin.m();
  if (m->njnt < 1 || m->jnt_type[0] != mjJNT_FREE)
    return ConfigStatus::Fail(ConfigError::kOption, "--scene: the robot has no floating base");
  const int k = mj_name2id(m, mjOBJ_KEY, key.c_str());
  if (k < 0)
    return ConfigStatus::Fail(ConfigError::kOption, "--scene-keyframe: the robot's model has no keyframe '" + key + "'");
  const double* qpos = m->key_qpos + k * m->nq;
  std::vector<double> joints;  // joint-id order, from the keyframe's qpos
  for (const model::JointMap& j : kin.robot().joints) joints.push_back(qpos[j.qpos_adr]);
  const Eigen::Quaterniond quat(qpos[3], qpos[4], qpos[5], qpos[6]);
  kin.SetBasePose(Eigen::Vector3d(qpos[0], qpos[1], qpos[2]), quat.normalized());
  kin.SetJointPositions(joints.data());
  kin.UpdatePositions();
  const Eigen::Vector3d mid = 0.5 * (kin.p_WSole(kin.left_sole()) + kin.p_WSole(kin.right_sole()));
  const Eigen::Vector3d x = quat.normalized() * Eigen::Vector3d::UnitX();
  *X_WE = Eigen::Isometry3d::Identity();
  X_WE->linear() = Eigen::AngleAxisd(std::atan2(x.y(), x.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  X_WE->translation() = Eigen::Vector3d(mid.x(), mid.y(), 0.0);
  kin.SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  return ConfigStatus::Ok();
}

bool ReachController::PlaceScene() {
  // the scene's obstacles in the base frame as the robot stands now (planner thread)
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = request_quat_WB_.normalized().toRotationMatrix();
  X_WB.translation() = request_p_WB_;
  X_WB = X_WE_ * X_WB;  // the estimator's frame into the scene's world
  std::vector<planning::SceneBox> boxes = reach_.boxes;
  for (const model::SceneObstacle& o : reach_.scene) {
    planning::SceneBox b;
    b.name = o.name;
    b.half_size = o.half_size;
    b.X_BO = model::BoxInFrame(o, X_WB);
    boxes.push_back(b);
  }
  std::string error;
  std::unique_ptr<planning::PostureCheck> check =
      planning::PostureCheck::Create(file_, boxes, group_, reach_.clearance, &error);
  if (!check) {
    result_ = planning::PlanResult();
    result_.reason = "--scene: " + error;
    return false;
  }
  check_ = std::move(check);
  return true;
}

}  // namespace ohrp::controllers
