// The linearly implicit soft-foot force (issue 11, part 1), in the spirit of Drake's TAMSI,
// with the normal law integrated over the step's motion rather than sampled at its start.
//
// MuJoCo's step is semi-implicit Euler, x1 = x0 + h v1, v1 = v0 + h a: a leapfrog whose
// velocities belong to the intervals between the positions. The force held over the step at x0
// stands for the interval [t0 - h/2, t0 + h/2]; here each point's normal force is the average
// of the law along the straight path through x0 with the velocity of the interval before (v0)
// and after (v1, unknown): per point, with delta its depth and r = -v . n its rate,
//     fn = k w / h * [ int_0^h max(0, delta - r0 s)^n wt(s) ds + int_0^h max(0, delta + r1 s)^n wt(s) ds ]
//          * (1 + c r1),
// wt(s) = (1 - lam)(1 - s/h) + lam/2. With lam = 0 (the hat) this is the force of the
// variational integrator whose potential is averaged along the path: a bounce keeps its energy
// and a contact that starts or ends within a step is integrated exactly along that path (a
// point that is outside at x0 but inside at x1 pushes already), whatever the phase. lam = 1
// (the box) is as accurate at the transitions and unconditionally stable in the linear range
// (the average acceleration of Newmark's beta = 1/4; the hat is beta = 1/6, stable for
// (omega h)^2 < 12); per sole body lam rises from 0 where (omega h)^2 = h^2 tr(A K) passes 6.
// The damper sees the rate at the step's end (backward Euler: stable at any damping).
// v1 comes from one Newton step about v1 = v0 through the sole bodies' apparent inverse inertia
// A = J M^-1 J^T (MuJoCo's mass matrix, coupling the soles of one robot):
//     W = W0 + B dv,        dv = dv_free + h A (W - W0),
// W0 the wrench at v1 = v0, B its derivative in the end twist (normal law, and the friction
// spring and damper as before: beta h k_t + b_t), dv_free the twist change the step would make
// with W0, predicted from the previous step's accelerations plus the change of the contact
// wrench since then (no extra mj_forward). Where the state did not come from the previous step
// (the first step, a state set from outside) the accelerations are computed for it: a stale
// prediction is what the step's whole impact rests on at large steps (a block given its state
// after an mj_forward with gravity left 0.07 instead of 0.31 at 8 ms, 1.007 at 16 ms). No
// allocation: everything is sized in Create.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "contact/soft_contact.h"
#include "small_dense.h"

namespace ohrp::contact {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// the friction spring sees the displacement the step's velocity change adds, beta h dv (stable
// at any step for beta >= 1/4); its damper the velocity at the step's end
constexpr double kSpringBeta = 0.25;
constexpr double kDamperGamma = 1.0;
// the hat window while (omega h)^2 stays below this, half its stability limit of 12
constexpr double kHatLimit = 6.0;

Eigen::Matrix3d Skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d s;
  s << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return s;
}

// The 6x6 force Jacobian about the centre of mass of a body's points, each with the 3x3
// Jacobian P = b I + c n n^T (force on the body per motion of the point; symmetric): the point
// moves by G x with G = [I, -R], R = [r]x, its force acts as G^T f, so its share is
// G^T P G = [[P, -P R], [R P, -R P R]] (R^T = -R). With m = n x r (n^T R = m^T, R n = -m,
// R R = r r^T - |r|^2 I) the blocks are sums of outer products,
//   P R = b R + c n m^T,   R P = b R - c m n^T,   -R P R = b (|r|^2 I - r r^T) + c m m^T,
// so the points are summed first and the matrix is assembled once.
class PointSum {
 public:
  void Add(double b, double c, const Eigen::Vector3d& normal, const Eigen::Vector3d& arm) {
    // local copies: the sums below cannot alias them, so they stay in registers
    const double n[3] = {normal[0], normal[1], normal[2]}, r[3] = {arm[0], arm[1], arm[2]};
    const double m[3] = {n[1] * r[2] - n[2] * r[1], n[2] * r[0] - n[0] * r[2],
                         n[0] * r[1] - n[1] * r[0]};
    b_ += b;
    br2_ += b * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    int k = 0;  // the upper triangle of the symmetric sums, row by row
    for (int i = 0; i < 3; ++i) {
      const double cn = c * n[i], cm = c * m[i], brr = b * r[i];
      br_[i] += brr;
      for (int j = 0; j < 3; ++j) nm_[i][j] += cn * m[j];
      for (int j = i; j < 3; ++j, ++k) {
        nn_[k] += cn * n[j];
        mm_[k] += cm * m[j];
        rr_[k] += brr * r[j];
      }
    }
  }
  void Write(Mat6* out) const {
    static constexpr int kUpper[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    Mat6& o = *out;
    const Eigen::Matrix3d R = Skew(Eigen::Vector3d(br_[0], br_[1], br_[2]));  // sum of b R
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const int u = kUpper[i][j];
        o(i, j) = nn_[u];
        o(i, j + 3) = -R(i, j) - nm_[i][j];
        o(i + 3, j) = R(i, j) - nm_[j][i];
        o(i + 3, j + 3) = mm_[u] - rr_[u];
      }
      o(i, i) += b_;
      o(i + 3, i + 3) += br2_;
    }
  }

 private:
  double b_ = 0, br2_ = 0, br_[3] = {0, 0, 0};
  double nm_[3][3] = {}, nn_[6] = {}, mm_[6] = {}, rr_[6] = {};  // nn, mm, rr: upper triangles
};

// int_0^h max(0, d0 + a s)^n wt(s) ds, wt(s) = (1 - lam)(1 - s/h) + lam / 2, and its
// derivative in a, int n max(0, d0 + a s)^(n-1) s wt(s) ds (the ends of the part where the
// depth is positive move with a, but the integrand is 0 there), by Gauss-Legendre over that
// part (exact for n = 1)
struct Integral {
  double value = 0, slope = 0;
};
Integral Segment(double d0, double a, double h, double n, double lam) {
  double lo = 0, hi = h;
  if (a > 0) {
    if (d0 + a * h <= 0) return {};
    if (d0 < 0) lo = -d0 / a;
  } else if (a < 0) {
    if (d0 <= 0) return {};
    if (d0 + a * h < 0) hi = -d0 / a;
  } else if (d0 <= 0) {
    return {};
  }
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  Integral out;
  auto add = [&](double s, double weight) {
    const double depth = std::max(d0 + a * s, 0.0);
    const double wt = weight * ((1 - lam) * (1 - s / h) + 0.5 * lam);
    if (n == 1) {
      out.value += depth * wt;
      out.slope += s * wt;
    } else {
      const double pn1 = std::pow(depth, n - 1);
      out.value += pn1 * depth * wt;
      out.slope += n * pn1 * s * wt;
    }
  };
  if (n == 1) {  // polynomials of degree 2: two points are exact
    const double x = half * 0.5773502691896258;
    add(mid - x, half);
    add(mid + x, half);
    return out;
  }
  const double x1 = half * 0.3399810435848563, x2 = half * 0.8611363115940526;
  add(mid - x1, half * 0.6521451548625461);
  add(mid + x1, half * 0.6521451548625461);
  add(mid - x2, half * 0.3478548451374538);
  add(mid + x2, half * 0.3478548451374538);
  return out;
}

// one point's normal force at the end rate r1 and its derivative in r1 (0 where it is 0)
struct Normal {
  double fn = 0, dfn = 0;
};
Normal WindowForce(const SoftContactParams& p, double area, double delta, double r0, double r1,
                   double h, double lam) {
  const double scale = p.stiffness * area / h;
  const Integral before = Segment(delta, -r0, h, p.exponent, lam);
  const Integral after = Segment(delta, r1, h, p.exponent, lam);
  const double spring = scale * (before.value + after.value);
  Normal out;
  out.fn = spring * (1 + p.damping * r1);
  if (out.fn <= 0) return Normal{};
  const double dspring = scale * after.slope;
  out.dfn = dspring * (1 + p.damping * r1) + spring * p.damping;
  return out;
}

}  // namespace

void SoftFootContact::AllocateImplicit(const mjModel* m) {
  const int nb = static_cast<int>(bodies_.size());
  chain_.assign(nb, {});
  for (int k = 0; k < nb; ++k) {
    // the body's last dof, or that of its nearest ancestor with dofs, then up the dof tree
    int dof = -1;
    for (int b = bodies_[k]; b > 0 && dof < 0; b = m->body_parentid[b])
      if (m->body_dofnum[b] > 0) dof = m->body_dofadr[b] + m->body_dofnum[b] - 1;
    for (; dof >= 0; dof = m->dof_parentid[dof]) chain_[k].push_back(dof);
  }
  // the half solve's eliminations within each chain (what mj_solveM2 does over all the dofs,
  // restricted to the dofs the body's Jacobian can be non-zero at): row `to` of X loses qLD[adr]
  // times row `from`, in the order of `from` (descending dofs, each row final when it is used)
  solve_.assign(nb, {});
  x_.assign(nb, {});
  jc_.assign(nb, {});
  for (int k = 0; k < nb; ++k) {
    const std::vector<int>& chain = chain_[k];
    auto position = [&](int dof) {
      return static_cast<int>(std::find(chain.begin(), chain.end(), dof) - chain.begin());
    };
    for (int p = 0; p < static_cast<int>(chain.size()); ++p) {
      const int i = chain[p];
      if (m->dof_simplenum[i]) continue;
      int adr = m->dof_Madr[i] + 1;
      for (int j = m->dof_parentid[i]; j >= 0; j = m->dof_parentid[j])
        solve_[k].push_back({p, position(j), adr++});
    }
    x_[k] = ChainRows::Zero(static_cast<int>(chain.size()), 6);
    jc_[k] = x_[k];
  }
  // per pair of bodies (k < l) the chain positions of the dofs both have
  shared_.assign(static_cast<size_t>(nb) * nb, {});
  for (int k = 0; k < nb; ++k)
    for (int l = k + 1; l < nb; ++l)
      for (int pk = 0; pk < static_cast<int>(chain_[k].size()); ++pk)
        for (int pl = 0; pl < static_cast<int>(chain_[l].size()); ++pl)
          if (chain_[k][pk] == chain_[l][pl])
            shared_[static_cast<size_t>(k) * nb + l].push_back({pk, pl});
  const int n = 6 * nb;
  stiff_.assign(bodies_.size(), Mat6::Zero());
  damp_.assign(bodies_.size(), Mat6::Zero());
  normal_.assign(bodies_.size(), Eigen::Vector3d::Zero());
  jac_.assign(static_cast<size_t>(n) * m->nv, 0);
  mobility_ = Eigen::MatrixXd::Zero(n, n);
  system_ = Eigen::MatrixXd::Zero(n, n);
  dv_ = rhs_ = correction_ = wrench_ = Eigen::VectorXd::Zero(n);
}

void SoftFootContact::ApplyImplicit(const mjModel* m, mjData* d, bool mass_factored) {
  const SoftContactParams& p = params_;
  const double h = m->opt.timestep;
  const int nb = static_cast<int>(bodies_.size());
  const int nv = m->nv;
  // the free motion is predicted from the accelerations of the step that led to this state;
  // a state that did not come from the previous step (the first one, a state set from outside)
  // gets its own, computed here
  const bool accelerations_fresh = d->time == next_time_;
  next_time_ = d->time + h;
  // per body: the static stiffness K about the centre of mass (for the window's lam), and
  // whether any point touches or may touch during the step
  bool any = false;
  for (int k = 0; k < nb; ++k) {
    const int b = bodies_[k];
    const Eigen::Vector3d com = Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * b);
    PointSum stiff;
    for (size_t s = 0; s < sole_geom_.size(); ++s) {
      if (m->geom_bodyid[sole_geom_[s]] != b) continue;
      for (const PointForce& f : wrenches_[s].per_point) {
        any = true;
        if (f.depth_signed <= 0) continue;
        const double area = grid_[s][f.index].weight;
        const double kn = p.exponent * p.stiffness * area *
                          (p.exponent == 1 ? 1.0 : std::pow(f.depth_signed, p.exponent - 1));
        const double kt = f.slipping ? 0.0 : p.tangential_stiffness * area;
        stiff.Add(kt, kn - kt, f.normal, f.pos - com);  // kn n n^T + kt (I - n n^T)
      }
    }
    stiff.Write(&stiff_[k]);
  }
  if (!any) {
    Apply(m, d);
    return;
  }
  // the accelerations if they are not the previous step's, the mass matrix at this state, the
  // stacked body Jacobians and A = J M^-1 J^T
  if (!accelerations_fresh) {
    if (mass_factored) {  // after mj_step1: the rest of mj_forward
      mj_fwdActuation(m, d);
      mj_fwdAcceleration(m, d);
      mj_fwdConstraint(m, d);
    } else {
      mj_forward(m, d);
    }
  } else if (!mass_factored) {
    mj_crb(m, d);
    mj_factorM(m, d);
  }
  for (int k = 0; k < nb; ++k) {
    mjtNum* rows = jac_.data() + static_cast<size_t>(6 * k) * nv;
    mj_jacBodyCom(m, d, rows, rows + 3 * nv, bodies_[k]);
  }
  // half of the solve for each body's six Jacobian rows, X = D^-1/2 L'^-1 J^T (M = L' D L), on
  // the dofs of its chain only (J is zero elsewhere), then A = X^T X: half the work of
  // mj_solveM and a symmetric product. X holds a chain position per row, the six Jacobian
  // rows side by side.
  for (int k = 0; k < nb; ++k) {
    const std::vector<int>& chain = chain_[k];
    ChainRows& x = x_[k];
    for (int p = 0; p < static_cast<int>(chain.size()); ++p)
      for (int r = 0; r < 6; ++r) x(p, r) = jac_[size_t(6 * k + r) * nv + chain[p]];
    jc_[k] = x;
    for (const Elimination& e : solve_[k]) x.row(e.to) -= d->qLD[e.adr] * x.row(e.from);
    for (int p = 0; p < static_cast<int>(chain.size()); ++p) x.row(p) *= d->qLDiagSqrtInv[chain[p]];
    internal::Gram6(x, mobility_.block<6, 6>(6 * k, 6 * k));
    for (int l = 0; l < k; ++l) {
      Mat6 a = Mat6::Zero();
      for (const auto& [pl, pk] : shared_[size_t(l) * nb + k])
        a.noalias() += x_[l].row(pl).transpose() * x.row(pk);
      mobility_.block<6, 6>(6 * l, 6 * k) = a;
      mobility_.block<6, 6>(6 * k, 6 * l) = a.transpose();
    }
  }
  // per body: W0 (the window force at v1 = v0, and the friction of the law at the start) and
  // B = dW / d(end twist)
  for (int k = 0; k < nb; ++k) {
    const int b = bodies_[k];
    const Eigen::Vector3d com = Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * b);
    // tr(A K) (both symmetric)
    const double w2 = h * h * mobility_.block<6, 6>(6 * k, 6 * k).cwiseProduct(stiff_[k]).sum();
    const double lam = w2 > kHatLimit ? 1 - kHatLimit / w2 : 0.0;
    Vec6 w0 = Vec6::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    PointSum damp;
    for (size_t s = 0; s < sole_geom_.size(); ++s) {
      if (m->geom_bodyid[sole_geom_[s]] != b) continue;
      for (const PointForce& f : wrenches_[s].per_point) {
        const double area = grid_[s][f.index].weight;
        const Normal nf = WindowForce(p, area, f.depth_signed, f.pen_vel, f.pen_vel, h, lam);
        // friction: the law's spring and damper, limited by this normal force (a point that
        // enters within the step grips as it pushes)
        Eigen::Vector3d ft = f.ft_trial;
        const double limit = p.friction * nf.fn, mag = ft.norm();
        const bool slipping = mag > limit;
        if (slipping) ft *= mag > 0 ? limit / mag : 0.0;
        const Eigen::Vector3d force = nf.fn * f.normal + ft;
        const Eigen::Vector3d r = f.pos - com;
        w0.head<3>() += force;
        w0.tail<3>() += r.cross(force);
        if (nf.fn > 0) normal += nf.fn * f.normal;
        // the end rate is -(v1 . n): the force on the body per end velocity of the point,
        // -dfn n n^T - t (I - n n^T)
        const double kt = slipping || f.depth <= 0 ? 0.0 : p.tangential_stiffness * area;
        const double bt = slipping ? 0.0 : p.tangential_damping * area;
        const double t = kSpringBeta * h * kt + kDamperGamma * bt;
        damp.Add(-t, t - nf.dfn, f.normal, r);
      }
    }
    damp.Write(&damp_[k]);
    wrench_.segment<6>(6 * k) = w0;
    normal_[k] = normal;
  }
  // the free twist change: last step's accelerations, plus what the contact changed since
  for (int k = 0; k < nb; ++k) correction_.segment<6>(6 * k) = wrench_.segment<6>(6 * k) - applied_[k];
  for (int k = 0; k < nb; ++k) {  // J qacc, over the chain's dofs
    Vec6 jqacc = Vec6::Zero();
    for (int p = 0; p < static_cast<int>(chain_[k].size()); ++p)
      jqacc += d->qacc[chain_[k][p]] * jc_[k].row(p).transpose();
    dv_.segment<6>(6 * k) = jqacc;
  }
  dv_.noalias() += mobility_ * correction_;
  dv_ *= h;
  // (I - h B A) g = B dv_free, per body block
  system_.setIdentity();
  for (int k = 0; k < nb; ++k) {
    system_.middleRows<6>(6 * k).noalias() -= h * damp_[k] * mobility_.middleRows<6>(6 * k);
    rhs_.segment<6>(6 * k) = damp_[k] * dv_.segment<6>(6 * k);
  }
  correction_ = rhs_;
  internal::SolveInPlace(&system_, &correction_);
  // the sum never pulls: the correction is cut where it would turn the normal force over
  for (int k = 0; k < nb; ++k) {
    if (normal_[k].squaredNorm() == 0) continue;
    const Eigen::Vector3d nrm = normal_[k].normalized();
    const double f0 = wrench_.segment<3>(6 * k).dot(nrm);
    const double df = correction_.segment<3>(6 * k).dot(nrm);
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
