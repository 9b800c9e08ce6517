// What a robot profile derives from a compiled model (shared by ApplyProfile and DraftProfile).
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <string>

namespace ohrp::model::profile {

inline constexpr double kLowestTolerance = 0.005;  // [m] geoms this close to the lowest touch

// The sole rectangle of body `b` from its lowest colliding geoms (all geoms when none collide),
// in the body's frame, whose z is taken as up: the points within kLowestTolerance of the lowest
// (a sphere's or capsule's bottom, a box's or mesh's vertices) bound it. `*how` says which
// geoms. False when the body has no geom or the rectangle is narrower than 1 mm.
bool DeriveSole(const mjModel* m, int b, std::array<double, 2>* size,
                std::array<double, 3>* centre, std::string* how);

// The lowest world z of body `b`'s colliding geoms (all geoms when none collide) in data `d`
// (kinematics computed); +inf when it has no geom.
double LowestZ(const mjModel* m, const mjData* d, int b);

// A box geom of body `b` whose name ends in "_SOLE" (the model's own sole), or -1.
int SoleGeom(const mjModel* m, int b);

// The body of the first free joint, else the first body under the world (-1: none).
int RootBody(const mjModel* m);

// True when a site of body `b` or of one of its ancestors carries a <force> and a <torque>.
bool HasForceTorque(const mjModel* m, int b);

// The site carrying a <gyro> and an <accelerometer>, or -1.
int ImuSite(const mjModel* m);

// True when a geom of body `b` collides (contype or conaffinity not 0).
inline bool Collides(const mjModel* m, int g) {
  return m->geom_contype[g] != 0 || m->geom_conaffinity[g] != 0;
}

}  // namespace ohrp::model::profile
