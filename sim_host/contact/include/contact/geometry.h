// The geometric step of the soft-foot contact (OpenHRP, IJRR 2004, section 3.3.1): where does a
// sole (a box, as in the robot model) penetrate the environment, and with which normal.
//
// What FCL 0.7 (Debian's libfcl 0.7.0, built with assertions) gives, measured on this machine,
// and what is computed here instead:
//  - mesh-mesh (BVHModel) contacts report per-triangle depths that are not penetration depths
//    and miss a mesh that lies wholly inside another: not used;
//  - fcl::distance with enable_signed_distance (GJK + EPA, libccd) between a small sphere and
//    an fcl::Box or fcl::Convex gives the correct signed distance and nearest points for generic
//    points, but for a sphere at a flat face of an fcl::Convex slab EPA aborts the process
//    (assertion `isOutsidePolytopeFace` in gjk_libccd-inl.h, ComputeVisiblePatch), and it costs
//    ~15 us per query; against an fcl::Halfspace it crashes (no libccd support function);
//  - fcl::distance WITHOUT signed distance (GJK only) between the sole's fcl::Box and a box,
//    convex or primitive is robust: it says whether the two touch (<= 0) or how far they are.
// So FCL is the narrow-phase test of each (sole, object) pair that survives the cheap bound,
// and the per-point constraint is computed in closed form, exactly: the sole's bottom face is
// sampled with a grid of points, and for each point inside an object its penetration is the
// distance to the nearest face of that object (for a convex object: min over its face planes;
// boxes, spheres, capsules, cylinders: their own closed forms), the normal that face's outward
// normal. That is the paper's "reasonable" constraint: the one that gives the smallest
// penetration depth in the point's neighbourhood. For a heightfield (not convex) the
// neighbourhood is the triangles of the 3 x 3 cells around the point: of those whose plane the
// point is below and through which it can leave (its projection on the plane lies in the
// triangle), the one with the smallest depth; the triangle under the point otherwise. When a
// point is inside several objects, the deepest one wins (the sole has to leave their union).
// The tests check these depths against FCL's signed distance where FCL is reliable (fcl::Box,
// generic points) and heightfields against MuJoCo's mj_ray.
// The cheap bound: world AABBs (for a plane: the lowest corner of the sole box along its
// normal), so that FCL is not called for a sole far from everything.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

namespace fcl {
template <typename S>
class CollisionGeometry;
}

namespace ohrp::contact {

enum class EnvKind { kPlane, kBox, kSphere, kCapsule, kCylinder, kConvexMesh, kHeightField };

// One static object of the environment, in world coordinates.
struct EnvObject {
  std::string name;
  EnvKind kind = EnvKind::kPlane;
  int geom_id = -1;                 // MuJoCo geom, when built from a model
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world <- object frame
  // Plane: the object's +z is the outward normal through its origin. Heightfield: no shape (FCL
  // has none). Others: the FCL shape, for the sole-vs-object narrow-phase test.
  std::shared_ptr<fcl::CollisionGeometry<double>> shape;
  Eigen::Vector3d local_center = Eigen::Vector3d::Zero();  // local AABB (unused for planes)
  Eigen::Vector3d local_half = Eigen::Vector3d::Zero();
  // Closed-form data: box half sizes / (radius, half length, -) / convex face planes (local
  // outward unit normal n and offset o: n.x - o <= 0 inside).
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector4d> planes;
  // Heightfield: nrow x ncol elevations [m] (row r at y = -sy + r*2sy/(nrow-1), column c at
  // x = -sx + c*2sx/(ncol-1)), half extents sx, sy, the solid goes down to z = -base.
  int hf_nrow = 0, hf_ncol = 0;
  double hf_sx = 0, hf_sy = 0, hf_base = 0;
  std::vector<double> hf_z;

  static EnvObject Plane(std::string name, const Eigen::Isometry3d& pose);
  static EnvObject Box(std::string name, const Eigen::Isometry3d& pose,
                       const Eigen::Vector3d& half_size);
  static EnvObject Sphere(std::string name, const Eigen::Isometry3d& pose, double radius);
  static EnvObject Capsule(std::string name, const Eigen::Isometry3d& pose, double radius,
                           double half_length);
  static EnvObject Cylinder(std::string name, const Eigen::Isometry3d& pose, double radius,
                            double half_length);
  // A heightfield (no FCL shape: bounded by its AABB only). Each cell is split into two
  // triangles along its (c, r)-(c+1, r+1) diagonal. heights: nrow*ncol, row-major, in metres.
  static EnvObject HeightField(std::string name, const Eigen::Isometry3d& pose, int nrow,
                               int ncol, double half_x, double half_y, double base,
                               std::vector<double> heights);
  // A convex polytope (fcl::Convex) from its hull vertices and triangles (outward, CCW).
  static EnvObject Convex(std::string name, const Eigen::Isometry3d& pose,
                          std::vector<Eigen::Vector3d> vertices,
                          const std::vector<int>& triangles);
};

// The sole: a box; its bottom face is the face at local z = -half.z().
struct SoleBox {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world <- sole frame
  Eigen::Vector3d half = Eigen::Vector3d::Zero();           // half sizes [m]
};

// A sample point of the bottom face, in the sole frame (z = -half.z), with its area fraction.
struct SamplePoint {
  double u = 0, v = 0;  // [m] along the sole's x and y
  double weight = 0;    // fraction of the face's area, sums to 1
};

// Grid of nx x ny points on the bottom face, the outer rows and columns on the face's edges
// (so that the sampled support polygon is the sole's own), weighted by the trapezoid rule
// (edge points carry half a cell, corners a quarter; the weights sum to 1). A single point
// along an axis sits in the middle.
std::vector<SamplePoint> MakeGrid(const Eigen::Vector3d& half, int nx, int ny);

// One penetrating sample point: the paper's intersecting point with its reasonable constraint.
struct PointContact {
  int index = -1;                            // sample point index in the grid
  int object = -1;                           // index of the environment object
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();     // world position of the sample point
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); // unit, out of the object (push direction)
  double depth = 0;                          // [m] > 0 inside; <= 0 for a point within the
                                             // search's reach outside (Find's `reach`)
};

struct GeometryStats {
  long long fcl_queries = 0;       // every fcl::distance call
  long long pairs_considered = 0;  // (sole, object) pairs looked at
  long long pairs_bound = 0;       // pairs rejected by the cheap bound (no FCL)
  long long pairs_fcl_far = 0;     // pairs rejected by one sole-vs-object FCL distance
  long long pairs_sampled = 0;     // pairs whose sample points were queried
};

class ContactGeometry {
 public:
  ContactGeometry(std::vector<EnvObject> env, double margin);

  std::vector<EnvObject>& env() { return env_; }
  const std::vector<EnvObject>& env() const { return env_; }
  const GeometryStats& stats() const { return stats_; }
  void ResetStats() { stats_ = {}; }

  // The penetrating points of the sole's bottom face (grid from MakeGrid with the same half),
  // and, with reach > 0, also the points outside but within `reach` [m] of an object (depth in
  // (-reach, 0]: the implicit step's points that may enter during the step; reach is capped at
  // the broad-phase margin). For a plane and a heightfield the outside distance is the exact
  // one; for the other objects a lower bound (a point may be listed a little early).
  void Find(const SoleBox& sole, const std::vector<SamplePoint>& grid,
            std::vector<PointContact>* out, double reach = 0);

  // Signed distance [m] of a world point to one object, closed form, no FCL: < 0 inside, exact
  // there (the depth of the nearest face) with that face's outward normal; > 0 outside (for a
  // box, cylinder or convex object then only a lower bound: only the sign is used).
  static double SignedDistance(const EnvObject& o, const Eigen::Vector3d& p,
                               Eigen::Vector3d* normal);

 private:
  bool CheapBoundSeparated(const SoleBox& sole, const EnvObject& o) const;
  std::vector<EnvObject> env_;
  double margin_;
  GeometryStats stats_;
  std::vector<int> candidates_;
};

}  // namespace ohrp::contact
