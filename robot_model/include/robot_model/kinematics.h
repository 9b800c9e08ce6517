// The robot as a kinematics and dynamics library: MuJoCo on the same MJCF as the simulator,
// never stepped, queried for forward kinematics, Jacobians, the centre of mass, the mass matrix
// and gravity torques. This is what the paper's controllers share with its simulator (section
// 3.2): the same parser and the same kinematics.
//
// Units and frames: SI throughout. W is the world frame, B the base (the body of the robot's
// free joint), F a frame of interest (a body, a site, a sole). Names say which frame a quantity
// is of and in which frame it is expressed: p_WF is the position of F in W, R_WF the rotation
// from F to W, J_WF the Jacobian of F's velocity in W.
//
// Generalised coordinates as this library indexes them (nv() columns):
//   - floating base (the robot has a free joint): columns 0..5 are the base's velocity, first
//     the linear velocity v_WB of the base origin in W, then the angular velocity w_WB in W;
//   - then the segment's joints in joint-id order (RobotMap::joints: the targets of the motors),
//     column base_columns() + j for joint id j.
//   Joints of the model that the segment does not carry (passive joints) stay at the value of
//   the model's reference configuration and have no column.
//
// Usage per control cycle (no allocation after construction):
//   kin.SetBasePose(p_WB, quat_WB); kin.SetJointPositions(q); kin.Update();
//   kin.p_WSole(left), kin.J_WSole(left, J), kin.p_WCoM(), ...
// Queries read the state of the last Update(); calling them before the first Update() gives
// the model's reference configuration. A Kinematics object is not thread-safe; each thread
// (or each controller) owns its own.
//
// Cost: Update() recomputes only what changed since the last one (nothing when the state was
// set to the same values, the velocity part alone when only velocities changed);
// UpdatePositions() leaves the CoM velocity out, for the callers that do not read it (IK
// iterations, the estimator's relative kinematics). The CoM and the motion axes behind the
// Jacobians and the dynamics are computed on the first query that needs them, the poses of
// sites and soles on each query; results are those of MuJoCo's full mj_kinematics, mj_comPos,
// mj_comVel, mj_subtreeVel run once per change of the state, bit for bit.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "robot_model/model.h"

namespace ohrp::model {

// One sole of the robot: a box geom whose name ends in "_SOLE" (the soft-foot convention of
// mjcf/hrp1s/README.md). Its frame S is the centre of the box's bottom face, axes of the box.
struct SoleMap {
  std::string name;       // geom name, e.g. "LLEG_SOLE"
  int geom_id = -1;
  int body_id = -1;       // the body the sole is fixed to (the foot)
  double half_size[3] = {0, 0, 0};  // box half sizes along the sole's x, y, z [m]
  int force_sensor = -1;  // index in RobotMap::forces of the F/T sensor between this sole and
                          // the rest of the robot (the nearest ancestor-side site), -1 if none
};

// The soles of `m` in geom order, each matched to its F/T sensor in `robot` (if any).
std::vector<SoleMap> FindSoles(const mjModel* m, const RobotMap& robot);

class Kinematics {
 public:
  // Loads the MJCF at `path` and maps the robot (model.h). Null with `*error` set (MuJoCo's
  // text prefixed by the file name, or MapRobot's reason) on failure.
  static std::unique_ptr<Kinematics> Load(const std::string& path, std::string* error);
  // The same from a model in memory; `m` is copied (the caller keeps ownership of its own).
  static std::unique_ptr<Kinematics> FromModel(const mjModel* m, std::string* error);
  ~Kinematics();
  Kinematics(const Kinematics&) = delete;
  Kinematics& operator=(const Kinematics&) = delete;

  //---------------- the robot ----------------
  const mjModel* m() const { return m_; }
  const RobotMap& robot() const { return robot_; }
  const std::vector<SoleMap>& soles() const { return soles_; }
  int njoint() const { return static_cast<int>(robot_.joints.size()); }
  bool floating() const { return robot_.base_body >= 0; }
  int base_columns() const { return floating() ? 6 : 0; }
  int nv() const { return base_columns() + njoint(); }
  double mass() const { return robot_.total_mass; }  // [kg]

  // ids by name, -1 when absent: segment joint id, MuJoCo body and site ids, index in soles()
  int JointId(std::string_view name) const;
  int BodyId(std::string_view name) const;
  int SiteId(std::string_view name) const;
  int SoleIndex(std::string_view name) const;
  // the sole on the robot's left (+y of the base in the reference configuration) and right;
  // -1 when the robot does not have two soles
  int left_sole() const { return left_sole_; }
  int right_sole() const { return right_sole_; }
  // The segment joints on the path from `root_body` (exclusive) to `tip_body`, from the root
  // outwards. Empty when tip is not a descendant of root.
  std::vector<int> Chain(int root_body, int tip_body) const;

  //---------------- state ----------------
  // the base pose (ignored for a fixed-base robot); quat_WB is normalised here
  void SetBasePose(const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& quat_WB);
  // joint positions, njoint() values in joint-id order [rad or m]
  void SetJointPositions(const double* q);
  // velocities (used by Update for the CoM velocity): base v_WB and w_WB in W, joints dq
  void SetBaseVelocity(const Eigen::Vector3d& v_WB, const Eigen::Vector3d& w_WB);
  void SetJointVelocities(const double* dq);
  // computes positions, orientations, the centre of mass and its velocity for the state set
  // above (MuJoCo's mj_kinematics, mj_comPos, mj_comVel, mj_subtreeVel)
  void Update();
  // the same without the CoM velocity: every query but v_WCoM() reads the state set above;
  // v_WCoM() keeps the value of the last Update()
  void UpdatePositions();

  // the state as set (joint positions in joint-id order)
  double q(int j) const;
  Eigen::Vector3d p_WB() const;
  Eigen::Quaterniond quat_WB() const;

  //---------------- forward kinematics (after Update) ----------------
  Eigen::Vector3d p_WBody(int body) const;
  Eigen::Matrix3d R_WBody(int body) const;
  Eigen::Vector3d p_WSite(int site) const;
  Eigen::Matrix3d R_WSite(int site) const;
  Eigen::Vector3d p_WSole(int sole) const;  // centre of the sole's bottom face
  Eigen::Matrix3d R_WSole(int sole) const;
  Eigen::Vector3d p_WCoM() const;           // centre of mass of the whole robot
  Eigen::Vector3d v_WCoM() const;           // its velocity, from the velocities set [m/s]

  //---------------- Jacobians (after Update), 6 x nv() or 3 x nv() ----------------
  // Rows 0-2: velocity in W of the point p_W (given in W) moving with `body`; rows 3-5: the
  // body's angular velocity in W. `J` must be 6 x nv().
  void J_WBodyPoint(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const;
  void J_WSole(int sole, Eigen::Ref<Eigen::MatrixXd> J) const;   // of frame S, 6 x nv()
  void J_WSite(int site, Eigen::Ref<Eigen::MatrixXd> J) const;   // 6 x nv()
  void J_WCoM(Eigen::Ref<Eigen::MatrixXd> J) const;              // 3 x nv()

  //---------------- dynamics (after Update) ----------------
  // joint-space mass matrix in our columns (kinetic energy v^T M v / 2 with the base's w in
  // W), nv() x nv(), rotor armature included
  void MassMatrix(Eigen::Ref<Eigen::MatrixXd> M);
  // generalised gravity forces that hold the current configuration still (nv(): base wrench
  // then joint torques [N m or N]); the joint part is what the motors must supply. Sign: this
  // is dV/dq for the potential V = m g z_CoM, i.e. MuJoCo's qfrc_bias at zero velocity (the
  // velocities set are ignored); for a floating base its first six values are the weight
  // (0, 0, m g) and its moment about the base origin, in W.
  void GravityTorques(Eigen::Ref<Eigen::VectorXd> tau_g);

 private:
  Kinematics() = default;
  bool Init(mjModel* m, std::string* error);
  // copies MuJoCo's 3 x nv Jacobian rows (jac, world frame) into our columns
  void ToColumns(const mjtNum* jac_mj, Eigen::Ref<Eigen::MatrixXd> J, int row0) const;
  // MuJoCo's composite inertias and motion axes (mj_comPos), once per mj_kinematics
  void EnsureCom() const;
  // the world pose of a frame fixed on `body` (MuJoCo's geom or site convention)
  void FrameToWorld(int body, const mjtNum* pos, const mjtNum* quat, mjtByte sameframe,
                    mjtNum xpos[3], mjtNum xmat[9]) const;

  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  mjModel m_bodies_{};  // a shallow copy of *m_ without geoms and sites, for mj_kinematics
  // what is up to date for the state set: the bodies' poses (mj_kinematics), the composite
  // inertias and motion axes (mj_comPos), the CoM velocity (v_WCoM_)
  bool frames_valid_ = false;
  mutable bool com_valid_ = false;
  bool velocity_valid_ = false;
  RobotMap robot_;
  std::vector<SoleMap> soles_;
  int left_sole_ = -1, right_sole_ = -1;
  int com_body_ = 0;                  // root of the robot's subtree (the base, or the world)
  std::vector<int> column_of_dof_;    // MuJoCo dof -> our column, -1 when not carried
  std::vector<int> joint_of_jnt_;     // MuJoCo joint -> segment joint id, -1 when not carried
  Eigen::Vector3d w_WB_ = Eigen::Vector3d::Zero();   // base angular velocity as set, in W
  Eigen::Vector3d v_WCoM_ = Eigen::Vector3d::Zero(); // computed by Update
  mutable std::vector<mjtNum> jacp_, jacr_, dense_;  // scratch, sized at construction
  std::vector<mjtNum> momentum_;      // 3 x nbody scratch: the bodies' subtree momenta
};

}  // namespace ohrp::model
