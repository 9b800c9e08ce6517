// The online self-collision check: the file against the header, then one Filter per cycle.
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

}  // namespace

bool SelfCollisionGuard::FileMatches(const std::string& path, const shm::SegmentHeader& header) {
  collision::SelfCollisionFile f;
  std::string error;
  return collision::ReadSelfCollisionFile(path, &f, &error) &&
         f.robot.model_hash == header.model_hash;
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
  checker_ = collision::SelfCollision::Create(file_.robot, &error);
  if (!checker_) return path + ": " + error;
  period_ = header.control_period;
  // every pair the check may need, allocated once
  every_ = file_.online;
  for (const auto& r : file_.ranges)
    for (const auto& p : r.pairs)
      if (std::find(every_.begin(), every_.end(), p) == every_.end()) every_.push_back(p);
  range_pairs_.clear();
  for (const auto& r : file_.ranges) {
    range_pairs_.emplace_back();
    for (const auto& p : r.pairs)
      range_pairs_.back().push_back(
          static_cast<int>(std::find(every_.begin(), every_.end(), p) - every_.begin()));
  }
  check_ = std::make_unique<collision::IncrementalCheck>(checker_.get(), every_);
  list_.reserve(every_.size());
  on_list_.assign(every_.size(), 0);
  // postures: the actuated joints, then the passive ones (measured: sensors.passive_q)
  const int nq = collision::NumJoints(file_.robot);
  if (nq - njoint_ != header.npassive)
    return path + ": has " + std::to_string(nq - njoint_) + " passive joints, the segment " +
           std::to_string(header.npassive);
  q_.assign(nq, 0.0);
  q_ahead_.assign(nq, 0.0);
  last_q_.assign(nq, std::nan(""));  // matches no posture
  safe_.assign(nq, 0.0);
  return "";
}

void SelfCollisionGuard::Activate(const shm::SensorBlock& sensors) {
  for (int j = 0; j < njoint_; ++j) safe_[j] = std::isfinite(sensors.q[j]) ? sensors.q[j] : 0.0;
  for (size_t k = njoint_; k < safe_.size(); ++k)  // passive joints, as measured
    safe_[k] = std::isfinite(sensors.passive_q[k - njoint_]) ? sensors.passive_q[k - njoint_] : 0.0;
  safe_distance_ = Closest(safe_).min_distance;
}

collision::CheckResult SelfCollisionGuard::Closest(const std::vector<double>& q) {
  // the online pairs, plus the pairs of every safe range q leaves (each once)
  list_.clear();
  std::fill(on_list_.begin(), on_list_.end(), 0);
  const size_t online = file_.online.size();
  for (size_t i = 0; i < online; ++i) list_.push_back(static_cast<int>(i)), on_list_[i] = 1;
  for (size_t ri = 0; ri < file_.ranges.size(); ++ri) {
    const auto& r = file_.ranges[ri];
    if (q[r.joint] >= r.lo && q[r.joint] <= r.hi) continue;
    for (int k : range_pairs_[ri])
      if (!on_list_[k]) list_.push_back(k), on_list_[k] = 1;
  }
  // the pairs that cannot have come within the margin since they were measured are skipped
  check_->MoveTo(q);
  return check_->Check(list_, file_.margin);
}

bool SelfCollisionGuard::Filter(const shm::SensorBlock& sensors, shm::CommandBlock* c) {
  // the commanded posture, and the one a period ahead
  for (int j = 0; j < njoint_; ++j) {
    const shm::JointCommand& jc = c->joint[j];
    const bool position = jc.mode == shm::JointMode::kPosition && std::isfinite(jc.q_ref);
    q_[j] = position ? jc.q_ref : sensors.q[j];
    const double v = position && std::isfinite(jc.dq_ref) ? jc.dq_ref : sensors.dq[j];
    q_ahead_[j] = q_[j] + (std::isfinite(v) ? v : 0.0) * period_;
  }
  for (size_t k = njoint_; k < q_.size(); ++k) {  // passive joints: measured, never commanded
    const double v = sensors.passive_dq[k - njoint_];
    q_[k] = sensors.passive_q[k - njoint_];
    q_ahead_[k] = q_[k] + (std::isfinite(v) ? v : 0.0) * period_;
  }
  // the same posture as the last cycle's (a held pose): the same answer, no check; a posture
  // that does not move within the period (no velocity): one check, not two
  if (q_ != last_q_) {
    last_q_ = q_;  // same size: no allocation
    last_now_ = Closest(q_);
  }
  const collision::CheckResult now = last_now_;
  const collision::CheckResult ahead = q_ahead_ == q_ ? now : Closest(q_ahead_);
  const collision::CheckResult& worst = ahead.min_distance < now.min_distance ? ahead : now;
  // while holding, only a command near the held references may resume: a far one could jump
  // through a link (a hand through a thigh is deep, then apart again on the other side)
  double jump = 0;
  for (int j = 0; j < njoint_; ++j) jump = std::max(jump, std::abs(q_[j] - safe_[j]));
  const bool far = holding_ && jump > kResumeStep;
  // close, and penetrating or closer than the last safe references: hold them
  const bool close = worst.closest >= 0 && worst.min_distance < file_.margin &&
                     (worst.min_distance <= 0 || worst.min_distance < safe_distance_);
  if (far || close) {
    holding_ = true;
    ++held_cycles_;
    if (first_time_ < 0 && close) {
      first_time_ = sensors.time;
      first_pair_ = every_[worst.closest];
      first_distance_ = worst.min_distance;
    }
    if (close && worst.min_distance < closest_distance_) {
      closest_distance_ = worst.min_distance;
      closest_pair_ = every_[worst.closest];
    }
    for (int j = 0; j < njoint_; ++j) {
      c->joint[j].q_ref = safe_[j];
      c->joint[j].dq_ref = 0.0;
    }
    return true;
  }
  holding_ = false;
  safe_ = q_;
  safe_distance_ = now.min_distance;
  return false;
}

void SelfCollisionGuard::Report(const std::string& program, std::ostream& out) const {
  if (held_cycles_ == 0) return;
  const auto name = [&](collision::LinkPair p) {
    return file_.robot.links[p.a].name + " / " + file_.robot.links[p.b].name;
  };
  char b[512];
  std::snprintf(b, sizeof(b),
                "%s: self-collision: held the last safe references in %ld cycles; first at "
                "%.3f s, pair %s at %.1f mm; closest commanded %s at %.1f mm (margin %.1f mm)\n",
                program.c_str(), held_cycles_, first_time_, name(first_pair_).c_str(),
                1e3 * first_distance_, name(closest_pair_).c_str(), 1e3 * closest_distance_,
                1e3 * file_.margin);
  out << b;
}

}  // namespace ohrp::controllers
