// Passive joints on the hardware path (issue 31, item 5): OpenHRP's SampleRobot on its rubber
// bushes (mjcf/hrp1s/scene_bush.wrl: three passive joints under each sole, six at each wrist).
// sim_host publishes their encoders in the sensor block; on the hardware path the emulated
// sensor board sends them (protocol version 3), the udp plugin reads them into the IoState and
// hw_driver publishes and logs them. Both producers' data logs must then say the same: the
// bushes' deflection under the robot's weight, not the zeros the hardware path read before.
// The fixture: driver_e2e.h.
#include "driver_e2e.h"

namespace ohrp::hw::udp::e2e {
namespace {

const std::string kBushScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_bush.wrl";

TEST_F(DriverEndToEnd, PassiveJointsReadTheSameOnSimHostAndThroughTheDriver) {
  // 1. sim_host, native contact (the bushes are the soft feet), posture to half-sitting
  const std::string sim_log = Path("sim.csv");
  pid_t sim = Exec({kBin + "/sim_host", "--scene", kBushScene, "--contact", "native", "--segment",
                    segment_ + "s", "--duration", "4", "--log", sim_log, "--progress", "0"},
                   Path("sim.out"));
  const std::string shm = "/dev/shm/" + shm::SegmentObjectName(segment_ + "s");
  bool up = false;
  for (auto t0 = Clock::now(); !up && Since(t0) < kMaxWall;) {
    up = fs::exists(shm);
    if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(up) << ReadFile(Path("sim.out"));
  pid_t posture = Exec({kBin + "/posture", "--segment", segment_ + "s", "--ramp", "1.0",
                        "--no-self-collision"},
                       Path("posture_sim.out"));
  ASSERT_EQ(WaitExit(&sim, kMaxWall), 0) << ReadFile(Path("sim.out"));
  ASSERT_EQ(WaitExit(&posture, kMaxWall), 0) << ReadFile(Path("posture_sim.out"));

  // 2. the same robot on the emulated boards through hw_driver
  scene_ = kBushScene;
  posture_args_ = {"--no-self-collision"};
  ASSERT_EQ(RunChain({"--contact", "native"},
                     {"--duration", "4", "--io-arg", kBoardTimeout, "--board-timeout-cycles",
                      kBoardCycles, "--log", Path("driver.csv")}),
            0)
      << ReadFile(Path("driver.out"));

  // 3. the passive joints: the columns with a velocity (dq_), in both logs
  datalog::Table s, d;
  std::string error;
  ASSERT_TRUE(s.Load(sim_log, &error)) << error;
  ASSERT_TRUE(d.Load(Path("driver.csv"), &error)) << error;
  std::vector<std::string> passive;
  for (const auto& n : s.names())
    if (n.rfind("dq_", 0) == 0) passive.push_back(n.substr(3));
  ASSERT_EQ(passive.size(), 18u) << "3 bushes under each sole, 6 at each wrist";
  // the robot rocks on its bushes (stand_bush.yaml: +-4 mm at about 1.3 Hz, not in phase in two
  // runs): each joint's mean over the standing part, t >= 2 s, is compared
  const auto mean_after = [](const datalog::Table& t, int column, double from) {
    const auto& time = t.col(t.Column("time"));
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < time.size(); ++i)
      if (time[i] >= from) sum += t.col(column)[i], ++n;
    return n ? sum / n : NAN;
  };
  double deepest_sim = 0, deepest_drv = 0, worst = 0;
  std::string deepest;
  for (const std::string& p : passive) {
    const int cs = s.Column("q_" + p), cd = d.Column("q_" + p);
    ASSERT_GE(cs, 0) << p;
    ASSERT_GE(cd, 0) << "the driver's log has no q_" << p;
    ASSERT_GE(d.Column("dq_" + p), 0) << p;
    const double qs = mean_after(s, cs, 2.0), qd = mean_after(d, cd, 2.0);
    std::printf("[ figures  ] %-20s mean after 2 s: sim_host %+.6f, driver %+.6f\n", p.c_str(), qs, qd);
    worst = std::fmax(worst, std::fabs(qs - qd));
    if (std::fabs(qs) > std::fabs(deepest_sim)) {
      deepest_sim = qs;
      deepest_drv = qd;
      deepest = p;
    }
  }
  // standing, the bushes under the soles give a fraction of a millimetre or of a degree (hrpsys'
  // stiffnesses, robot_profile.h): not the zeros the hardware path read before
  EXPECT_GT(std::fabs(deepest_sim), 1e-4) << deepest;
  EXPECT_LT(std::fabs(deepest_sim), 0.02) << deepest;
  EXPECT_NEAR(deepest_drv, deepest_sim, 0.3 * std::fabs(deepest_sim)) << deepest;
  EXPECT_LT(worst, 0.3 * std::fabs(deepest_sim)) << "a passive joint reads differently";
  std::printf("[ figures  ] %zu passive joints in both logs; the largest mean %s: sim_host %.6f, "
              "driver %.6f; largest difference of the means %.6f\n",
              passive.size(), deepest.c_str(), deepest_sim, deepest_drv, worst);
}

}  // namespace
}  // namespace ohrp::hw::udp::e2e
