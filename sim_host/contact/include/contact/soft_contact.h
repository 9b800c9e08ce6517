// The soft-foot contact bound to a MuJoCo model: soles (box geoms) against static environment
// geoms, forces written into mjData.
//
// Where the force goes: d->xfrc_applied of the sole's body (a world-frame force and torque at
// the body's centre of mass, d->xipos). Not qfrc_applied through mj_applyFT: both move the
// robot the same way, but MuJoCo builds the external body forces cfrc_ext (used by
// mj_rnePostConstraint, hence by the force/torque sensors of the ankles) from xfrc_applied and
// its own contacts only, so a generalized force would be invisible to the F/T sensors.
// Who clears it: nobody. MuJoCo never clears xfrc_applied (nor qfrc_applied); Apply() removes
// what it added on its previous call before adding the new wrench, so other writers that add
// to xfrc_applied are kept, and Remove() takes this contact's share out (call it when the model
// is switched off). Whoever writes xfrc_applied with "=" must do so before Apply().
//
// Timing, per physics step:
//   contact.ApplyBeforeStep(m, d);   // kinematics at the current qpos/qvel, forces, xfrc_applied
//   mj_step(m, d);
//   contact.Commit();                // the friction anchors of this step become the state
// The force is held over the step (explicit in every integrator; for RK4 a zero-order hold,
// unless EvaluateAtEveryStage(true) moves the evaluation into mjcb_control, where the
// kinematics are current at each stage). Commit() keeps the anchors of the FIRST evaluation since the last Commit (the one at
// the start of the step), so stage evaluations or an extra mj_forward never advance them.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/LU>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "contact/force.h"
#include "contact/geometry.h"
#include "contact/params.h"

namespace ohrp::contact {

class SoftFootContact {
 public:
  // sole_geoms: names of box geoms (the soles). env_geoms: names of static geoms (welded to the
  // world) they touch; empty = every geom of the world body that is not a sole. Supported
  // environment geoms: plane, box, sphere, capsule, cylinder, mesh (its convex hull, as MuJoCo
  // collides it), heightfield (its elevations are copied here: changes to m->hfield_data after
  // Create are not seen). The parameters are validated for
  // the model's timestep and mass_scale [kg], the smallest mass riding on one sole (see
  // Validate). Returns null with a message in *error.
  static std::unique_ptr<SoftFootContact> Create(const mjModel* m,
                                                 const std::vector<std::string>& sole_geoms,
                                                 const std::vector<std::string>& env_geoms,
                                                 const SoftContactParams& params,
                                                 double mass_scale, std::string* error);

  // Computes the wrench of every sole from d's kinematics (xpos/xmat, cvel, subtree_com must
  // be current: after mj_forward, inside mjcb_control, or after UpdateKinematics). Does not
  // touch d and does not advance the friction state. with_reach: also list the points outside
  // that may enter within a step (what the implicit step integrates; they carry no force here).
  const std::vector<SoleWrench>& Evaluate(const mjModel* m, const mjData* d,
                                          bool with_reach = false);
  // Writes the last evaluation into d->xfrc_applied (replacing its previous contribution).
  void Apply(const mjModel* m, mjData* d);
  // mj_kinematics + mj_comPos + mj_comVel at the current qpos/qvel (what mj_step recomputes
  // anyway), then Evaluate and Apply: the call to make just before mj_step. When implicit()
  // (the default), the applied wrench is the implicit one (see implicit.cc): the law averaged
  // along the step's path, the end velocity from one Newton step through the sole bodies'
  // apparent inertia; wrenches() stay the law at the step's start.
  void ApplyBeforeStep(const mjModel* m, mjData* d);
  // The same between mj_step1 and mj_step2 (Euler and implicit integrators), which have just
  // computed the kinematics, the com velocities and the factorised mass matrix at this state:
  // nothing is computed twice (mj_step would redo them after ApplyBeforeStep). Identical forces.
  void ApplyAfterStep1(const mjModel* m, mjData* d);
  static void UpdateKinematics(const mjModel* m, mjData* d);
  // Advances the friction anchors (call after mj_step).
  void Commit();

  // Forces at every stage of the integrator. Off (the default), ApplyBeforeStep evaluates the
  // contact once at the start of the step and MuJoCo holds that force through it: exact for
  // Euler and implicit, a zero-order hold that makes RK4 first-order in the contact. On, the
  // contact is evaluated and applied from MuJoCo's mjcb_control, which mj_forward calls after
  // the velocity stage: at the start of mj_step and at each of RK4's three later stages, with
  // the kinematics of that stage, so RK4 stays fourth-order; ApplyBeforeStep then does nothing
  // (mj_step's own mj_forward does the work), Commit still keeps the anchors of the first
  // evaluation since the last commit (the step's start), and wrenches() after mj_step are those
  // of the last stage evaluated. mjcb_control is process-wide: one contact at a time can be on
  // (false with *error otherwise); a callback installed before is called first and restored
  // when this contact is switched off or destroyed.
  bool EvaluateAtEveryStage(bool on, std::string* error = nullptr);
  bool at_every_stage() const { return at_every_stage_; }
  // Linearly implicit force in ApplyBeforeStep (default on); off = the explicit law held over
  // the step (the former scheme, kept for comparison). Stage evaluation (RK4) stays explicit.
  // Create validates for the implicit step unless the model's integrator is RK4: switching
  // it off may leave parameters the explicit step cannot take (Validate with kExplicit says).
  void SetImplicit(bool on) { implicit_ = on; }
  bool implicit() const { return implicit_; }
  ~SoftFootContact();
  SoftFootContact(const SoftFootContact&) = delete;
  SoftFootContact& operator=(const SoftFootContact&) = delete;
  // Removes this contact's share from d->xfrc_applied.
  void Remove(mjData* d);

  // The contact's own state, for restarting a simulation from a saved point: the committed
  // friction anchors and the wrench Apply() last added per sole body (so that the next Apply()
  // replaces it in a restored d->xfrc_applied). Restore it together with the mjData it goes with.
  struct State {
    std::vector<std::vector<Anchor>> anchors;
    std::vector<Eigen::Matrix<double, 6, 1>> applied;
  };
  State SaveState() const { return {anchors_, applied_}; }
  // Takes a state saved from this contact or from one created on the same model and soles;
  // false (nothing changed) when its sizes do not match.
  bool RestoreState(const State& state);

  const std::vector<SoleWrench>& wrenches() const { return wrenches_; }
  // what Apply / the implicit step last put into xfrc_applied, per sole body (force, torque
  // about its centre of mass): the force held over the step
  const std::vector<Eigen::Matrix<double, 6, 1>>& applied() const { return applied_; }
  const std::vector<int>& sole_geoms() const { return sole_geom_; }
  const std::vector<int>& sole_bodies() const { return bodies_; }  // each once, in A's order
  // the sole bodies' apparent inverse inertia A = J M^-1 J^T (6 rows per sole body: linear
  // then angular, about its centre of mass) of the last implicit step that had a contact
  const Eigen::MatrixXd& mobility() const { return mobility_; }
  const SoftContactParams& params() const { return params_; }
  // ImpactNote of the parameters at the model's step (implicit step only; "" when it resolves
  // impacts): sim_host prints it at the start of a run and with --explain
  const std::string& impact_note() const { return impact_note_; }
  ContactGeometry& geometry() { return geometry_; }
  const GeometryStats& stats() const { return geometry_.stats(); }

 private:
  SoftFootContact(ContactGeometry geometry, const SoftContactParams& params);
  // the linearly implicit correction added to the evaluated wrenches (implicit.cc)
  void AllocateImplicit(const mjModel* m);
  // mass_factored: d->qM and d->qLD are those of this state already (after mj_step1)
  void ApplyImplicit(const mjModel* m, mjData* d, bool mass_factored);

  ContactGeometry geometry_;
  SoftContactParams params_;
  std::vector<int> sole_geom_;
  std::vector<Eigen::Vector3d> sole_half_;
  std::vector<std::vector<SamplePoint>> grid_;
  std::vector<std::vector<Anchor>> anchors_;   // committed
  std::vector<std::vector<Anchor>> proposed_;  // from the first evaluation since Commit
  bool proposed_valid_ = false;
  std::vector<std::vector<Anchor>> scratch_;
  std::vector<SoleWrench> wrenches_;
  std::vector<PointContact> points_;
  std::string impact_note_;
  std::vector<int> bodies_;                               // bodies carrying soles, each once
  std::vector<Eigen::Matrix<double, 6, 1>> applied_;      // per body: what Apply() added
  bool at_every_stage_ = false;
  // implicit step scratch, sized at Create: per body 6x6 matrices about the centre of mass, the
  // stacked body Jacobians (6 rows per body), their half solves D^-1/2 L'^-1 J^T, the apparent
  // inverse inertia, twist changes, wrenches and the LU of the small system
  bool implicit_ = true;
  // stiff_: the law's static stiffness (for the window's lam); damp_: the wrench's derivative
  // in the end twist; normal_: the direction the sum of the normal forces must not turn over
  std::vector<Eigen::Matrix<double, 6, 6>> stiff_, damp_;
  std::vector<Eigen::Vector3d> normal_;
  std::vector<mjtNum> jac_;
  // per body the dofs that move it (its own and its ancestors', descending): the only columns
  // where its Jacobian and D^-1/2 L'^-1 J^T are not zero; the half solve's eliminations within
  // the chain (row `to` -= qLD[adr] row `from`, positions in the chain); per pair of bodies
  // k < l the positions of the dofs both chains have ([k * bodies + l]); per body its Jacobian
  // and its half solve on the chain (a row per chain position, the six Jacobian rows as columns)
  struct Elimination {
    int from, to, adr;
  };
  using ChainRows = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;
  std::vector<std::vector<int>> chain_;
  std::vector<std::vector<Elimination>> solve_;
  std::vector<std::vector<std::pair<int, int>>> shared_;
  std::vector<ChainRows> jc_, x_;
  Eigen::MatrixXd mobility_, system_;
  // the time the next step starts at if the state comes from the step this one made: the
  // accelerations in mjData are then that step's (see ApplyImplicit)
  double next_time_ = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd dv_, rhs_, correction_, wrench_;
};

}  // namespace ohrp::contact
