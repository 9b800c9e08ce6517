// The robot standing on the uneven floor of mjcf/hrp1s/scene_uneven.xml (a heightfield of
// gentle waves, +-3 mm) on its soft soles: the contact normals at the soles' points follow the
// surface (checked against the closed-form gradient of the waves the heightfield samples) and
// the soles carry m g. (The ringing of the foot forces on this floor is bounded by the
// force_ringing check of scenarios/stand_uneven.yaml and compared with MuJoCo's contacts by
// the test contact_ringing_rough_floor.)
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "leaning_robot.h"

namespace ohrp::sim {
namespace {

// The waves of tools/scripts/make_hfield.py, as scene_uneven.xml places them: elevation size
// 0.006 m, geom at z = -0.003 m, normalised height 0.5 + 0.25 sin(2 pi x / 0.4 + 0.3)
// + 0.25 sin(2 pi y / 0.5 + 1.1). Returns the upward unit normal at (x, y).
Eigen::Vector3d WaveNormal(double x, double y) {
  const double gx = 0.006 * 0.25 * (2 * M_PI / 0.4) * std::cos(2 * M_PI * x / 0.4 + 0.3);
  const double gy = 0.006 * 0.25 * (2 * M_PI / 0.5) * std::cos(2 * M_PI * y / 0.5 + 1.1);
  return Eigen::Vector3d(-gx, -gy, 1.0).normalized();
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI;
}

TEST(UnevenFloor, NormalsFollowTheSurfaceAndTheSolesCarryTheRobot) {
  testing::LeaningRobot r;
  r.Load("mjcf/hrp1s/scene_uneven.xml", "halfsit_uneven", 0, -0.06, 1.0);
  if (HasFatalFailure()) return;
  mjModel* m = r.m();
  mjData* d = r.d();
  contact::SoftFootContact* soft = &r.soft();
  double fz_sum = 0;
  int fz_n = 0;
  while (d->time < 5.0) {
    ASSERT_TRUE(r.Step());
    ASSERT_TRUE(std::isfinite(d->qpos[2])) << "t = " << d->time;
    if (d->time >= 3.0) {
      const auto& w = soft->wrenches();
      fz_sum += w[0].force.z() + w[1].force.z();
      ++fz_n;
    }
  }

  // 1. normals: every touching point's normal is the surface's, within 0.25 deg (the
  // heightfield's 2 cm triangles approximate the waves' slope of up to 1.4 deg to ~0.2 deg);
  // and the surface really is tilted there (a vertical normal would fail by up to 1.7 deg)
  soft->ApplyBeforeStep(m, d);
  double worst = 0, largest_tilt = 0;
  int points = 0;
  for (const contact::SoleWrench& w : soft->wrenches()) {
    ASSERT_TRUE(w.in_contact);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const contact::PointForce& p : w.per_point) {
      if (p.depth <= 0) continue;  // outside, listed for the implicit step: not touching
      const Eigen::Vector3d expected = WaveNormal(p.pos.x(), p.pos.y());
      worst = std::max(worst, AngleDeg(p.normal, expected));
      largest_tilt = std::max(largest_tilt, AngleDeg(expected, Eigen::Vector3d::UnitZ()));
      mean += p.fn * expected;
      ++points;
    }
    // the sole's resultant normal is the load-weighted surface normal under it
    EXPECT_LT(AngleDeg(w.normal, mean.normalized()), 0.1);
  }
  std::printf("uneven floor: %d points touch; normals within %.3f deg of the surface's, which "
              "tilts up to %.2f deg\n", points, worst, largest_tilt);
  // The joints hold the pose stiffly, so a sole cannot roll onto a floor that tilts across it
  // by 1 deg (2.5 mm over its width against a 0.2 mm sink): each sole stands on one long edge
  // (a row of 5 points) or more, as a position-controlled robot without compliance does.
  EXPECT_GE(points, 10);
  EXPECT_LT(worst, 0.25);
  EXPECT_GT(largest_tilt, 0.5);

  // 2. the soles carry the whole robot (m g, within 1 %) from 3 s to 5 s
  const double weight = r.robot().total_mass * -m->opt.gravity[2];
  EXPECT_NEAR(fz_sum / fz_n, weight, 0.01 * weight);
}

}  // namespace
}  // namespace ohrp::sim
