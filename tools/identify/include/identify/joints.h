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
//
// Standard errors: each fit refitted kBootstrapRefits times on its residuals resampled in
// blocks of kBootstrapBlock consecutive rows (a moving-block bootstrap with a fixed seed, so a
// log gives the same figures every time): y* = A x + r*, x* refitted, the std of x* over the
// refits. The blocks keep the residuals' correlation over neighbouring rows (a misfit that
// varies slowly along the chirp), which the least-squares formula (kept as *_se_ols) takes for
// independent noise. The servo's at its chosen lag.
#pragma once

#include <string>
#include <vector>

#include "robot_model/joint_params.h"

namespace ohrp::identify {

inline constexpr double kSaturated = 0.02;
inline constexpr int kBootstrapRefits = 50;
inline constexpr int kBootstrapBlock = 32;         // rows
inline constexpr unsigned kBootstrapSeed = 35;
inline constexpr double kExcitedSpan = 1e-3;       // [rad] a data log's joint whose reference
inline constexpr size_t kExcitedRows = 100;       // spans more, changing in this many rows
                                                   // or more, was excited

struct JointLog {
  std::string joint;
  std::vector<double> t, ref, q, dq, tau;
  // the reference velocity as the servo had it (a data log's dqref_); empty: the reference's
  // change since the row before (excite's rate), which on the boards' time is not the commands'
  // when the driver's commands reach the boards irregularly (two in one board cycle, none in the
  // next)
  std::vector<double> dref;
};

struct JointFitOptions {
  double v_min = 0.02;  // [rad/s] samples slower than this stay out of the dynamics fit
  int max_lag = 100;    // cycles tried for the servo's lag
};

struct JointEstimate {
  std::string joint;
  size_t samples = 0, moving = 0;  // all, and those in the dynamics fit
  double inertia = 0, inertia_se = 0;  // [kg m^2]; se: the bootstrap's (above)
  double viscous = 0, viscous_se = 0;  // [N m s/rad]
  double coulomb = 0, coulomb_se = 0;  // [N m]
  double inertia_se_ols = 0, viscous_se_ols = 0, coulomb_se_ols = 0;  // the formula's
  double dynamics_rms = 0, tau_rms = 0;  // residual and torque RMS [N m]
  int lag_cycles = 0;
  double period = 0;                   // [s] mean sample period
  double lag = 0;                      // [s] lag_cycles * period
  double kp = 0, kd = 0, servo_rms = 0;
  double kp_se = 0, kd_se = 0;         // the bootstrap's at the chosen lag
  size_t gaps = 0;                     // rows more than one period after the row before
  size_t saturated = 0;                // rows left out of the servo fit
};

// Reads an excite log (CSV: time, then JOINT_ref, JOINT_q, JOINT_dq, JOINT_tau per joint).
bool ReadExciteLog(const std::string& path, std::vector<JointLog>* joints, std::string* error);

// Reads a data log (hw_driver --log, best with --log-dq --log-time board; sim_host --log): the
// joints whose reference (qref_) spans more than kExcitedSpan and changes in kExcitedRows rows
// or more, each with its q_, qref_, tau_ and
// dq_ (without dq_: the difference of q_ over the interval ending at the row), over the rows in
// which the controller drove the servos (the status column: no kNoController, kHolding,
// kServoOff, kEmergencyStop, kShuttingDown, kDiverged; the others are gaps). A row whose q, dq
// and tau repeat the row before's bit for bit is a board without a new state (its time another
// board's): left out of that joint (counted in `*repeated`), as a row the driver missed. In the
// boards' time base rows are whole board cycles apart, some 2-10 (cycles the driver missed): the
// fits take the period as the median interval, the dynamics only rows one period after the row
// before, the servo's lag in those periods (a missed cycle's reference the row before's).
bool ReadJointDataLog(const std::string& path, std::vector<JointLog>* joints, size_t* repeated,
                      std::string* error);

// Either: an excite log (its second column ends in _ref) or a data log. `*note` says which and
// what was left out.
bool ReadJointLog(const std::string& path, std::vector<JointLog>* joints, std::string* note,
                  std::string* error);

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
