// The paper's figure-12 experiment on a block: a tall rigid body standing on one soft sole,
// tilted slightly about the pitch axis and released, rocks with the frequency and decay that
// the linearised rigid-body-on-spring-damper model predicts from the contact parameters.
// The model (small angles, coordinates x = horizontal displacement of the sole's bottom
// centre, theta = pitch about it; COM at height h above it, mass m, inertia I_c about it):
//   M = [[m, m h], [m h, I_c + m h^2]],  K = [[k_t, 0], [0, K_th - m g h]],
//   C = [[b_t, 0], [0, B_th]],  K_th = k S,  B_th = c m g S  (Hunt-Crossley linearised at the
//   static sink m g / k),  S = sum over the sample points of w_i u_i^2 (the grid's own second
//   moment of area, per unit area).
// Reference: the pitch-dominated eigenvalue of that model. Asserted: damped frequency within
// 2 % and decay rate within 10 % (the bound for the robot).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::DataPtr;
using testing::LoadString;
using testing::ModelPtr;

constexpr double kG = 9.81;

TEST(ContactOscillation, TiltedBlockRocksAsTheLinearisedModelPredicts) {
  const double dt = 1e-4, m = 60, h = 0.3, Ic = 2.0;
  const std::string xml =
      "<mujoco><option timestep=\"" + std::to_string(dt) +
      "\" integrator=\"Euler\"/><default><geom contype=\"0\" conaffinity=\"0\"/></default>"
      "<worldbody><geom name=\"floor\" type=\"plane\" size=\"5 5 0.1\"/>"
      "<body name=\"block\" pos=\"0 0 0.5\"><freejoint/>"
      "<inertial pos=\"0 0 " + std::to_string(h - testing::kSoleHalf[2]) + "\" mass=\"" +
      std::to_string(m) + "\" diaginertia=\"" + std::to_string(Ic) + " " + std::to_string(Ic) +
      " 1\"/><geom name=\"sole\" type=\"box\" size=\"0.125 0.07 0.01\"/></body>"
      "</worldbody></mujoco>";
  std::string error;
  ModelPtr model = LoadString(xml, &error);
  ASSERT_TRUE(model) << error;
  DataPtr d(mj_makeData(model.get()));
  SoftContactParams p;  // the defaults
  auto contact = SoftFootContact::Create(model.get(), {"sole"}, {}, p, m, &error);
  ASSERT_TRUE(contact) << error;

  // The linearised model.
  double S = 0;
  for (const SamplePoint& s :
       MakeGrid(Eigen::Vector3d(testing::kSoleHalf[0], testing::kSoleHalf[1], 0), p.grid_x,
                p.grid_y)) {
    S += s.weight * s.u * s.u;
  }
  const double sink = m * kG / p.stiffness;
  const double hc = h + sink;  // the bottom centre is `sink` under the floor
  Eigen::Matrix2d M, K, C;
  M << m, m * hc, m * hc, Ic + m * hc * hc;
  K << p.tangential_stiffness, 0, 0, p.stiffness * S - m * kG * hc;
  C << p.tangential_damping, 0, 0, p.damping * m * kG * S;
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  A.topRightCorner<2, 2>() = Eigen::Matrix2d::Identity();
  A.bottomLeftCorner<2, 2>() = -M.inverse() * K;
  A.bottomRightCorner<2, 2>() = -M.inverse() * C;
  Eigen::EigenSolver<Eigen::Matrix4d> es(A);
  // The slower oscillatory pair is the rocking (the other is the sole's shear mode).
  std::complex<double> rock(0, 1e9);
  for (int i = 0; i < 4; ++i) {
    const auto ev = es.eigenvalues()[i];
    if (ev.imag() > 0 && ev.imag() < rock.imag()) rock = ev;
  }
  const double w_ref = rock.imag(), sigma_ref = -rock.real();

  // Tilt by 0.5 mrad about y around the bottom centre at its static sink (every point stays in
  // contact: 0.1 m * 0.5 mrad = 0.05 mm < the 0.196 mm sink), release.
  const double theta0 = 5e-4;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(theta0, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d bottom(0, 0, -sink);
  const Eigen::Vector3d pos = bottom + q * Eigen::Vector3d(0, 0, testing::kSoleHalf[2]);
  for (int k = 0; k < 3; ++k) d->qpos[k] = pos[k];
  d->qpos[3] = q.w();
  d->qpos[4] = q.x();
  d->qpos[5] = q.y();
  d->qpos[6] = q.z();

  std::vector<double> t, th;
  const int steps = static_cast<int>(1.5 / dt);
  for (int i = 0; i < steps; ++i) {
    contact->ApplyBeforeStep(model.get(), d.get());
    mj_step(model.get(), d.get());
    contact->Commit();
    const Eigen::Quaterniond qe(d->qpos[3], d->qpos[4], d->qpos[5], d->qpos[6]);
    const Eigen::Matrix3d R = qe.toRotationMatrix();
    t.push_back((i + 1) * dt);
    th.push_back(std::atan2(R(0, 2), R(2, 2)));
  }
  // Upward zero crossings (interpolated) give the period; the positive peaks the decay.
  std::vector<double> up, peaks_t, peaks;
  for (size_t i = 1; i + 1 < th.size(); ++i) {
    if (th[i - 1] < 0 && th[i] >= 0) up.push_back(t[i - 1] + dt * th[i - 1] / (th[i - 1] - th[i]));
    if (th[i] > th[i - 1] && th[i] >= th[i + 1] && th[i] > 0) {
      peaks_t.push_back(t[i]);
      peaks.push_back(th[i]);
    }
  }
  ASSERT_GE(up.size(), 4u);
  ASSERT_GE(peaks.size(), 4u);
  const double period = (up.back() - up.front()) / (up.size() - 1);
  const double w_sim = 2 * M_PI / period;
  const double sigma_sim =
      std::log(peaks.front() / peaks.back()) / (peaks_t.back() - peaks_t.front());
  std::printf("rocking: damped frequency %.3f rad/s (linear model %.3f, error %.2f %%), decay "
              "rate %.3f 1/s (linear model %.3f, error %.2f %%), %zu periods\n",
              w_sim, w_ref, 100 * (w_sim - w_ref) / w_ref, sigma_sim, sigma_ref,
              100 * (sigma_sim - sigma_ref) / sigma_ref, up.size() - 1);
  EXPECT_NEAR(w_sim, w_ref, 0.02 * w_ref);
  EXPECT_NEAR(sigma_sim, sigma_ref, 0.10 * sigma_ref);
}

}  // namespace
}  // namespace ohrp::contact
