// Tests hw_emulator as a process, driven through the udp plugin the way hw_driver drives it:
// position hold keeps HRP-1S standing, injected loss is counted, a silent board is marked, a board
// reset turns its servos off until re-armed, run-time faults through the control file, errors
// and SIGINT. Bounds are generous: the machine may be loaded.
#include "emulator_fixture.h"

namespace ohrp::hw::udp {
namespace {

using namespace emulator_test;  // NOLINT(build/namespaces): the fixture of these tests


TEST_F(EmulatorTest, PositionHoldKeepsTheRobotStanding) {
  const int port = Start({"--duration", "2.0"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  ASSERT_EQ(Drive(), 0) << Stderr();
  auto r = Result();
  ASSERT_FALSE(r.empty()) << Stderr();
  EXPECT_NEAR(r["time"], 2.0, 0.01);
  EXPECT_NEAR(r["base_z_start"], 0.7235, 1e-3);
  // the straight-legged robot stands: its base sinks by the servos' stiffness only
  EXPECT_GT(r["base_z_end"], 0.70) << Stderr();
  EXPECT_GT(r["base_z_min"], 0.70);
  EXPECT_LT(r["tilt_max_deg"], 3.0);
  EXPECT_GT(r["commands"], 1000);
  EXPECT_EQ(r["commands_lost"], 0);
  // what the boards said: servos on, the feet carry the weight (~ m g in total)
  for (int j = 0; j < 29; ++j) EXPECT_TRUE(state_.servo_on[j]) << j;
  EXPECT_GT(state_.force[0].force[2] + state_.force[1].force[2], 100.0);
  EXPECT_NEAR(state_.imu[0].accel[2], 9.81, 1.0);
  const UdpIoStats& s = io_.stats();
  ASSERT_GT(s.rtt_count, 500u);
  std::printf("[ figures  ] stand: base z %.4f -> %.4f m (min %.4f), tilt max %.2f deg; "
              "command->state round trip p50 %.3f ms, p99 %.3f ms, max %.3f ms, mean %.3f ms "
              "(%llu samples); lost %llu\n",
              r["base_z_start"], r["base_z_end"], r["base_z_min"], r["tilt_max_deg"],
              1e3 * s.RttPercentile(0.5), 1e3 * s.RttPercentile(0.99), 1e3 * s.rtt_max_s,
              1e3 * s.rtt_sum_s / s.rtt_count, static_cast<unsigned long long>(s.rtt_count),
              static_cast<unsigned long long>(s.lost_total()));
}

TEST_F(EmulatorTest, InjectedLossIsCountedOnBothSides) {
  const int port = Start({"--duration", "2.0", "--loss", "0.01", "--seed", "7"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  ASSERT_EQ(Drive(), 0) << Stderr();
  auto r = Result();
  ASSERT_FALSE(r.empty()) << Stderr();
  const double sent = r["states_sent"], dropped = r["states_dropped"];
  const double counted = static_cast<double>(io_.stats().lost_total());
  // the loss rate is about what was asked
  EXPECT_GT(dropped, 0.005 * (sent + dropped));
  EXPECT_LT(dropped, 0.02 * (sent + dropped));
  // every injected loss is counted but those before a board's first or after its last packet
  // (at most 2 per board); more only where this machine lost packets itself (a full receive
  // buffer while the test was not scheduled, or a refused send)
  const double local = static_cast<double>(io_.stats().kernel_dropped) + r["send_failed"];
  EXPECT_GE(counted, dropped - 12);
  EXPECT_LE(counted, dropped + local);
  // the boards count the commands lost on the way to them the same way
  EXPECT_GE(r["commands_lost"], r["commands_dropped"] - 10);
  EXPECT_LE(r["commands_lost"], r["commands_dropped"] + 10);
  EXPECT_GT(r["base_z_end"], 0.70);
  std::printf("[ figures  ] 1%% loss: %.0f state packets, %.0f dropped by the emulator, %.0f "
              "counted lost by the plugin (%.0f lost on this machine); commands: %.0f dropped, "
              "%.0f counted by the boards\n",
              sent + dropped, dropped, counted, local, r["commands_dropped"], r["commands_lost"]);
}

TEST_F(EmulatorTest, ASilentBoardIsMarkedWhileTheOthersGoOn) {
  const int port = Start({"--duration", "1.5", "--silent", "2@0.5"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=1000", "timeout_ms.2=50"});
  bool only_2_silent = false;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand*) {
              only_2_silent = only_2_silent || s.silent_boards == (1u << 2);
            }),
            0)
      << Stderr();
  EXPECT_TRUE(only_2_silent);
  EXPECT_EQ(io_.stats().board[2].silent_events, 1u);
  // the others answered through the end: at least ~1 s of packets after board 2 fell silent
  EXPECT_GT(io_.stats().board[3].received, io_.stats().board[2].received + 500);
}

TEST_F(EmulatorTest, AResetBoardTurnsItsServosOffUntilRearmed) {
  const int port = Start({"--duration", "1.5", "--reset", "0@0.3"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=1000"});
  enum { kBefore, kResetSeen, kRearming, kBackOn } phase = kBefore;
  int rearm_cycles = 0;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand* c) {
              switch (phase) {
                case kBefore:
                  if (s.faults & io_fault::kBoardReset) {
                    phase = kResetSeen;
                    for (int j = 0; j < 6; ++j) EXPECT_FALSE(s.servo_on[j]) << j;
                    EXPECT_TRUE(s.servo_on[6]);
                  }
                  break;
                case kResetSeen:  // as a driver's safety would: servo off, then on again
                  for (int j = 0; j < 6; ++j) c->servo_on[j] = false;
                  if (!(s.faults & io_fault::kBoardReset)) phase = kRearming;
                  break;
                case kRearming:
                  for (int j = 0; j < 6; ++j) c->servo_on[j] = true;
                  if (s.servo_on[0] && ++rearm_cycles > 5) phase = kBackOn;
                  break;
                case kBackOn:
                  break;
              }
            }),
            0)
      << Stderr();
  EXPECT_EQ(phase, kBackOn);
  for (int j = 0; j < 29; ++j) EXPECT_TRUE(state_.servo_on[j]) << j;
  EXPECT_EQ(io_.stats().board[0].lost, 0u);  // the restart of its numbering is no loss
}

// Sessions (PROTOCOL.md): a second driver (another socket, another session) is refused while
// the first one commands, and flagged to the first; once the first is gone for the boards' hold
// time, the boards bind to the new one, which then reads them without the flag.
TEST_F(EmulatorTest, TheBoardsTakeOnlyTheirDriversCommandsAndANewDriverOnceItIsGone) {
  const int port = Start({"--duration", "2.5"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=1000"});
  UdpIo other;
  IoConfig c = Hrp1s().config;
  c.args = {"port=" + std::to_string(port), "quiet=1", "timeout_ms=1000"};
  IoCommand off;  // every servo off
  IoState theirs;
  int cycles = 0;
  bool flagged = false, all_on = true, bound = false;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand*) {
              ++cycles;
              if (cycles == 200) {
                std::string e;
                ASSERT_TRUE(other.open(c, &e)) << e;
                other.write(off);  // refused: not the boards' driver
              }
              if (cycles > 200 && cycles < 1000) {
                flagged = flagged || s.foreign_boards != 0;
                for (int j = 0; j < 29; ++j) all_on = all_on && s.servo_on[j];
              }
              if (cycles == 1000) io_.close();  // the first driver is gone
              if (cycles > 1000) {
                other.read(&theirs);
                other.write(off);
                bound = bound || (other.stats().board[0].received > 50 && theirs.foreign_boards == 0);
              }
            }),
            0)
      << Stderr();
  EXPECT_TRUE(flagged);
  EXPECT_TRUE(all_on) << "the second driver's servo-off reached the boards";
  EXPECT_TRUE(bound) << "the new driver was never bound";
  EXPECT_GE(Result()["foreign"], 1) << Stderr();
}

TEST_F(EmulatorTest, TheControlFileInjectsFaultsWhileRunning) {
  const std::string control = (dir_ / "control").string();
  { std::ofstream(control) << "# faults\n"; }
  const int port = Start({"--duration", "1.2", "--control", control});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=1000"});
  int step = 0;
  double stuck_fz = 0;
  int same = 0;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand*) {
              if (step == 0 && s.time_ns > 200000000) {  // 0.2 s of robot time
                std::ofstream(control, std::ios::app) << "stuck ft0\n";
                step = 1;
              } else if (step == 1 && (s.faults & io_fault::kSensorStuck)) {
                stuck_fz = s.force[0].force[2];
                step = 2;
              } else if (step == 2) {
                same += s.force[0].force[2] == stuck_fz;
                if (same > 50) {
                  std::ofstream(control, std::ios::app) << "estop on\n";
                  step = 3;
                }
              } else if (step == 3 && (s.faults & io_fault::kEmergencyStop)) {
                step = 4;
              }
            }),
            0)
      << Stderr();
  EXPECT_EQ(step, 4) << Stderr();
  // e-stop: every servo off
  for (int j = 0; j < 29; ++j) EXPECT_FALSE(state_.servo_on[j]) << j;
  EXPECT_NE(Stderr().find("control 'estop on'"), std::string::npos);
}

TEST_F(EmulatorTest, LatePacketsAreStaleAndSaturatedSensorsFlagged) {
  const int port = Start({"--duration", "1.0", "--late", "0.05", "--late-ms", "3", "--saturate",
                          "ft1@0.3"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=1000"});
  bool saturated = false;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand*) {
              if (s.faults & io_fault::kSensorSaturated) {
                saturated = true;
                EXPECT_EQ(std::fabs(s.force[1].force[2]), 2000.0);
                EXPECT_EQ(std::fabs(s.force[1].torque[0]), 300.0);
              }
            }),
            0)
      << Stderr();
  EXPECT_TRUE(saturated);
  auto r = Result();
  uint64_t stale = 0;
  for (int b = 0; b < io_.stats().nboards; ++b) stale += io_.stats().board[b].stale;
  // a late packet arrives after newer ones: a gap first, then refused as stale
  EXPECT_GT(r["late"], 100);
  EXPECT_GE(static_cast<double>(stale), r["late"] - 12);
  EXPECT_LE(static_cast<double>(stale), r["late"]);
  // each stale packet left a gap counted lost, except one whose gap the reader had not yet
  // counted when the run ended (seen once in CI: 267 lost, 268 stale)
  EXPECT_GE(static_cast<double>(io_.stats().lost_total()), static_cast<double>(stale) - 2);
}

TEST_F(EmulatorTest, BadOptionsAreRefusedWithAMessage) {
  Spawn({"--model", "/nonexistent.xml"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("nonexistent.xml"), std::string::npos) << Stderr();
  Spawn({"--model", kScene, "--boards", "0-5,6-12"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("29 joints"), std::string::npos) << Stderr();
  Spawn({"--model", kScene, "--silent", "9@1"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("BOARD 0..5"), std::string::npos) << Stderr();
  Spawn({"--model", kScene, "--period", "0.0015"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("whole multiple"), std::string::npos) << Stderr();
  Spawn({"--model", kScene, "--loss", "1.5"});
  EXPECT_EQ(Wait(), 2);
  Spawn({"--help"});
  EXPECT_EQ(Wait(), 0);
}

TEST_F(EmulatorTest, SigintEndsTheRunCleanly) {
  const int port = Start({});
  ASSERT_GT(port, 0);
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130);
  EXPECT_NE(Stderr().find("hw_emulator: result exit=130"), std::string::npos) << Stderr();
}

TEST_F(EmulatorTest, NoDriverEndsTheRunAfterTheWait) {
  Start({}, "0.2");
  EXPECT_EQ(Wait(), 5);
  EXPECT_NE(Stderr().find("no command packet within"), std::string::npos) << Stderr();
}

// issue 31: the contact under the soles is chosen as sim_host chooses it (sim_host/
// contact_choice.h): --contact auto by default, so HRP-1S's colliding *_SOLE boxes are the soft
// soles; a robot profile's `contact: native` (its soles non-colliding markers) resolves to
// MuJoCo's contact; an explicit --contact wins; a contact file that is not there is refused
TEST_F(EmulatorTest, TheContactIsChosenAsSimHostChoosesIt) {
  auto contact_of = [&](std::vector<std::string> extra) {
    if (Start(extra) <= 0) return std::string("(no start)");
    kill(pid_, SIGINT);
    EXPECT_EQ(Wait(), 130) << Stderr();
    const std::string text = Stderr();
    const size_t at = text.find("; contact ");
    return at == std::string::npos ? std::string("(not said)")
                                   : text.substr(at + 10, text.find(';', at + 10) - at - 10);
  };
  EXPECT_EQ(contact_of({}), "soft");
  EXPECT_EQ(contact_of({"--contact", "native"}), "native");
  EXPECT_EQ(contact_of({"--contact", "rigid"}), "rigid");
  Spawn({"--model", kScene, "--contact-file", (dir_ / "none.yaml").string()});
  EXPECT_EQ(Wait(), 2);
  // a profile whose soles are markers (contact: native) over G1, when the menagerie is there
  const fs::path g1 = fs::path(OHRP_SOURCE_DIR).parent_path() /
                      "shared/external/menagerie/unitree_g1/scene.xml";
  if (!fs::exists(g1)) GTEST_SKIP() << g1 << " is not there";
  for (const char* mode : {"native", "soft"}) {
    const std::string profile = (dir_ / (std::string("g1_") + mode + ".yaml")).string();
    std::ofstream(profile) << "model: " << g1.string() << "\n"
                           << "feet:\n  left: {body: left_ankle_roll_link}\n"
                           << "  right: {body: right_ankle_roll_link}\n"
                           << "contact: " << mode << "\n";
    fs::remove(err_);  // the last run's text is not this one's
    Spawn({"--model", profile, "--wait-driver", "30", "--period", "0.002"});
    const auto t0 = Clock::now();
    while (Running() && Since(t0) < kMaxWall && Stderr().find("; contact ") == std::string::npos)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    kill(pid_, SIGINT);
    EXPECT_EQ(Wait(), 130) << Stderr();
    EXPECT_NE(Stderr().find(std::string("; contact ") + mode + ";"), std::string::npos)
        << mode << ": " << Stderr();
  }
}

}  // namespace
}  // namespace ohrp::hw::udp
