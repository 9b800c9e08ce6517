// Tests the divergence watch (sim_host/divergence.h): what it detects (non-finite state,
// MuJoCo's bad-acceleration reset, an energy jump nothing paid for), what it must not flag (a
// push it is told about, the standing robot, OpenHRP's SamplePD walk), and its energy account
// against MuJoCo's own (mjENBL_ENERGY), and without that flag (a free fall is not a blow-up).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "controllers/trajectory.h"
#include "stability_util.h"

namespace ohrp::sim::stability {
namespace {

// a 1 kg ball on a slider and a pendulum: nothing touches anything
constexpr const char* kBodies = R"(
<mujoco model="bodies">
  <compiler angle="radian"/>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <body name="ball" pos="0 0 1">
      <freejoint name="ball"/>
      <geom type="sphere" size="0.05" mass="1" contype="0" conaffinity="0"/>
    </body>
    <body name="pendulum" pos="1 0 1">
      <joint name="swing" type="hinge" axis="0 1 0" stiffness="2"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="0.5" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>)";

TEST(DivergenceWatch, EnergyAgreesWithMujocosAndAFreeFallIsNotFlagged) {
  auto sim = Sim::FromString(kBodies);
  ASSERT_TRUE(sim);
  mjModel* m = sim->m();
  mjData* d = sim->d();
  d->qpos[7] = 0.5;  // the pendulum starts swung out (its spring and gravity store energy)
  m->opt.enableflags |= mjENBL_ENERGY;
  DivergenceWatch watch(m);
  watch.Start(m, d);
  double largest_lag = 0;
  for (int k = 1; k <= 1000; ++k) {
    mj_step(m, d);
    ASSERT_FALSE(watch.Check(m, d, k));
    // MuJoCo's energy of the same state, with current kinematics; the watch's positions lag one
    // step: at most the bodies' weights times their vertical travel in one step
    const double watch_energy = watch.energy();
    mj_forward(m, d);
    const double mujoco = d->energy[0] + d->energy[1];
    const double lag = 9.81 * (1.0 * std::fabs(d->qvel[2]) + 0.5 * 0.25 * std::fabs(d->qvel[6])) *
                           m->opt.timestep + 2 * std::fabs(d->qvel[6]) * m->opt.timestep;
    ASSERT_NEAR(watch_energy, mujoco, lag + 1e-9) << "step " << k;
    largest_lag = std::max(largest_lag, std::fabs(watch_energy - mujoco));
  }
  EXPECT_GT(largest_lag, 0.05) << "the lag bound is not exercised";
  // one second of free fall and swing: E stays within that lag of E(0)
  EXPECT_NEAR(d->qvel[2], -9.81, 0.02);
  EXPECT_LE(watch.max_excess(), 0.11);
  EXPECT_NEAR(watch.energy(), watch.energy_start(), 0.11);
}

// The watch's kinetic energy walks MuJoCo's sparse mass matrix itself: it must equal
// 1/2 v^T (M v) from mj_mulM, on trees with free, ball, slide and hinge joints (HRP-1S, and a
// chain hanging from a free body), at random postures and velocities
TEST(DivergenceWatch, KineticEnergyIsHalfVTransposeMV) {
  constexpr const char* kTree = R"(
<mujoco model="tree">
  <worldbody>
    <body name="base" pos="0 0 1">
      <freejoint/>
      <geom type="box" size="0.2 0.1 0.05" mass="5" contype="0" conaffinity="0"/>
      <body name="upper" pos="0.2 0 0">
        <joint name="shoulder" type="ball"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1" contype="0" conaffinity="0"/>
        <body name="lower" pos="0.3 0 0">
          <joint name="elbow" type="hinge" axis="0 1 0"/>
          <joint name="twist" type="hinge" axis="1 0 0"/>
          <joint name="reach" type="slide" axis="1 0 0"/>
          <geom type="capsule" fromto="0 0 0 0.25 0.05 0" size="0.02" mass="0.7" contype="0" conaffinity="0"/>
        </body>
      </body>
    </body>
    <body name="arm" pos="1 0 1">
      <joint name="swing" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="0.5" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
</mujoco>)";
  for (const bool robot : {false, true}) {
    auto sim = robot ? Sim::FromScene(Src("mjcf/hrp1s/scene_flat.xml")) : Sim::FromString(kTree);
    ASSERT_TRUE(sim);
    mjModel* m = sim->m();
    mjData* d = sim->d();
    DivergenceWatch watch(m);
    std::vector<double> mv(m->nv);
    unsigned seed = 7;
    auto uniform = [&seed] {
      seed = seed * 1103515245u + 12345u;
      return ((seed >> 8) & 0xffff) / 32768.0 - 1.0;  // [-1, 1)
    };
    for (int trial = 0; trial < 50; ++trial) {
      for (int i = 0; i < m->nq; ++i) d->qpos[i] = m->qpos0[i] + 0.5 * uniform();
      mj_normalizeQuat(m, d->qpos);
      for (int i = 0; i < m->nv; ++i) d->qvel[i] = 3 * uniform();
      watch.Start(m, d);  // E(0) of this state: writes d->energy as every check does
      mj_mulM(m, d, mv.data(), d->qvel);
      double expected = 0;
      for (int i = 0; i < m->nv; ++i) expected += 0.5 * d->qvel[i] * mv[i];
      ASSERT_GT(expected, 0.1);
      EXPECT_NEAR(d->energy[1], expected, 1e-12 * expected)
          << (robot ? "HRP-1S" : "tree") << ", trial " << trial;
    }
  }
}

// MuJoCo 2.2's mj_energyPos is 0 without the scene's `energy` flag: the watch computes the
// potential energy itself, so a body falling for 3 s (44 m, 430 J of kinetic energy against a
// 15 J margin) is not energy from nowhere, and a real jump is still caught
TEST(DivergenceWatch, FreeFallWithoutTheEnergyFlagIsNotFlaggedAndAJumpStillIs) {
  auto sim = Sim::FromString(kBodies);
  ASSERT_TRUE(sim);
  mjModel* m = sim->m();
  mjData* d = sim->d();
  d->qpos[7] = 0.5;  // the pendulum's spring stores energy too
  ASSERT_FALSE(m->opt.enableflags & mjENBL_ENERGY);
  DivergenceWatch watch(m);
  watch.Start(m, d);
  EXPECT_NEAR(watch.energy_start(), -(-9.81) * (1.0 * 1.0 + 0.5 * (1.0 - 0.25 * std::cos(0.5))) +
                                        0.5 * 2.0 * 0.25, 1e-6)
      << "m g z of both bodies and the spring's k q^2 / 2";
  for (int k = 1; k <= 3000; ++k) {
    mj_step(m, d);
    ASSERT_FALSE(watch.Check(m, d, k)) << "step " << k << ": " << watch.Diagnose(m, d).what;
  }
  EXPECT_NEAR(d->qvel[2], -3 * 9.81, 0.05);
  EXPECT_NEAR(watch.energy(), watch.energy_start(), 0.35) << "a fall conserves E (lag M g v dt)";

  // 20 m/s sideways from nowhere (200 J): still an energy blow-up
  mj_step(m, d);
  d->qvel[0] = 20;
  ASSERT_TRUE(watch.Check(m, d, 3001));
  EXPECT_EQ(watch.kind(), DivergenceKind::kEnergy);
}

TEST(DivergenceWatch, NonFiniteStateIsCaughtAndNamesTheJoint) {
  auto sim = Sim::FromString(kBodies);
  ASSERT_TRUE(sim);
  mjModel* m = sim->m();
  mjData* d = sim->d();
  DivergenceWatch watch(m);
  watch.Start(m, d);
  for (int k = 1; k <= 10; ++k) {
    mj_step(m, d);
    ASSERT_FALSE(watch.Check(m, d, k));
  }
  mj_step(m, d);
  d->qvel[6] = std::numeric_limits<double>::quiet_NaN();  // the pendulum's dof
  ASSERT_TRUE(watch.Check(m, d, 11));
  EXPECT_EQ(watch.kind(), DivergenceKind::kNonFinite);
  const Diagnosis x = watch.Diagnose(m, d);
  EXPECT_EQ(x.step, 11u);
  EXPECT_NEAR(x.time, 0.010, 1e-9) << "the time of the last finite state";
  ASSERT_FALSE(x.dofs.empty());
  EXPECT_EQ(x.dofs[0].joint, "swing");
  EXPECT_EQ(x.bodies[0], "pendulum");
  EXPECT_NE(x.Text().find("step 11"), std::string::npos) << x.Text();
  // latched: later checks keep the first detection
  EXPECT_TRUE(watch.Check(m, d, 12));
  EXPECT_EQ(watch.Diagnose(m, d).step, 11u);
}

TEST(DivergenceWatch, MujocosBadAccelerationResetIsCaught) {
  auto sim = Sim::FromString(kBodies);
  ASSERT_TRUE(sim);
  mjModel* m = sim->m();
  mjData* d = sim->d();
  DivergenceWatch watch(m);
  watch.Start(m, d);
  mj_step(m, d);
  ASSERT_FALSE(watch.Check(m, d, 1));
  d->qfrc_applied[6] = 1e13;  // qacc beyond mjMAXVAL (1e10): MuJoCo warns and resets
  mj_step(m, d);
  EXPECT_EQ(d->warning[mjWARN_BADQACC].number, 1);
  EXPECT_EQ(d->qpos[7], 0.0) << "MuJoCo reset the state: finite, but garbage";
  ASSERT_TRUE(watch.Check(m, d, 2));
  EXPECT_EQ(watch.kind(), DivergenceKind::kMujocoReset);
  const Diagnosis x = watch.Diagnose(m, d);
  EXPECT_NE(x.what.find("bad acceleration"), std::string::npos) << x.what;
  EXPECT_EQ(x.dofs[0].joint, "swing") << "MuJoCo's warning names the dof";
}

TEST(DivergenceWatch, EnergyNobodyPaidForIsCaughtAndAPushThatPaysIsNot) {
  // 1. a velocity jump of 20 m/s on 1 kg (200 J) with no source: above the 9.81 J margin
  {
    auto sim = Sim::FromString(kBodies);
    ASSERT_TRUE(sim);
    mjModel* m = sim->m();
    mjData* d = sim->d();
    DivergenceWatch watch(m);
    EXPECT_NEAR(watch.margin(), 1.5 * 9.81 * 1.0, 1e-9) << "M g x 1 m";
    watch.Start(m, d);
    mj_step(m, d);
    ASSERT_FALSE(watch.Check(m, d, 1));
    d->qvel[0] = 20;
    ASSERT_TRUE(watch.Check(m, d, 2));
    EXPECT_EQ(watch.kind(), DivergenceKind::kEnergy);
    EXPECT_NEAR(watch.energy() - watch.energy_start(), 200, 1);
    EXPECT_NE(watch.Diagnose(m, d).what.find("energy blow-up"), std::string::npos);
  }
  // 2. the same kinetic energy given by a push of 20 N for 1 s (W = F^2 t^2 / 2m = 200 J)
  for (bool passive : {false, true}) {
    auto sim = Sim::FromString(kBodies);
    ASSERT_TRUE(sim);
    const int ball = mj_name2id(sim->m(), mjOBJ_BODY, "ball");
    sim->m()->opt.gravity[2] = 0;
    sim->d()->xfrc_applied[6 * ball + 0] = 20;
    RunResult r = sim->Run(1.0, {}, {}, passive ? std::vector<int>{ball} : std::vector<int>{});
    if (!passive) {
      ExpectStable(r, 1.0, 0.5);
      EXPECT_NEAR(r.work, 200, 2);
      EXPECT_NEAR(r.energy - r.energy0, 200, 2);
    } else {
      // declared a passive contact force, the same push is energy from nowhere
      ExpectDetected(r);
      EXPECT_EQ(r.diagnosis.kind, DivergenceKind::kEnergy);
    }
  }
}

//---------------- no false positive on the robot ----------------

TEST(DivergenceWatch, StandingRobotIsNotFlagged) {
  Robot r;
  LoadRobot(r, "mjcf/hrp1s/scene_flat.xml", "halfsit");
  ASSERT_TRUE(r.sim && r.soft);
  mjModel* m = r.sim->m();
  mjData* d = r.sim->d();
  RunResult res = r.sim->Run(3.0, [&] { r.servo->Apply(m, d); r.soft->ApplyBeforeStep(m, d); },
                             [&] { r.soft->Commit(); }, r.soles);
  // settling on the soles costs a little potential energy; nothing may appear from nowhere
  ExpectStable(res, 3.0, 1.0);
  EXPECT_GT(d->xpos[3 * r.map.base_body + 2], 0.6) << "the robot fell";
  EXPECT_LT(res.max_excess, 1e-3 * DivergenceWatch(m).margin());
  Note("false_positives_stand.txt",
       "HRP-1S standing 3 s on soft soles: largest E - E(0) - W " + Fmt("%.3g", res.max_excess) +
           " J of the " + Fmt("%.4g", DivergenceWatch(m).margin()) + " J margin");
}

TEST(DivergenceWatch, CheckCostsLittleNextToAStepOfTheRobot) {
  Robot r;
  LoadRobot(r, "mjcf/hrp1s/scene_flat.xml", "halfsit");
  ASSERT_TRUE(r.sim && r.soft);
  mjModel* m = r.sim->m();
  mjData* d = r.sim->d();
  DivergenceWatch watch(m);
  watch.SetPassiveBodies(r.soles);
  watch.Start(m, d);
  using Clock = std::chrono::steady_clock;
  constexpr int kSteps = 2000;
  double step_time = 0, check_time = 0;
  for (int k = 1; k <= kSteps; ++k) {
    const auto t0 = Clock::now();
    r.servo->Apply(m, d);
    r.soft->ApplyBeforeStep(m, d);
    mj_step(m, d);
    r.soft->Commit();
    const auto t1 = Clock::now();
    ASSERT_FALSE(watch.Check(m, d, k));
    const auto t2 = Clock::now();
    step_time += std::chrono::duration<double>(t1 - t0).count();
    check_time += std::chrono::duration<double>(t2 - t1).count();
  }
  // a loose bound (a shared machine): the figure itself goes to build/stability/cost.md
  EXPECT_LT(check_time, 0.25 * step_time);
  Note("cost.txt", "HRP-1S standing on soft soles, " + std::to_string(kSteps) +
                       " steps: servo + soft contact + mj_step " +
                       Fmt("%.2f", 1e6 * step_time / kSteps) + " us per step, the watch's Check " +
                       Fmt("%.2f", 1e6 * check_time / kSteps) + " us per step (" +
                       Fmt("%.1f", 100 * check_time / step_time) + " %)");
}

TEST(DivergenceWatch, SamplePdWalkIsNotFlagged) {
  const std::string dir = Src("../shared/external/openhrp3-sample/SamplePD/");
  controllers::Trajectory angles, velocities;
  controllers::Gains gains;
  ASSERT_TRUE(controllers::LoadTrajectory(dir + "angle.dat", &angles).ok());
  ASSERT_TRUE(controllers::LoadTrajectory(dir + "vel.dat", &velocities).ok());
  ASSERT_TRUE(controllers::LoadGains(dir + "PDgain.dat", &gains).ok());
  Robot r;
  LoadRobot(r, "mjcf/hrp1s/scene_flat.xml", "");
  ASSERT_TRUE(r.sim && r.soft);
  mjModel* m = r.sim->m();
  mjData* d = r.sim->d();
  const int n = static_cast<int>(r.map.joints.size());
  ASSERT_EQ(angles.njoint, n);
  // as the playback controller does: 2 s of linear ramp from the initial pose to the first
  // row, then the data against simulated time, every 2 ms, with the file's PD gains
  constexpr double kRamp = 2.0, kPeriod = 0.002;
  std::vector<double> q0(n), q(n), dq(n);
  for (int i = 0; i < n; ++i) q0[i] = d->qpos[r.map.joints[i].qpos_adr];
  double next_command = 0;
  const double duration = kRamp + angles.duration();
  RunResult res = r.sim->Run(
      duration,
      [&] {
        if (d->time >= next_command - 1e-9) {
          next_command += kPeriod;
          shm::CommandBlock c{};
          c.njoint = n;
          const double t = d->time;
          if (t < kRamp) {
            SampleTrajectory(angles, angles.start_time(), q.data());
            for (int i = 0; i < n; ++i) {
              q[i] = q0[i] + (q[i] - q0[i]) * t / kRamp;
              dq[i] = 0;
            }
          } else {
            SampleTrajectory(angles, angles.start_time() + t - kRamp, q.data());
            SampleTrajectory(velocities, velocities.start_time() + t - kRamp, dq.data());
          }
          for (int i = 0; i < n; ++i)
            c.joint[i] = {shm::JointMode::kPosition, 0, q[i], dq[i], 0, gains.kp[i], gains.kd[i]};
          EXPECT_EQ(r.servo->Accept(c), 0);
        }
        r.servo->Apply(m, d);
        r.soft->ApplyBeforeStep(m, d);
      },
      [&] { r.soft->Commit(); }, r.soles);
  ExpectStable(res, duration, 0.05 * DivergenceWatch(m).margin());
  Note("false_positives_walk.txt",
       "HRP-1S playing the SamplePD walk " + Fmt("%.3g", duration) +
           " s: largest E - E(0) - W " + Fmt("%.3g", res.max_excess) + " J of the " +
           Fmt("%.4g", DivergenceWatch(m).margin()) + " J margin (W = " + Fmt("%.4g", res.work) +
           " J)");
  EXPECT_GT(d->xpos[3 * r.map.base_body + 2], 0.5) << "the robot fell";
  EXPECT_GT(d->xpos[3 * r.map.base_body + 0], 0.3) << "the robot did not walk";
}

}  // namespace
}  // namespace ohrp::sim::stability
