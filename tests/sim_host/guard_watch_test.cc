// sim_host's view of the controller's self-collision guard (sim_host/guard_watch.h): the
// segment's guard records become hold episodes with their pair and distances.
#include "sim_host/guard_watch.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace ohrp::sim {
namespace {

shm::GuardRecord Record(bool holding, double distance = 0, const char* a = "", const char* b = "") {
  shm::GuardRecord g{};
  g.holding = holding ? 1 : 0;
  g.distance = distance;
  std::snprintf(g.link_a, sizeof(g.link_a), "%s", a);
  std::snprintf(g.link_b, sizeof(g.link_b), "%s", b);
  return g;
}

TEST(GuardWatch, HoldsBecomeEpisodesWithTheirPairAndDistances) {
  GuardWatch w;
  int64_t i = -7;
  EXPECT_EQ(w.Update(Record(false), 0.0, 0, &i), 0);
  EXPECT_EQ(w.Update(Record(true, 0.0017, "WAIST_R", "RARM_WRIST_R"), 1.0, 200, &i), +1);
  EXPECT_EQ(i, 0);
  EXPECT_EQ(w.Update(Record(true, -0.0300, "WAIST_R", "RARM_WRIST_P"), 1.005, 201, &i), 0);
  EXPECT_EQ(w.Update(Record(false), 1.010, 202, &i), -1);
  EXPECT_EQ(i, 0);
  EXPECT_EQ(w.Update(Record(true, 0.0010, "LARM_WRIST_R", "RARM_WRIST_R"), 2.0, 400, &i), +1);
  EXPECT_EQ(i, 1);
  const GuardSummary s = w.Summary();
  EXPECT_EQ(s.episodes, 2u);
  EXPECT_EQ(s.held_cycles, 3u);
  EXPECT_TRUE(s.holding_at_end);
  ASSERT_EQ(s.holds.size(), 2u);
  EXPECT_STREQ(s.holds[0].pair, "WAIST_R/RARM_WRIST_R");  // named at its begin
  EXPECT_EQ(s.holds[0].distance, 0.0017);
  EXPECT_EQ(s.holds[0].closest, -0.0300);
  EXPECT_EQ(s.holds[0].cycles, 2u);
  EXPECT_EQ(s.holds[0].begin_cycle, 200u);
  EXPECT_EQ(s.holds[0].end, 1.010);
  EXPECT_EQ(s.holds[0].end_cycle, 202u);
  EXPECT_EQ(s.holds[1].end, -1.0);  // held to the end
  EXPECT_EQ(s.closest, 0);
}

TEST(GuardWatch, EpisodesBeyondTheCapacityAreCountedNotKept) {
  GuardWatch w;
  int64_t i = 0;
  for (size_t k = 0; k < kMaxGuardHolds + 5; ++k) {
    EXPECT_EQ(w.Update(Record(true, 0.001, "A", "B"), 0.01 * k, 2 * k, &i), +1);
    EXPECT_EQ(i, static_cast<int64_t>(std::min(k, kMaxGuardHolds)));
    EXPECT_EQ(w.Update(Record(false), 0.01 * k + 0.005, 2 * k + 1, &i), -1);
  }
  const GuardSummary s = w.Summary();
  EXPECT_EQ(s.episodes, kMaxGuardHolds + 5);
  EXPECT_EQ(s.holds.size(), kMaxGuardHolds);
  EXPECT_FALSE(s.holding_at_end);
  EXPECT_GE(s.holds.back().end, 0.0);  // the last kept one ended
}

}  // namespace
}  // namespace ohrp::sim
