// The joints as identified, applied to a MuJoCo model (see joint_params.h). Apart from the
// file's reading and writing (joint_params.cc), so that a reader of scenarios does not call MuJoCo.
#include <mujoco/mujoco.h>

#include <cmath>
#include <string>
#include <vector>

#include "robot_model/joint_params.h"

namespace ohrp::model {

void SetDofFrictionloss(mjModel* m, int dof, double coulomb) {
  m->dof_frictionloss[dof] = coulomb;
  m->dof_solimp[dof * mjNIMP + 0] = kFrictionImpedance;
  m->dof_solimp[dof * mjNIMP + 1] = kFrictionImpedance;
}

bool ApplyJointParams(const std::vector<JointParams>& joints, mjModel* m, mjData* data,
                      std::string* error) {
  std::vector<int> dof(joints.size());
  for (size_t i = 0; i < joints.size(); ++i) {
    const int j = mj_name2id(m, mjOBJ_JOINT, joints[i].joint.c_str());
    if (j < 0) {
      *error = joints[i].joint + ": the model has no such joint";
      return false;
    }
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) {
      *error = joints[i].joint + ": not a hinge or slide (a ball or free joint has no one armature)";
      return false;
    }
    dof[i] = m->jnt_dofadr[j];
  }
  bool armature = false;
  for (size_t i = 0; i < joints.size(); ++i) {
    const JointParams& p = joints[i];
    if (!std::isnan(p.armature)) m->dof_armature[dof[i]] = p.armature, armature = true;
    if (!std::isnan(p.damping)) m->dof_damping[dof[i]] = p.damping;
    if (!std::isnan(p.frictionloss)) SetDofFrictionloss(m, dof[i], p.frictionloss);
  }
  if (armature) mj_setConst(m, data);
  return true;
}

}  // namespace ohrp::model
