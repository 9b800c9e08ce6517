// Tests sim_host's self_collision effect (sim_host/self_collision_watch.h) on HRP-1S:
// - the pair list: every non-adjacent pair less those in contact at the zero posture, a keyframe
//   or the start (the thighs in the waist box at half-sitting), or a file's list by link name;
//   a file for another robot is refused;
// - agreement with MuJoCo's own collision detection on the same postures: the arm swung into
//   the leg (scenarios/trajectories/arm_into_leg.dat, replayed kinematically), each posture
//   checked by the watch and by mj_collision on a copy of the model in which every geom
//   collides (contype/conaffinity 1, no margin): the pairs MuJoCo finds penetrating by more
//   than kClear are the pairs the watch reports, and the other way round;
// - the report: first time, deepest penetration and cycles per pair, in the order of contact;
//   Check allocates nothing.
#include "../robot_model/count_allocations.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/self_collision_watch.h"

namespace ohrp::sim {
namespace {

// MuJoCo and the checker agree on pairs penetrating beyond this; closer to contact than this
// either may say either (the bound on distance errors; MuJoCo's cylinders go through
// MPR, whose depths can be off by millimetres: docs/selfcollision.md; on these postures the two
// agreed down to 0.5 mm)
constexpr double kClear = 0.001;  // [m]

std::string Src(const std::string& p) { return std::string(OHRP_SOURCE_DIR) + "/" + p; }

struct Hrp1s {
  Hrp1s() {
    model::InstallMujocoHandlers(nullptr);
    std::string error;
    scene = model::Scene::Load(Src("mjcf/hrp1s/scene_flat.xml"), &error);
    EXPECT_TRUE(scene) << error;
    EXPECT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  }
  std::unique_ptr<model::Scene> scene;
  model::RobotMap robot;
};

// the trajectory's rows: time, then the 29 joints in joint-id order
std::vector<std::vector<double>> Trajectory() {
  std::ifstream in(Src("scenarios/trajectories/arm_into_leg.dat"));
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream s(line);
    std::vector<double> r;
    for (double v; s >> v;) r.push_back(v);
    if (!r.empty()) rows.push_back(r);
  }
  return rows;
}

// linear interpolation of the trajectory at time t
std::vector<double> At(const std::vector<std::vector<double>>& rows, double t) {
  size_t i = 0;
  while (i + 2 < rows.size() && rows[i + 1][0] <= t) ++i;
  const auto& a = rows[i];
  const auto& b = rows[std::min(i + 1, rows.size() - 1)];
  const double s = b[0] > a[0] ? std::clamp((t - a[0]) / (b[0] - a[0]), 0.0, 1.0) : 0.0;
  std::vector<double> q(a.size() - 1);
  for (size_t j = 0; j < q.size(); ++j) q[j] = a[j + 1] + s * (b[j + 1] - a[j + 1]);
  return q;
}

TEST(SelfCollisionWatch, PairsLeaveOutPartsBuiltIntoEachOther) {
  Hrp1s h;
  std::string error;
  mjModel* m = h.scene->m();
  auto w = SelfCollisionWatch::Create(m, h.robot, "", &error);
  ASSERT_TRUE(w) << error;
  ASSERT_TRUE(h.scene->Reset("halfsit", &error)) << error;
  w->Start(h.scene->d());
  const SelfCollisionSummary s = w->Summary();
  EXPECT_EQ(s.links, 30);
  EXPECT_EQ(s.source, "all non-adjacent pairs");
  // 406 non-adjacent pairs (docs/selfcollision.md); each left-out pair is in contact where named
  EXPECT_EQ(s.pairs_checked + static_cast<int>(s.excluded.size()), 406);
  EXPECT_FALSE(s.excluded.empty());
  bool thigh_in_waist = false;
  for (const auto& e : s.excluded) thigh_in_waist |= e.find("WAIST") != std::string::npos && e.find("LEG_HIP") != std::string::npos;
  EXPECT_TRUE(thigh_in_waist) << "excluded: " << s.excluded.size();
  // at the start nothing of what is checked touches
  w->Check(h.scene->d(), 0, 0);
  EXPECT_TRUE(w->in_contact().empty());
  EXPECT_NE(w->Describe().find("of 30 links"), std::string::npos) << w->Describe();
}

TEST(SelfCollisionWatch, FileListByLinkNameAndAnotherRobotsFileRefused) {
  Hrp1s h;
  std::string error;
  auto w = SelfCollisionWatch::Create(h.scene->m(), h.robot, Src("mjcf/hrp1s/selfcollision.yaml"), &error);
  ASSERT_TRUE(w) << error;
  // the shipped file: its online pairs and those its safe ranges prune, each once
  collision::SelfCollisionFile f;
  ASSERT_TRUE(collision::ReadSelfCollisionFile(Src("mjcf/hrp1s/selfcollision.yaml"), &f, &error)) << error;
  std::set<std::pair<int, int>> listed;
  for (const auto& p : f.online) listed.insert({p.a, p.b});
  for (const auto& r : f.ranges)
    for (const auto& p : r.pairs) listed.insert({p.a, p.b});
  EXPECT_GT(f.online.size(), 0u);
  EXPECT_EQ(w->pairs().size(), listed.size());
  EXPECT_NE(w->Describe().find("selfcollision.yaml"), std::string::npos);
  // the file of HRP-1S against another kinematic tree: the right elbow moved down 1 cm
  mjModel* m = h.scene->m();
  const int elbow = mj_name2id(m, mjOBJ_BODY, "RARM_ELBOW");
  ASSERT_GE(elbow, 0);
  m->body_pos[3 * elbow + 2] -= 0.01;
  w = SelfCollisionWatch::Create(m, h.robot, Src("mjcf/hrp1s/selfcollision.yaml"), &error);
  EXPECT_FALSE(w);
  EXPECT_NE(error.find("model hash"), std::string::npos) << error;
  EXPECT_NE(error.find("ohrp_selfcollision"), std::string::npos) << error;
}

TEST(SelfCollisionWatch, AgreesWithMujocoOnTheArmIntoTheLeg) {
  Hrp1s h;
  std::string error;
  const mjModel* m0 = h.scene->m();
  auto w = SelfCollisionWatch::Create(m0, h.robot, "", &error);
  ASSERT_TRUE(w) << error;
  ASSERT_TRUE(h.scene->Reset("halfsit", &error)) << error;
  w->Start(h.scene->d());
  // MuJoCo's referee: a copy in which every geom collides with every other, no margin
  mjModel* m = mj_copyModel(nullptr, m0);
  for (int g = 0; g < m->ngeom; ++g) {
    m->geom_contype[g] = m->geom_conaffinity[g] = 1;
    m->geom_margin[g] = 0;
    m->geom_gap[g] = 0;
  }
  m->opt.disableflags &= ~mjDSBL_CONTACT;
  mjData* d = mj_makeData(m);
  mju_copy(d->qpos, h.scene->d()->qpos, m->nq);
  const auto& links = w->geometry().links;
  std::map<std::string, int> pair_index;
  for (size_t i = 0; i < w->pairs().size(); ++i) {
    const auto& p = w->pairs()[i];
    pair_index[links[p.a].name + "/" + links[p.b].name] = static_cast<int>(i);
    pair_index[links[p.b].name + "/" + links[p.a].name] = static_cast<int>(i);
  }
  const auto rows = Trajectory();
  ASSERT_GT(rows.size(), 3u);
  ASSERT_EQ(rows[0].size(), h.robot.joints.size() + 1);
  int postures = 0, both = 0, arm_leg = 0;
  std::set<std::string> seen;
  for (double t = 0; t <= rows.back()[0] + 1e-9; t += 0.005, ++postures) {
    const std::vector<double> q = At(rows, t);
    for (size_t j = 0; j < q.size(); ++j) d->qpos[h.robot.joints[j].qpos_adr] = q[j];
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_collision(m, d);
    // MuJoCo's deepest penetration per checked pair
    std::vector<double> mujoco(w->pairs().size(), 0.0);
    for (int c = 0; c < d->ncon; ++c) {
      const char* b1 = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[d->contact[c].geom1]);
      const char* b2 = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[d->contact[c].geom2]);
      if (!b1 || !b2) continue;  // the floor
      const auto it = pair_index.find(std::string(b1) + "/" + b2);
      if (it == pair_index.end()) continue;  // left out (built into each other), or the floor
      mujoco[it->second] = std::min(mujoco[it->second], d->contact[c].dist);
    }
    w->Check(d, t, postures);
    std::vector<double> ours(w->pairs().size(), 0.0);
    for (int i : w->in_contact()) ours[i] = w->distances()[i];
    for (size_t i = 0; i < ours.size(); ++i) {
      const std::string name = links[w->pairs()[i].a].name + "/" + links[w->pairs()[i].b].name;
      if (mujoco[i] < -kClear) {
        EXPECT_LT(ours[i], 0.0) << "t=" << t << " MuJoCo finds " << name << " " << -1e3 * mujoco[i]
                                << " mm deep, the watch reports no contact";
      }
      if (ours[i] < -kClear) {
        EXPECT_LT(mujoco[i], 0.0) << "t=" << t << " the watch reports " << name << " "
                                  << -1e3 * ours[i] << " mm deep, MuJoCo no contact";
      }
      if (ours[i] < -kClear && mujoco[i] < -kClear) {
        ++both;
        seen.insert(name);
        arm_leg += name.rfind("RARM_", 0) == 0 && name.find("/RLEG_") != std::string::npos;
      }
    }
  }
  std::string names;
  for (const auto& n : seen) names += n + " ";
  std::printf("%d postures; %d (posture, pair) penetrations beyond %.0f mm found by both: %s\n",
              postures, both, 1e3 * kClear, names.c_str());
  // the test means something: the hand does go into the leg, and both say so
  EXPECT_GT(arm_leg, 10);
  // the report: the pairs in the order of first contact, each with its deepest penetration
  const SelfCollisionSummary s = w->Summary();
  ASSERT_FALSE(s.pairs.empty());
  EXPECT_EQ(s.checks, static_cast<uint64_t>(postures));
  for (size_t i = 1; i < s.pairs.size(); ++i) EXPECT_LE(s.pairs[i - 1].first_time, s.pairs[i].first_time);
  for (const auto& p : s.pairs) {
    EXPECT_GT(p.deepest, 0.0) << p.pair;
    EXPECT_GE(p.deepest_time, p.first_time) << p.pair;
    EXPECT_LE(p.cycles, s.cycles_in_contact) << p.pair;
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}

// Check measures again only the pairs whose links can have moved as far as their last distance:
// on a random walk through the joint limits (steps from 0.1 mrad to 0.3 rad per joint, so some
// checks move nothing noticeable and some jump), the pairs it reports in contact, and their
// depths, are exactly those of a full check of every pair at every posture
TEST(SelfCollisionWatch, SkippingPairsThatCannotHaveMovedMissesNothing) {
  Hrp1s h;
  std::string error;
  auto w = SelfCollisionWatch::Create(h.scene->m(), h.robot, "", &error);
  ASSERT_TRUE(w) << error;
  ASSERT_TRUE(h.scene->Reset("halfsit", &error)) << error;
  mjData* d = h.scene->d();
  w->Start(d);
  auto full = collision::SelfCollision::Create(w->geometry(), &error);
  ASSERT_TRUE(full) << error;
  const auto& g = w->geometry();
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  const size_t nj = h.robot.joints.size();
  std::vector<double> q(nj), all(w->pairs().size());
  for (size_t j = 0; j < nj; ++j) q[j] = d->qpos[h.robot.joints[j].qpos_adr];
  long contacts = 0;
  const int kChecks = 3000;
  for (int k = 0; k < kChecks; ++k) {
    const double step = std::pow(10.0, -4 + 3.5 * (0.5 + 0.5 * u(rng)));  // 1e-4 .. 0.3 rad
    for (size_t j = 0; j < nj; ++j) {
      q[j] = std::clamp(q[j] + step * u(rng), g.q_min[j], g.q_max[j]);
      d->qpos[h.robot.joints[j].qpos_adr] = q[j];
    }
    w->Check(d, k, k);
    full->SetPose(q);
    full->Check(w->pairs(), 0.0, all);
    std::vector<int> expected;
    for (size_t i = 0; i < all.size(); ++i)
      if (all[i] < 0) expected.push_back(static_cast<int>(i));
    ASSERT_EQ(w->in_contact(), expected) << "check " << k << ", step " << step;
    for (int i : expected) EXPECT_EQ(w->distances()[i], all[i]);
    contacts += static_cast<long>(expected.size());
  }
  const SelfCollisionSummary s = w->Summary();
  std::printf("%d checks, %ld (check, pair) contacts; %llu of %zu pair measurements made\n", kChecks,
              contacts, static_cast<unsigned long long>(s.measured), kChecks * w->pairs().size());
  EXPECT_GT(contacts, 100);  // the walk does reach contacts
  EXPECT_LT(s.measured, kChecks * w->pairs().size());  // and skips some
}

// the run's closest approach (issue 29): the smallest signed distance any pair had at any check,
// its pair and time, equal to a full check's (every pair measured every time) on a random walk
// from half-sitting (steps up to 0.05 rad a joint) that goes into contact
TEST(SelfCollisionWatch, TheClosestApproachIsTheFullChecksSmallestDistance) {
  Hrp1s h;
  std::string error;
  auto w = SelfCollisionWatch::Create(h.scene->m(), h.robot, "", &error);
  ASSERT_TRUE(w) << error;
  ASSERT_TRUE(h.scene->Reset("halfsit", &error)) << error;
  mjData* d = h.scene->d();
  w->Start(d);
  auto full = collision::SelfCollision::Create(w->geometry(), &error);
  ASSERT_TRUE(full) << error;
  const auto& g = w->geometry();
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1, 1);
  const size_t nj = h.robot.joints.size();
  std::vector<double> q(nj), all(w->pairs().size());
  for (size_t j = 0; j < nj; ++j) q[j] = d->qpos[h.robot.joints[j].qpos_adr];
  double closest = 1e9, closest_time = -1;
  int closest_pair = -1;
  for (int k = 0; k < 400; ++k) {
    for (size_t j = 0; j < nj; ++j) {
      q[j] = std::clamp(q[j] + 0.05 * u(rng), g.q_min[j], g.q_max[j]);
      d->qpos[h.robot.joints[j].qpos_adr] = q[j];
    }
    w->Check(d, 0.005 * k, k);
    full->SetPose(q);
    full->Check(w->pairs(), 1.0, all);  // every pair within 1 m measured
    for (size_t i = 0; i < all.size(); ++i) {
      if (all[i] < closest) {
        closest = all[i];
        closest_time = 0.005 * k;
        closest_pair = static_cast<int>(i);
      }
    }
  }
  const SelfCollisionSummary s = w->Summary();
  ASSERT_LT(closest, SelfCollisionWatch::kClosestRange);
  EXPECT_TRUE(s.closest_exact);
  EXPECT_NEAR(s.closest, closest, 1e-9);
  EXPECT_EQ(s.closest_time, closest_time);
  const auto& links = g.links;
  EXPECT_EQ(s.closest_pair, links[w->pairs()[closest_pair].a].name + "/" + links[w->pairs()[closest_pair].b].name);
  std::printf("closest approach %.1f mm (%s at %.3f s)\n", 1e3 * s.closest, s.closest_pair.c_str(),
              s.closest_time);

  // standing still at halfsit: the closest pair (the ankles, 40 mm apart) is beyond the range,
  // so the summary gives a lower bound, no pair, and says so
  auto still = SelfCollisionWatch::Create(h.scene->m(), h.robot, "", &error);
  ASSERT_TRUE(still) << error;
  ASSERT_TRUE(h.scene->Reset("halfsit", &error)) << error;
  still->Start(h.scene->d());
  still->Check(h.scene->d(), 0, 0);
  const SelfCollisionSummary t = still->Summary();
  EXPECT_FALSE(t.closest_exact);
  EXPECT_TRUE(t.closest_pair.empty());
  EXPECT_GE(t.closest, SelfCollisionWatch::kClosestRange);
  EXPECT_LE(t.closest, 0.040 + 1e-4);  // a lower bound of the ankles' 40 mm
}

TEST(SelfCollisionWatch, CheckAllocatesNothing) {
#ifndef OHRP_CAN_COUNT
  GTEST_SKIP() << "allocations are counted in the normal build (glibc, no sanitizers)";
#else
  Hrp1s h;
  std::string error;
  auto w = SelfCollisionWatch::Create(h.scene->m(), h.robot, "", &error);
  ASSERT_TRUE(w) << error;
  ASSERT_TRUE(h.scene->Reset("halfsit", &error)) << error;
  w->Start(h.scene->d());
  const auto rows = Trajectory();
  mjData* d = h.scene->d();
  std::vector<std::vector<double>> postures;
  for (double t = 0; t <= rows.back()[0]; t += 0.05) postures.push_back(At(rows, t));
  const long n = ohrp::testing::Allocations([&] {
    for (size_t k = 0; k < postures.size(); ++k) {
      for (size_t j = 0; j < postures[k].size(); ++j) d->qpos[h.robot.joints[j].qpos_adr] = postures[k][j];
      w->Check(d, 0.05 * k, k);
    }
  });
  EXPECT_EQ(n, 0);
  EXPECT_FALSE(w->Summary().pairs.empty());  // the postures did reach contact
#endif
}

}  // namespace
}  // namespace ohrp::sim
