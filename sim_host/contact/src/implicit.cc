// The linearly implicit soft-foot force (issue 11, part 1), in the spirit of Drake's TAMSI:
// the spring and damper of every touching point are linearised about the step's start, and
// the force added over the step is the one at the step's end to first order,
//     W = W0 + (beta h K + gamma D) dv,        dv = dv_free + h A (W - W0),
// where W is the wrench on each sole body about its centre of mass, v its twist, K and D the
// 6x6 stiffness and damping of the bed of springs about that point, A = J M^-1 J^T the sole
// bodies' apparent inverse inertia (from MuJoCo's mass matrix, coupling the soles of one robot)
// and dv_free the twist change the step would make with the explicit W0. dv_free is predicted
// from the previous step's accelerations plus the change of the contact wrench since then
// (one mj_forward is not spent on it). No allocation: everything is sized in Create.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "contact/soft_contact.h"

namespace ohrp::contact {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// the spring sees the displacement the step's velocity change adds, beta h dv: with MuJoCo's
// semi-implicit Euler (q += h v_next) this keeps the map of an undamped spring area-preserving
// (no numerical damping, no energy gain) and makes it stable at any step for beta >= 1/4
// (beta h^2 k / m in place of the explicit scheme's 0: Newmark's average acceleration)
constexpr double kSpringBeta = 0.25;
// the damper sees gamma dv: 1 = the velocity at the step's end (backward Euler; measured: the
// trapezoidal 1/2 leaves a 10 kg block bouncing at 1 m/s with 5 x the converged restitution)
constexpr double kDamperGamma = 1.0;

Eigen::Matrix3d Skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d s;
  s << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return s;
}

// adds a point's 3x3 force Jacobian P (force on the body per motion of the point) about the
// centre of mass: the point moves by G x with G = [I, -[r]x], its force acts as G^T f
void AddPoint(const Eigen::Matrix3d& P, const Eigen::Vector3d& r, Mat6* out) {
  Eigen::Matrix<double, 3, 6> G;
  G.leftCols<3>().setIdentity();
  G.rightCols<3>() = -Skew(r);
  *out += G.transpose() * P * G;
}

}  // namespace

void SoftFootContact::AllocateImplicit(const mjModel* m) {
  const int n = 6 * static_cast<int>(bodies_.size());
  stiff_.assign(bodies_.size(), Mat6::Zero());
  damp_.assign(bodies_.size(), Mat6::Zero());
  jac_.assign(static_cast<size_t>(n) * m->nv, 0);
  minv_jt_.assign(static_cast<size_t>(n) * m->nv, 0);
  mobility_ = Eigen::MatrixXd::Zero(n, n);
  system_ = Eigen::MatrixXd::Zero(n, n);
  dv_ = rhs_ = correction_ = wrench_ = Eigen::VectorXd::Zero(n);
  lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
}

void SoftFootContact::ApplyImplicit(const mjModel* m, mjData* d) {
  const SoftContactParams& p = params_;
  const double h = m->opt.timestep;
  const int nb = static_cast<int>(bodies_.size());
  const int nv = m->nv;
  // per body: the explicit wrench W0 about the centre of mass and the bed's K and D there
  bool any = false;
  for (int k = 0; k < nb; ++k) {
    const int b = bodies_[k];
    const Eigen::Vector3d com = Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * b);
    Vec6 w0 = Vec6::Zero();
    stiff_[k].setZero();
    damp_[k].setZero();
    for (size_t s = 0; s < sole_geom_.size(); ++s) {
      const SoleWrench& w = wrenches_[s];
      if (!w.in_contact || m->geom_bodyid[sole_geom_[s]] != b) continue;
      w0.head<3>() += w.force;
      w0.tail<3>() += w.torque + (w.point - com).cross(w.force);
      for (const PointForce& f : w.per_point) {
        if (f.fn <= 0) continue;  // the law is clamped at zero: no slope
        const double area = grid_[s][f.index].weight;
        const double delta = f.depth_fit;
        // d fn / d delta and d fn / d delta', delta growing as the point moves against n
        const double kn = p.exponent * p.stiffness * area * std::pow(delta, p.exponent - 1) *
                          (1 + p.damping * f.pen_vel);
        const double dn = p.stiffness * area * std::pow(delta, p.exponent) * p.damping;
        const Eigen::Matrix3d nn = f.normal * f.normal.transpose();
        const Eigen::Matrix3d tt = Eigen::Matrix3d::Identity() - nn;
        const double kt = f.slipping ? 0.0 : p.tangential_stiffness * area;
        const double bt = f.slipping ? 0.0 : p.tangential_damping * area;
        const Eigen::Vector3d r = f.pos - com;
        AddPoint(-(kn * nn + kt * tt), r, &stiff_[k]);
        AddPoint(-(dn * nn + bt * tt), r, &damp_[k]);
        any = true;
      }
    }
    wrench_.segment<6>(6 * k) = w0;
  }
  if (!any) {
    Apply(m, d);
    return;
  }
  // the mass matrix at this state, the stacked body Jacobians and A = J M^-1 J^T
  mj_crb(m, d);
  mj_factorM(m, d);
  const int n = 6 * nb;
  for (int k = 0; k < nb; ++k) {
    mjtNum* rows = jac_.data() + static_cast<size_t>(6 * k) * nv;
    mj_jacBodyCom(m, d, rows, rows + 3 * nv, bodies_[k]);
  }
  mj_solveM(m, d, minv_jt_.data(), jac_.data(), n);
  using RowMat = Eigen::Matrix<mjtNum, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMat> J(jac_.data(), n, nv);
  const Eigen::Map<const RowMat> X(minv_jt_.data(), n, nv);
  const Eigen::Map<const Eigen::VectorXd> qacc(d->qacc, nv);
  mobility_.noalias() = J * X.transpose();
  // the free twist change: last step's accelerations, plus what the contact changed since
  for (int k = 0; k < nb; ++k) correction_.segment<6>(6 * k) = wrench_.segment<6>(6 * k) - applied_[k];
  dv_.noalias() = J * qacc;
  dv_.noalias() += mobility_ * correction_;
  dv_ *= h;
  // (I - h B A) g = B dv_free, B = beta h K + gamma D, per body block
  system_.setIdentity();
  for (int k = 0; k < nb; ++k) {
    const Mat6 B = kSpringBeta * h * stiff_[k] + kDamperGamma * damp_[k];
    system_.middleRows<6>(6 * k).noalias() -= h * B * mobility_.middleRows<6>(6 * k);
    rhs_.segment<6>(6 * k) = B * dv_.segment<6>(6 * k);
  }
  lu_.compute(system_);
  correction_.noalias() = lu_.solve(rhs_);
  // the sum never pulls: the correction is cut where it would turn the normal force over
  for (int k = 0; k < nb; ++k) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (size_t s = 0; s < sole_geom_.size(); ++s)
      if (wrenches_[s].in_contact && m->geom_bodyid[sole_geom_[s]] == bodies_[k])
        normal += wrenches_[s].normal_force * wrenches_[s].normal;
    if (normal.squaredNorm() == 0) continue;
    normal.normalize();
    const double f0 = wrench_.segment<3>(6 * k).dot(normal);
    const double df = correction_.segment<3>(6 * k).dot(normal);
    double scale = 1;
    if (f0 + df < 0 && df < 0) scale = std::max(0.0, f0 / -df);
    wrench_.segment<6>(6 * k) += scale * correction_.segment<6>(6 * k);
  }
  // into xfrc_applied, replacing this contact's previous share
  for (int k = 0; k < nb; ++k) {
    const int b = bodies_[k];
    for (int i = 0; i < 6; ++i) d->xfrc_applied[6 * b + i] += wrench_[6 * k + i] - applied_[k][i];
    applied_[k] = wrench_.segment<6>(6 * k);
  }
}

}  // namespace ohrp::contact
