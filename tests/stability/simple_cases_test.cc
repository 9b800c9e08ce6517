// Hard cases on small models (mjcf/stability/): each runs a stable setting for a stated
// simulated time (finite, energy within its input work, no warning, a closed-form or sanity
// figure) and an unstable setting that the divergence watch must catch.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/soft_contact.h"
#include "stability_util.h"

namespace ohrp::sim::stability {
namespace {

constexpr double kG = 9.81;

//---------------- very stiff soft-foot springs at the largest step the check accepts ----------------

// the largest dt that contact::Validate accepts (bisection to 0.1 %)
double LargestAcceptedStep(const contact::SoftContactParams& p, double mass) {
  double lo = 1e-7, hi = 1e-1;
  std::string why;
  EXPECT_TRUE(contact::Validate(p, lo, mass, &why)) << why;
  EXPECT_FALSE(contact::Validate(p, hi, mass, &why));
  while (hi / lo > 1.001) {
    const double mid = std::sqrt(lo * hi);
    (contact::Validate(p, mid, mass, nullptr) ? lo : hi) = mid;
  }
  return lo;
}

TEST(Stability, StiffSoftFootStableAtTheLargestAcceptedStepAndRefusedOrDivergingBeyond) {
  ResetRows("stiff_soft_foot");
  const double mass = 10.001;  // [kg] block + sole
  contact::SoftContactParams p;
  p.stiffness = 1e8;  // [N/m] 33x the robot's sole: 1 um of sink for the block
  const double dt_max = LargestAcceptedStep(p, mass);
  const double duration = 1.0;  // [s]
  const double rest = mass * kG / p.stiffness;  // [m] static sink (linear spring)
  const std::string what = "soft sole k = 1e8 N/m under a 10 kg block";

  // drop: the height of the sole's bottom face above the floor at the start (< 0: sunk)
  auto run = [&](double dt, double claimed_mass, double drop, double* depth,
                 bool implicit = false) {
    auto sim = Sim::FromFile(Src("mjcf/stability/stiff_sole_block.xml"));
    EXPECT_TRUE(sim);
    sim->m()->opt.timestep = dt;
    sim->d()->qpos[2] += drop - 0.01;  // the model starts 1 cm up
    std::string error;
    auto soft = contact::SoftFootContact::Create(sim->m(), {"B_SOLE"}, {}, p, claimed_mass, &error);
    EXPECT_TRUE(soft) << error;
    soft->SetImplicit(implicit);  // the explicit law's limits, unless asked
    sim->context.soft = soft.get();
    sim->context.soft_mass_scale = mass;  // the real one, for the diagnosis
    const int block = mj_name2id(sim->m(), mjOBJ_BODY, "block");
    RunResult r = sim->Run(duration, [&] { soft->ApplyBeforeStep(sim->m(), sim->d()); },
                           [&] { soft->Commit(); }, {block});
    *depth = soft->wrenches()[0].depth;
    return r;
  };

  // stable at dt_max with the load the check assumes (<= 3 m g): set down at rest
  double depth = 0;
  RunResult stable = run(dt_max, mass, -rest, &depth);
  ExpectStable(stable, duration, 1e-6);
  EXPECT_NEAR(depth, rest, 0.02 * rest);
  WriteRow("stiff_soft_foot", what,
           "dt = " + Fmt("%.3g", dt_max) + " s (the largest Validate accepts), set down at rest",
           stable,
           "rest depth " + Fmt("%.4g", depth * 1e6) + " um vs m g/k = " + Fmt("%.4g", rest * 1e6) +
               " um");

  // 5 % beyond: refused, and the message says why and what works
  std::string why;
  EXPECT_FALSE(contact::Validate(p, 1.05 * dt_max, mass, &why, contact::StepScheme::kExplicit));
  EXPECT_NE(why.find("too stiff"), std::string::npos) << why;

  // the same accepted step with a 1 cm drop: the impact loads the sole ~140 m g, far beyond the
  // check's 3 m g, and the Hunt-Crossley damper's step number 2 dt c k delta / m passes 4
  RunResult dropped = run(dt_max, mass, 0.01, &depth);
  ExpectDetected(dropped, "soft-foot sole B_SOLE");
  WriteRow("stiff_soft_foot", what, "the same dt, dropped from 1 cm", dropped,
           "impact load ~ sqrt(2 k m g h) = " +
               Fmt("%.3g", std::sqrt(2 * p.stiffness * mass * kG * 0.01) / (mass * kG)) +
               " m g (the check assumes 3 m g)");

  // twice the step at rest: dt^2 k / m = 4x the accepted spring term, beyond the explicit
  // limit; forced through by claiming an 8x heavier block
  RunResult unstable = run(2 * dt_max, 8 * mass, -rest, &depth);
  ExpectDetected(unstable, "soft-foot sole B_SOLE");
  WriteRow("stiff_soft_foot", what,
           "dt = " + Fmt("%.3g", 2 * dt_max) + " s at rest (Validate refuses from " +
               Fmt("%.3g", 1.05 * dt_max) + " s; forced through)",
           unstable, "dt^2 k/m = " + Fmt("%.3g", 4 * dt_max * dt_max * p.stiffness / mass));

  // the implicit step (the default; its check accepts any step) holds both: the drop and the
  // doubled step settle. The drop's energy may exceed its start by ~1 % (measured 0.8 %) for a
  // step: the sole enters the floor unopposed for the part of the step after touching
  RunResult drop_i = run(dt_max, mass, 0.01, &depth, true);
  ExpectStable(drop_i, duration, 2e-2 * mass * kG * 0.01);
  WriteRow("stiff_soft_foot", what, "the same dt, dropped from 1 cm, implicit step", drop_i, "-");
  RunResult twice_i = run(2 * dt_max, mass, -rest, &depth, true);
  ExpectStable(twice_i, duration, 1e-6);
  EXPECT_NEAR(depth, rest, 0.02 * rest);
  WriteRow("stiff_soft_foot", what, "dt = " + Fmt("%.3g", 2 * dt_max) + " s at rest, implicit step",
           twice_i, "rest depth " + Fmt("%.4g", depth * 1e6) + " um");
}

//---------------- 1000:1 mass ratio stack ----------------

// sums the normal forces of the contacts between `body` and the world (the floor)
double FloorForce(const mjModel* m, const mjData* d) {
  double f_total = 0;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& con = d->contact[c];
    mjtNum f[6];
    mj_contactForce(m, d, c, f);
    if (m->geom_bodyid[con.geom1] == 0 || m->geom_bodyid[con.geom2] == 0) f_total += f[0];
  }
  return f_total;
}

TEST(Stability, MassRatioStackHoldsOnStiffImpedanceContactAndDivergesWithADirectStiffness) {
  ResetRows("mass_ratio");
  const double duration = 2.0, dt = 0.001;
  const double weight = 1001 * kG;
  auto load = [&](int setting) {
    auto sim = Sim::FromFile(Src("mjcf/stability/mass_ratio_stack.xml"));
    EXPECT_TRUE(sim);
    mjModel* m = sim->m();
    for (int g = 0; g < m->ngeom; ++g) {
      if (setting == 1) {  // sim_host's "rigid": time constant 2 steps, impedance 0.99..0.9999
        m->geom_solref[mjNREF * g] = 2 * dt;
        m->geom_solimp[mjNIMP * g] = 0.99;
        m->geom_solimp[mjNIMP * g + 1] = 0.9999;
      } else if (setting == 2) {  // a direct stiffness that holds the heavy box to 1 mm
        m->geom_solref[mjNREF * g] = -1e7;      // [N/m]
        m->geom_solref[mjNREF * g + 1] = -2e4;  // [N s/m]
      }
    }
    return sim;
  };
  auto sink = [](Sim* s) {
    const int heavy = mj_name2id(s->m(), mjOBJ_BODY, "heavy");
    return 0.15 - s->d()->xpos[3 * heavy + 2];
  };

  // stable: the stiff-impedance setting holds the 1000 kg box on the 1 kg one
  auto sim = load(1);
  RunResult r = sim->Run(duration);
  ExpectStable(r, duration, 0.01 * weight * 0.1);  // 1 % of the stack's weight x 10 cm
  const double floor = FloorForce(sim->m(), sim->d()), s1 = sink(sim.get());
  EXPECT_NEAR(floor, weight, 0.01 * weight) << "statics: the floor carries both boxes";
  EXPECT_LT(s1, 0.002) << "the heavy box sank into the light one";
  WriteRow("mass_ratio", "1000 kg box on a 1 kg box (native contact)",
           "solref 2 dt, solimp 0.99..0.9999 (sim_host's rigid contact), dt = 1 ms", r,
           "floor force " + Fmt("%.5g", floor) + " N vs (M+m) g = " + Fmt("%.5g", weight) +
               " N; heavy box sank " + Fmt("%.3g", s1 * 1e3) + " mm");

  // MuJoCo's default contact (solref 0.02, solimp 0.9..0.95) is finite and loses energy, so
  // no watch can call it diverged, but it is not plausible: the regulariser scales with the
  // light box's inverse mass and the heavy box crushes through it
  auto soft = load(0);
  RunResult r0 = soft->Run(duration);
  EXPECT_FALSE(r0.diverged) << r0.diagnosis.Text();
  const double s0 = sink(soft.get());
  EXPECT_GT(s0, 0.05) << "MuJoCo's defaults held the stack: this case's premise changed";
  WriteRow("mass_ratio", "1000 kg box on a 1 kg box (native contact)",
           "MuJoCo's default solref 0.02 s, solimp 0.9..0.95", r0,
           "**implausible**: the heavy box sank " + Fmt("%.3g", s0 * 1e3) +
               " mm, through the light box (finite, energy falling: not a divergence)");

  // unstable: a direct stiffness (solref < 0) of 1e7 N/m, sized for the heavy box, puts the
  // light box at omega dt = sqrt(1e7 / 1) * 1e-3 = 3.2 > 2
  auto bad = load(2);
  RunResult u = bad->Run(duration);
  ExpectDetected(u, "direct stiffness");
  EXPECT_EQ(u.diagnosis.kind, DivergenceKind::kEnergy);
  WriteRow("mass_ratio", "1000 kg box on a 1 kg box (native contact)",
           "direct stiffness solref -1e7 N/m, -2e4 N s/m", u,
           "omega dt of the light box = " + Fmt("%.3g", std::sqrt(1e7 / 1.0) * dt));
}

//---------------- high PD gains on light links ----------------

TEST(Stability, HighGainsOnLightLinksHoldWithTheImplicitIntegratorAndDivergeWithEuler) {
  ResetRows("pd_gains");
  const double duration = 2.0;
  auto sim = Sim::FromFile(Src("mjcf/stability/pd_light_arm.xml"));
  ASSERT_TRUE(sim);
  mjModel* m = sim->m();
  m->opt.integrator = mjINT_IMPLICIT;
  RunResult r = sim->Run(duration);
  // the actuators do work (input W); the rest of the energy must not grow
  ExpectStable(r, duration, 1e-3);
  // statics: kp e = gravity torque at the horizontal pose (links 50 g, 10 cm)
  const double kp = m->actuator_gainprm[0], mass = 0.05, l = 0.1;
  const double tau1 = mass * kG * (0.5 * l) + mass * kG * (1.5 * l);
  const double tau2 = mass * kG * (0.5 * l);
  const double q1 = sim->d()->qpos[0], q2 = sim->d()->qpos[1];
  // the axis is -y: gravity turns the links to negative q; e2 adds to link 2's angle
  EXPECT_NEAR(q1, -tau1 / kp, 0.05 * tau1 / kp);
  EXPECT_NEAR(q2, -tau2 / kp, 0.05 * tau2 / kp + 1e-4);
  const double inertia = sim->d()->qM[m->dof_Madr[1]];
  WriteRow("pd_gains", "2 light links (50 g), kp 50, kd 0.5",
           "implicit integrator, dt = 1 ms (kd taken implicitly)", r,
           "sag q1 " + Fmt("%.4g", q1) + " rad vs -tau_g/kp = " + Fmt("%.4g", -tau1 / kp) +
               "; 2 dt kd/I = " + Fmt("%.3g", 2 * 0.001 * 0.5 / inertia));

  auto bad = Sim::FromFile(Src("mjcf/stability/pd_light_arm.xml"));
  ASSERT_TRUE(bad);
  RunResult u = bad->Run(duration);
  ExpectDetected(u, "gain too high for the inertia");
  WriteRow("pd_gains", "2 light links (50 g), kp 50, kd 0.5", "Euler, dt = 1 ms", u, "-");
}

//---------------- a long chain ----------------

TEST(Stability, LongStiffChainConservesEnergyAtSmallStepsAndDivergesAtLarge) {
  ResetRows("long_chain");
  const double duration = 0.5;
  auto sim = Sim::FromFile(Src("mjcf/stability/chain120.xml"));
  ASSERT_TRUE(sim);
  ASSERT_EQ(sim->m()->nv, 120);
  RunResult r = sim->Run(duration);
  // passive: no input; the energy is conserved up to the step's error
  const double scale = 1.2 * kG * 0.6;  // M g L/2 [J]
  ExpectStable(r, duration, 0.02 * scale);
  EXPECT_GT(r.energy, r.energy0 - 0.05 * scale) << "the conservative chain lost energy";
  // sanity: the tip never farther from the anchor than the chain's length
  const int tip = sim->m()->nbody - 1;
  const double* p = sim->d()->xpos + 3 * tip;
  const double reach = std::sqrt(p[0] * p[0] + p[1] * p[1] + (p[2] - 1) * (p[2] - 1)) + 0.01;
  EXPECT_LE(reach, 1.2 + 1e-6);
  WriteRow("long_chain", "120-link cable, bending k 0.5 N m/rad", "Euler, dt = 0.2 ms", r,
           "abs(E - E(0)) = " + Fmt("%.3g", std::fabs(r.energy - r.energy0)) + " J of M g L/2 = " +
               Fmt("%.3g", scale) + " J");

  auto bad = Sim::FromFile(Src("mjcf/stability/chain120.xml"));
  ASSERT_TRUE(bad);
  bad->m()->opt.timestep = 0.002;
  RunResult u = bad->Run(duration);
  ExpectDetected(u, "joint spring");
  WriteRow("long_chain", "120-link cable, bending k 0.5 N m/rad", "Euler, dt = 2 ms", u, "-");
}

//---------------- a closed kinematic loop ----------------

TEST(Stability, ClosedLoopSwingsClosedAndLevelAndDivergesWithAnUnsafeConstraint) {
  ResetRows("closed_loop");
  const double duration = 3.0, theta0 = 1.0;  // [s], [rad] released from 57 degrees
  auto start = [&](Sim* s) {
    s->d()->qpos[0] = theta0;
    s->d()->qpos[1] = -theta0;
    s->d()->qpos[2] = theta0;
  };
  auto sim = Sim::FromFile(Src("mjcf/stability/four_bar.xml"));
  ASSERT_TRUE(sim);
  start(sim.get());
  const mjModel* m = sim->m();
  const int coupler = mj_name2id(m, mjOBJ_BODY, "coupler"), rocker = mj_name2id(m, mjOBJ_BODY, "rocker");
  double gap = 0, tilt = 0, lowest = 1;
  RunResult r = sim->Run(duration, {}, [&] {
    // loop closure: the coupler's far end against the rocker's end
    const mjData* d = sim->d();
    mjtNum a[3], b[3];
    const mjtNum pa[3] = {0.3, 0, 0}, pb[3] = {0, 0, -0.2};
    mju_rotVecMat(a, pa, d->xmat + 9 * coupler);
    mju_rotVecMat(b, pb, d->xmat + 9 * rocker);
    double e = 0;
    for (int k = 0; k < 3; ++k) {
      const double diff = d->xpos[3 * coupler + k] + a[k] - d->xpos[3 * rocker + k] - b[k];
      e += diff * diff;
    }
    gap = std::max(gap, std::sqrt(e));
    tilt = std::max(tilt, std::fabs(d->qpos[0] + d->qpos[1]));  // the coupler's pitch
    lowest = std::min(lowest, d->xpos[3 * coupler + 2]);
  });
  const double scale = 2 * kG * 0.2;  // the swing's mass x g x link length [J]
  ExpectStable(r, duration, 0.01 * scale);
  EXPECT_LT(gap, 1e-3) << "the loop opened";
  EXPECT_LT(tilt, 1e-2) << "a parallelogram keeps its coupler level";
  // energy: the swing never gets lower than the bottom (0.8 m) nor swings higher than released
  EXPECT_GE(lowest, 0.8 - 2e-3);
  WriteRow("closed_loop", "parallelogram four-bar (connect equality), released at 57 deg",
           "Euler, dt = 1 ms, default solref, refsafe on", r,
           "largest loop gap " + Fmt("%.3g", gap * 1e3) + " mm, coupler pitch " +
               Fmt("%.3g", tilt * 1e3) + " mrad");

  auto bad = Sim::FromFile(Src("mjcf/stability/four_bar.xml"));
  ASSERT_TRUE(bad);
  start(bad.get());
  bad->m()->opt.disableflags |= mjDSBL_REFSAFE;
  bad->m()->eq_solref[0] = 0.25 * 0.001;
  RunResult u = bad->Run(duration);
  ExpectDetected(u, "constraint");
  WriteRow("closed_loop", "parallelogram four-bar (connect equality), released at 57 deg",
           "equality solref time constant dt/4, refsafe off", u, "-");
}

//---------------- a high-speed impact ----------------

TEST(Stability, HighSpeedImpactOnSoftSoleStableAtSmallStepDivergesAtTheRecommendedOne) {
  ResetRows("impact");
  const double duration = 0.3, speed = 10;  // [s], [m/s] down
  const double mass = 10.001;
  contact::SoftContactParams p;  // the robot's sole stiffness, k 3e6 N/m, with c 10 s/m: the
  p.damping = 10;                // default 30 s/m is refused for 10 kg at 1 ms, 10 s/m passes
  auto run = [&](double dt, bool implicit = false) {
    auto sim = Sim::FromFile(Src("mjcf/stability/impact_block.xml"));
    EXPECT_TRUE(sim);
    sim->m()->opt.timestep = dt;
    std::string error;
    auto soft = contact::SoftFootContact::Create(sim->m(), {"B_SOLE"}, {}, p, mass, &error);
    EXPECT_TRUE(soft) << error;  // the parameter check accepts both steps
    if (!soft) return std::make_tuple(RunResult{}, 0.0, 0.0);
    soft->SetImplicit(implicit);  // the explicit law's limits, unless asked
    sim->context.soft = soft.get();
    sim->context.soft_mass_scale = mass;
    sim->d()->qvel[2] = -speed;
    const int block = mj_name2id(sim->m(), mjOBJ_BODY, "block");
    double rebound = 0, deepest = 0;
    RunResult r = sim->Run(duration, [&] { soft->ApplyBeforeStep(sim->m(), sim->d()); },
                           [&] {
                             soft->Commit();
                             rebound = std::max(rebound, sim->d()->qvel[2]);
                             deepest = std::max(deepest, soft->wrenches()[0].depth);
                           },
                           {block});
    return std::make_tuple(r, rebound, deepest);
  };
  auto [r, rebound, deepest] = run(2e-5);
  const double e_in = 0.5 * mass * speed * speed + mass * kG * 0.05;
  ExpectStable(r, duration, 1e-3 * e_in);
  // Hunt-Crossley at c v = 100 >> 1 is nearly plastic: the rebound is slow, never faster than
  // the impact, and the sole stops within the depth where k delta^2 / 2 absorbs the energy
  EXPECT_LT(rebound, 0.2 * speed);
  EXPECT_LT(deepest, std::sqrt(2 * e_in / p.stiffness));
  WriteRow("impact", "10 kg soft-sole block at 10 m/s (k 3e6, c 10)", "dt = 0.02 ms", r,
           "rebound " + Fmt("%.3g", rebound) + " m/s; deepest " + Fmt("%.3g", deepest * 1e3) +
               " mm < sqrt(2E/k) = " + Fmt("%.3g", std::sqrt(2 * e_in / p.stiffness) * 1e3) + " mm");

  auto [u, rebound_u, deepest_u] = run(1e-3);
  ExpectDetected(u, "soft-foot sole B_SOLE");
  WriteRow("impact", "10 kg soft-sole block at 10 m/s (k 3e6, c 10)",
           "dt = 1 ms, explicit (its check accepts it: it linearises at 3 m g, not at impacts)",
           u, "-");

  // the implicit step at 1 ms takes the impact as the fine step does
  // (energy excess 0.2 % at the entry step, as for the drop above)
  auto [w, rebound_w, deepest_w] = run(1e-3, true);
  ExpectStable(w, duration, 1e-2 * e_in);
  EXPECT_LT(rebound_w, 0.2 * speed);
  EXPECT_LT(deepest_w, std::sqrt(2 * e_in / p.stiffness));
  WriteRow("impact", "10 kg soft-sole block at 10 m/s (k 3e6, c 10)", "dt = 1 ms, implicit step",
           w, "rebound " + Fmt("%.3g", rebound_w) + " m/s; deepest " +
                  Fmt("%.3g", deepest_w * 1e3) + " mm");
}

}  // namespace
}  // namespace ohrp::sim::stability
