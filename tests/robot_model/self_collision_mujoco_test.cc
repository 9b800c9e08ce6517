// The self-collision checker against MuJoCo's own collision detection (brute force): 100,000
// random postures of HRP-1S within its limits, every non-adjacent pair enabled in a copy of the
// model (contype/conaffinity 1, a margin so MuJoCo reports near pairs with their distance).
// - Zero false negatives with the shipped reduced list (the file's online pairs, plus the pairs
//   of each safe range the posture leaves), half the postures keeping the safe ranges: every
//   pair the checker or MuJoCo finds penetrating is on the list.
// - MuJoCo 2.2.2 is not an exact referee for these shapes (its box-box routine reports
//   penetrations of boxes 15 mm apart when a margin is set, its cylinders go through MPR, whose
//   depths are off by millimetres): each collision MuJoCo reports and the checker does not must
//   be proven apart by a separating axis (SupportDistance > 0), and the differences of the
//   distances are printed by shape type, not asserted.
// - Distances under 1 mm of the truth: each shape pair the checker measures apart within the
//   margin has its lower bound (the gap of the projections, independent of FCL) within 1 mm of
//   it; the truth lies between the two.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "collision/from_mjcf.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "robot_model/model.h"

namespace ohrp::collision {
namespace {

constexpr double kMargin = 0.02;        // [m] MuJoCo reports pairs closer than this
constexpr double kDistanceTol = 1e-3;   // [m] the bound on distance errors
constexpr double kDeepEnough = 1e-3;    // [m] a MuJoCo penetration beyond this is a collision
#ifdef OHRP_SANITIZE
constexpr int kPostures = 20000;  // -O1 with ASan is ~14x slower: the memory check, not the statistics
#else
constexpr int kPostures = 100000;
#endif

std::string Src(const char* p) { return std::string(OHRP_SOURCE_DIR) + "/" + p; }

TEST(SelfCollisionBruteForce, AgreesWithMujocoOnRandomPostures) {
  // the model, every geom colliding with every other (MuJoCo still skips parent and child)
  char err[512] = "";
  mjModel* m = mj_loadXML(Src("mjcf/hrp1s/hrp1s.xml").c_str(), nullptr, err, sizeof(err));
  ASSERT_TRUE(m) << err;
  for (int g = 0; g < m->ngeom; ++g) {
    m->geom_contype[g] = m->geom_conaffinity[g] = 1;
    m->geom_margin[g] = kMargin;
  }
  mjData* d = mj_makeData(m);
  model::RobotMap robot;
  RobotGeometry g;
  std::string error;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  ASSERT_TRUE(GeometryFromModel(m, robot, &g, &error)) << error;
  auto checker = SelfCollision::Create(g, &error);
  ASSERT_TRUE(checker) << error;
  SelfCollisionFile file;
  ASSERT_TRUE(ReadSelfCollisionFile(Src("mjcf/hrp1s/selfcollision.yaml"), &file, &error)) << error;

  // pair index by links; the structural pairs are left out of the comparison
  const std::vector<LinkPair> pairs = NonAdjacentPairs(g);
  std::map<std::pair<int, int>, int> index;
  for (size_t i = 0; i < pairs.size(); ++i) index[{pairs[i].a, pairs[i].b}] = static_cast<int>(i);
  std::vector<bool> structural(pairs.size(), false), online(pairs.size(), false);
  for (const LinkPair& p : file.structural) structural[index.at({p.a, p.b})] = true;
  for (const LinkPair& p : file.online) online[index.at({p.a, p.b})] = true;
  std::vector<int> link_of_body(m->nbody, -1);
  for (size_t l = 0; l < g.links.size(); ++l)
    link_of_body[mj_name2id(m, mjOBJ_BODY, g.links[l].name.c_str())] = static_cast<int>(l);

  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> q(g.joint_names.size()), mj_dist(pairs.size()), ours(pairs.size());
  std::vector<bool> checked(pairs.size());
  long collisions = 0, missed_by_list = 0, mujoco_only = 0, unproven = 0, compared = 0;
  long in_ranges = 0;
  std::vector<double> mujoco_error;
  std::map<std::string, long> missed;  // pair -> postures it was missed in
  double worst = 0;
  std::string worst_pair;
  for (int k = 0; k < kPostures; ++k) {
    // a posture within the limits; every other one keeps the file's safe ranges
    for (size_t j = 0; j < q.size(); ++j) q[j] = g.q_min[j] + u(rng) * (g.q_max[j] - g.q_min[j]);
    if (k % 2 == 0)
      for (const SafeRange& s : file.ranges) q[s.joint] = s.lo + u(rng) * (s.hi - s.lo);
    // the list a controller checks: online, plus each safe range the posture leaves
    checked = online;
    bool keeps = true;
    for (const SafeRange& s : file.ranges) {
      if (q[s.joint] >= s.lo && q[s.joint] <= s.hi) continue;
      keeps = false;
      for (const LinkPair& p : s.pairs) checked[index.at({p.a, p.b})] = true;
    }
    in_ranges += keeps;

    // MuJoCo: the closest contact of each link pair
    mju_copy(d->qpos, m->qpos0, m->nq);
    d->qpos[0] = d->qpos[1] = d->qpos[2] = 0;
    for (size_t j = 0; j < q.size(); ++j) d->qpos[robot.joints[j].qpos_adr] = q[j];
    mj_kinematics(m, d);
    mj_collision(m, d);
    std::fill(mj_dist.begin(), mj_dist.end(), INFINITY);
    for (int c = 0; c < d->ncon; ++c) {
      int a = link_of_body[m->geom_bodyid[d->contact[c].geom1]];
      int b = link_of_body[m->geom_bodyid[d->contact[c].geom2]];
      if (a > b) std::swap(a, b);
      const auto it = index.find({a, b});
      if (it != index.end()) mj_dist[it->second] = std::min(mj_dist[it->second], d->contact[c].dist);
    }

    // the checker on every pair, then the comparison
    checker->SetPose(q);
    checker->Check(pairs, kMargin, ours);
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (structural[i]) continue;
      const LinkPair p = pairs[i];
      // MuJoCo's collisions the checker does not see must be proven apart
      if (mj_dist[i] < -kDeepEnough && ours[i] > 0) {
        ++mujoco_only;
        bool proven = true;
        for (size_t sa = 0; sa < g.links[p.a].shapes.size(); ++sa)
          for (size_t sb = 0; sb < g.links[p.b].shapes.size(); ++sb)
            proven = proven && checker->SupportDistance(p.a, sa, p.b, sb) > 0;
        unproven += !proven;
      }
      // a collision (the checker's, or MuJoCo's unproven) must be on the reduced list
      if (ours[i] <= 0) {
        ++collisions;
        if (!checked[i]) {
          ++missed_by_list;
          ++missed[g.links[p.a].name + " / " + g.links[p.b].name + (keeps ? " (ranges kept)" : "")];
        }
      }
      // the distances: against MuJoCo (printed), against the lower bound (asserted)
      if (mj_dist[i] > 0 && mj_dist[i] < kMargin && ours[i] > 0 && ours[i] < kMargin) {
        mujoco_error.push_back(std::abs(ours[i] - mj_dist[i]));
      }
      if (ours[i] > 0 && ours[i] < kMargin && k % 10 == 0) {
        for (size_t sa = 0; sa < g.links[p.a].shapes.size(); ++sa)
          for (size_t sb = 0; sb < g.links[p.b].shapes.size(); ++sb) {
            const double d = checker->ShapeDistance(p.a, sa, p.b, sb, kMargin);
            if (!(d > 0 && d < kMargin)) continue;
            ++compared;
            const double e = d - checker->SupportDistance(p.a, sa, p.b, sb);
            if (e > worst) {
              worst = e;
              worst_pair = g.links[p.a].name + " / " + g.links[p.b].name;
            }
          }
      }
    }
  }
  std::sort(mujoco_error.begin(), mujoco_error.end());
  const auto at = [&](double f) { return mujoco_error.empty() ? 0.0 : 1e3 * mujoco_error[static_cast<size_t>(f * (mujoco_error.size() - 1))]; };
  std::printf("postures %d (%ld keep the safe ranges): collisions %ld, missed by the reduced list "
              "%ld; MuJoCo-only collisions %ld (unproven %ld); shape distances certified %ld, "
              "worst gap %.6f mm (%s); |checker - MuJoCo| over %zu near pairs: median %.3f mm, "
              "p99 %.3f mm, max %.3f mm\n",
              kPostures, in_ranges, collisions, missed_by_list, mujoco_only, unproven, compared,
              1e3 * worst, worst_pair.c_str(), mujoco_error.size(), at(0.5), at(0.99), at(1.0));
  for (const auto& [pair, n] : missed) std::printf("missed: %s in %ld postures\n", pair.c_str(), n);
  EXPECT_GT(collisions, 1000);  // the test sees collisions at all
  EXPECT_EQ(missed_by_list, 0);
  EXPECT_EQ(unproven, 0);
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, kDistanceTol) << worst_pair;
  mj_deleteData(d);
  mj_deleteModel(m);
}

}  // namespace
}  // namespace ohrp::collision
