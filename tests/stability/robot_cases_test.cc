// Hard cases on the HRP-1S robot (mjcf/hrp1s): starting deep in the floor, standing on the
// rough floor and on the stairs, and the straight (singular) knee. Each runs a stable setting
// for a stated simulated time and an unstable one that the divergence watch must catch.
#include <gtest/gtest.h>

#include <cmath>

#include "stability_util.h"

namespace ohrp::sim::stability {
namespace {

constexpr double kG = 9.81;

double TotalSoleForce(const Robot& r) {
  double f = 0;
  for (const auto& w : r.soft->wrenches()) f += w.normal_force;
  return f;
}

// the base's tilt from upright [rad]
double Tilt(const mjData* d, int body) {
  const double* R = d->xmat + 9 * body;
  return std::acos(std::clamp(R[8], -1.0, 1.0));
}

// moves the robot's base by (dx, dy, dz) and recomputes the kinematics
void MoveBase(Robot& r, double dx, double dy, double dz) {
  double* q = r.sim->d()->qpos + r.map.base_qpos;
  q[0] += dx;
  q[1] += dy;
  q[2] += dz;
  mj_forward(r.sim->m(), r.sim->d());
}

// the lowest point of a sole box's bottom face (world z) and its centre
double SoleBottom(const Robot& r, const char* name, double centre[3]) {
  const mjModel* m = r.sim->m();
  const mjData* d = r.sim->d();
  const int g = mj_name2id(m, mjOBJ_GEOM, name);
  for (int k = 0; k < 3; ++k) centre[k] = d->geom_xpos[3 * g + k];
  return d->geom_xpos[3 * g + 2] - m->geom_size[3 * g + 2];
}

//---------------- a robot starting deep in the floor ----------------

TEST(StabilityRobot, DeepPenetrationRecoversOnNativeContactAndLaunchesAnElasticSoftSole) {
  ResetRows("deep_penetration");
  const double depth = 0.03, duration = 2.0;  // [m] soles 3 cm into the floor, [s]
  // stable: MuJoCo's contact recovers the overlap critically damped (solref 0.02 s)
  Robot r;
  LoadRobot(r, "mjcf/hrp1s/scene_flat.xml", "halfsit", {}, ContactModel::kNative);
  ASSERT_TRUE(r.sim);
  const double z_stand = r.sim->d()->qpos[r.map.base_qpos + 2];
  MoveBase(r, 0, 0, -depth);
  const double mass = r.map.total_mass;
  RunResult res = RunRobot(r, duration);
  // the overlap's push lifts the robot by `depth` (M g depth) and may leave some speed: allowed
  // twice that from the contact, the rest must come from the servo's work
  ExpectStable(res, duration, 2 * mass * kG * depth);
  const double z_end = r.sim->d()->qpos[r.map.base_qpos + 2];
  EXPECT_NEAR(z_end, z_stand, 0.005) << "back at its standing height";
  EXPECT_LT(Tilt(r.sim->d(), r.map.base_body), 0.05);
  WriteRow("deep_penetration", "HRP-1S half-sitting, soles 3 cm in the floor",
           "native contact (solref 0.02 s, critically damped)", res,
           "base at " + Fmt("%.4f", z_end) + " m vs " + Fmt("%.4f", z_stand) +
               " m standing; lift energy M g d = " + Fmt("%.3g", mass * kG * depth) + " J");

  // unstable: an elastic soft sole (damping 0, which the check accepts): the spring releases
  // k d^2 / 2 per sole, 1350 J each, into a jump
  contact::SoftContactParams elastic;
  elastic.damping = 0;
  Robot u;
  LoadRobot(u, "mjcf/hrp1s/scene_flat.xml", "halfsit", elastic);
  ASSERT_TRUE(u.sim);
  MoveBase(u, 0, 0, -depth);
  RunResult bad = RunRobot(u, duration);
  ExpectDetected(bad, "penetration");
  EXPECT_EQ(bad.diagnosis.kind, DivergenceKind::kEnergy);
  WriteRow("deep_penetration", "HRP-1S half-sitting, soles 3 cm in the floor",
           "soft soles, damping 0 (elastic)", bad,
           "k d^2/2 = " + Fmt("%.4g", 0.5 * elastic.stiffness * depth * depth) + " J per sole");
}

//---------------- the rough floor and the stairs ----------------

// Stands the robot for 2 s with its right sole's heel end at x = heel_x (facing +x, or -x when
// `turned`: then the heel end is the sole's +x end), the sole's centre at y = y_right, its
// bottom 1 mm above `top` [m]. The defaults hold it; soles far too stiff for the step diverge.
void StandOnTerrain(const std::string& file, const std::string& scene, const std::string& what,
                    double heel_x, double y_right, double top, bool turned) {
  ResetRows(file);
  const double duration = 2.0;
  auto place = [&](Robot& r) {
    if (turned) {  // yaw by pi about the base
      double* q = r.sim->d()->qpos + r.map.base_qpos;
      q[0] = -q[0];
      q[1] = -q[1];
      q[3] = 0, q[4] = 0, q[5] = 0, q[6] = 1;
      mj_forward(r.sim->m(), r.sim->d());
    }
    double c[3];
    const double bottom = SoleBottom(r, "RLEG_SOLE", c);
    const double half_length = r.sim->m()->geom_size[3 * mj_name2id(r.sim->m(), mjOBJ_GEOM, "RLEG_SOLE")];
    const double centre_x = turned ? heel_x - half_length : heel_x + half_length;
    MoveBase(r, centre_x - c[0], y_right - c[1], top + 0.001 - bottom);
  };
  Robot r;
  LoadRobot(r, scene, "halfsit");
  ASSERT_TRUE(r.sim);
  place(r);
  const double z0 = r.sim->d()->qpos[r.map.base_qpos + 2];
  RunResult res = RunRobot(r, duration);
  ExpectStable(res, duration, 5.0);
  const double weight = r.map.total_mass * kG;
  const double force = TotalSoleForce(r);
  const double tilt = Tilt(r.sim->d(), r.map.base_body);
  const double drop = z0 - r.sim->d()->qpos[r.map.base_qpos + 2];
  EXPECT_NEAR(force, weight, 0.02 * weight) << "at rest the soles carry the weight";
  EXPECT_LT(tilt, 0.15) << "the robot leans or fell";
  EXPECT_LT(drop, 0.03);
  const contact::SoftContactParams defaults;
  WriteRow(file, what,
           "soft soles, defaults (k " + Fmt("%.3g", defaults.stiffness) + " N/m, c " +
               Fmt("%.3g", defaults.damping) + " s/m), dt = 1 ms",
           res,
           "sole forces " + Fmt("%.5g", force) + " N vs M g = " + Fmt("%.5g", weight) +
               " N; base tilt " + Fmt("%.3g", tilt * 180 / M_PI) + " deg, sank " +
               Fmt("%.3g", drop * 1e3) + " mm");

  // unstable: the same contact at a 10 ms step with the explicit law held over the step. The
  // explicit check refuses it (the Hunt-Crossley term 2 dt c 3 g alone is 5.9 > 2); forced by
  // setting the step up after the contact was created for 1 ms
  const double big_dt = 0.01;
  std::string why;
  EXPECT_FALSE(contact::Validate({}, big_dt, 0.5 * r.map.total_mass, &why,
                                 contact::StepScheme::kExplicit));
  Robot u;
  LoadRobot(u, scene, "halfsit");
  ASSERT_TRUE(u.sim);
  place(u);
  u.sim->m()->opt.timestep = big_dt;
  u.soft->SetImplicit(false);
  RunResult bad = RunRobot(u, duration);
  ExpectDetected(bad, "soft-foot sole");
  WriteRow(file, what, "the same soles at dt = 10 ms, explicit (refused by its check, forced)",
           bad, "-");

  // the implicit step (the default, which accepts 10 ms) holds the robot there
  EXPECT_TRUE(contact::Validate({}, big_dt, 0.5 * r.map.total_mass, &why,
                                contact::StepScheme::kImplicit)) << why;
  Robot v;
  LoadRobot(v, scene, "halfsit");
  ASSERT_TRUE(v.sim);
  place(v);
  v.sim->m()->opt.timestep = big_dt;
  RunResult held = RunRobot(v, duration);
  ExpectStable(held, duration, 5.0);
  WriteRow(file, what, "the same soles at dt = 10 ms, implicit (accepted)", held,
           "base tilt " + Fmt("%.3g", Tilt(v.sim->d(), v.map.base_body) * 180 / M_PI) + " deg");
}

TEST(StabilityRobot, RoughFloorRightFootOnAStone) {
  // stone_0_0 of scene_rough.xml: 16 cm square, 5 mm high, x 0.47..0.63, y -0.48..-0.32. The
  // robot faces -x (towards the flat start area; facing +x its toes would land on the next row
  // of stones) with the heel end of its right sole 5 cm inside the stone's front edge: 11 cm of
  // the sole on the stone, the toes over the floor, the left sole on the floor 5 mm lower. (On
  // the 15 mm stone_0_2 the stiff-jointed robot, which has no balance control, topples.)
  StandOnTerrain("rough_floor", "mjcf/hrp1s/scene_rough.xml",
                 "HRP-1S facing -x, right heel 11 cm on a 5 mm stone, the rest on the floor", 0.58,
                 -0.4, 0.005, true);
}

TEST(StabilityRobot, StairsBothFeetOnTheFirstStep) {
  // step1 of scene_stairs.xml: tread 10 cm high from x = 0.5 to 0.8; both heels 1 cm inside
  // its edge. With the heel row of sample points over the edge, the next row (6.25 cm on)
  // leaves the centre of mass 6 mm inside the sampled support and the robot topples backwards
  // off the step (measured; a finer grid_x would be needed there)
  StandOnTerrain("stairs", "mjcf/hrp1s/scene_stairs.xml",
                 "HRP-1S on the first step (10 cm), heels 1 cm from its edge", 0.51, -0.09, 0.10,
                 false);
}

//---------------- the straight knee ----------------

// A crouch controller on both legs: the ankle should rise relative to the pelvis at `rate`
// [m/s]; the joint rates come from the plain inverse of the leg's sagittal Jacobian (hip pitch,
// knee; rows x and z), integrated into position references. With the knee straight the
// Jacobian is singular (both columns horizontal) and the inverse is infinite.
struct Crouch {
  struct Leg {
    int ankle = -1, hip_i = -1, knee_i = -1;
  };
  std::vector<Leg> legs;
  std::vector<double> q_ref, jac;
  double rate = 0.04;
  double sigma_min = 1e9;  // smallest singular value of the leg Jacobians seen [m]

  explicit Crouch(const Robot& r) {
    const mjModel* m = r.sim->m();
    for (const std::string side : {"RLEG", "LLEG"}) {
      Leg l;
      l.ankle = mj_name2id(m, mjOBJ_BODY, (side + "_ANKLE_P").c_str());
      for (size_t i = 0; i < r.map.joints.size(); ++i) {
        if (r.map.joints[i].name == side + "_HIP_P") l.hip_i = static_cast<int>(i);
        if (r.map.joints[i].name == side + "_KNEE") l.knee_i = static_cast<int>(i);
      }
      legs.push_back(l);
    }
    for (const auto& j : r.map.joints) q_ref.push_back(r.sim->d()->qpos[j.qpos_adr]);
    jac.resize(3 * m->nv);
  }
  void Update(const Robot& r) {
    const mjModel* m = r.sim->m();
    const mjData* d = r.sim->d();
    for (const Leg& l : legs) {
      const int hip = r.map.joints[l.hip_i].dof_adr, knee = r.map.joints[l.knee_i].dof_adr;
      mj_jacBody(m, d, jac.data(), nullptr, l.ankle);
      // the pelvis's own motion is in the free joint's columns; the leg's are these two
      const double a = jac[hip], b = jac[knee], c = jac[2 * m->nv + hip], e = jac[2 * m->nv + knee];
      const double tr = a * a + b * b + c * c + e * e, det = a * e - b * c;
      sigma_min = std::min(
          sigma_min, std::sqrt(std::max(0.0, 0.5 * (tr - std::sqrt(std::max(0.0, tr * tr - 4 * det * det))))));
      // J^-1 (0, rate): the plain inverse
      const double hip_rate = -b * rate / det, knee_rate = a * rate / det;
      q_ref[l.hip_i] += m->opt.timestep * hip_rate;
      q_ref[l.knee_i] += m->opt.timestep * knee_rate;
    }
  }
  shm::CommandBlock Commands(const Robot& r) const {
    shm::CommandBlock c{};
    c.njoint = static_cast<int>(q_ref.size());
    for (size_t i = 0; i < q_ref.size(); ++i) {
      const model::JointMap& j = r.map.joints[i];
      c.joint[i] = {shm::JointMode::kPosition, 0, q_ref[i], 0, 0, j.default_kp, j.default_kd};
    }
    return c;
  }
};

TEST(StabilityRobot, StraightKneeHoldsThroughTheServoAndANaiveInverseIntoCtrlIsCaught) {
  ResetRows("straight_knee");
  const double duration = 1.5;
  // stable: the naive controller's references go through sim_host's servo, which refuses the
  // non-finite ones joint by joint: the joints hold and the robot stands on straight knees
  Robot r;
  LoadRobot(r, "mjcf/hrp1s/scene_flat.xml", "");  // qpos0: every joint 0, knees straight
  ASSERT_TRUE(r.sim);
  const double z0 = r.sim->d()->qpos[r.map.base_qpos + 2];
  Crouch crouch(r);
  RunResult res = RunRobot(r, duration, [&] {
    crouch.Update(r);
    r.servo->Accept(crouch.Commands(r));
  });
  ExpectStable(res, duration, 5.0);
  EXPECT_LT(crouch.sigma_min, 1e-9) << "the straight leg's Jacobian is singular";
  EXPECT_GT(r.servo->rejected_total(), 0u) << "the servo refused the infinite references";
  const double weight = r.map.total_mass * kG, force = TotalSoleForce(r);
  EXPECT_NEAR(force, weight, 0.02 * weight);
  const double sank = z0 - r.sim->d()->qpos[r.map.base_qpos + 2];
  EXPECT_LT(std::fabs(sank), 0.005);
  WriteRow("straight_knee", "HRP-1S on straight knees, inverse-Jacobian crouch command",
           "references through sim_host's servo (refuses non-finite ones)", res,
           "leg Jacobian sigma_min " + Fmt("%.2g", crouch.sigma_min) + " m; " +
               std::to_string(r.servo->rejected_total()) + " joint commands refused; sole forces " +
               Fmt("%.5g", force) + " N vs M g " + Fmt("%.5g", weight) + " N");

  // unstable: the same controller writing its PD torques into d->ctrl itself
  Robot u;
  LoadRobot(u, "mjcf/hrp1s/scene_flat.xml", "");
  ASSERT_TRUE(u.sim);
  Crouch naive(u);
  mjModel* m = u.sim->m();
  mjData* d = u.sim->d();
  RunResult bad = u.sim->Run(
      duration,
      [&] {
        naive.Update(u);
        for (size_t i = 0; i < naive.q_ref.size(); ++i) {
          const model::JointMap& j = u.map.joints[i];
          d->ctrl[j.actuator_id] =
              j.default_kp * (naive.q_ref[i] - d->qpos[j.qpos_adr]) - j.default_kd * d->qvel[j.dof_adr];
        }
        u.soft->ApplyBeforeStep(m, d);
      },
      [&] { u.soft->Commit(); }, u.soles);
  ExpectDetected(bad, "non-finite or huge control");
  EXPECT_EQ(bad.diagnosis.kind, DivergenceKind::kNonFinite);
  EXPECT_NE(bad.diagnosis.what.find("ctrl"), std::string::npos) << bad.diagnosis.what;
  WriteRow("straight_knee", "HRP-1S on straight knees, inverse-Jacobian crouch command",
           "the same PD written into d->ctrl directly", bad, "-");
}

}  // namespace
}  // namespace ohrp::sim::stability
