// Tests hw_driver's robot model and the replay plugin as a process, with the real binary:
// hw_driver and sim_host publish the same model hash for the same MJCF, an OpenHRP VRML model
// read directly publishes the robot of its MJCF, and the replay plugin plays a CSV data log
// into the segment.
#include "driver_process.h"

namespace ohrp::hw {
namespace {

namespace fs = std::filesystem;
using testing::HwDriverProcess;
using testing::Peek;

//---------------- the robot model's identity ----------------

TEST_F(HwDriverProcess, PublishesTheSameModelHashAsSimHostForTheSameModel) {
  Start({"--duration", "120", "--watchdog-cycles", "1000000"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  other_segment_ = segment_ + "_sim";
  child_ = Exec({std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", model_, "--segment",
                 other_segment_, "--physics-dt", "0.001", "--control-period", "0.002",
                 "--wait-controller", "60", "--progress", "0"},
                Path("sim_host.stderr"));
  ASSERT_TRUE(WaitRunning(other_segment_)) << Read("sim_host.stderr");

  Peek hw(segment_), sim(other_segment_);
  const shm::SegmentHeader& h = hw.get().header;
  const shm::SegmentHeader& s = sim.get().header;
  EXPECT_EQ(h.producer_kind, shm::ProducerKind::kHardware);
  EXPECT_EQ(s.producer_kind, shm::ProducerKind::kSimulation);
  EXPECT_NE(h.model_hash, 0u);
  EXPECT_EQ(h.model_hash, s.model_hash);
  // and the hash this process computes from the same file
  {
    std::string error;
    auto scene = model::Scene::Load(model_, &error);
    ASSERT_NE(scene, nullptr) << error;
    model::RobotMap robot;
    ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
    EXPECT_EQ(model::ModelHash(scene->m(), robot), h.model_hash);
    EXPECT_EQ(model::CheckModelMatches(scene->m(), robot, s), "");
  }
  // the identity fields, closed forms of kModel: two 1 kg links, axes z then y
  for (const shm::SegmentHeader* p : {&h, &s}) {
    EXPECT_EQ(p->nbody, 2);
    EXPECT_DOUBLE_EQ(p->total_mass, 2.0);
    EXPECT_DOUBLE_EQ(p->link_mass[0], 1.0);
    EXPECT_DOUBLE_EQ(p->link_mass[1], 1.0);
    EXPECT_EQ(p->joint_axis[0][2], 1.0);
    EXPECT_EQ(p->joint_axis[1][1], 1.0);
  }

  kill(child_, SIGINT);
  EXPECT_NE(WaitExit(&child_), -1) << Read("sim_host.stderr");
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
}

//---------------- an OpenHRP VRML model read directly ----------------

TEST_F(HwDriverProcess, VrmlModelPublishesTheRobotOfItsMjcf) {
  model_ = std::string(OHRP_SOURCE_DIR) + "/../shared/external/openhrp3-sample/sample1.wrl";
  Start({"--duration", "120", "--watchdog-cycles", "1000000"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek hw(segment_);
  const shm::SegmentHeader& h = hw.get().header;
  EXPECT_EQ(h.njoint, 29);
  // the same robot as mjcf/hrp1s/hrp1s.xml: the same identity
  std::string error;
  auto scene = model::Scene::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml", &error);
  ASSERT_NE(scene, nullptr) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  EXPECT_EQ(model::ModelHash(scene->m(), robot), h.model_hash);
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
}

//---------------- replay ----------------

TEST_F(HwDriverProcess, ReplayPlaysTheLogsPositionsIntoTheSegment) {
  // a sim_host data log: q_j1 = 0.5 t, q_j2 = -0.4 t, every 5 ms for 2 s (within the joints'
  // ranges: a value outside them is an implausible reading, board_checks.h)
  std::string csv = "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,base_vx,base_vy,"
                    "base_vz,q_j1,q_j2,qref_j1,qref_j2,tau_j1,tau_j2,ft_fx,ft_fy,ft_fz,ft_tx,ft_ty,"
                    "ft_tz,imu_gx,imu_gy,imu_gz,imu_ax,imu_ay,imu_az,imu_qw,imu_qx,imu_qy,imu_qz,"
                    "status,rejected\n";
  for (int r = 0; r <= 400; ++r) {
    const double t = 0.005 * r;
    char row[512];
    std::snprintf(row, sizeof(row),
                  "%.9g,0,0,0,1,0,0,0,0,0,0,%.9g,%.9g,0,0,1.5,-1.5,0,0,%.9g,0,0,0,0,0,0,0,0,9.81,"
                  "1,0,0,0,65,0\n",
                  t, 0.5 * t, -0.4 * t, 10 + t);
    csv += row;
  }
  const std::string log = Write("log.csv", csv);
  Start({"--io-arg", "file=" + log, "--servo-off-time", "0.01"}, REPLAY_IO_PATH);
  ASSERT_TRUE(WaitSegment()) << Stderr();
  shm::RobotAdaptor a;
  shm::Status st;
  for (int i = 0; i < 200 && !(st = a.open(segment_)).ok(); ++i) usleep(2000);
  ASSERT_TRUE(st.ok()) << st.message;
  shm::SensorBlock s{};
  int checked = 0;
  for (;;) {
    const shm::ReadResult r = a.read(&s);
    if (r != shm::ReadResult::kOk) {
      EXPECT_EQ(r, shm::ReadResult::kProducerStopped);
      break;
    }
    const double t = 0.001 * static_cast<double>(s.cycle);  // the replay's time at cycle k
    if (t > 2.0 || (s.status & shm::status::kShuttingDown)) continue;
    ASSERT_NEAR(s.q[0], 0.5 * t, 1e-9) << "cycle " << s.cycle;
    ASSERT_NEAR(s.q[1], -0.4 * t, 1e-9);
    ASSERT_NEAR(s.dq[0], 0.5, 1e-6);
    ASSERT_NEAR(s.tau[1], -1.5, 1e-12);
    ASSERT_NEAR(s.force[0].force[2], 10 + t, 1e-9);
    ASSERT_NEAR(s.imu[0].accel[2], 9.81, 1e-12);
    ++checked;
  }
  a.close();
  EXPECT_GT(checked, 10);
  EXPECT_EQ(Wait(), 0) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  EXPECT_EQ(Summary()["outcome"], "end_of_data");
}

}  // namespace
}  // namespace ohrp::hw
