// The online self-collision check of every controller (the paper's section 4.1, step 3), on the
// MEASURED state and what the robot can do (docs/selfcollision.md, "The online check"):
//
//   predict   per joint, the motion this cycle's command can cause: the servo law of the
//             command (tau = kp (q_ref - q) + kd (dq_ref - dq) + tau_ff, clamped to the
//             header's tau_max): the last period's measured acceleration plus the change of
//             servo torque over the inertia (within the file's `dynamics:` bounds: the links
//             beyond alone while their support force sensor says they carry no load: below a
//             twentieth of the weight, until above a tenth, else the bound under any contact), the load changing by the gravity bound
//             times the angle turned; without a last period, the load anywhere within the
//             gravity bound; acting for two periods (this one and one of latency before a brake
//             can act), then a brake at the joint's deceleration (tau_max less what holding
//             needs: the measured torque, at most the gravity bound; over inertia_max) within
//             its speed limit where known: an interval of
//             positions per joint around the measured one, the box the motion stays in.
//   certify   each pair of the reduced list (online, the pairs of every safe range the box
//             leaves, structural pairs with the file's floors) stays clear along the motion by
//             conservative advancement: from the measured posture along the nominal motion
//             (the middle acceleration for the horizon, then each joint braked at its rate),
//             the distance less the envelope (how far the motion within the bounds can be from
//             the nominal one, times the links' reach: collision::LinkReach, r_ja + r_jb) less
//             what the links can travel until the next sample stays at or above the limit;
//             the next sample is as far as that allows, within a bounded number of distance
//             evaluations a cycle (uncertified: brake, the safe side). A pair's limit is the margin (a structural
//             pair's floor), or, for a pair already closer, the largest distance it had since,
//             less a tolerance: moving away is allowed, creeping closer is not.
//   brake     a command that is not certified is replaced, for the joints on the chains of
//             the pairs it could not certify (between each pair's links and their common
//             ancestor; every joint when the work bound ran out) among the arms, the torso and every
//             leg whose foot carries no load (never a loaded leg: braking a stance leg drops
//             the robot), by the braking trajectory from the
//             measured state (each joint's velocity ramped to zero at its deceleration, q_ref
//             and dq_ref consistent), then a hold where it stopped; any later command the check
//             certifies resumes.
//   retreat   a pair that a joint the guard may not brake (a loaded leg, a passive joint) is
//             closing, predicted below its limit plus twice the tolerance from that side's
//             measured motion: the brakeable joints on its chain move away along the gradient
//             of its distance, within their limits and speed (self_collision_retreat.cc).
//
// Configure reads the file and checks it against the segment's header (model hash, joint
// names, a `dynamics:` section); Filter runs every cycle and allocates, throws and logs
// nothing. No MuJoCo: the file carries the links' geometry and the joints' dynamics.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "collision/incremental_check.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "shm_bridge/layout.h"

namespace ohrp::controllers {

class SelfCollisionGuard {
 public:
  // Reads `path` and checks it against `header`. Returns an empty string when the guard is
  // ready, else why not (the file's own message with file:line, or the robot it is for).
  std::string Configure(const std::string& path, const shm::SegmentHeader& header);

  // Whose file `path` is, for a default file: kThisModel (the header's model hash), kThisRobot
  // (another hash, but the robot's name or its joint names are the header's: the model
  // changed, the file must be regenerated), kAnotherRobot (another name and other joints), or
  // kUnreadable. `*robot` gets the file's robot name.
  // kUnpublished: the producer publishes no model hash (0), so no file can be checked against it.
  enum class Owner { kThisModel, kThisRobot, kAnotherRobot, kUnreadable, kUnpublished };
  static Owner FileOwner(const std::string& path, const shm::SegmentHeader& header,
                         std::string* robot);

  // Starts from the measured posture (each pair's limit from its distance there).
  void Activate(const shm::SensorBlock& sensors);

  // Checks that the motion `commands` can cause from the measured state, and a brake after
  // it, stays clear; otherwise replaces the commands by the brake (then the hold). Returns true
  // when it replaced them (braking or holding this cycle).
  bool Filter(const shm::SensorBlock& sensors, shm::CommandBlock* commands);

  // The counts, the first and closest pairs, one paragraph; nothing when nothing happened.
  void Report(const std::string& program, std::ostream& out) const;
  // "pair A / B at X mm (predicted), N hold(s)" of the closest hold, for failure messages
  std::string HoldSummary() const;

  bool holding() const { return braking_ || retreating_; }  // braking, holding or retreating
  // the retreat (self_collision_retreat.cc): cycles in which some brakeable joints moved away
  // from a pair a support leg was closing, and the episodes
  long retreat_cycles() const { return retreat_cycles_; }
  uint64_t retreats() const { return retreats_; }
  bool retreating() const { return retreating_; }
  uint64_t holds() const { return holds_; }          // hold episodes begun
  long held_cycles() const { return held_cycles_; }  // cycles braking or holding
  collision::LinkPair hold_pair() const { return closest_pair_; }  // the closest hold's pair
  double hold_distance() const { return closest_distance_; }  // [m] its predicted lower bound
  long uncertified_cycles() const { return uncertified_cycles_; }  // work bound reached
  long violations() const { return violations_; }  // a measured distance below its limit
  // "links measured closer than their limit N time(s), closest A / B at X mm": "" when none
  std::string ViolationSummary() const;
  // Monitoring only: the check runs and counts the cycles it would have braked, but the
  // commands are left alone; measured distances below their limit are still counted. For
  // controllers whose motion a brake would make unsafe (walk: a stance leg braked mid-step
  // topples the robot; Controller::guard_may_brake).
  void set_monitor_only(bool on) { monitor_only_ = on; }
  // Whether a leg whose foot carries no load is braked (default: yes). Off for controllers whose
  // balance moves the legs (Controller::guard_may_brake_legs: balance, walk): every leg with a
  // foot is then never braked, as a loaded one (the inertia still follows the measured load).
  void set_brake_unloaded_legs(bool on) { brake_legs_ = on; }
  bool monitor_only() const { return monitor_only_; }
  long warned_cycles() const { return warned_cycles_; }
  // cycles in which a leg with a foot was braked (its foot unloaded: UpdateLoads)
  long leg_brake_cycles() const { return leg_brake_cycles_; }
  // joint j's foot carries load this cycle (always false for a joint without a foot beyond)
  bool loaded(int j) const { return j >= 0 && j < static_cast<int>(loaded_.size()) && loaded_[j]; }
  const collision::SelfCollisionFile& file() const { return file_; }

  // The motion interval of one joint [rad or m], relative to its measured position: where it
  // can be during `horizon` [s] under a constant acceleration in [a_lo, a_hi] from velocity v
  // (capped at v_max when > 0), then a brake at `decel` to rest. Exposed for tests.
  static void Excursion(double v, double a_lo, double a_hi, double horizon, double v_max,
                        double decel, double* lo, double* hi);
  // the same with the velocity kept within [min(v, v_floor), max(v, v_ceil)] over the horizon
  static void Excursion(double v, double a_lo, double a_hi, double horizon, double v_floor,
                        double v_ceil, double decel, double* lo, double* hi);
  // Narrows [*v_floor, *v_ceil] (the velocity's band over `horizon` [s], sound on entry) by the
  // servo's damping: a joint under command `c` (position or velocity mode, kd > 0) from (q, v)
  // carrying a load within [load_lo, load_hi] (|load| <= tau_max) has its velocity pulled
  // towards dq_ref + (kp (q_ref - q) + tau_ff - load) / kd whatever its inertia, so it stays
  // between v and that over the horizon. Exposed for tests.
  static void VelocityBand(const shm::JointCommand& c, double q, double v, double load_lo,
                           double load_hi, double tau_max, double horizon, double* v_floor,
                           double* v_ceil);

  // joint j's braking deceleration [rad/s^2 or m/s^2] with a load of `tau_measured` [N m]
  // (>= 0, its magnitude; NaN: unknown): (tau_max - min(gravity_max, load)) / inertia_max, at
  // least a tenth of tau_max / inertia_max
  double Deceleration(int j, double tau_measured) const;
  // the same with the inertia given [kg m^2]
  double Decelerate(int j, double tau_measured, double inertia) const;

  // the certification's distance evaluations in the last Filter (at most kWorkBound; the
  // measured posture's incremental check comes on top): what bounds the guard's cycle
  int last_evaluations() const { return last_evaluations_; }
  static constexpr int kWorkBound = 160;

 private:
  // each joint's interval of motion for `c` from the measured state into box_lo_/box_hi_
  // (absolute positions); false when a measured value is not finite
  bool Predict(const shm::SensorBlock& sensors, const shm::CommandBlock& c) noexcept;
  // Predict's stages, per joint: what this cycle allows of one joint's motion
  struct JointMotion {
    double inertia = 0;   // [kg m^2] the inertia it drives (the links beyond alone, unloaded)
    bool observed = false;  // last period's acceleration and the torque measured
    double slack = 0;     // [N m] how much the load can change over the horizon
    double base = 0, a0 = 0;  // the measured torque [N m] and acceleration [rad/s^2] (observed)
    double a_lo = 0, a_hi = 0;        // [rad/s^2] the acceleration's bounds
    double v_floor = 0, v_ceil = 0;   // [rad/s] the velocity's band over the horizon
  };
  // the acceleration's bounds from the servo law and the measured load, and the brake's rate
  // (decel_); false when the command's torque cannot be bounded
  bool BoundAcceleration(int j, const shm::SensorBlock& sensors, const shm::JointCommand& c,
                         double speed, double horizon, JointMotion* m) noexcept;
  // the velocity's band: the speed limit, and the servo's damping against the load's bounds
  void BoundVelocity(int j, double q, double v, const shm::JointCommand& c, double horizon,
                     JointMotion* m) const noexcept;
  // the nominal motion (the middle acceleration, then the brake) and its envelope
  void PlanNominal(int j, double q, double v, double horizon, const JointMotion* m) noexcept;
  // the passive joints' boxes (their measured speed over the whole motion); false when a
  // measured value is not finite
  bool PredictPassive(const shm::SensorBlock& sensors) noexcept;
  // Filter's stages: the first cycle after Activate (only measured, the brake from the measured
  // state); a cycle whose measurement is not finite (a brake under way goes on); each pair's
  // limit from the measured posture; the motion certified (false: the worst brakeable pair
  // and its predicted lower bound); the hold begun or continued
  bool MeasureFirstCycle(const shm::SensorBlock& sensors, shm::CommandBlock* c) noexcept;
  bool Unjudged(const shm::SensorBlock& sensors, shm::CommandBlock* c) noexcept;
  void TrackMeasuredLimits() noexcept;
  bool CertifyMotion(int* worst, double* predicted) noexcept;
  void Hold(const shm::SensorBlock& sensors, int worst, double predicted,
            shm::CommandBlock* c) noexcept;
  // this cycle's pairs: the online ones, the structural ones with floors, the pairs of every
  // safe range the box leaves
  void ListPairs();
  // the nominal motion's posture at time t [s] into centre_
  void Nominal(double t);
  // pair i (index into every_) stays clear along the motion; false with its predicted lower
  // bound
  bool Certify(int i, double* bound);
  // pair i is brakeable (some joint the brake acts on moves it) and those joints' motion this
  // cycle (the command over the horizon, then to rest, and its envelope) can bring it within
  // the tolerance of its limit: else the brake cannot decide its approach (made by the support
  // legs): it is monitored this cycle, not braked. A pair the check only bounded is measured
  // first (one evaluation of the work bound; none left: braked)
  bool BrakeHelps(int i);
  // the braking trajectory's next reference into `c` (a retreating joint's ramp goes to its
  // retreat velocity instead of rest)
  void Brake(const shm::SensorBlock& sensors, shm::CommandBlock* c);

  // The retreat (self_collision_retreat.cc, issue 29): a pair of the list whose links a
  // support leg (a joint the guard may not brake) is closing, measured within the leg's reach
  // (its measured speed and acceleration over kRetreatLookahead periods) of its limit plus
  // twice the tolerance: the gradient of its distance over the pair's joints (central
  // differences at the measured posture: n^T (J_a - J_b) where the distance is smooth), the
  // rate at which the support side closes it (the gradient times the measured velocities and
  // accelerations), and the rate the brakeable side (the pair's other joints: arm, torso) must
  // move away at so that the prediction stays above the limit plus the tolerance. The
  // retreat velocity is the inertia-weighted least-norm solution of those rates (Kaczmarz over
  // the pairs), then kept from pushing other close pairs of the same joints closer, within the
  // joint limits (a joint that would cross one within the look-ahead is locked) and speed (one
  // factor for all, so the direction is kept); Brake ramps each joint to it at its braking
  // rate (one factor for all). False: no pair needs it.
  bool PlanRetreat() noexcept;
  // pair i's distance at posture q (its two links only); one evaluation
  double PairDistance(int i, const std::vector<double>& q, double cutoff) noexcept;
  // the gradient of pair i's distance over its joints into g (nq_), false when out of work
  bool Gradient(int i, double d, int* budget, double* g) noexcept;
  // the retreat velocity from the pairs' gradients and rates into retreat_v_
  void SolveRetreat() noexcept;
  // keeps retreat_v_ from bringing other measured pairs of the retreating joints closer
  void ProjectOthers(int* budget) noexcept;
  static constexpr int kMaxRetreatPairs = 4;
  static constexpr int kRetreatBudget = 64;     // distance evaluations a cycle
  static constexpr double kRetreatLookahead = 6;  // [periods]
  static constexpr double kRetreatSpeed = 1.0;  // [rad/s] where the file states no limit
  std::vector<double> meas_v_, meas_a_;  // per joint (nq_): measured velocity, acceleration
  std::vector<double> grad_, scratch_q_;  // per joint (nq_): scratch
  std::vector<double> retreat_v_;         // per joint: the retreat's velocity
  std::vector<char> retreat_;             // per joint: retreating this cycle
  std::vector<int> retreat_pairs_;        // the pairs retreated from (kMaxRetreatPairs)
  std::vector<double> retreat_grad_, retreat_rate_;  // their gradients (nq_ each), rates [m/s]
  int nretreat_ = 0;
  bool retreating_ = false;
  long retreat_cycles_ = 0;
  uint64_t retreats_ = 0;

  collision::SelfCollisionFile file_;
  std::unique_ptr<collision::SelfCollision> checker_;
  std::unique_ptr<collision::IncrementalCheck> check_;  // over every_
  int njoint_ = 0;
  static constexpr bool kCheckStructuralFloors = false;  // (Configure says why)
  // joint j has a foot beyond it (by the file's dynamics: its support sensor)
  bool CarriesFoot(int j) const { return !file_.dynamics[j].support_sensor.empty(); }
  // joint j carries load this cycle: a foot beyond it whose force sensor reads load (with
  // hysteresis, UpdateLoads), or whose sensor the segment lacks or reads no finite value (the
  // conservative side: a loaded leg is never braked, braking a stance leg drops the robot)
  // A leg is braked only while NO foot carries load (the robot hangs on its rig, is lifted or in
  // flight): standing on one foot, the other leg's motion may be a step the guard cannot see,
  // and braking it mid-step drops the robot (walk_samplepd_4ms: a swing ankle braked 2.0 mm
  // from the stance one; the walks fell with their swing legs braked)
  bool Supports(int j) const {
    return CarriesFoot(j) && (loaded_[j] != 0 || standing_ || !brake_legs_);
  }
  bool standing_ = true;    // some foot carries load this cycle (UpdateLoads)
  bool brake_legs_ = true;  // set_brake_unloaded_legs
  // each joint's loaded_ from the measured forces: loaded above the file's support_force (a
  // tenth of the weight), unloaded below half of it, else as last cycle; standing_: any is
  void UpdateLoads(const shm::SensorBlock& sensors, bool first);
  std::vector<char> brakeable_;  // per pair of every_: some actuated joint moves it (an arm, or a
                                 // leg whose foot may leave the ground); braked when one of
                                 // them is not Supports() this cycle
  std::vector<char> loaded_;     // per joint: carries load this cycle (UpdateLoads)
  // per joint: on the chain of a pair this cycle's check could not certify (a joint that
  // moves one of its links relative to the other: between the two links and their common
  // ancestor); only those are braked, the others follow the controller (balance's waist when
  // the pair is arm / leg below it, the other arm). Every joint when the work bound ran out.
  std::vector<char> chain_;
  // marks the chain of pair i (index into every_) in chain_
  void MarkChain(int i) noexcept;
  std::vector<char> braked_;     // per joint: under the brake last cycle (Brake starts a joint
                                 // from its measured state when not: a foot that left the ground)
  long leg_brake_cycles_ = 0;    // cycles a leg with a foot (unloaded) was braked
  bool monitor_only_ = false;
  long warned_cycles_ = 0;
  long unjudged_cycles_ = 0;                 // a measurement not finite: nothing predicted                   // monitoring only: cycles it would have braked
  double warned_distance_ = 1e9;             // [m] their closest predicted pair
  collision::LinkPair warned_pair_;
  double violation_distance_ = 1e9;          // [m] the closest measured distance below a limit
  collision::LinkPair violation_pair_;
  int nq_ = 0;  // posture size: the actuated joints, then the passive ones
  double period_ = 0;     // [s]
  double check_cutoff_ = 0;  // [m] the incremental check's: answers above it are lower bounds
  double tolerance_ = 0;  // [m] a close pair may come this much closer than its farthest since
  std::vector<collision::LinkPair> every_;   // online, then structural with floors, then ranges'
  std::vector<double> base_limit_;           // per pair: margin, or a structural pair's floor
  std::vector<double> limit_;                // per pair: this cycle's limit [m]
  std::vector<double> coef_;                 // per pair and joint: r_ja + r_jb [m/rad]
  std::vector<std::vector<int>> range_pairs_;  // per safe range, its pairs' indices in every_
  size_t always_ = 0;                        // every_[0, always_) is checked every cycle
  std::vector<int> list_;
  std::vector<char> on_list_;
  // per joint
  std::vector<double> tau_max_, kp_default_, kd_default_, decel_;  // decel_ [rad/s^2]
  std::vector<double> q_, box_lo_, box_hi_;                          // [rad]
  std::vector<double> brake_q_, brake_v_, brake_decel_;  // the brake's references and rate
  std::vector<double> brake_ff_;  // this cycle's controller feed-forward torque, kept under the brake
  std::vector<double> last_dq_;  // the last cycle's measured velocities
  bool have_last_ = false;
  bool measuring_ = false;  // the first cycle after Activate: only measured (Filter)
  std::vector<int> support_;  // per joint, the header's index of its support force sensor, -1
  // the nominal motion per joint: the measured velocity, the middle acceleration over the
  // horizon, the velocity and position where the brake begins, its duration, the largest
  // speed, and how far the motion within the bounds can be from the nominal one
  std::vector<double> v0_, a_mid_, v1_, q1_, stop_, speed_, envelope_;
  double horizon_end_ = 0;   // [s] when the last joint has stopped
  std::vector<double> centre_;  // a posture of the nominal motion
  int budget_ = 0;  // distance evaluations left this cycle
  int last_evaluations_ = 0;  // the certification's distance evaluations in the last Filter
  static constexpr int kBudget = kWorkBound;
  static constexpr int kMonitorBudget = 16;  // of it, for the pairs only support legs move

  bool braking_ = false;
  uint64_t holds_ = 0;
  long held_cycles_ = 0, uncertified_cycles_ = 0, violations_ = 0;
  double first_time_ = -1, closest_distance_ = 1e9, first_distance_ = 0;  // [s], [m]
  collision::LinkPair first_pair_, closest_pair_;
};

}  // namespace ohrp::controllers
