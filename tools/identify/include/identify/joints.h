// ohrp identify --joints: a joint's inertia, viscous and Coulomb friction, and its servo's delay
// and realised PD gains, from a log of its excitation (controllers/excite.h: per cycle time, and
// per joint reference, measured position, velocity and torque). One joint at a time, the others
// held (their motion is not modelled).
//
// Dynamics: with its parent still, a hinge's torque is
//   tau = I qdd + b qd + c sign(qd) + A sin q + B cos q
// (the last two: gravity on the subtree about a fixed axis, whatever its mass and centre).
// The torque logged in row k is taken as the one that moved the joint from row k-1's state to
// row k's over the interval (a board that applies one torque per cycle and reports it with the
// state it produced: hw_emulator at one physics step per board cycle); so qdd is the backward
// difference of qd and the other terms are at row k-1's state. Least squares over the rows
// where |qd| >= v_min (Coulomb friction is indeterminate at rest); standard errors from the
// residual. I is the joint's total inertia about its axis (link + armature): the armature is I
// minus the link's, from the model. Under sim_host (several physics steps per control cycle,
// the torque changing within it) the fit is biased.
//
// Servo: the torque the joint got is the PD of the reference `lag` cycles earlier,
//   tau_k = kp (ref_{k-L} - q_{k-1}) + kd (dref_{k-L} - qd_{k-1}) + tau0,   dref the reference's
//   rate as commanded (its change over the interval since the previous row, as excite sends it),
//   L counted in cycles of the log's period (a row the logger missed: the row before in force),
// fitted for each L in 0..max_lag; the L of least residual is the lag (the chain's own latency
// included: one control cycle in sim_host), kp and kd the gains as realised. Rows whose |tau|
// is within kSaturated of the largest logged are taken as the servo at its torque limit and left
// out of this fit (not of the dynamics'): a saturated servo is not the PD law.
#pragma once

#include <string>
#include <vector>

#include "robot_model/joint_params.h"

namespace ohrp::identify {

inline constexpr double kSaturated = 0.02;

struct JointLog {
  std::string joint;
  std::vector<double> t, ref, q, dq, tau;
};

struct JointFitOptions {
  double v_min = 0.02;  // [rad/s] samples slower than this stay out of the dynamics fit
  int max_lag = 100;    // cycles tried for the servo's lag
};

struct JointEstimate {
  std::string joint;
  size_t samples = 0, moving = 0;  // all, and those in the dynamics fit
  double inertia = 0, inertia_se = 0;  // [kg m^2]
  double viscous = 0, viscous_se = 0;  // [N m s/rad]
  double coulomb = 0, coulomb_se = 0;  // [N m]
  double dynamics_rms = 0, tau_rms = 0;  // residual and torque RMS [N m]
  int lag_cycles = 0;
  double period = 0;                   // [s] mean sample period
  double lag = 0;                      // [s] lag_cycles * period
  double kp = 0, kd = 0, servo_rms = 0;
  size_t saturated = 0;                // rows left out of the servo fit
};

// Reads an excite log (CSV: time, then JOINT_ref, JOINT_q, JOINT_dq, JOINT_tau per joint).
bool ReadExciteLog(const std::string& path, std::vector<JointLog>* joints, std::string* error);

// Fits one joint's log. False with `*error` when there is too little motion to fit.
bool EstimateJoint(const JointLog& log, const JointFitOptions& o, JointEstimate* e,
                   std::string* error);

// The model the excitation ran on: its file (MJCF, VRML, URDF or robot profile) and the
// keyframe the other joints held (empty: the model's initial posture).
// With `draws_for`, also a sweep of that scenario with the parameters drawn `draws` times within
// their standard errors (WriteDrawSweep).
struct JointModel {
  std::string model, keyframe;
  std::string draws_for;
  int draws = 8;
};

// The estimates as the model's joint parameters (robot_model/joint_params.h): armature = the
// identified total inertia less the links' share from the model (its mass matrix's diagonal in
// the keyframe, the joint at its mean logged position, the model's armature left out), damping
// = the viscous friction, frictionloss = the Coulomb friction; a negative value is left out
// (the model's stays) with a line in `*warnings`. False with `*error` when the model does not
// load or lacks a joint.
bool JointParamsFromEstimates(const std::vector<JointLog>& logs,
                              const std::vector<JointEstimate>& estimates,
                              const JointModel& model, std::vector<model::JointParams>* out,
                              std::vector<std::string>* warnings, std::string* error);

// OUT_DIR/joints_draws.yaml: a sweep of `model.draws_for` (a scenario name or file) with each
// parameter of `params` that has a value and a positive standard error drawn `model.draws`
// times from a normal distribution about it (std: the estimate's standard error; clipped to 3
// of them and to >= 0; seeds 1, 2, ...), zipped into one axis; checked as `ohrp sweep` reads
// it before it is written. Returns the exit code (2 with the reason on stderr).
int WriteDrawSweep(const std::string& log, const std::vector<model::JointParams>& params,
                   const std::vector<JointEstimate>& estimates, const JointModel& model,
                   const std::string& path);

// ohrp identify --joints LOG: every joint of the excite log fitted, a table on stdout and
// OUT_DIR/joints.json; with `model.model` also OUT_DIR/joints.yaml, the file sim_host's
// --joint-file applies. Returns the exit code: 0, 2 (the log unreadable, a joint that cannot be
// fitted, a model that does not load or lacks a joint, with the reason on stderr).
int IdentifyJoints(const std::string& log, const std::string& out_dir, const JointFitOptions& o,
                   const JointModel& model = {});

}  // namespace ohrp::identify
