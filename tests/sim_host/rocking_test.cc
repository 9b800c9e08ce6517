// Tests the paper's damped oscillation (OpenHRP IJRR 2004, figure 12): the robot standing on
// its soft soles with stiff joints and no balance feedback, tilted about the pitch axis by a
// push and released, rocks with the frequency and decay that the linearised rigid body on the
// soles' spring-dampers predicts from the foot parameters.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "contact/geometry.h"
#include "identify/rocking.h"
#include "leaning_robot.h"

namespace ohrp::sim {
namespace {

constexpr double kDt = 0.0005;        // [s] stiff joints want a small step
constexpr double kGainScale = 100;    // joint kp x 100 (kd x 10): ~60 Hz joints, rigid next to the ~3 Hz rocking
constexpr double kLean = -0.06;       // [rad] on both ankle pitches: the load centre moves under the sole's middle
constexpr double kPushTorque = 40;    // [N m] about the world y axis
constexpr double kPushStart = 3.0, kPushEnd = 3.5, kEnd = 6.5;  // [s]

double Pitch(const mjData* d, int body) {
  const double* q = d->xquat + 4 * body;
  return std::asin(std::clamp(2 * (q[0] * q[2] - q[3] * q[1]), -1.0, 1.0));
}

// The linearised model (the rigid robot on the sample points of its soles, in the sagittal
// plane) is identify/rocking.h's PredictRocking, which ohrp identify inverts.
using identify::Mode;
using identify::PredictRocking;

TEST(Rocking, StandingRobotRocksAsTheLinearisedSpringDamperPredicts) {
  testing::LeaningRobot r;
  r.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", kDt, kLean, kGainScale);
  if (HasFatalFailure()) return;
  mjModel* m = r.m();
  mjData* d = r.d();
  const model::RobotMap& robot = r.robot();
  const contact::SoftFootContact* soft = &r.soft();

  // stiff joints holding the half-sitting pose, leaned forward at the ankles over the first
  // second, pushed about the pitch axis and released
  const int base = robot.base_body;
  std::vector<double> t_free, pitch_free;
  while (d->time < kEnd) {
    const bool push = d->time >= kPushStart && d->time < kPushEnd;
    d->xfrc_applied[6 * base + 4] = push ? kPushTorque : 0.0;
    ASSERT_TRUE(r.Step());
    if (d->time >= kPushEnd + 0.05) {
      t_free.push_back(d->time);
      pitch_free.push_back(Pitch(d, base));
    }
  }

  // measured: period from upward zero crossings of the pitch about its mean, decay from the
  // ratio of successive peaks (logarithmic decrement)
  double mean = 0;
  for (double p : pitch_free) mean += p;
  mean /= pitch_free.size();
  std::vector<double> ups, peaks;
  double peak = 0;
  for (size_t i = 1; i < pitch_free.size(); ++i) {
    const double a = pitch_free[i - 1] - mean, b = pitch_free[i] - mean;
    peak = std::max(peak, b);
    if (a < 0 && b >= 0) {
      ups.push_back(t_free[i - 1] + (t_free[i] - t_free[i - 1]) * (-a) / (b - a));
      if (ups.size() > 1) peaks.push_back(peak);
      peak = 0;
    }
  }
  ASSERT_GE(ups.size(), 4u) << "no oscillation after the release";
  const double period = (ups.back() - ups.front()) / (ups.size() - 1);
  const double omega_measured = 2 * M_PI / period;
  // peaks[k] lies between ups[k] and ups[k+1]; skip the first (transient of the release) and
  // stop where the amplitude falls below a fifth of the second peak: past that, what is left
  // of the other modes and of the settling offset biases the ratio
  ASSERT_GE(peaks.size(), 3u);
  size_t last = 2;
  while (last + 1 < peaks.size() && peaks[last + 1] > 0.2 * peaks[1]) ++last;
  const double decrement = std::log(peaks[1] / peaks[last]) / static_cast<double>(last - 1);
  const double zeta_measured = decrement / std::sqrt(4 * M_PI * M_PI + decrement * decrement);

  // predicted: from the robot's mass, inertia and centre of mass and the soles' sample points
  mj_forward(m, d);
  const double* com = d->subtree_com + 3 * base;
  double Iyy = 0;
  for (int b = 1; b < m->nbody; ++b) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->ximat + 9 * b);
    const Eigen::Vector3d I(m->body_inertia + 3 * b);
    const Eigen::Vector3d rb = Eigen::Vector3d(d->xipos + 3 * b) - Eigen::Vector3d(com);
    const Eigen::Matrix3d Iw = R * I.asDiagonal() * R.transpose() +
                               m->body_mass[b] * (rb.squaredNorm() * Eigen::Matrix3d::Identity() - rb * rb.transpose());
    Iyy += Iw(1, 1);
  }
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;
  for (int g : soft->sole_geoms()) {
    const Eigen::Vector3d half(m->geom_size + 3 * g);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->geom_xmat + 9 * g);
    const Eigen::Vector3d c(d->geom_xpos + 3 * g);
    for (const auto& sp : contact::MakeGrid(half, soft->params().grid_x, soft->params().grid_y)) {
      const Eigen::Vector3d p = c + R * Eigen::Vector3d(sp.u, sp.v, -half.z());
      points.emplace_back(p.x() - com[0], p.z() - com[2]);
      weights.push_back(sp.weight);
    }
  }
  const Mode predicted = PredictRocking(points, weights, robot.total_mass, Iyy,
                                        -m->opt.gravity[2], soft->params());
  RecordProperty("omega_measured", std::to_string(omega_measured));
  RecordProperty("omega_predicted", std::to_string(predicted.omega_d));
  RecordProperty("zeta_measured", std::to_string(zeta_measured));
  RecordProperty("zeta_predicted", std::to_string(predicted.zeta));
  std::printf("rocking: measured %.2f rad/s, zeta %.4f (peaks 2-%zu); predicted %.2f rad/s, zeta %.4f\n",
              omega_measured, zeta_measured, last + 1, predicted.omega_d, predicted.zeta);
  // the paper's criterion: frequency and decay within 10 %
  EXPECT_NEAR(omega_measured, predicted.omega_d, 0.10 * predicted.omega_d);
  EXPECT_NEAR(zeta_measured, predicted.zeta, 0.10 * predicted.zeta);
}

}  // namespace
}  // namespace ohrp::sim
