// The walking pattern generator: preview control on the gait's ZMP reference
// (pattern_generator.h).
#include "walking/pattern_generator.h"

#include <algorithm>
#include <cmath>

namespace ohrp::walking {

double SwingZmpGain(const std::vector<LegBody>& leg, double hip_height, double com_height,
                    double total_mass, double gravity) {
  double m_leg = 0, moment = 0;
  for (const LegBody& b : leg) {
    m_leg += b.mass;
    moment += b.mass * b.height;
  }
  if (!(hip_height > 0) || !(total_mass > m_leg) || !(gravity > 0)) return 0;
  const double z_rest = (total_mass * com_height - moment) / (total_mass - m_leg);
  double kappa = 0;
  for (const LegBody& b : leg) {
    const double share = std::clamp((hip_height - b.height) / hip_height, 0.0, 1.0);
    kappa += b.mass * share * (z_rest - b.height);
  }
  return kappa / (total_mass * gravity);
}

void PatternGenerator::SizeHorizon() {
  ref_[0].assign(gains_.horizon() + 1, 0.0);
  ref_[1].assign(gains_.horizon() + 1, 0.0);
  feet_[0].assign(gains_.horizon() + 3, Eigen::Vector2d::Zero());
  feet_[1].assign(gains_.horizon() + 3, Eigen::Vector2d::Zero());
}

bool PatternGenerator::Configure(const GaitOptions& gait, const PreviewOptions& preview,
                                 std::string* error) {
  if (const std::string e = CheckGaitOptions(gait); !e.empty()) {
    *error = "gait: " + e;
    return false;
  }
  gait_options_ = gait;
  if (!gains_.Compute(preview, error)) return false;
  SizeHorizon();
  return true;
}

bool PatternGenerator::Start(double t, const FeetPose& feet, const Eigen::Vector3d& com,
                             std::string* error) {
  ground0_ = 0.5 * (feet.p[0].z() + feet.p[1].z());
  const double zc = com.z() - ground0_;
  if (!(zc > 0.05)) {
    *error = "pattern generator: the CoM is " + std::to_string(zc) + " m above the feet";
    return false;
  }
  if (std::abs(zc - gains_.options().zc) > 1e-3) {
    PreviewOptions o = gains_.options();
    o.zc = zc;
    if (!gains_.Compute(o, error)) return false;
    SizeHorizon();
  }
  t_ = t;
  gait_.Start(t, feet, gait_options_);
  // standing: the ZMP reference is the middle of the feet; the CoM starts at rest where it is
  // (it moves over the middle if it is not there)
  axis_[0].Reset(gains_, Eigen::Vector3d(com.x(), 0, 0), com.x());
  axis_[1].Reset(gains_, Eigen::Vector3d(com.y(), 0, 0), com.y());
  sample_.zmp_swing.setZero();
  Sample();
  return true;
}

int PatternGenerator::Replace(const std::vector<Footstep>& steps) { return gait_.Replace(t_, steps); }

void PatternGenerator::ShiftCoM(const Eigen::Vector2d& dc, const Eigen::Vector2d& dv) {
  for (int a = 0; a < 2; ++a) axis_[a].Shift(Eigen::Vector3d(dc[a], dv[a], 0));
  Sample();
}

const WalkSample& PatternGenerator::Advance() {
  const double dt = gains_.options().dt;
  const int n = gains_.horizon();
  if (swing_gain_ != 0) {
    SwingShare(dt, n);
  } else {
    for (int j = 0; j <= n; ++j) {
      const Eigen::Vector3d p = gait_.Zmp(t_ + j * dt);
      ref_[0][j] = p.x();
      ref_[1][j] = p.y();
    }
  }
  axis_[0].Step(gains_, ref_[0].data());
  axis_[1].Step(gains_, ref_[1].data());
  t_ += dt;
  Sample();
  return sample_;
}

void PatternGenerator::SwingShare(double dt, int n) {
  // the ZMP reference and the feet over the horizon (feet sample j + 1 is time t_ + j dt), the
  // feet's accelerations by second differences; the preview's reference is the gait's less the
  // legs' share
  GaitState s;
  for (int j = 0; j <= n + 2; ++j) {
    gait_.At(t_ + (j - 1) * dt, &s);
    feet_[0][j] = s.feet.p[0].head<2>();
    feet_[1][j] = s.feet.p[1].head<2>();
    if (j >= 1 && j <= n + 1) {
      ref_[0][j - 1] = s.zmp.x();
      ref_[1][j - 1] = s.zmp.y();
    }
  }
  const double k = swing_gain_ / (dt * dt);
  for (int j = 0; j <= n; ++j) {
    Eigen::Vector2d a = Eigen::Vector2d::Zero();
    for (int f = 0; f < 2; ++f) a += feet_[f][j + 2] - 2 * feet_[f][j + 1] + feet_[f][j];
    ref_[0][j] -= k * a.x();
    ref_[1][j] -= k * a.y();
    // after this step the generator's time is t_ + dt: its share is sample 1's
    if (j == 1) sample_.zmp_swing = k * a;
  }
}

void PatternGenerator::Sample() {
  sample_.t = t_;
  gait_.At(t_, &sample_.gait);
  for (int a = 0; a < 2; ++a) {
    const Eigen::Vector3d& x = axis_[a].state();
    sample_.com[a] = x[0];
    sample_.dcom[a] = x[1];
    sample_.ddcom[a] = x[2];
    sample_.zmp[a] = axis_[a].zmp(gains_);
  }
  sample_.com.z() = zc() + sample_.gait.zmp.z();
  sample_.dcom.z() = sample_.gait.dz_ground;
  sample_.ddcom.z() = sample_.gait.ddz_ground;
}

}  // namespace ohrp::walking
