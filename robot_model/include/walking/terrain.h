// The ground a walk is planned on, from a scene: footsteps put onto the surfaces (their height
// and tilt under the sole), as the paper's platform shares the simulator's model of the
// environment with the controllers (a map given to the robot; the robot's state still comes
// from its own sensors).
//
// The terrain is the scene's static geometry: every geom on a body welded to the world (planes,
// boxes, spheres, capsules, cylinders, ellipsoids, height fields, meshes), the robot's own geoms
// excluded. The walk's start frame is the robot's at the scene's initial state (or a keyframe):
// x, y at the midpoint of its two soles, z at their bottom, yaw the base's heading; the
// estimator's world frame at start is the same (robot_model/estimator.h).
//
// Under a sole (a rectangle at a footstep's position and yaw) the surface is sampled by
// vertical rays on a 5 x 3 grid (inset 5 mm from the edges). The sole lands as a rigid plate
// resting on those points: on the lowest plane (at the sole's centre) that leaves every sample
// on or below it, the upper hull's facet over the centre (of equally low planes, the least
// tilted). On a slope that is the slope; across
// a crease (the foot of a ramp) or over a stone's edge it rests on the highest points, tilted
// between them (`planar` then says the surface is not one plane within 2 mm). A sole with a hit
// missing (over a hole or off the terrain) is refused.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "walking/footsteps.h"

namespace ohrp::walking {

struct SurfaceSample {
  double z = 0;               // height of the sole's centre on the surface (start frame) [m]
  double roll = 0, pitch = 0; // the surface's tilt (Footstep::roll, pitch) [rad]
  bool planar = true;         // the hits lie on the sole's plane within 2 mm
  // the samples within 2 mm of the sole's plane, as a rectangle in the sole's frame (reaching
  // the sole's edge where the outermost samples touch): where it bears [m]
  Eigen::Vector2d contact_centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d contact_half = Eigen::Vector2d::Zero();
};

class TerrainMap {
 public:
  // the terrain of the MJCF scene at `path`, the start frame from its robot (the first free
  // joint's body, its soles: geoms named *_SOLE) at the initial state or `keyframe`; null with
  // `*error` (file, what is missing) on failure
  static std::unique_ptr<TerrainMap> Load(const std::string& path, const std::string& keyframe,
                                          std::string* error);
  ~TerrainMap();
  TerrainMap(const TerrainMap&) = delete;
  TerrainMap& operator=(const TerrainMap&) = delete;

  // the surface under a sole of half size `half` (x along the sole, y across) centred at `p`
  // (start frame) with `yaw`; false (and why) when a ray finds no surface
  bool SurfaceUnder(const Eigen::Vector2d& p, double yaw, const Eigen::Vector2d& half,
                    SurfaceSample* out, std::string* why) const;
  // each step (from the stance `start`) gets its z, roll and pitch from the surface under its
  // sole (limits.sole_half_size); a step whose sole would rest across an edge (not one plane
  // under it) is moved to the nearest spot within `search` [m] (1 cm grid) where it rests on one
  // plane and where it and the next step keep `limits`, and stays (tilted on the edge) if there
  // is none; false with `*error` naming the step (counted from 1) that has no surface under it
  bool PlaceSteps(std::vector<Footstep>* steps, const FeetPose& start, const StepLimits& limits,
                  double search, std::string* error) const;

  // the start frame in the scene's world: origin and yaw
  const Eigen::Vector3d& origin() const { return origin_; }
  double yaw() const { return yaw_; }
  int geom_count() const { return static_cast<int>(geoms_.size()); }

 private:
  TerrainMap() = default;
  // the height [m, world] of the highest terrain surface on the vertical through (x, y) of
  // the world, or false
  bool Height(double x, double y, double* z) const;

  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> geoms_;  // the terrain's geoms
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double yaw_ = 0;
  double top_ = 0;          // above every terrain geom [m, world]
};

}  // namespace ohrp::walking
