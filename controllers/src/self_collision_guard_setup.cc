// The online self-collision check's set-up (see self_collision_guard.h): the file's owner, the
// file checked against the segment's header, and the first cycle's state (Activate). The
// cycle itself is in self_collision_guard.cc.
#include "controllers/self_collision_guard.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>

namespace ohrp::controllers {
namespace {

std::string Hex(uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof(b), "0x%llx", static_cast<unsigned long long>(v));
  return b;
}

// a torque limit the guard can use: the header's, or none (infinite) when it states none
double Limit(double tau_max) {
  return std::isfinite(tau_max) && tau_max > 0 && tau_max < 1e9 ? tau_max : INFINITY;
}

}  // namespace

SelfCollisionGuard::Owner SelfCollisionGuard::FileOwner(const std::string& path,
                                                        const shm::SegmentHeader& header,
                                                        std::string* robot) {
  collision::SelfCollisionFile f;
  std::string error;
  robot->clear();
  if (!collision::ReadSelfCollisionFile(path, &f, &error)) return Owner::kUnreadable;
  *robot = f.robot.name;
  if (f.robot.model_hash == header.model_hash) return Owner::kThisModel;
  // a producer that publishes no model identity (hash 0): no file can be verified for it
  if (header.model_hash == 0) return Owner::kUnpublished;
  const int n = std::clamp(header.njoint, 0, shm::kMaxJoints);
  bool same_joints = static_cast<int>(f.robot.joint_names.size()) == n;
  for (int j = 0; same_joints && j < n; ++j)
    same_joints = f.robot.joint_names[j] == std::string(header.joint_names[j], strnlen(header.joint_names[j], shm::kNameLen));
  const std::string name(header.robot_name, strnlen(header.robot_name, sizeof(header.robot_name)));
  return same_joints || f.robot.name == name ? Owner::kThisRobot : Owner::kAnotherRobot;
}

std::string SelfCollisionGuard::Configure(const std::string& path,
                                          const shm::SegmentHeader& header) {
  std::string error;
  if (!collision::ReadSelfCollisionFile(path, &file_, &error)) return error;
  // the same robot: model hash, joint count and names
  if (file_.robot.model_hash != header.model_hash)
    return path + ": is for robot " + file_.robot.name + " (model hash " +
           Hex(file_.robot.model_hash) + "), the segment's robot has model hash " +
           Hex(header.model_hash) + " (regenerate it with ohrp_selfcollision --model ...)";
  njoint_ = header.njoint;
  if (static_cast<int>(file_.robot.joint_names.size()) != njoint_)
    return path + ": has " + std::to_string(file_.robot.joint_names.size()) +
           " joints, the segment " + std::to_string(njoint_);
  for (int j = 0; j < njoint_; ++j)
    if (file_.robot.joint_names[j] != std::string(header.joint_names[j], strnlen(header.joint_names[j], shm::kNameLen)))
      return path + ": joint " + std::to_string(j) + " is " + file_.robot.joint_names[j] +
             ", the segment's is " + header.joint_names[j];
  // the braking check needs what the joints can do: never guessed
  if (static_cast<int>(file_.dynamics.size()) != njoint_)
    return path + ": has no dynamics: section (the joints' inertia and gravity bounds the "
                  "braking check needs): regenerate it with ohrp_selfcollision --model ... "
                  "(docs/selfcollision.md)";
  // postures: the actuated joints, then the passive ones (measured: sensors.passive_q)
  nq_ = collision::NumJoints(file_.robot);
  if (nq_ - njoint_ != header.npassive)
    return path + ": has " + std::to_string(nq_ - njoint_) + " passive joints, the segment " +
           std::to_string(header.npassive);
  checker_ = collision::SelfCollision::Create(file_.robot, &error);
  if (!checker_) return path + ": " + error;
  period_ = header.control_period;
  tolerance_ = std::max(0.5 * file_.margin, 1e-3);
  // every pair the check may need, allocated once: online, structural with floors, ranges'
  every_ = file_.online;
  base_limit_.assign(every_.size(), file_.margin);
  // Structural pairs are not checked yet: their floors come from the zero and reference
  // postures only, and HRP-1S's knee/ankle boxes overlap deeper with any knee bend past
  // half-sitting (walking, balancing), so the floor stopped ordinary motion (issue 29: the
  // floors need the postures the robot's motions use, not two)
  const bool floors = kCheckStructuralFloors &&
                      file_.structural_floor.size() == file_.structural.size();
  for (size_t k = 0; floors && k < file_.structural.size(); ++k) {
    every_.push_back(file_.structural[k]);
    base_limit_.push_back(file_.structural_floor[k]);
  }
  always_ = every_.size();
  for (const auto& r : file_.ranges)
    for (const auto& p : r.pairs)
      if (std::find(every_.begin(), every_.end(), p) == every_.end()) {
        every_.push_back(p);
        base_limit_.push_back(file_.margin);
      }
  range_pairs_.clear();
  for (const auto& r : file_.ranges) {
    range_pairs_.emplace_back();
    for (const auto& p : r.pairs)
      range_pairs_.back().push_back(
          static_cast<int>(std::find(every_.begin(), every_.end(), p) - every_.begin()));
  }
  limit_ = base_limit_;
  // the incremental check measures every pair that may be within the tolerance of its limit
  // (BrakeHelps brakes those): a lower bound it keeps for a pair is then above limit + tolerance
  // (with the margin alone, a pair's bound decaying with the support legs' travel to just
  // above the margin read as 'near its limit' and braked the arms of every walk)
  check_cutoff_ = *std::max_element(base_limit_.begin(), base_limit_.end()) + tolerance_;
  // per pair and joint, how far the pair's two links move per unit of the joint
  const auto reach = collision::LinkReach(file_.robot);
  coef_.assign(every_.size() * nq_, 0.0);
  // A joint beyond which BOTH links lie (an ancestor of both: G1's waist for its torso and
  // arms) moves them rigidly together: their distance does not depend on it, so it adds
  // nothing (with it, G1's waist settling after the stand braked the shoulder 2.9 mm from
  // the torso for 18 cycles)
  const auto moves = [&](int l, int joint) {
    for (const auto& jr : reach[l])
      if (jr.first == joint) return true;
    return false;
  };
  for (size_t i = 0; i < every_.size(); ++i)
    for (int l : {every_[i].a, every_[i].b})
      for (const auto& [joint, r] : reach[l])
        if (!(moves(every_[i].a, joint) && moves(every_[i].b, joint))) coef_[i * nq_ + joint] += r;
  // a pair the brake may act on: some actuated joint moves it. Which of them it acts on is
  // decided each cycle from the measured forces (UpdateLoads): an arm always, a leg with a foot
  // while its foot carries no load (in the air: a swing leg, a robot on its rig); a loaded leg
  // is never braked (braking a stance leg topples the robot): its pairs are monitored
  brakeable_.assign(every_.size(), 0);
  for (size_t i = 0; i < every_.size(); ++i)
    for (int j = 0; j < njoint_; ++j)
      if (coef_[i * nq_ + j] > 0) brakeable_[i] = 1;
  check_ = std::make_unique<collision::IncrementalCheck>(checker_.get(), every_);
  list_.reserve(every_.size());
  on_list_.assign(every_.size(), 0);
  // per joint: the torque limit, the servo's default gains; the braking deceleration is set
  // each cycle from the measured torque (Predict)
  tau_max_.assign(njoint_, 0.0);
  kp_default_.assign(njoint_, 0.0);
  kd_default_.assign(njoint_, 0.0);
  decel_.assign(nq_, 1.0);  // passive joints: never braked (their stop_ is 0)
  for (int j = 0; j < njoint_; ++j) {
    tau_max_[j] = Limit(header.tau_max[j]);
    kp_default_[j] = header.default_kp[j];
    kd_default_[j] = header.default_kd[j];
    decel_[j] = Deceleration(j, INFINITY);
  }
  // each joint's support sensor, by the header's force sensor names (-1: none)
  support_.assign(njoint_, -1);
  for (int j = 0; j < njoint_; ++j)
    for (int f = 0; f < std::clamp(header.nforce, 0, shm::kMaxForceSensors); ++f)
      if (!file_.dynamics[j].support_sensor.empty() &&
          file_.dynamics[j].support_sensor == std::string(header.force_names[f], strnlen(header.force_names[f], shm::kNameLen)))
        support_[j] = f;
  loaded_.assign(njoint_, 0);
  for (int j = 0; j < njoint_; ++j) loaded_[j] = CarriesFoot(j) ? 1 : 0;  // until measured
  braked_.assign(njoint_, 0);
  chain_.assign(njoint_, 1);
  q_.assign(nq_, 0.0);
  box_lo_.assign(nq_, 0.0);
  box_hi_.assign(nq_, 0.0);
  brake_q_.assign(njoint_, 0.0);
  brake_v_.assign(njoint_, 0.0);
  brake_decel_.assign(decel_.begin(), decel_.begin() + njoint_);
  brake_ff_.assign(njoint_, 0.0);
  last_dq_.assign(njoint_, 0.0);
  have_last_ = false;
  centre_.assign(nq_, 0.0);
  for (auto* v : {&v0_, &a_mid_, &v1_, &q1_, &stop_, &speed_, &envelope_}) v->assign(nq_, 0.0);
  for (auto* v : {&meas_v_, &meas_a_, &grad_, &scratch_q_}) v->assign(nq_, 0.0);
  retreat_v_.assign(njoint_, 0.0);
  retreat_.assign(njoint_, 0);
  retreat_pairs_.assign(kMaxRetreatPairs, -1);
  retreat_grad_.assign(static_cast<size_t>(kMaxRetreatPairs) * nq_, 0.0);
  retreat_rate_.assign(kMaxRetreatPairs, 0.0);
  return "";
}

void SelfCollisionGuard::Activate(const shm::SensorBlock& sensors) {
  UpdateLoads(sensors, true);
  std::fill(braked_.begin(), braked_.end(), 0);
  for (int j = 0; j < njoint_; ++j) {
    q_[j] = std::isfinite(sensors.q[j]) ? sensors.q[j] : 0.0;
    brake_q_[j] = q_[j];
    brake_v_[j] = 0.0;
  }
  for (int k = njoint_; k < nq_; ++k)  // passive joints, as measured
    q_[k] = std::isfinite(sensors.passive_q[k - njoint_]) ? sensors.passive_q[k - njoint_] : 0.0;
  // each pair's limit: the margin, or less than its distance now by the tolerance
  check_->MoveTo(q_);
  const double cutoff = *std::max_element(base_limit_.begin(), base_limit_.end());
  check_->CheckAll(cutoff);
  for (size_t i = 0; i < every_.size(); ++i)
    limit_[i] = std::min(base_limit_[i], check_->distance(static_cast<int>(i)) - tolerance_);
  braking_ = false;
  retreating_ = false;
  // no acceleration measured yet: the first cycle measures (Filter)
  for (int j = 0; j < njoint_; ++j) last_dq_[j] = std::isfinite(sensors.dq[j]) ? sensors.dq[j] : 0.0;
  have_last_ = false;
  measuring_ = true;
}

}  // namespace ohrp::controllers
