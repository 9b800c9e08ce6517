// The linearised rocking of the standing robot on its soft soles (see rocking.h).
#include "identify/rocking.h"

#include <cmath>

#include "contact/geometry.h"

namespace ohrp::identify {

Mode PredictRocking(const std::vector<Eigen::Vector2d>& r, const std::vector<double>& w, double m,
                    double Iyy, double g, const contact::SoftContactParams& p) {
  // static depths: a load plane delta_i = a + b r_x,i with sum k w delta = m g and no moment
  // about the centre of mass, sum k w delta r_x = 0
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  for (size_t i = 0; i < r.size(); ++i) {
    A(0, 0) += p.stiffness * w[i];
    A(0, 1) += p.stiffness * w[i] * r[i].x();
    A(1, 0) += p.stiffness * w[i] * r[i].x();
    A(1, 1) += p.stiffness * w[i] * r[i].x() * r[i].x();
  }
  const Eigen::Vector2d ab = A.colPivHouseholderQr().solve(Eigen::Vector2d(m * g, 0));
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero();
  double load_times_height = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    // an unloaded point (delta < 0) carries nothing: the linear model then describes the
    // loaded part only
    const double delta = std::max(0.0, ab(0) + ab(1) * r[i].x());
    // a small pitch th moves the point by (th r_z, -th r_x)
    const Eigen::Vector3d jx(1, 0, r[i].y()), jz(0, 1, -r[i].x());
    const double kn = delta > 0 ? p.stiffness * w[i] : 0.0, bn = p.damping * kn * delta;
    K += kn * jz * jz.transpose() + p.tangential_stiffness * w[i] * jx * jx.transpose();
    B += bn * jz * jz.transpose() + p.tangential_damping * w[i] * jx * jx.transpose();
    load_times_height += kn * delta * r[i].y();  // r_z < 0: below the centre of mass
  }
  K(2, 2) += load_times_height;  // the static loads' lever shortens as the body tilts: - m g h
  const Eigen::Matrix3d M = Eigen::Vector3d(m, m, Iyy).asDiagonal();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(6, 6);
  S.topRightCorner(3, 3) = Eigen::Matrix3d::Identity();
  S.bottomLeftCorner(3, 3) = -M.inverse() * K;
  S.bottomRightCorner(3, 3) = -M.inverse() * B;
  Eigen::EigenSolver<Eigen::MatrixXd> es(S);
  Mode slowest{1e30, 0};
  for (int k = 0; k < 6; ++k) {
    const auto l = es.eigenvalues()(k);
    if (l.imag() > 1e-6 && l.imag() < slowest.omega_d) slowest = {l.imag(), -l.real() / std::abs(l)};
  }
  if (slowest.omega_d == 1e30) slowest = {0, 0};
  return slowest;
}

bool GeometryAt(const mjModel* m, const std::vector<std::pair<std::string, double>>& q,
                const contact::SoftContactParams& p, RockingGeometry* out, std::string* error) {
  mjData* d = mj_makeData(m);
  for (const auto& [name, value] : q) {
    const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    if (j < 0) {
      mj_deleteData(d);
      *error = "the model has no joint '" + name + "'";
      return false;
    }
    d->qpos[m->jnt_qposadr[j]] = value;
  }
  mj_kinematics(m, d);
  mj_comPos(m, d);
  std::vector<int> soles;
  for (int g = 0; g < m->ngeom; ++g) {
    const char* n = mj_id2name(m, mjOBJ_GEOM, g);
    const std::string s = n ? n : "";
    if (s.size() >= 5 && s.compare(s.size() - 5, 5, "_SOLE") == 0 && m->geom_type[g] == mjGEOM_BOX)
      soles.push_back(g);
  }
  if (soles.empty()) {
    mj_deleteData(d);
    *error = "the model has no box geom named *_SOLE (the soft soles)";
    return false;
  }
  // the robot: every body below the world's children's roots (subtree of body 1's root)
  const int root = m->body_rootid[m->geom_bodyid[soles.front()]];
  const Eigen::Vector3d com(d->subtree_com + 3 * root);
  // the soles' frame: the first sole's rotation (the soles stand flat: this frame is level)
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Rs(d->geom_xmat + 9 * soles.front());
  double mass = 0;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_rootid[b] != root) continue;
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->ximat + 9 * b);
    const Eigen::Vector3d Ib(m->body_inertia + 3 * b);
    const Eigen::Vector3d rb = Eigen::Vector3d(d->xipos + 3 * b) - com;
    I += R * Ib.asDiagonal() * R.transpose() +
         m->body_mass[b] * (rb.squaredNorm() * Eigen::Matrix3d::Identity() - rb * rb.transpose());
    mass += m->body_mass[b];
  }
  out->mass = mass;
  out->Iyy = (Rs.transpose() * I * Rs)(1, 1);
  out->g = -m->opt.gravity[2];
  out->points.clear();
  out->weights.clear();
  double x_mid = 0, z_sole = 0;
  for (int g : soles) {
    const Eigen::Vector3d half(m->geom_size + 3 * g);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->geom_xmat + 9 * g);
    const Eigen::Vector3d c(d->geom_xpos + 3 * g);
    for (const auto& sp : contact::MakeGrid(half, p.grid_x, p.grid_y)) {
      const Eigen::Vector3d pt = Rs.transpose() * (c + R * Eigen::Vector3d(sp.u, sp.v, -half.z()) - com);
      out->points.emplace_back(pt.x(), pt.z());
      out->weights.push_back(sp.weight);
    }
    const Eigen::Vector3d mid = Rs.transpose() * (c - com);
    x_mid += mid.x() / static_cast<double>(soles.size());
    z_sole += (mid.z() - half.z()) / static_cast<double>(soles.size());
  }
  out->com_height = -z_sole;
  out->com_ahead = -x_mid;
  mj_deleteData(d);
  return true;
}

bool InvertRocking(const RockingGeometry& geo, const contact::SoftContactParams& p, double omega_d,
                   double zeta, double* k, double* d, std::string* error, double k_lo,
                   double k_hi, double d_hi) {
  contact::SoftContactParams q = p;
  auto mode = [&](double kk, double dd) {
    q.stiffness = kk;
    q.damping = dd;
    return PredictRocking(geo.points, geo.weights, geo.mass, geo.Iyy, geo.g, q);
  };
  // K: on the rocking branch omega_d grows with K. At very soft soles the body topples (no
  // rocking mode) and the slowest oscillating mode is another one, so the bracket is found on a
  // grid (log K) where omega_d rises through the target, then bisected
  double lo = 0, hi = 0;
  auto bracket_k = [&](double dd) {
    constexpr int kGrid = 80;
    double k_prev = k_lo, w_prev = mode(k_lo, dd).omega_d;
    for (int i = 1; i <= kGrid; ++i) {
      const double kk = k_lo * std::pow(k_hi / k_lo, static_cast<double>(i) / kGrid);
      const double w = mode(kk, dd).omega_d;
      if (w_prev > 0 && w > w_prev && w_prev <= omega_d && omega_d <= w) {
        lo = k_prev;
        hi = kk;
        return true;
      }
      k_prev = kk;
      w_prev = w;
    }
    return false;
  };
  if (!bracket_k(p.damping)) {
    *error = "a rocking frequency of " + std::to_string(omega_d / (2 * M_PI)) +
             " Hz lies outside what stiffnesses " + std::to_string(k_lo) + " .. " +
             std::to_string(k_hi) + " N/m give on the rocking branch";
    return false;
  }
  for (int i = 0; i < 100; ++i) {
    const double mid = std::sqrt(lo * hi);
    (mode(mid, p.damping).omega_d < omega_d ? lo : hi) = mid;
  }
  *k = std::sqrt(lo * hi);
  // D: zeta grows with D; bisection (the damping also lowers omega_d a little: one more pass
  // of K at the found D)
  for (int pass = 0; pass < 2; ++pass) {
    double dl = 0, dh = d_hi;
    if (!(zeta > mode(*k, dl).zeta && zeta < mode(*k, dh).zeta)) {
      *error = "a damping ratio of " + std::to_string(zeta) + " lies outside what damping 0 .. " +
               std::to_string(d_hi) + " s/m gives at K = " + std::to_string(*k) + " N/m";
      return false;
    }
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (dl + dh);
      (mode(*k, mid).zeta < zeta ? dl : dh) = mid;
    }
    *d = 0.5 * (dl + dh);
    if (!bracket_k(*d)) {
      *error = "no stiffness gives a rocking frequency of " + std::to_string(omega_d / (2 * M_PI)) +
               " Hz at D = " + std::to_string(*d) + " s/m";
      return false;
    }
    for (int i = 0; i < 100; ++i) {
      const double mid = std::sqrt(lo * hi);
      (mode(mid, *d).omega_d < omega_d ? lo : hi) = mid;
    }
    *k = std::sqrt(lo * hi);
  }
  return true;
}

}  // namespace ohrp::identify
