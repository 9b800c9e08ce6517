// The standing stabilizer (see stabilizer.h).
#include "controllers/stabilizer.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace ohrp::controllers {
namespace {

constexpr double kGravity = 9.81;        // [m/s^2]
constexpr double kMinHeight = 0.1;       // CoM height used below this [m]
constexpr double kLoadedFoot = 30.0;     // a foot carrying less [N] gets no damping control

double Clamp(double v, double lim) { return std::clamp(v, -lim, lim); }

}  // namespace

bool MeasureZmp(const FootWrench* feet, int n, double ground_z, double min_fz,
                Eigen::Vector2d* p_W) {
  // moment balance about the ZMP p on z = ground_z: the horizontal moments vanish there
  double fz = 0, mx = 0, my = 0;
  for (int i = 0; i < n; ++i) {
    const FootWrench& w = feet[i];
    const double h = w.p_WS.z() - ground_z;
    fz += w.f_W.z();
    mx += -w.n_W.y() - h * w.f_W.x() + w.p_WS.x() * w.f_W.z();
    my += w.n_W.x() - h * w.f_W.y() + w.p_WS.y() * w.f_W.z();
  }
  if (!(fz > min_fz) || !std::isfinite(mx) || !std::isfinite(my)) return false;
  *p_W = Eigen::Vector2d(mx / fz, my / fz);
  return true;
}

Stabilizer::Stabilizer(StabilizerGains gains) : gains_(gains) { Reset(); }

void Stabilizer::Reset() {
  out_ = StabilizerOutput{};
  torso_rate_[0] = torso_rate_[1] = 0;
}

void Stabilizer::Reset(const Eigen::Vector2d ground_tilt[2]) {
  Reset();
  for (int i = 0; i < 2; ++i) {
    out_.foot_roll[i] = out_.rest_roll[i] = Clamp(ground_tilt[i].x(), gains_.max_ground_tilt);
    out_.foot_pitch[i] = out_.rest_pitch[i] = Clamp(ground_tilt[i].y(), gains_.max_ground_tilt);
  }
}

void Stabilizer::SetFootTilt(int i, double roll, double pitch) {
  out_.foot_roll[i] = out_.rest_roll[i] = Clamp(roll, gains_.max_ground_tilt);
  out_.foot_pitch[i] = out_.rest_pitch[i] = Clamp(pitch, gains_.max_ground_tilt);
}

// one cycle: the ZMP measured and desired, the support it is held inside, the load's shares,
// then each strategy in turn (ankle damping, sole heights, the slow CoM term, the torso)
const StabilizerOutput& Stabilizer::Update(const StabilizerInput& in, double dt) noexcept {
  const Eigen::Vector2d c = in.c.head<2>();
  MeasureZmpAtFeet(in);
  DesireZmpFromDcm(in);
  HoldZmpInsideSupport(in.support, c);
  const Eigen::Vector2d excess = out_.zmp_desired_raw - out_.zmp_desired;
  const double fz_total = in.feet[0].f_W.z() + in.feet[1].f_W.z();
  const Eigen::Vector2d residual = ShareLoadBetweenFeet(in.support);
  for (int i = 0; i < 2; ++i) DampFoot(in, i, out_.fz_share[i] * fz_total, residual, dt);
  DampSoleHeights(in, fz_total, dt);
  CorrectComSlowly(in, c, dt);
  SwayTorso(in, excess, dt);
  return out_;
}

//---------------- measured ZMP ----------------
void Stabilizer::MeasureZmpAtFeet(const StabilizerInput& in) noexcept {
  Eigen::Vector2d zmp;
  out_.zmp_valid = MeasureZmp(in.feet, 2, in.support.ground_z, 0.1 * in.mass * kGravity, &zmp);
  if (out_.zmp_valid) out_.zmp_measured = zmp;
}

//---------------- desired ZMP from the DCM ----------------
void Stabilizer::DesireZmpFromDcm(const StabilizerInput& in) noexcept {
  const StabilizerGains& g = gains_;
  const double h = std::max(in.c.z() - in.support.ground_z, kMinHeight);
  const double omega = std::sqrt(kGravity / h);
  const Eigen::Vector2d c = in.c.head<2>();
  out_.dcm = c + in.dc.head<2>() / omega;
  const Eigen::Vector2d dcm_ref = in.c_ref + in.dc_ref / omega;
  const Eigen::Vector2d zmp_ref = in.c_ref - in.ddc_ref / (omega * omega) + in.zmp_ref_offset;
  out_.zmp_desired_raw = zmp_ref + (1.0 + g.k_dcm / omega) * (out_.dcm - dcm_ref);
}

// the support: the supporting sole, or the bounding box of both soles' corners, less the
// margin (in the sole's frame for one sole, in W for two)
void Stabilizer::HoldZmpInsideSupport(const Support& s, const Eigen::Vector2d& c) noexcept {
  const StabilizerGains& g = gains_;
  const int n_support = int(s.supporting[0]) + int(s.supporting[1]);
  if (n_support == 1) {
    const int i = s.supporting[0] ? 0 : 1;
    const Eigen::Rotation2Dd R(s.yaw[i]);
    const Eigen::Vector2d inner = (s.half_size[i].array() - g.support_margin).max(0.0);
    const Eigen::Vector2d local = R.inverse() * (out_.zmp_desired_raw - s.centre[i]);
    out_.zmp_desired = s.centre[i] + R * local.cwiseMax(-inner).cwiseMin(inner);
  } else if (n_support == 2) {
    Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
    for (int i = 0; i < 2; ++i) {
      const Eigen::Rotation2Dd R(s.yaw[i]);
      for (int cx : {-1, 1}) {
        for (int cy : {-1, 1}) {
          const Eigen::Vector2d corner =
              s.centre[i] + R * Eigen::Vector2d(cx * s.half_size[i].x(), cy * s.half_size[i].y());
          lo = lo.cwiseMin(corner);
          hi = hi.cwiseMax(corner);
        }
      }
    }
    lo.array() += g.support_margin;
    hi.array() -= g.support_margin;
    lo = lo.cwiseMin(0.5 * (lo + hi));
    hi = hi.cwiseMax(lo);
    out_.zmp_desired = out_.zmp_desired_raw.cwiseMax(lo).cwiseMin(hi);
  } else {
    out_.zmp_desired = c;  // no support: nothing to clamp to
  }
}

//---------------- distribution to the feet ----------------
// the shares from p_d's position along the line between the soles' centres; what they leave
// of p_d (across that line) is carried inside the soles (returned)
Eigen::Vector2d Stabilizer::ShareLoadBetweenFeet(const Support& s) noexcept {
  const Eigen::Vector2d& pd = out_.zmp_desired;
  const Eigen::Vector2d line = s.centre[0] - s.centre[1];
  const double span2 = line.squaredNorm();
  double alpha = span2 > 1e-12 ? std::clamp((pd - s.centre[1]).dot(line) / span2, 0.0, 1.0) : 0.5;
  if (!s.supporting[0]) alpha = 0.0;
  if (!s.supporting[1]) alpha = 1.0;
  out_.fz_share[0] = alpha;
  out_.fz_share[1] = 1.0 - alpha;
  return pd - (alpha * s.centre[0] + (1.0 - alpha) * s.centre[1]);
}

//---------------- ankle strategy: foot damping control ----------------
// foot i turns so that its moment about the sensor meets the desired force `fz_d` [N] at the
// desired CoP (`residual` held inside the sole), and returns towards its rest orientation
void Stabilizer::DampFoot(const StabilizerInput& in, int i, double fz_d,
                          const Eigen::Vector2d& residual, double dt) noexcept {
  const StabilizerGains& g = gains_;
  const Support& s = in.support;
  double* roll = out_.foot_roll;
  double* pitch = out_.foot_pitch;
  const FootWrench& w = in.feet[i];
  const double back = dt / g.ankle_recovery;  // return towards the rest orientation
  if (!g.ankle_strategy || !s.supporting[i] || !(w.f_W.z() > kLoadedFoot)) {
    roll[i] -= back * (roll[i] - out_.rest_roll[i]);
    pitch[i] -= back * (pitch[i] - out_.rest_pitch[i]);
    return;
  }
  const Eigen::Rotation2Dd R(s.yaw[i]);
  const Eigen::Vector2d inner = (s.half_size[i].array() - g.support_margin).max(0.0);
  const Eigen::Vector2d cop =
      s.centre[i] + R * (R.inverse() * residual).cwiseMax(-inner).cwiseMin(inner);
  const double cop_x = cop.x(), cop_y = cop.y();
  const double dzs = s.ground_z - w.p_WS.z();  // the CoP lies below the sensor
  // moment about the sensor of the desired force at the desired CoP
  const double nx_d = (cop_y - w.p_WS.y()) * fz_d - dzs * w.f_W.y();
  const double ny_d = dzs * w.f_W.x() - (cop_x - w.p_WS.x()) * fz_d;
  roll[i] += dt * (w.n_W.x() - nx_d) / g.ankle_damping - back * (roll[i] - out_.rest_roll[i]);
  pitch[i] += dt * (w.n_W.y() - ny_d) / g.ankle_damping - back * (pitch[i] - out_.rest_pitch[i]);
  // the offsets about the rest (the ground's tilt: a 10 deg slope is beyond the offsets' clamp)
  roll[i] = out_.rest_roll[i] + Clamp(roll[i] - out_.rest_roll[i], g.max_foot_rotation);
  pitch[i] = out_.rest_pitch[i] + Clamp(pitch[i] - out_.rest_pitch[i], g.max_foot_rotation);
  if (g.ground_adaptation > 0) AdaptRestToGround(in, i, dt);
}

// ground adaptation: while sole i's own CoP stays well inside it, it stands flat, and its
// measured tilt is the ground's
void Stabilizer::AdaptRestToGround(const StabilizerInput& in, int i, double dt) noexcept {
  const StabilizerGains& g = gains_;
  const Support& s = in.support;
  const FootWrench& w = in.feet[i];
  const Eigen::Rotation2Dd R(s.yaw[i]);
  const double fz = w.f_W.z();
  const double px = w.p_WS.x() + (-w.n_W.y() - (w.p_WS.z() - s.ground_z) * w.f_W.x()) / fz;
  const double py = w.p_WS.y() + (w.n_W.x() - (w.p_WS.z() - s.ground_z) * w.f_W.y()) / fz;
  const Eigen::Vector2d d = (R.inverse() * (Eigen::Vector2d(px, py) - s.centre[i])).cwiseAbs();
  if ((s.half_size[i] - d).minCoeff() > g.flat_margin) {
    const double k = dt / g.ground_adaptation;
    out_.rest_roll[i] += k * (in.sole_tilt[i].x() - out_.rest_roll[i]);
    out_.rest_pitch[i] += k * (in.sole_tilt[i].y() - out_.rest_pitch[i]);
    out_.rest_roll[i] = Clamp(out_.rest_roll[i], g.max_ground_tilt);
    out_.rest_pitch[i] = Clamp(out_.rest_pitch[i], g.max_ground_tilt);
  }
}

//---------------- ankle strategy: sole height difference ----------------
void Stabilizer::DampSoleHeights(const StabilizerInput& in, double fz_total, double dt) noexcept {
  const StabilizerGains& g = gains_;
  const Support& s = in.support;
  if (g.ankle_strategy && s.supporting[0] && s.supporting[1] && fz_total > kLoadedFoot) {
    const double diff_m = in.feet[0].f_W.z() - in.feet[1].f_W.z();
    const double diff_d = (out_.fz_share[0] - out_.fz_share[1]) * fz_total;
    out_.dz += dt * ((diff_m - diff_d) / g.z_damping - out_.dz / g.z_recovery);
  } else {
    out_.dz -= dt * out_.dz / g.z_recovery;
  }
  out_.dz = Clamp(out_.dz, g.max_dz);
}

//---------------- slow CoM correction ----------------
// only while the robot is quasi-static: during a push the DCM law acts, and what the
// integral would gather there (wind-up) would have to unwind slowly afterwards
void Stabilizer::CorrectComSlowly(const StabilizerInput& in, const Eigen::Vector2d& c,
                                  double dt) noexcept {
  const StabilizerGains& g = gains_;
  if ((out_.dcm - in.c_ref).norm() < g.com_integral_band)
    out_.com_offset += dt * g.k_com_integral * (in.c_ref - c);
  out_.com_offset = out_.com_offset.cwiseMax(-g.max_com_offset).cwiseMin(g.max_com_offset);
}

//---------------- hip strategy: the torso supplies what the soles cannot ----------------
// L_dot_y = m g e_x and L_dot_x = -m g e_y move the effective ZMP by e (stabilizer.h);
// `excess` is what the support clamp cut off the desired ZMP
void Stabilizer::SwayTorso(const StabilizerInput& in, const Eigen::Vector2d& excess,
                           double dt) noexcept {
  const StabilizerGains& g = gains_;
  const double w0 = g.hip_return;
  double acc[2] = {0, 0};
  if (g.hip_strategy) {
    const Eigen::Vector2d e_T = Eigen::Rotation2Dd(-in.heading) * excess;  // the torso's axes
    const double moment[2] = {in.mass * kGravity * e_T.x(), -in.mass * kGravity * e_T.y()};
    for (int k = 0; k < 2; ++k)
      if (g.torso_inertia[k] > 0) acc[k] = g.hip_gain * g.torso_share[k] * moment[k] / g.torso_inertia[k];
  }
  double* angle[2] = {&out_.torso_pitch, &out_.torso_roll};
  for (int k = 0; k < 2; ++k) {
    const double a = acc[k] - w0 * w0 * *angle[k] - 2.0 * w0 * torso_rate_[k];
    torso_rate_[k] += dt * a;
    *angle[k] += dt * torso_rate_[k];
    if (std::abs(*angle[k]) > g.torso_limit[k]) {
      *angle[k] = Clamp(*angle[k], g.torso_limit[k]);
      torso_rate_[k] = 0;
    }
  }
}

}  // namespace ohrp::controllers
