// The measuring machinery of bench_accuracy: the position metric, restarts from reference states
// (exact reproduction, and that the restored contact state matters), the convergence orders of
// Euler and RK4 on the pendulum chain, and the closed forms against their formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "accuracy.h"

namespace ohrp::accuracy {
namespace {

const std::string kSrc = OHRP_SOURCE_DIR;

// MuJoCo errors abort, and a warning during a test fails it.
class Accuracy : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model::InstallMujocoHandlers([](const char* msg) {
      std::fprintf(stderr, "MuJoCo error: %s\n", msg);
      std::abort();
    });
  }
  void SetUp() override { warnings_ = model::WarningCount(); }
  void TearDown() override {
    EXPECT_EQ(model::WarningCount(), warnings_) << "MuJoCo warning: " << model::LastWarning();
  }
  long warnings_ = 0;
};

SceneSpec Pendulum(double duration) {
  SceneSpec s;
  s.name = "pendulum";
  s.path = kSrc + "/mjcf/bench/pendulum_chain.xml";
  s.keyframe = "release";
  s.contacts = {Contact::kNone};
  s.duration = duration;
  return s;
}

SceneSpec Box(double duration) {
  SceneSpec s;
  s.name = "box";
  s.path = kSrc + "/mjcf/bench/box_slide.xml";
  s.keyframe = "drop";
  s.contacts = {Contact::kSoft, Contact::kNative, Contact::kRigid};
  s.geometries = {"box", "mesh8"};
  s.soles = {"box"};
  s.soft_mass = 60;
  s.duration = duration;
  return s;
}

SceneSpec Stand(double duration) {
  SceneSpec s;
  s.name = "hrp1s_stand";
  s.path = kSrc + "/mjcf/hrp1s/scene_flat.xml";
  s.keyframe = "halfsit";
  s.contacts = {Contact::kSoft};
  s.servo = true;
  s.soft_mass = 65.4;
  s.duration = duration;
  return s;
}

Setting RefSetting(Contact c, double dt = 1.0 / 16000) {
  Setting s;
  s.integrator = Integrator::kRK4;
  s.dt = dt;
  s.contact = c;
  s.iterations = 200;
  s.tolerance = 1e-12;
  return s;
}

TEST_F(Accuracy, PositionErrorIsTheMeanBodyDistance) {
  const std::vector<double> a = {0, 0, 0, 1, 2, 3};
  EXPECT_EQ(PositionError(a, a), 0.0);
  // body 1 moved by (3, 4, 0) mm, body 2 by (0, 0, 1) mm: mean of 5 mm and 1 mm
  const std::vector<double> b = {0.003, 0.004, 0, 1, 2, 3.001};
  EXPECT_NEAR(PositionError(a, b), 3e-3, 1e-15);
}

TEST_F(Accuracy, PendulumClosedFormPeriod) {
  // small amplitude: the exact period tends to the small-angle one times (1 + theta0^2 / 16)
  const double t0 = 2 * M_PI * std::sqrt(0.26 / (9.81 * 0.5));
  const double th = 0.01;
  EXPECT_NEAR(PendulumPeriod(0.26, 1, 9.81, 0.5, th), t0 * (1 + th * th / 16), 1e-9 * t0);
  // large amplitude, a known value: K(sin 45 deg) = 1.854074677 (theta0 = 90 deg)
  EXPECT_NEAR(PendulumPeriod(1, 1, 1, 1, M_PI / 2), 4 * 1.854074677301372, 1e-10);
}

// Restarting the reference's own setting from its states reproduces it: every state the
// integration depends on is restored (warm start, applied forces, soft-contact anchors).
TEST_F(Accuracy, RestartReproducesTheReference) {
  struct Case {
    SceneSpec scene;
    Contact contact;
  };
  const std::vector<Case> cases = {{Pendulum(0.128), Contact::kNone},
                                   {Box(0.192), Contact::kSoft},
                                   {Box(0.192), Contact::kNative},
                                   {Stand(0.064), Contact::kSoft}};
  for (const Case& c : cases) {
    Reference ref;
    std::string error;
    // a coarser reference step keeps the test short; the logic is the same
    ASSERT_TRUE(MakeReference(c.scene, RefSetting(c.contact, 0.25e-3), 0.016, &ref, &error))
        << error;
    const PieceResult r = RunPieces(c.scene, ref.setting, ref, 3, 2);
    std::printf("[%s %s] restart of the reference setting: pos error %.3e m, force error %.3e N\n",
                c.scene.name.c_str(), ContactName(c.contact), r.pos_error, r.force_error);
    EXPECT_FALSE(r.diverged) << r.note;
    EXPECT_LE(r.pos_error, 1e-12);
    EXPECT_LE(r.force_error, 1e-9);
    EXPECT_GT(r.sim_time, 0);
    EXPECT_GT(r.cpu, 0);
  }
}

// The soft contact's friction anchors are state: a restart that forgets them (anchors
// inactive) does not reproduce the standing robot, which the restart above does.
TEST_F(Accuracy, SoftContactAnchorsAreState) {
  const SceneSpec scene = Stand(0.064);
  Reference ref;
  std::string error;
  ASSERT_TRUE(MakeReference(scene, RefSetting(Contact::kSoft, 0.25e-3), 0.016, &ref, &error))
      << error;
  auto sim = Sim::Create(scene, ref.setting, &error);
  ASSERT_TRUE(sim) << error;
  Snapshot s = ref.states[1];
  ASSERT_TRUE(s.has_soft);
  int active = 0;
  for (auto& sole : s.soft.anchors)
    for (auto& a : sole) {
      active += a.active;
      a.active = false;
    }
  ASSERT_GT(active, 0) << "the standing robot should have stuck sample points";
  sim->Restore(s);
  const int spw = static_cast<int>(std::lround(0.016 / ref.setting.dt));
  sim->Advance(spw);
  std::vector<double> pos;
  sim->Positions(&pos);
  const double err = PositionError(pos, ref.positions[2]);
  std::printf("restart without the anchors: %.3e m after 16 ms\n", err);
  EXPECT_GT(err, 1e-9);
}

// Observed order log2(e(2h) / e(h)) on the pendulum chain (no contact): Euler ~1, RK4 ~4.
TEST_F(Accuracy, ConvergenceOrdersOnThePendulumChain) {
  const SceneSpec scene = Pendulum(0.512);
  Reference ref;
  std::string error;
  ASSERT_TRUE(MakeReference(scene, RefSetting(Contact::kNone), 0.016, &ref, &error)) << error;
  auto err = [&](Integrator in, double dt) {
    Setting s;
    s.integrator = in;
    s.dt = dt;
    s.contact = Contact::kNone;
    const PieceResult r = RunPieces(scene, s, ref, 4, 8);
    EXPECT_FALSE(r.diverged) << r.note;
    return r.pos_error;
  };
  const double e4 = err(Integrator::kEuler, 4e-3), e2 = err(Integrator::kEuler, 2e-3),
               e1 = err(Integrator::kEuler, 1e-3);
  const double r16 = err(Integrator::kRK4, 16e-3), r8 = err(Integrator::kRK4, 8e-3),
               r4 = err(Integrator::kRK4, 4e-3);
  const double pe1 = std::log2(e4 / e2), pe2 = std::log2(e2 / e1);
  const double pr1 = std::log2(r16 / r8), pr2 = std::log2(r8 / r4);
  std::printf("euler: %.3e %.3e %.3e m (orders %.2f %.2f); rk4: %.3e %.3e %.3e m (orders %.2f "
              "%.2f)\n", e4, e2, e1, pe1, pe2, r16, r8, r4, pr1, pr2);
  EXPECT_NEAR(pe1, 1.0, 0.25);
  EXPECT_NEAR(pe2, 1.0, 0.25);
  EXPECT_NEAR(pr1, 4.0, 0.7);
  EXPECT_NEAR(pr2, 4.0, 0.7);
  EXPECT_LT(r4, e1);  // RK4 at 4 ms beats Euler at 1 ms here
}

TEST_F(Accuracy, PendulumPeriodMeasured) {
  const double exact = PendulumPeriod(0.26, 1, 9.81, 0.5, 0.1);
  const std::string path = kSrc + "/mjcf/bench/pendulum_single.xml";
  Setting s;
  s.contact = Contact::kNone;
  s.integrator = Integrator::kRK4;
  s.dt = 1e-3;
  const double rk4 = MeasurePendulumPeriod(path, s, 3);
  s.integrator = Integrator::kEuler;
  const double eu1 = MeasurePendulumPeriod(path, s, 3);
  s.dt = 4e-3;
  const double eu4 = MeasurePendulumPeriod(path, s, 3);
  std::printf("period exact %.9f s; rk4 1 ms %.9f, euler 1 ms %.9f, euler 4 ms %.9f\n", exact,
              rk4, eu1, eu4);
  EXPECT_NEAR(rk4, exact, 1e-8 * exact);
  // symplectic Euler: phase error of second order, (omega h)^2 / 24 relative
  const double omega = 2 * M_PI / exact;
  EXPECT_NEAR(eu1, exact, 3 * std::pow(omega * 1e-3, 2) / 24 * exact + 1e-8);
  EXPECT_GT(std::fabs(eu4 - exact), 4 * std::fabs(eu1 - exact));
}

TEST_F(Accuracy, FreeFallClosedForm) {
  const SceneSpec box = Box(0.1);
  Setting s;
  s.contact = Contact::kNative;
  s.integrator = Integrator::kRK4;
  s.dt = 1e-3;
  double v = 0, x = 0;
  EXPECT_LT(FreeFallError(box, s, &v, &x), 1e-12);  // RK4 integrates a parabola exactly
  // semi-implicit Euler: z_n = z0 - g h^2 n (n + 1) / 2, off by g h t / 2
  s.integrator = Integrator::kEuler;
  EXPECT_NEAR(FreeFallError(box, s, &v, &x), 9.81 * 1e-3 * 0.096 / 2, 1e-12);
}

TEST_F(Accuracy, SoftFootClosedForms) {
  const SceneSpec box = Box(0.1);
  Setting s;
  s.contact = Contact::kSoft;
  s.integrator = Integrator::kEuler;
  s.dt = 0.25e-3;
  double v = 0, x = 0;
  std::string note;
  const double sink = StaticSink(box, s, &v, &x, &note);
  std::printf("static sink %.6e m, law %.6e m: %.3e relative %s\n", v, x, sink, note.c_str());
  // the block comes to rest where k delta^n = m g: only what is left of the settling after
  // 1.5 s remains (tests/contact/static_test states 1 % after 2 s on a tilted landing)
  EXPECT_LT(sink, 1e-6);
  const double e = Restitution(box, s, &v, &x, &note);
  std::printf("restitution %.5f, law %.5f: %.3e relative %s\n", v, x, e, note.c_str());
  EXPECT_LT(e, 2e-3);  // tests/contact/impact_test states 2 % at 0.1 ms
  // the law's own restitution, first order in c v for small c v: 1 - (2/3) c v
  EXPECT_NEAR(contact::HuntCrossleyRestitution(3e6, 1, 1, 60, 0.01, 1e-7), 1 - 2.0 / 3 * 0.01, 2e-4);
  // a step the contact's parameter check refuses is reported, not run (RK4: the law at its
  // stages is explicit; the implicit step of the other integrators takes any step)
  s.integrator = Integrator::kRK4;
  s.dt = 16e-3;
  note.clear();
  EXPECT_TRUE(std::isnan(StaticSink(box, s, &v, &x, &note)));
  EXPECT_NE(note.find("refused"), std::string::npos) << note;
}

TEST_F(Accuracy, BallRollsAtFiveSevenths) {
  SceneSpec ball;
  ball.name = "ball";
  ball.xml = BallXml();
  ball.keyframe = "slide";
  ball.contacts = {Contact::kNative};
  ball.geometries = {"sphere", "ico0", "ico1", "ico2", "ico3"};
  ball.soles = {"sphere"};
  Setting s;
  s.contact = Contact::kNative;
  s.dt = 1e-3;
  double v = 0, x = 0;
  const double e = RollingError(ball, s, &v, &x);
  std::printf("ball rolls at %.5f m/s, 5/7 v0 = %.5f\n", v, x);
  EXPECT_LT(e, 0.01 * x);  // MuJoCo's soft contact creeps a little
  EXPECT_NEAR(x, 2.0 * 5 / 7, 1e-12);
}

}  // namespace
}  // namespace ohrp::accuracy
