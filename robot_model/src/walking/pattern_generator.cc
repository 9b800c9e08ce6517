// The walking pattern generator: preview control on the gait's ZMP reference
// (pattern_generator.h).
#include "walking/pattern_generator.h"

#include <cmath>

namespace ohrp::walking {

bool PatternGenerator::Configure(const GaitOptions& gait, const PreviewOptions& preview,
                                 std::string* error) {
  if (const std::string e = CheckGaitOptions(gait); !e.empty()) {
    *error = "gait: " + e;
    return false;
  }
  gait_options_ = gait;
  if (!gains_.Compute(preview, error)) return false;
  ref_[0].assign(gains_.horizon() + 1, 0.0);
  ref_[1].assign(gains_.horizon() + 1, 0.0);
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
    ref_[0].assign(gains_.horizon() + 1, 0.0);
    ref_[1].assign(gains_.horizon() + 1, 0.0);
  }
  t_ = t;
  gait_.Start(t, feet, gait_options_);
  // standing: the ZMP reference is the middle of the feet; the CoM starts at rest where it is
  // (it moves over the middle if it is not there)
  axis_[0].Reset(gains_, Eigen::Vector3d(com.x(), 0, 0), com.x());
  axis_[1].Reset(gains_, Eigen::Vector3d(com.y(), 0, 0), com.y());
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
  for (int j = 0; j <= n; ++j) {
    const Eigen::Vector3d p = gait_.Zmp(t_ + j * dt);
    ref_[0][j] = p.x();
    ref_[1][j] = p.y();
  }
  axis_[0].Step(gains_, ref_[0].data());
  axis_[1].Step(gains_, ref_[1].data());
  t_ += dt;
  Sample();
  return sample_;
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
