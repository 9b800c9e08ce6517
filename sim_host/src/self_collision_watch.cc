// sim_host's self_collision effect (see self_collision_watch.h).
#include "sim_host/self_collision_watch.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "collision/from_mjcf.h"
#include "collision/pair_file.h"
#include "shm_bridge/clock.h"

namespace ohrp::sim {
namespace {

std::string Hex(uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof(b), "0x%llx", static_cast<unsigned long long>(v));
  return b;
}

}  // namespace

std::unique_ptr<SelfCollisionWatch> SelfCollisionWatch::Create(const mjModel* m,
                                                               const model::RobotMap& robot,
                                                               const std::string& file,
                                                               std::string* error) {
  std::unique_ptr<SelfCollisionWatch> w(new SelfCollisionWatch());
  w->robot_ = &robot;
  collision::RobotGeometry g;
  std::string why;
  if (!collision::GeometryFromModel(m, robot, &g, &why)) {
    *error = "self_collision: the robot's geometry cannot be checked: " + why;
    return nullptr;
  }
  w->checker_ = collision::SelfCollision::Create(g, &why);
  if (!w->checker_) {
    *error = "self_collision: " + why;
    return nullptr;
  }
  const std::vector<collision::LinkPair> all = collision::NonAdjacentPairs(g);
  w->all_pairs_ = static_cast<int>(all.size());
  w->q_.assign(collision::NumJoints(g), 0.0);  // actuated, then passive joints
  if (file.empty()) {
    w->source_ = "all non-adjacent pairs";
    w->pairs_ = all;
    // parts built into each other: in contact at the model's zero posture (qpos0, as built) or
    // in a keyframe
    collision::PostureFromQpos(robot, m->qpos0, w->q_);
    w->checker_->SetPose(w->q_);
    w->ExcludeTouching("the zero posture");
    for (int k = 0; k < m->nkey; ++k) {
      collision::PostureFromQpos(robot, m->key_qpos + k * m->nq, w->q_);
      w->checker_->SetPose(w->q_);
      const char* n = mj_id2name(m, mjOBJ_KEY, k);
      w->ExcludeTouching(std::string("keyframe ") + (n ? n : std::to_string(k)));
    }
  } else {
    collision::SelfCollisionFile f;
    if (!collision::ReadSelfCollisionFile(file, &f, &why)) {
      *error = "--self-collision: " + why;
      return nullptr;
    }
    if (f.robot.model_hash != g.model_hash) {
      *error = "--self-collision: " + file + " is for robot " + f.robot.name + " (model hash " +
               Hex(f.robot.model_hash) + "), the scene's robot " + robot.name + " has " +
               Hex(g.model_hash) + " (make one with ohrp_selfcollision --model SCENE --out FILE)";
      return nullptr;
    }
    w->from_file_ = true;
    w->source_ = file;
    std::vector<collision::LinkPair> listed = f.online;
    for (const auto& r : f.ranges) listed.insert(listed.end(), r.pairs.begin(), r.pairs.end());
    for (const auto& p : listed) {
      const int a = collision::FindLink(g, f.robot.links[p.a].name);
      const int b = collision::FindLink(g, f.robot.links[p.b].name);
      if (a < 0 || b < 0) {
        *error = "--self-collision: " + file + ": the pair " + f.robot.links[p.a].name + "/" +
                 f.robot.links[p.b].name + " names a link the scene's robot does not have";
        return nullptr;
      }
      const collision::LinkPair q{std::min(a, b), std::max(a, b)};
      if (std::find(w->pairs_.begin(), w->pairs_.end(), q) == w->pairs_.end()) w->pairs_.push_back(q);
    }
  }
  w->TrackPairs();
  return w;
}

std::string SelfCollisionWatch::PairName(const collision::LinkPair& p) const {
  const auto& links = checker_->robot().links;
  return links[p.a].name + "/" + links[p.b].name;
}

void SelfCollisionWatch::ExcludeTouching(const std::string& where) {
  std::vector<double> distance(pairs_.size());
  checker_->Check(pairs_, 0.0, distance);
  std::vector<collision::LinkPair> kept;
  for (size_t i = 0; i < pairs_.size(); ++i) {
    if (distance[i] <= 0) excluded_.push_back(PairName(pairs_[i]) + " (" + where + ")");
    else kept.push_back(pairs_[i]);
  }
  pairs_ = std::move(kept);
}

void SelfCollisionWatch::TrackPairs() {
  const size_t n = pairs_.size();
  check_ = std::make_unique<collision::IncrementalCheck>(checker_.get(), pairs_);
  in_contact_.clear();
  in_contact_.reserve(n);
  first_time_.assign(n, -1.0);
  deepest_.assign(n, 0.0);
  deepest_time_.assign(n, 0.0);
  first_cycle_.assign(n, 0);
  cycles_.assign(n, 0);
  order_.clear();
  order_.reserve(n);
}

void SelfCollisionWatch::ReadPose(const mjData* d) {
  collision::PostureFromQpos(*robot_, d->qpos, q_);
  checker_->SetPose(q_);
}

void SelfCollisionWatch::Start(const mjData* d) {
  if (from_file_) return;
  ReadPose(d);
  const size_t before = pairs_.size();
  ExcludeTouching("the initial state");
  if (pairs_.size() != before) TrackPairs();  // the per-pair state follows the list (set-up)
}

void SelfCollisionWatch::Check(const mjData* d, double time, uint64_t cycle) {
  const double t0 = ThreadCpuSeconds();
  collision::PostureFromQpos(*robot_, d->qpos, q_);  // the simulated passive joints too
  check_->MoveTo(q_);
  const uint64_t before = check_->measured();
  check_->CheckAll(kClosestRange);
  measured_ += check_->measured() - before;
  in_contact_.clear();
  for (size_t i = 0; i < pairs_.size(); ++i) {
    // a pair not measured carries a lower bound above kClosestRange
    const double x = check_->distance(static_cast<int>(i));
    if (x < closest_) {
      closest_ = x;
      closest_time_ = time;
      closest_cycle_ = cycle;
      closest_pair_ = x <= kClosestRange ? static_cast<int>(i) : -1;
    }
    if (!(x < 0)) continue;
    in_contact_.push_back(static_cast<int>(i));
    if (first_time_[i] < 0) {
      first_time_[i] = time;
      first_cycle_[i] = cycle;
      order_.push_back(static_cast<int>(i));
    }
    ++cycles_[i];
    if (-x > deepest_[i]) {
      deepest_[i] = -x;
      deepest_time_[i] = time;
    }
  }
  ++checks_;
  cycles_in_contact_ += !in_contact_.empty();
  const double dt = ThreadCpuSeconds() - t0;
  check_seconds_ += dt;
  check_max_ = std::max(check_max_, dt);
}

std::string SelfCollisionWatch::Describe() const {
  const int links = static_cast<int>(checker_->robot().links.size());
  std::string s = std::to_string(pairs_.size()) + " link pairs of " + std::to_string(links) +
                  " links checked every control cycle with the controllers' checker (";
  if (from_file_) {
    s += "the online and safe-range pairs of " + source_ + ")";
  } else {
    s += "all " + std::to_string(all_pairs_) + " non-adjacent pairs";
    if (!excluded_.empty())
      s += " less " + std::to_string(excluded_.size()) + " in contact at the zero posture, a keyframe or the start";
    s += ")";
  }
  const auto& unchecked = checker_->robot().unchecked;
  if (!unchecked.empty()) {
    s += "; not in the geometry, never checked:";
    for (size_t i = 0; i < unchecked.size(); ++i) s += (i ? "; " : " ") + unchecked[i];
  }
  return s;
}

SelfCollisionSummary SelfCollisionWatch::Summary() const {
  SelfCollisionSummary s;
  s.on = true;
  s.source = source_;
  s.links = static_cast<int>(checker_->robot().links.size());
  s.pairs_checked = static_cast<int>(pairs_.size());
  s.excluded = excluded_;
  s.checks = checks_;
  s.measured = measured_;
  s.cycles_in_contact = cycles_in_contact_;
  s.check_seconds = check_seconds_;
  s.check_max = check_max_;
  s.closest = closest_pair_ >= 0 ? closest_ : std::max(closest_, kClosestRange);
  s.closest_exact = closest_pair_ >= 0;
  if (s.closest_exact) s.closest_pair = PairName(pairs_[closest_pair_]);
  s.closest_time = closest_time_;
  s.closest_cycle = closest_cycle_;
  for (int i : order_) {
    SelfCollisionHit h;
    h.pair = PairName(pairs_[i]);
    h.first_time = first_time_[i];
    h.first_cycle = first_cycle_[i];
    h.deepest = deepest_[i];
    h.deepest_time = deepest_time_[i];
    h.cycles = cycles_[i];
    s.pairs.push_back(h);
  }
  return s;
}

}  // namespace ohrp::sim
