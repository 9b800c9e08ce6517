// A robot's joints as identified (issue 35, item 4): per joint, the rotor inertia (MuJoCo's
// armature), viscous friction (damping) and Coulomb friction (frictionloss) that the robot has
// and the model may lack. `ohrp identify --joints --model ...` writes the file; sim_host
// (`--joint-file`, or a robot profile's `joint_file:`) applies it to the model, which is
// otherwise unchanged. SI units: kg m^2, N m s/rad, N m (a slide: kg, N s/m, N).
//
//   # written by ohrp identify --joints (the comments say from what)
//   joints:
//     LARM_ELBOW: {armature: 15.0, damping: 2.05, frictionloss: 1.42}
//     RARM_ELBOW: {damping: 1.9}          # a key left out keeps the model's value
//     RLEG_KNEE: {delay: 0.02}            # [s] the actuator's command delay (a whole number
//                                         # of control periods; sim_host's CommandDelay)
//
// Values replace the model's (they are not added). Set-up only: nothing here is for the
// real-time path.
#pragma once

#include <cmath>
#include <string>
#include <vector>

struct mjModel_;
typedef struct mjModel_ mjModel;
struct mjData_;
typedef struct mjData_ mjData;

namespace ohrp::model {

struct JointParams {
  std::string joint;
  double armature = NAN;      // [kg m^2] NaN: the model's
  double damping = NAN;       // [N m s/rad]
  double frictionloss = NAN;  // [N m]
  double delay = NAN;         // [s] the actuator applies a command this long after it is sent
  std::string note;           // written as a comment after the entry (e.g. the standard errors)
};

// The largest value each key takes (a mistake, not a robot, beyond it).
inline constexpr double kMaxArmature = 1e4, kMaxDamping = 1e5, kMaxFrictionloss = 1e5;
inline constexpr double kMaxDelay = 0.1;

// MuJoCo's friction loss is a soft constraint: under a torque below it a joint creeps. Its
// impedance (solimp's first two values, MuJoCo's default 0.9) is raised to this on a joint given
// a Coulomb friction: a hinge of 0.2 kg m^2 under 80 % of its friction creeps at 1e-4 of the
// speed it would reach in 1 s without friction (1e-3 at the default).
inline constexpr double kFrictionImpedance = 0.99;

// Reads the file. False with `*error` as "FILE:LINE: KEY: what is wrong (what would do)".
bool ReadJointParamsFile(const std::string& path, std::vector<JointParams>* joints,
                         std::string* error);

// Writes the file (one line per joint, its note as a comment; `header` lines as comments on
// top). False with `*error` when it cannot be written whole.
bool WriteJointParamsFile(const std::string& path, const std::vector<JointParams>& joints,
                          const std::vector<std::string>& header, std::string* error);

// Applies the values to the model's joints by name. False with `*error` naming a joint the
// model does not have or one that is not a hinge or slide (nothing is changed then). `data`
// (of `m`) is used to recompute the model's constants after an armature changed (MuJoCo 2.2
// folds the armature into the mass matrix through mj_setConst).
bool ApplyJointParams(const std::vector<JointParams>& joints, mjModel* m, mjData* data,
                      std::string* error);

// Sets one dof's Coulomb friction with kFrictionImpedance (the emulator's gap uses it too).
void SetDofFrictionloss(mjModel* m, int dof, double coulomb);

// Each model joint's command delay in control periods (0 where the file gives none), in the
// order of `joint_names`. False with `*error` naming the joint whose delay is not a whole
// number of `period`s (within 1e-6 of one).
bool JointDelayCycles(const std::vector<JointParams>& joints, const std::vector<std::string>& joint_names,
                      double period, std::vector<int>* cycles, std::string* error);

// "LARM_ELBOW armature 15 damping 2.05 frictionloss 1.42; ..." for start-up lines and summaries.
std::string DescribeJointParams(const std::vector<JointParams>& joints);

}  // namespace ohrp::model
