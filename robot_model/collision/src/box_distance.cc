// Box-box distance from their features: corners against boxes, edges against edges.
#include "box_distance.h"

#include <algorithm>
#include <cmath>

namespace ohrp::collision {
namespace {

Eigen::Vector3d Corner(const Eigen::Isometry3d& X, const Eigen::Vector3d& h, int i) {
  return X * Eigen::Vector3d((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(),
                             (i & 4 ? 1 : -1) * h.z());
}

// the point of the box closest to p_W
Eigen::Vector3d ClosestInBox(const Eigen::Isometry3d& X, const Eigen::Vector3d& h,
                             const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p = X.inverse() * p_W;
  return X * p.cwiseMax(-h).cwiseMin(h);
}

// the closest points of segments p0-p1 and q0-q1 (clamped parameters, as in Ericson's book)
void SegmentSegment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                    const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, Eigen::Vector3d* c_p,
                    Eigen::Vector3d* c_q) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.dot(d1), e = d2.dot(d2), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
  const double den = a * e - b * b;
  double s = den > 1e-18 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  *c_p = p0 + s * d1;
  *c_q = q0 + t * d2;
}

}  // namespace

double BoxBoxDistance(const Eigen::Isometry3d& X_WA, const Eigen::Vector3d& h_a,
                      const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& h_b,
                      Eigen::Vector3d* p_a, Eigen::Vector3d* p_b) {
  double best = INFINITY;
  auto keep = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double d = (a - b).norm();
    if (d < best) best = d, *p_a = a, *p_b = b;
  };
  // corners of each against the other box
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d ca = Corner(X_WA, h_a, i), cb = Corner(X_WB, h_b, i);
    keep(ca, ClosestInBox(X_WB, h_b, ca));
    keep(ClosestInBox(X_WA, h_a, cb), cb);
  }
  // the 12 edges of each: from each corner with a 0 bit, along that bit
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) {
      if (i & (1 << k)) continue;
      const Eigen::Vector3d a0 = Corner(X_WA, h_a, i), a1 = Corner(X_WA, h_a, i | (1 << k));
      for (int j = 0; j < 8; ++j)
        for (int l = 0; l < 3; ++l) {
          if (j & (1 << l)) continue;
          Eigen::Vector3d ca, cb;
          SegmentSegment(a0, a1, Corner(X_WB, h_b, j), Corner(X_WB, h_b, j | (1 << l)), &ca, &cb);
          keep(ca, cb);
        }
    }
  return best;
}

}  // namespace ohrp::collision
