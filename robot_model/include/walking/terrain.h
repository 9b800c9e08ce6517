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
  // A step whose toes come nearer a riser ahead (terrain higher than the sole's plane by more
  // than kLevelChange) than kShinLean of the riser's height is moved the same way to the
  // nearest spot that keeps it; with none within `search`, false with `*error` naming the step,
  // the clearance and the limit.
  bool PlaceSteps(std::vector<Footstep>* steps, const FeetPose& start, const StepLimits& limits,
                  double search, std::string* error) const;
  // each step's clear_z: the highest terrain under its sole swept from where that foot stands
  // before it (from `start` on) to where it lands (the sole's yaw interpolated; sampled every
  // 5 mm of the way on an 11 x 3 grid of the sole, its edges included)
  void SetSwingClearance(std::vector<Footstep>* steps, const FeetPose& start,
                         const StepLimits& limits) const;
  // the distance [m] from the toe of `s` (its sole's front edge, limits.sole_half_size) to the
  // nearest point ahead, within kToeReach, where the terrain stands higher than the sole's plane
  // (through s.p, tilted by s.roll, s.pitch) by more than kLevelChange (a riser), on the sole's
  // centre line and its two side edges (sampled every 5 mm, the riser's face bisected to
  // 0.1 mm); kToeReach when there is none. `*need`: kShinLean times that riser's height above
  // the plane (0 when none)
  double ToeClearance(const Footstep& s, const StepLimits& limits, double* need = nullptr) const;
  // the toes of `s` at least kShinLean of its height from a riser ahead
  bool ToesClear(const Footstep& s, const StepLimits& limits) const;

  // A goal (x, y, yaw in the start's mid frame, as PlanToGoal) across the terrain, one level
  // at a time: PlanToGoal's strides placed as PlaceSteps places them, until a step's way from
  // its stance sole crosses a rise (the surface's height jumps by more than kLevelChange between
  // points 5 mm apart: a stair's riser, not a slope or a stone); that step lands where its whole
  // sole, a margin around it included (MarginFor), rests on one plane of the new level (of the run
  // of such spots along its heading nearest the planned one, within the limits, the middle going
  // up and the farthest going down; the swing no longer than max_forward: from
  // beside the other foot), and the other foot closes beside it (one stair at
  // a time: a step-to gait); from a stance too far back to reach the new level within
  // max_forward, both feet first step to the farthest spot of their own level (the edge). Then
  // the rest is planned again from there. Each step carries its height and tilt. False with
  // `*error` naming the step that has no surface, no spot on the new level within the limits
  // (a tread shorter than the sole and the margins, or beyond max_forward) or no spot beside it.
  // A goal whose soles (side by side, limits.width apart) would rest across a rise, or within
  // kLevelMargin of one, is moved along its heading to the nearest spot (within a sole's length)
  // where both rest on one level with that margin, and `*note` (when given) says how far; none:
  // false naming the goal. A step towards the edge of a level that does not bring the feet
  // nearer the goal is refused (no way on towards it) rather than walked back and forth.
  // Every step keeps its toes clear of a riser ahead (ToesClear).
  bool PlanGoalAcross(const FeetPose& start, double x, double y, double yaw,
                      const StepLimits& limits, double search, std::vector<Footstep>* steps,
                      std::string* error, std::string* note = nullptr) const;
  static constexpr double kLevelChange = 0.02;  // [m] a rise between two levels
  static constexpr double kLevelMargin = 0.02;  // [m] around a sole landing on a new level
  // [m per m] a sole's toes keep this share of a riser's height (above the sole) from it: the
  // stance shin leans forward over the toes while the CoM rises onto the stair, and reaches a
  // higher riser's nose sooner (HRP-1S, a 0.15 m riser: at 1.8 cm the left shin touched the
  // nose, at 3.0 cm = 0.2 x 0.15 m it cleared; docs/walking.md)
  static constexpr double kShinLean = 0.2;
  static constexpr double kToeReach = 0.1;  // [m] risers looked for this far ahead of the toes

  // the start frame in the scene's world: origin and yaw
  const Eigen::Vector3d& origin() const { return origin_; }
  double yaw() const { return yaw_; }
  int geom_count() const { return static_cast<int>(geoms_.size()); }

 private:
  TerrainMap() = default;
  // the height [m, world] of the highest terrain surface on the vertical through (x, y) of
  // the world, or false
  bool Height(double x, double y, double* z) const;
  // the largest jump of the terrain's height between neighbouring points 5 mm apart on the way
  // from a to b (start frame) [m]
  double LargestRise(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;
  // how far around a sole its level must reach: behind its heel, before its toes [m] (and
  // kLevelMargin to either side)
  struct LevelMargin {
    double back = kLevelMargin, front = kLevelMargin;
  };
  // kLevelMargin all round; going down none before the toes
  static LevelMargin MarginFor(bool down);
  // the surface under `s` when its sole and `margin` around it rest on one plane
  bool OnOneLevel(const Footstep& s, const StepLimits& limits, const LevelMargin& margin,
                  SurfaceSample* out) const;
  // `s` moved along its heading to a spot within the limits against `feet` where it rests on one
  // plane, across a rise from its stance sole (new_level) or not; the nearest to the planned spot
  // first, or the farthest forward (`farthest`); on a new level, of the run of such spots
  // around it, the middle going up (the sole centred on a stair's tread) and the farthest going
  // down (the heel farthest past the nose); false when there is none
  // (with `fixed`, that margin; otherwise MarginFor the step's way down or not)
  bool PlaceOnLevel(const FeetPose& feet, Footstep* s, const StepLimits& limits, bool new_level,
                    bool farthest, const LevelMargin* fixed = nullptr) const;
  // the surface under the sole of `s` (and `margin` around it) rises by more than kLevelChange
  // (along or across it)
  bool SoleAcrossRise(const Footstep& s, const StepLimits& limits, double margin = 0) const;
  // the goal `g` moved along its heading to the nearest spot (within a sole's length) where
  // both soles of the stance rest on one level with kLevelMargin, the toes clear; false if none
  // (a goal with no surface under a sole is left where it is)
  bool GoalOnOneLevel(Frame2* g, const StepLimits& limits) const;
  // the other foot's step beside `last` (limits.width apart, parallel) on its level, appended to
  // `steps` and `feet`; false with `*error` when the spot is not on one plane with `margin`
  bool CloseBeside(FeetPose* feet, const Footstep& last, const LevelMargin& margin,
                   const StepLimits& limits, std::vector<Footstep>* steps, std::string* error) const;

  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> geoms_;  // the terrain's geoms
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double yaw_ = 0;
  double top_ = 0;          // above every terrain geom [m, world]
};

}  // namespace ohrp::walking
