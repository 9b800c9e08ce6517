// The step's damping fold (sim_host/damping_fold.h): joint damping through the armature and
// qfrc_applied for the Euler step is MuJoCo's own implicit damping (closed form of a damped
// rotor; MuJoCo's mj_step on a damped chain under gravity, with passive forces on and off),
// and nothing outside the step sees it (model, qfrc_applied, the mass matrix).
#include "sim_host/damping_fold.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "../robot_model/test_models.h"
#include "sim_host/step.h"

namespace ohrp::sim {
namespace {

using model::testing::LoadString;

// a rotor, heavily damped for its step: h d / I = 0.8 (explicit damping would ring)
constexpr const char* kRotor = R"(
<mujoco model="rotor">
  <option timestep="0.01" integrator="Euler" gravity="0 0 0"/>
  <worldbody>
    <body name="rotor">
      <joint name="j" type="hinge" axis="0 0 1" armature="0.4" damping="40"/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>
    </body>
  </worldbody>
</mujoco>)";

// a chain under gravity: damped and undamped hinges, a damped slide, no limits
constexpr const char* kChain = R"(
<mujoco model="chain">
  <option timestep="0.002" integrator="Euler"/>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint name="ja" type="hinge" axis="0 1 0" damping="0.5"/>
      <inertial pos="0.2 0 0" mass="1" diaginertia="0.01 0.02 0.02"/>
      <body name="b" pos="0.4 0 0">
        <joint name="jb" type="hinge" axis="0 1 0"/>
        <inertial pos="0.15 0 0" mass="0.5" diaginertia="0.005 0.01 0.01"/>
        <body name="c" pos="0.3 0 0">
          <joint name="jc" type="hinge" axis="1 0 0" armature="0.01" damping="2"/>
          <joint name="sc" type="slide" axis="1 0 0" damping="5"/>
          <inertial pos="0.1 0 0.05" mass="0.3" diaginertia="0.002 0.003 0.003"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)";

struct Model {
  explicit Model(const char* xml) {
    std::string error;
    m = LoadString(xml, &error);
    EXPECT_TRUE(m) << error;
    d = mj_makeData(m);
  }
  ~Model() {
    mj_deleteData(d);
    mj_deleteModel(m);
  }
  mjModel* m = nullptr;
  mjData* d = nullptr;
};

// v_n = v0 (I / (I + h d))^n: the backward-Euler decay of a damped rotor, step by step
TEST(DampingFold, DampedRotorDecaysAsBackwardEuler) {
  Model r(kRotor);
  ASSERT_TRUE(r.m);
  mj_forward(r.m, r.d);
  const double inertia = r.d->qM[0], h = r.m->opt.timestep, damping = r.m->dof_damping[0];
  ASSERT_NEAR(inertia, 0.5, 1e-12);
  const double v0 = 2.0, ratio = inertia / (inertia + h * damping);
  r.d->qvel[0] = v0;
  PhysicsStep step(r.m, r.d, {});
  double q = 0, v = v0;
  for (int n = 1; n <= 50; ++n) {
    ASSERT_TRUE(step.Step());
    v *= ratio;
    q += h * v;
    ASSERT_NEAR(r.d->qvel[0], v, 1e-12 * v0) << "step " << n;
    ASSERT_NEAR(r.d->qpos[0], q, 1e-12) << "step " << n;
    // nothing outside the step sees the fold
    ASSERT_EQ(r.m->dof_damping[0], damping);
    ASSERT_EQ(r.m->dof_armature[0], 0.4);
    ASSERT_EQ(r.d->qfrc_applied[0], 0.0);
    ASSERT_NEAR(r.d->qM[0], inertia, 1e-15);
  }
  EXPECT_LT(r.d->qvel[0], 1e-10 * v0);  // and it did decay: 0.11^50
}

// The fold is MuJoCo's mj_step: a chain swinging under gravity with damped hinges and a damped
// slide, an external qfrc_applied that must survive, with passive forces on and off (then only
// the armature part acts, as in mj_Euler)
TEST(DampingFold, IsMujocosImplicitDampingOnAChain) {
  for (bool passive : {true, false}) {
    Model fold(kChain), ref(kChain);
    ASSERT_TRUE(fold.m && ref.m);
    for (Model* x : {&fold, &ref}) {
      if (!passive) x->m->opt.disableflags |= mjDSBL_PASSIVE;
      x->d->qpos[0] = 0.3;
      x->d->qvel[2] = 4.0;
      x->d->qfrc_applied[1] = 0.2;
    }
    PhysicsStep step(fold.m, fold.d, {});
    ASSERT_EQ(DampingFold(fold.m).dofs().size(), 3u);
    double worst = 0, worst_m = 0;
    for (int n = 0; n < 1000; ++n) {
      ASSERT_TRUE(step.Step());
      mj_step(ref.m, ref.d);
      for (int i = 0; i < fold.m->nv; ++i) {
        worst = std::max(worst, std::abs(fold.d->qpos[i] - ref.d->qpos[i]));
        worst = std::max(worst, fold.m->opt.timestep * std::abs(fold.d->qvel[i] - ref.d->qvel[i]));
      }
      for (int k = 0; k < fold.m->nM; ++k)
        worst_m = std::max(worst_m, std::abs(fold.d->qM[k] - ref.d->qM[k]));
      ASSERT_EQ(fold.d->qfrc_applied[1], 0.2);
      for (int i = 0; i < fold.m->nv; ++i) {
        ASSERT_EQ(fold.m->dof_damping[i], ref.m->dof_damping[i]);
        ASSERT_EQ(fold.m->dof_armature[i], ref.m->dof_armature[i]);
      }
    }
    EXPECT_LT(worst, 1e-9) << (passive ? "passive on" : "passive off");
    EXPECT_LT(worst_m, 1e-9) << (passive ? "passive on" : "passive off");
    // and the chain did swing and the damping did act
    EXPECT_GT(std::abs(fold.d->qpos[0] - 0.3), 0.1);
  }
}

// The comparisons above would also pass if the fold did nothing (MuJoCo integrates the damping
// itself then): with Euler, during the step MuJoCo must see no damping, the armature a + h d
// (dof_M0 too for a simple dof) and the force -d v in qfrc_applied, on top of what was there
TEST(DampingFold, EulerStepSeesNoDampingWhileFolded) {
  Model r(kRotor);
  ASSERT_TRUE(r.m);
  ASSERT_TRUE(r.m->dof_simplenum[0]);
  const double h = r.m->opt.timestep, a = r.m->dof_armature[0], d = r.m->dof_damping[0];
  const double m0 = r.m->dof_M0[0];
  r.d->qvel[0] = 2.0;
  r.d->qfrc_applied[0] = 0.25;
  DampingFold fold(r.m);
  ASSERT_TRUE(fold.Begin(r.m, r.d));
  EXPECT_EQ(r.m->dof_damping[0], 0.0);
  EXPECT_DOUBLE_EQ(r.m->dof_armature[0], a + h * d);
  EXPECT_DOUBLE_EQ(r.m->dof_M0[0], m0 + h * d);
  EXPECT_DOUBLE_EQ(r.d->qfrc_applied[0], 0.25 - d * 2.0);
  mj_step(r.m, r.d);
  fold.End(r.m, r.d);
  EXPECT_EQ(r.m->dof_damping[0], d);
  EXPECT_EQ(r.m->dof_armature[0], a);
  EXPECT_EQ(r.m->dof_M0[0], m0);
  EXPECT_EQ(r.d->qfrc_applied[0], 0.25);
}

// RK4 integrates damping its own way: the fold leaves it alone
TEST(DampingFold, LeavesRk4Alone) {
  Model r(kChain);
  ASSERT_TRUE(r.m);
  r.m->opt.integrator = mjINT_RK4;
  DampingFold fold(r.m);
  EXPECT_FALSE(fold.Begin(r.m, r.d));
  EXPECT_EQ(r.m->dof_damping[0], 0.5);
  fold.End(r.m, r.d);
  EXPECT_EQ(r.m->dof_armature[0], 0.0);
}

}  // namespace
}  // namespace ohrp::sim
