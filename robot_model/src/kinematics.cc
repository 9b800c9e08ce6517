// Kinematics and dynamics on MuJoCo used as a library (see kinematics.h).
//
// Our generalised velocity v differs from MuJoCo's qvel in two ways: passive joints have no
// column (they stay at qpos0 and their velocity is zero), and the free joint's angular velocity
// is w_WB in W where MuJoCo's is in the base frame B. With R = R_WB the map is
//   qvel_mj = T v,  T = identity but for the base's angular block, which is R^T,
// so a Jacobian becomes J_mj T (angular columns times R^T), a generalised force T^T f_mj
// (angular entries times R) and the mass matrix T^T M_mj T.
//
// Work per Update is only what a query needs (see kinematics.h): setters note whether a value
// changed; mj_kinematics runs on a shallow copy of the model that has no geoms and no sites
// (the robot has many geoms, the queries need a few sole and site poses, which are computed
// per query with MuJoCo's own mj_local2Global, as mj_kinematics would); mj_comPos runs on the
// first query that needs it; the CoM velocity sums the bodies' momenta as mj_subtreeVel does
// (same operations in the same order) without its angular momenta, which nothing here reads.
#include "robot_model/kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "robot_model/load.h"

namespace ohrp::model {
namespace {

using RowMatrix3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// MuJoCo's row-major 3x3 as an Eigen matrix
Eigen::Matrix3d Mat(const mjtNum* xmat) { return Eigen::Map<const RowMatrix3>(xmat); }

// v <- R v for the three values p[0], p[stride], p[2 stride]
void RotateTriplet(const Eigen::Matrix3d& R, mjtNum* p, int stride) {
  const Eigen::Vector3d v(p[0], p[stride], p[2 * stride]);
  const Eigen::Vector3d w = R * v;
  p[0] = w.x();
  p[stride] = w.y();
  p[2 * stride] = w.z();
}

// sets *x to v, true when that changed its bits (so -0 vs 0 and NaNs count as they compute)
bool Assign(mjtNum* x, mjtNum v) {
  if (std::memcmp(x, &v, sizeof v) == 0) return false;
  *x = v;
  return true;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

//---------------- soles ----------------

std::vector<SoleMap> FindSoles(const mjModel* m, const RobotMap& robot) {
  std::vector<SoleMap> soles;
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    if (!name || m->geom_type[g] != mjGEOM_BOX || !EndsWith(name, "_SOLE")) continue;
    SoleMap s;
    s.name = name;
    s.geom_id = g;
    s.body_id = m->geom_bodyid[g];
    for (int k = 0; k < 3; ++k) s.half_size[k] = m->geom_size[3 * g + k];
    // the F/T sensor on the sole's body or on its nearest ancestor
    for (int b = s.body_id; b > 0 && s.force_sensor < 0; b = m->body_parentid[b]) {
      for (size_t f = 0; f < robot.forces.size(); ++f) {
        if (m->site_bodyid[robot.forces[f].site_id] == b) {
          s.force_sensor = static_cast<int>(f);
          break;
        }
      }
    }
    soles.push_back(s);
  }
  return soles;
}

//---------------- set-up ----------------

std::unique_ptr<Kinematics> Kinematics::Load(const std::string& path, std::string* error) {
  // a robot profile, an OpenHRP VRML file, MJCF or URDF (load.h)
  mjModel* m = LoadMujocoModel(path, error);
  if (!m) return nullptr;
  std::unique_ptr<Kinematics> kin(new Kinematics());
  if (!kin->Init(m, error)) {
    *error = "model '" + path + "': " + *error;
    return nullptr;
  }
  return kin;
}

std::unique_ptr<Kinematics> Kinematics::FromModel(const mjModel* m, std::string* error) {
  mjModel* copy = mj_copyModel(nullptr, m);
  if (!copy) {
    *error = "cannot copy the MuJoCo model";
    return nullptr;
  }
  std::unique_ptr<Kinematics> kin(new Kinematics());
  if (!kin->Init(copy, error)) return nullptr;
  return kin;
}

Kinematics::~Kinematics() {
  if (d_) mj_deleteData(d_);
  if (m_) mj_deleteModel(m_);
}

bool Kinematics::Init(mjModel* m, std::string* error) {
  m_ = m;  // owned from here on, also on failure
  d_ = mj_makeData(m_);
  if (!d_) {
    *error = "cannot allocate mjData";
    return false;
  }
  // the model as mj_kinematics sees it: the same arrays, geoms and sites left out
  m_bodies_ = *m_;
  m_bodies_.ngeom = 0;
  m_bodies_.nsite = 0;
  if (!MapRobot(m_, &robot_, error)) return false;
  com_body_ = floating() ? robot_.base_body : 0;

  // columns: the base's six, then the segment's joints in joint-id order
  column_of_dof_.assign(m_->nv, -1);
  joint_of_jnt_.assign(m_->njnt, -1);
  if (floating()) {
    for (int k = 0; k < 6; ++k) column_of_dof_[robot_.base_dof + k] = k;
  }
  for (int j = 0; j < njoint(); ++j) {
    column_of_dof_[robot_.joints[j].dof_adr] = base_columns() + j;
    joint_of_jnt_[robot_.joints[j].joint_id] = j;
  }
  jacp_.assign(3 * m_->nv, 0);
  jacr_.assign(3 * m_->nv, 0);
  dense_.assign(static_cast<size_t>(m_->nv) * std::max(m_->nv, 1), 0);
  momentum_.assign(3 * m_->nbody, 0);

  // the reference configuration (qpos0, zero velocity): mj_makeData starts there
  Update();

  // soles, and which is left: larger y in the base frame at the reference configuration
  soles_ = FindSoles(m_, robot_);
  if (soles_.size() == 2) {
    const Eigen::Matrix3d R_WB = floating() ? R_WBody(robot_.base_body) : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d p = floating() ? p_WBody(robot_.base_body) : Eigen::Vector3d::Zero();
    const double y0 = (R_WB.transpose() * (p_WSole(0) - p)).y();
    const double y1 = (R_WB.transpose() * (p_WSole(1) - p)).y();
    if (y0 != y1) {
      left_sole_ = y0 > y1 ? 0 : 1;
      right_sole_ = 1 - left_sole_;
    }
  }
  return true;
}

//---------------- names ----------------

int Kinematics::JointId(std::string_view name) const {
  for (int j = 0; j < njoint(); ++j) {
    if (robot_.joints[j].name == name) return j;
  }
  return -1;
}

int Kinematics::BodyId(std::string_view name) const {
  return mj_name2id(m_, mjOBJ_BODY, std::string(name).c_str());
}

int Kinematics::SiteId(std::string_view name) const {
  return mj_name2id(m_, mjOBJ_SITE, std::string(name).c_str());
}

int Kinematics::SoleIndex(std::string_view name) const {
  for (size_t s = 0; s < soles_.size(); ++s) {
    if (soles_[s].name == name) return static_cast<int>(s);
  }
  return -1;
}

std::vector<int> Kinematics::Chain(int root_body, int tip_body) const {
  std::vector<int> chain;
  if (root_body < 0 || tip_body < 0 || root_body >= m_->nbody || tip_body >= m_->nbody) return {};
  // walk from the tip up to the root, collecting the bodies' segment joints backwards
  int b = tip_body;
  for (; b != root_body && b > 0; b = m_->body_parentid[b]) {
    for (int k = m_->body_jntnum[b] - 1; k >= 0; --k) {
      const int j = joint_of_jnt_[m_->body_jntadr[b] + k];
      if (j >= 0) chain.push_back(j);
    }
  }
  if (b != root_body) return {};  // reached the world without meeting the root
  std::reverse(chain.begin(), chain.end());
  return chain;
}

//---------------- state ----------------

void Kinematics::SetBasePose(const Eigen::Vector3d& p_WB, const Eigen::Quaterniond& quat_WB) {
  if (!floating()) return;
  mjtNum* qpos = d_->qpos + robot_.base_qpos;
  const Eigen::Quaterniond q = quat_WB.normalized();
  const mjtNum v[7] = {p_WB.x(), p_WB.y(), p_WB.z(), q.w(), q.x(), q.y(), q.z()};
  bool changed = false;
  for (int k = 0; k < 7; ++k) changed |= Assign(qpos + k, v[k]);
  if (changed) frames_valid_ = false;
}

void Kinematics::SetJointPositions(const double* q) {
  bool changed = false;
  for (int j = 0; j < njoint(); ++j) changed |= Assign(d_->qpos + robot_.joints[j].qpos_adr, q[j]);
  if (changed) frames_valid_ = false;
}

void Kinematics::SetBaseVelocity(const Eigen::Vector3d& v_WB, const Eigen::Vector3d& w_WB) {
  if (!floating()) return;
  mjtNum* qvel = d_->qvel + robot_.base_dof;
  bool changed = false;
  for (int k = 0; k < 3; ++k) {
    changed |= Assign(qvel + k, v_WB[k]);
    // turned into MuJoCo's body-frame angular velocity by Update (needs R_WB)
    changed |= Assign(w_WB_.data() + k, w_WB[k]);
  }
  if (changed) velocity_valid_ = false;
}

void Kinematics::SetJointVelocities(const double* dq) {
  bool changed = false;
  for (int j = 0; j < njoint(); ++j) changed |= Assign(d_->qvel + robot_.joints[j].dof_adr, dq[j]);
  if (changed) velocity_valid_ = false;
}

void Kinematics::UpdatePositions() {
  if (frames_valid_) return;
  // the bodies' positions and orientations, the joints' anchors and axes (not geoms, sites)
  mj_kinematics(&m_bodies_, d_);
  frames_valid_ = true;
  com_valid_ = false;
  velocity_valid_ = false;
}

void Kinematics::EnsureCom() const {
  if (com_valid_) return;
  // the subtrees' centres of mass, the composite inertias and the motion axes (for Jacobians)
  mj_comPos(m_, d_);
  com_valid_ = true;
}

void Kinematics::Update() {
  if (frames_valid_ && velocity_valid_) return;
  // the base's angular velocity in B, as MuJoCo's free joint wants it
  if (floating()) {
    mjtNum R[9];
    mju_quat2Mat(R, d_->qpos + robot_.base_qpos + 3);
    const Eigen::Vector3d w_B = Mat(R).transpose() * w_WB_;
    for (int k = 0; k < 3; ++k) d_->qvel[robot_.base_dof + 3 + k] = w_B[k];
  }
  UpdatePositions();
  EnsureCom();
  // the bodies' spatial velocities
  mj_comVel(m_, d_);
  // the CoM velocity: each body's momentum (mass times the velocity of its centre of mass)
  // added to its parent's from the leaves inwards, the robot's subtree's over its mass
  mjtNum* p = momentum_.data();
  for (int b = 0; b < m_->nbody; ++b) {
    mjtNum v[6];  // angular, then linear velocity at the body's centre of mass, in W
    mj_objectVelocity(m_, d_, mjOBJ_BODY, b, v, 0);
    mju_scl3(p + 3 * b, v + 3, m_->body_mass[b]);
  }
  for (int b = m_->nbody - 1; b > 0; --b) mju_addTo3(p + 3 * m_->body_parentid[b], p + 3 * b);
  mjtNum v_com[3];
  mju_scl3(v_com, p + 3 * com_body_, 1 / std::max(mjMINVAL, m_->body_subtreemass[com_body_]));
  v_WCoM_ = Eigen::Map<const Eigen::Vector3d>(v_com);
  velocity_valid_ = true;
}

double Kinematics::q(int j) const { return d_->qpos[robot_.joints[j].qpos_adr]; }

Eigen::Vector3d Kinematics::p_WB() const {
  if (!floating()) return Eigen::Vector3d::Zero();
  const mjtNum* qpos = d_->qpos + robot_.base_qpos;
  return {qpos[0], qpos[1], qpos[2]};
}

Eigen::Quaterniond Kinematics::quat_WB() const {
  if (!floating()) return Eigen::Quaterniond::Identity();
  const mjtNum* qpos = d_->qpos + robot_.base_qpos;
  return {qpos[3], qpos[4], qpos[5], qpos[6]};
}

//---------------- forward kinematics ----------------

Eigen::Vector3d Kinematics::p_WBody(int body) const {
  return Eigen::Map<const Eigen::Vector3d>(d_->xpos + 3 * body);
}

Eigen::Matrix3d Kinematics::R_WBody(int body) const { return Mat(d_->xmat + 9 * body); }

void Kinematics::FrameToWorld(int body, const mjtNum* pos, const mjtNum* quat, mjtByte sameframe,
                              mjtNum xpos[3], mjtNum xmat[9]) const {
  mj_local2Global(d_, xpos, xmat, pos, quat, body, sameframe);
}

Eigen::Vector3d Kinematics::p_WSite(int site) const {
  mjtNum p[3];
  FrameToWorld(m_->site_bodyid[site], m_->site_pos + 3 * site, nullptr, m_->site_sameframe[site], p,
               nullptr);
  return Eigen::Map<const Eigen::Vector3d>(p);
}

Eigen::Matrix3d Kinematics::R_WSite(int site) const {
  mjtNum R[9];
  FrameToWorld(m_->site_bodyid[site], nullptr, m_->site_quat + 4 * site, m_->site_sameframe[site],
               nullptr, R);
  return Mat(R);
}

Eigen::Vector3d Kinematics::p_WSole(int sole) const {
  // the centre of the box offset by half its height along its -z
  const SoleMap& s = soles_[sole];
  const int g = s.geom_id;
  mjtNum centre[3], R[9];
  FrameToWorld(m_->geom_bodyid[g], m_->geom_pos + 3 * g, m_->geom_quat + 4 * g,
               m_->geom_sameframe[g], centre, R);
  return Eigen::Map<const Eigen::Vector3d>(centre) - s.half_size[2] * Mat(R).col(2);
}

Eigen::Matrix3d Kinematics::R_WSole(int sole) const {
  const int g = soles_[sole].geom_id;
  mjtNum R[9];
  FrameToWorld(m_->geom_bodyid[g], nullptr, m_->geom_quat + 4 * g, m_->geom_sameframe[g], nullptr,
               R);
  return Mat(R);
}

Eigen::Vector3d Kinematics::p_WCoM() const {
  EnsureCom();
  return Eigen::Map<const Eigen::Vector3d>(d_->subtree_com + 3 * com_body_);
}

Eigen::Vector3d Kinematics::v_WCoM() const { return v_WCoM_; }

//---------------- Jacobians ----------------

void Kinematics::ToColumns(const mjtNum* jac_mj, Eigen::Ref<Eigen::MatrixXd> J, int row0) const {
  const int nv_mj = m_->nv;
  for (int r = 0; r < 3; ++r) {
    for (int i = 0; i < nv_mj; ++i) {
      const int c = column_of_dof_[i];
      if (c >= 0) J(row0 + r, c) = jac_mj[r * nv_mj + i];
    }
  }
  // the base's angular columns: MuJoCo's (w in B) times R_WB^T gives ours (w in W)
  if (floating()) {
    const Eigen::Matrix3d R_WB = R_WBody(robot_.base_body);
    for (int r = 0; r < 3; ++r) {
      const Eigen::Vector3d x(J(row0 + r, 3), J(row0 + r, 4), J(row0 + r, 5));
      const Eigen::Vector3d y = R_WB * x;  // (x^T R^T)^T
      for (int k = 0; k < 3; ++k) J(row0 + r, 3 + k) = y[k];
    }
  }
}

void Kinematics::J_WBodyPoint(int body, const Eigen::Vector3d& p_W,
                              Eigen::Ref<Eigen::MatrixXd> J) const {
  const mjtNum point[3] = {p_W.x(), p_W.y(), p_W.z()};
  EnsureCom();
  mj_jac(m_, d_, jacp_.data(), jacr_.data(), point, body);
  ToColumns(jacp_.data(), J, 0);
  ToColumns(jacr_.data(), J, 3);
}

void Kinematics::J_WSole(int sole, Eigen::Ref<Eigen::MatrixXd> J) const {
  J_WBodyPoint(soles_[sole].body_id, p_WSole(sole), J);
}

void Kinematics::J_WSite(int site, Eigen::Ref<Eigen::MatrixXd> J) const {
  J_WBodyPoint(m_->site_bodyid[site], p_WSite(site), J);
}

void Kinematics::J_WCoM(Eigen::Ref<Eigen::MatrixXd> J) const {
  EnsureCom();
  mj_jacSubtreeCom(m_, d_, jacp_.data(), com_body_);
  ToColumns(jacp_.data(), J, 0);
}

//---------------- dynamics ----------------

void Kinematics::MassMatrix(Eigen::Ref<Eigen::MatrixXd> M) {
  const int nv_mj = m_->nv;
  // MuJoCo's composite rigid body inertia (armature added), as a dense row-major matrix
  EnsureCom();
  mj_crb(m_, d_);
  mj_fullM(m_, dense_.data(), d_->qM);
  // T^T M T: the base's angular rows and columns turned by R_WB
  if (floating()) {
    const Eigen::Matrix3d R_WB = R_WBody(robot_.base_body);
    const int a = robot_.base_dof + 3;
    for (int i = 0; i < nv_mj; ++i) RotateTriplet(R_WB, dense_.data() + i * nv_mj + a, 1);
    for (int j = 0; j < nv_mj; ++j) RotateTriplet(R_WB, dense_.data() + a * nv_mj + j, nv_mj);
  }
  for (int i = 0; i < nv_mj; ++i) {
    const int ci = column_of_dof_[i];
    if (ci < 0) continue;
    for (int j = 0; j < nv_mj; ++j) {
      const int cj = column_of_dof_[j];
      if (cj >= 0) M(ci, cj) = dense_[i * nv_mj + j];
    }
  }
}

void Kinematics::GravityTorques(Eigen::Ref<Eigen::VectorXd> tau_g) {
  // MuJoCo's bias force at zero velocity: mj_rne reads the velocity only through cvel and
  // cdof_dot (mj_comVel's outputs, used by Update for v_WCoM and kept in v_WCoM_ there), so
  // zeroing them leaves gravity alone; qvel, and so v_WCoM(), stay as set
  EnsureCom();
  mju_zero(d_->cvel, 6 * m_->nbody);
  mju_zero(d_->cdof_dot, 6 * m_->nv);
  mjtNum* f = dense_.data();  // nv values of scratch (dense_ holds nv x nv)
  mj_rne(m_, d_, 0, f);
  if (floating()) RotateTriplet(R_WBody(robot_.base_body), f + robot_.base_dof + 3, 1);
  for (int i = 0; i < m_->nv; ++i) {
    const int c = column_of_dof_[i];
    if (c >= 0) tau_g[c] = f[i];
  }
}

}  // namespace ohrp::model
