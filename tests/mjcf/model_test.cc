// Tests of the HRP-1S-class MJCF model (mjcf/hrp1s/), generated from OpenHRP's SampleRobot
// (sample1.wrl; tests/robot_model/vrml_test.cc compares it with the VRML reader's robot). Every
// expected number below is read off the VRML file by hand, not from the generated XML.
#include <mujoco/mujoco.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

std::string g_warnings;

void OnMujocoError(const char* msg) {
  // MuJoCo's default handler waits for Enter on stdin; never return into MuJoCo either.
  std::fprintf(stderr, "MuJoCo error: %s\n", msg);
  std::abort();
}

void OnMujocoWarning(const char* msg) {
  g_warnings += msg;
  g_warnings += "\n";
}

const std::string kDir = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/";
const std::array<const char*, 4> kScenes = {"scene_flat.xml", "scene_slope.xml",
                                            "scene_rough.xml", "scene_stairs.xml"};

// jointId order of sample1.wrl (jointId 0..28)
const std::array<const char*, 29> kJoints = {
    "RLEG_HIP_R",      "RLEG_HIP_P",      "RLEG_HIP_Y",      "RLEG_KNEE",
    "RLEG_ANKLE_P",    "RLEG_ANKLE_R",    "RARM_SHOULDER_P", "RARM_SHOULDER_R",
    "RARM_SHOULDER_Y", "RARM_ELBOW",      "RARM_WRIST_Y",    "RARM_WRIST_P",
    "RARM_WRIST_R",    "LLEG_HIP_R",      "LLEG_HIP_P",      "LLEG_HIP_Y",
    "LLEG_KNEE",       "LLEG_ANKLE_P",    "LLEG_ANKLE_R",    "LARM_SHOULDER_P",
    "LARM_SHOULDER_R", "LARM_SHOULDER_Y", "LARM_ELBOW",      "LARM_WRIST_Y",
    "LARM_WRIST_P",    "LARM_WRIST_R",    "WAIST_P",         "WAIST_R",
    "CHEST"};

// Sum of the 30 Segment masses of sample1.wrl:
//   trunk  WAIST_LINK0 27 + WAIST_LINK1 6 + WAIST_LINK2 30 + WAIST_LINK3 13      = 76.0
//   arm    LINK1..7: 0.4 + 2.2 + 0.4 + 2.2 + 0.4 + 0.4 + 0.4 = 6.4, two arms      = 12.8
//   leg    LINK1..6: 2.5 + 2.0 + 5.1 + 7.0 + 2.5 + 1.9 = 21.0, two legs           = 42.0
//   total                                                                          = 130.8 kg
constexpr double kTotalMass = 76.0 + 12.8 + 42.0;
// mass of the link that carries each ankle force sensor (RLEG_LINK6 / LLEG_LINK6)
constexpr double kFootLinkMass = 1.9;
// WAIST Joint translation in the VRML; the kinematic chain below it puts the sole bottoms
// at 0.3535 + 0.3 + 0.07 = 0.7235 m below the WAIST origin
constexpr double kInitWaistZ = 0.7235;

struct Model {
  mjModel* m = nullptr;
  mjData* d = nullptr;
  std::string error;
  explicit Model(const std::string& file) {
    char err[1000] = "";
    m = mj_loadXML(file.c_str(), nullptr, err, sizeof(err));
    error = err;
    if (m) d = mj_makeData(m);
  }
  ~Model() {
    if (d) mj_deleteData(d);
    if (m) mj_deleteModel(m);
  }
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
};

class HrpModel : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mju_user_error = OnMujocoError;
    mju_user_warning = OnMujocoWarning;
  }
  void SetUp() override { g_warnings.clear(); }
};

int Id(const mjModel* m, mjtObj type, const char* name) { return mj_name2id(m, type, name); }

// lowest z of a box geom (world frame)
double BoxBottom(const mjModel* m, const mjData* d, int g) {
  const mjtNum* R = d->geom_xmat + 9 * g;
  const mjtNum* s = m->geom_size + 3 * g;
  return d->geom_xpos[3 * g + 2] -
         (std::fabs(R[6]) * s[0] + std::fabs(R[7]) * s[1] + std::fabs(R[8]) * s[2]);
}

// sensor vector rotated from the site frame into the world frame
std::array<double, 3> SensorWorld(const mjModel* m, const mjData* d, const char* sensor) {
  int s = Id(m, mjOBJ_SENSOR, sensor);
  std::array<double, 3> w{0, 0, 0};
  if (s < 0) return w;
  int site = m->sensor_objid[s];
  const mjtNum* R = d->site_xmat + 9 * site;
  const mjtNum* v = d->sensordata + m->sensor_adr[s];
  for (int i = 0; i < 3; ++i) w[i] = R[3 * i] * v[0] + R[3 * i + 1] * v[1] + R[3 * i + 2] * v[2];
  return w;
}

TEST_F(HrpModel, EverySceneAndTheRobotAloneLoad) {
  std::vector<std::string> files(kScenes.begin(), kScenes.end());
  files.push_back("hrp1s.xml");
  for (const auto& f : files) {
    Model mm(kDir + f);
    ASSERT_NE(mm.m, nullptr) << f << ": " << mm.error;
    EXPECT_EQ(mm.error, "") << f;
    EXPECT_EQ(mm.m->nu, 29) << f;
    EXPECT_EQ(mm.m->nq, 7 + 29) << f;
    EXPECT_EQ(mm.m->nkey, f == "scene_slope.xml" ? 3 : 2) << f;  // + halfsit_ramp
    EXPECT_EQ(mm.m->opt.timestep, 0.001) << f;
    EXPECT_EQ(mm.m->opt.integrator, mjINT_EULER) << f;
  }
  EXPECT_EQ(g_warnings, "");
}

TEST_F(HrpModel, ActuatorsAreTheJointsInJointIdOrder) {
  Model mm(kDir + "scene_flat.xml");
  ASSERT_NE(mm.m, nullptr) << mm.error;
  const mjModel* m = mm.m;
  ASSERT_EQ(m->nu, 29);
  for (int i = 0; i < 29; ++i) {
    SCOPED_TRACE(kJoints[i]);
    const char* an = mj_id2name(m, mjOBJ_ACTUATOR, i);
    ASSERT_NE(an, nullptr);
    EXPECT_STREQ(an, kJoints[i]);
    EXPECT_EQ(m->actuator_trntype[i], mjTRN_JOINT);
    int j = m->actuator_trnid[2 * i];
    EXPECT_STREQ(mj_id2name(m, mjOBJ_JOINT, j), kJoints[i]);
    EXPECT_EQ(m->jnt_type[j], mjJNT_HINGE);
    EXPECT_EQ(m->actuator_gear[6 * i], 1.0);
    EXPECT_EQ(m->actuator_ctrllimited[i], 1);
    EXPECT_EQ(m->actuator_forcelimited[i], 1);
    double lo = m->actuator_ctrlrange[2 * i], hi = m->actuator_ctrlrange[2 * i + 1];
    EXPECT_EQ(lo, -hi);
    EXPECT_GE(hi, 50.0);
    EXPECT_LE(hi, 600.0);
    EXPECT_EQ(m->actuator_forcerange[2 * i + 1], hi);
    // armature = rotorInertia 3e-4 * gearRatio 200^2
    EXPECT_NEAR(m->dof_armature[m->jnt_dofadr[j]], 3e-4 * 200 * 200, 1e-9);
    EXPECT_LE(m->dof_damping[m->jnt_dofadr[j]], 0.1);
    EXPECT_EQ(m->jnt_stiffness[j], 0.0);
    EXPECT_EQ(m->jnt_limited[j], 1);
    EXPECT_LT(m->jnt_range[2 * j], 0.0);
    EXPECT_GT(m->jnt_range[2 * j + 1], 0.0);
  }
  // a few joint facts straight from the VRML
  auto range = [&](const char* n, int k) { return m->jnt_range[2 * Id(m, mjOBJ_JOINT, n) + k]; };
  EXPECT_NEAR(range("LARM_SHOULDER_P", 0), -3.14159, 1e-9);
  EXPECT_NEAR(range("LARM_SHOULDER_P", 1), 1.5708, 1e-9);
  EXPECT_NEAR(range("RARM_WRIST_R", 0), -0.122173, 1e-9);
  EXPECT_NEAR(range("RARM_WRIST_R", 1), 1.309, 1e-9);
  const double* ax = m->jnt_axis + 3 * Id(m, mjOBJ_JOINT, "CHEST");  // default jointAxis z
  EXPECT_EQ(ax[2], 1.0);
  ax = m->jnt_axis + 3 * Id(m, mjOBJ_JOINT, "RLEG_HIP_R");
  EXPECT_EQ(ax[0], 1.0);
  // free root
  int root = Id(m, mjOBJ_JOINT, "root");
  ASSERT_GE(root, 0);
  EXPECT_EQ(m->jnt_type[root], mjJNT_FREE);
  EXPECT_STREQ(mj_id2name(m, mjOBJ_BODY, m->jnt_bodyid[root]), "WAIST");
  EXPECT_EQ(m->body_parentid[m->jnt_bodyid[root]], 0);
}

TEST_F(HrpModel, TotalMassIsTheVrmlSum) {
  for (const char* f : kScenes) {
    Model mm(kDir + f);
    ASSERT_NE(mm.m, nullptr) << mm.error;
    EXPECT_NEAR(mj_getTotalmass(mm.m), kTotalMass, 1e-6) << f;
  }
  Model mm(kDir + "scene_flat.xml");
  const mjModel* m = mm.m;
  int foot = Id(m, mjOBJ_BODY, "RLEG_ANKLE_R");
  ASSERT_GE(foot, 0);
  EXPECT_NEAR(m->body_mass[foot], kFootLinkMass, 1e-12);
  // RLEG_LINK6: centerOfMass 0.080 0 -0.03, momentsOfInertia diag 0.005291 0.012084 0.013
  EXPECT_NEAR(m->body_ipos[3 * foot], 0.08, 1e-12);
  EXPECT_NEAR(m->body_ipos[3 * foot + 2], -0.03, 1e-12);
  EXPECT_NEAR(m->body_inertia[3 * foot], 0.005291, 1e-9);
  EXPECT_NEAR(m->body_inertia[3 * foot + 1], 0.012084, 1e-9);
  EXPECT_NEAR(m->body_inertia[3 * foot + 2], 0.013, 1e-9);
}

TEST_F(HrpModel, SensorsCamerasAndSitesExist) {
  Model mm(kDir + "scene_flat.xml");
  ASSERT_NE(mm.m, nullptr) << mm.error;
  const mjModel* m = mm.m;
  for (int i = 0; i < 29; ++i) {
    std::string j = kJoints[i];
    int s = Id(m, mjOBJ_SENSOR, ("q_" + j).c_str());
    ASSERT_GE(s, 0) << j;
    EXPECT_EQ(m->sensor_type[s], mjSENS_JOINTPOS);
    EXPECT_STREQ(mj_id2name(m, mjOBJ_JOINT, m->sensor_objid[s]), j.c_str());
    s = Id(m, mjOBJ_SENSOR, ("dq_" + j).c_str());
    ASSERT_GE(s, 0) << j;
    EXPECT_EQ(m->sensor_type[s], mjSENS_JOINTVEL);
    s = Id(m, mjOBJ_SENSOR, ("tau_" + j).c_str());
    ASSERT_GE(s, 0) << j;
    EXPECT_EQ(m->sensor_type[s], mjSENS_ACTUATORFRC);
    EXPECT_EQ(m->sensor_objid[s], i);
  }
  struct FS {
    const char* name;
    const char* body;
  };
  // ankles first, then wrists
  const FS fs[] = {{"rfsensor", "RLEG_ANKLE_R"},
                   {"lfsensor", "LLEG_ANKLE_R"},
                   {"rhsensor", "RARM_WRIST_P"},
                   {"lhsensor", "LARM_WRIST_P"}};
  int prev = -1;
  for (const auto& f : fs) {
    int site = Id(m, mjOBJ_SITE, f.name);
    ASSERT_GE(site, 0) << f.name;
    EXPECT_STREQ(mj_id2name(m, mjOBJ_BODY, m->site_bodyid[site]), f.body);
    int sf = Id(m, mjOBJ_SENSOR, (std::string(f.name) + "_f").c_str());
    int st = Id(m, mjOBJ_SENSOR, (std::string(f.name) + "_t").c_str());
    ASSERT_GE(sf, 0) << f.name;
    ASSERT_GE(st, 0) << f.name;
    EXPECT_EQ(m->sensor_type[sf], mjSENS_FORCE);
    EXPECT_EQ(m->sensor_type[st], mjSENS_TORQUE);
    EXPECT_EQ(m->sensor_objid[sf], site);
    EXPECT_EQ(m->sensor_objid[st], site);
    EXPECT_GT(sf, prev);
    EXPECT_EQ(st, sf + 1);
    prev = st;
  }
  // ankle sensors 0.07 m under the ankle joint (VRML ForceSensor translation 0 0 -0.07)
  EXPECT_NEAR(m->site_pos[3 * Id(m, mjOBJ_SITE, "rfsensor") + 2], -0.07, 1e-12);
  int imu = Id(m, mjOBJ_SITE, "imu");
  ASSERT_GE(imu, 0);
  EXPECT_STREQ(mj_id2name(m, mjOBJ_BODY, m->site_bodyid[imu]), "CHEST");
  const struct {
    const char* name;
    int type;
  } imus[] = {{"gyrometer", mjSENS_GYRO},
              {"gsensor", mjSENS_ACCELEROMETER},
              {"imu_quat", mjSENS_FRAMEQUAT}};
  for (const auto& s : imus) {
    int id = Id(m, mjOBJ_SENSOR, s.name);
    ASSERT_GE(id, 0) << s.name;
    EXPECT_EQ(m->sensor_type[id], s.type);
    EXPECT_EQ(m->sensor_objid[id], imu);
  }
  for (const char* cam : {"LeftCamera", "RightCamera"}) {
    int c = Id(m, mjOBJ_CAMERA, cam);
    ASSERT_GE(c, 0) << cam;
    EXPECT_STREQ(mj_id2name(m, mjOBJ_BODY, m->cam_bodyid[c]), "CHEST");
    EXPECT_NEAR(m->cam_fovy[c], 45.0, 1e-3);  // fieldOfView default 0.785398 rad
  }
  // cameras at VISION_SENSOR translation (0.15, +-0.05, 0.15), looking forward and 30 deg down
  mjData* d = mm.d;
  mj_forward(m, d);
  int lc = Id(m, mjOBJ_CAMERA, "LeftCamera");
  const mjtNum* R = d->cam_xmat + 9 * lc;
  EXPECT_NEAR(-R[2], std::cos(M_PI / 6), 1e-3);   // view direction = -z column, x part
  EXPECT_NEAR(-R[8], -std::sin(M_PI / 6), 1e-3);  // z part
  EXPECT_GT(R[7], 0.8);                           // camera up (y) points up
  EXPECT_NEAR(m->cam_pos[3 * lc + 1], 0.05, 1e-12);
  // only the sole boxes can collide
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == 0) continue;
    const char* n = mj_id2name(m, mjOBJ_GEOM, g);
    bool sole = n && (!std::strcmp(n, "RLEG_SOLE") || !std::strcmp(n, "LLEG_SOLE"));
    EXPECT_EQ(m->geom_contype[g] != 0 || m->geom_conaffinity[g] != 0, sole) << g;
  }
}

TEST_F(HrpModel, SolesOnTheFloorInTheInitPose) {
  Model mm(kDir + "scene_flat.xml");
  ASSERT_NE(mm.m, nullptr) << mm.error;
  const mjModel* m = mm.m;
  mjData* d = mm.d;
  mj_resetData(m, d);
  for (int i = 7; i < m->nq; ++i) EXPECT_EQ(d->qpos[i], 0.0);
  EXPECT_NEAR(d->qpos[2], kInitWaistZ, 1e-9);
  mj_forward(m, d);
  for (const char* sole : {"RLEG_SOLE", "LLEG_SOLE"}) {
    int g = Id(m, mjOBJ_GEOM, sole);
    ASSERT_GE(g, 0) << sole;
    EXPECT_EQ(m->geom_type[g], mjGEOM_BOX);
    EXPECT_NEAR(BoxBottom(m, d, g), 0.0, 1e-3) << sole;
    EXPECT_GE(BoxBottom(m, d, g), -1e-6) << sole;
  }
  int key = Id(m, mjOBJ_KEY, "init");
  ASSERT_GE(key, 0);
  for (int i = 0; i < m->nq; ++i) EXPECT_NEAR(m->key_qpos[key * m->nq + i], m->qpos0[i], 1e-9);
}

TEST_F(HrpModel, HalfsitKeySitsOnTheFloor) {
  Model mm(kDir + "scene_flat.xml");
  ASSERT_NE(mm.m, nullptr) << mm.error;
  const mjModel* m = mm.m;
  mjData* d = mm.d;
  int key = Id(m, mjOBJ_KEY, "halfsit");
  ASSERT_GE(key, 0);
  mj_resetDataKeyframe(m, d, key);
  // qpos is in tree order, not jointId order: look the joints up by name
  auto q = [&](const char* n) { return d->qpos[m->jnt_qposadr[Id(m, mjOBJ_JOINT, n)]]; };
  for (const char* side : {"R", "L"}) {
    std::string s(side);
    EXPECT_NEAR(q((s + "LEG_HIP_P").c_str()), -0.35, 1e-9);
    EXPECT_NEAR(q((s + "LEG_KNEE").c_str()), 0.70, 1e-9);
    EXPECT_NEAR(q((s + "LEG_ANKLE_P").c_str()), -0.35, 1e-9);
    EXPECT_NEAR(q((s + "ARM_SHOULDER_P").c_str()), 0.17, 1e-9);
    EXPECT_NEAR(q((s + "ARM_ELBOW").c_str()), -0.52, 1e-9);
  }
  EXPECT_NEAR(q("RARM_SHOULDER_R"), -0.17, 1e-9);  // away from the body
  EXPECT_NEAR(q("LARM_SHOULDER_R"), 0.17, 1e-9);
  // hip-to-ankle 0.6535 m, thigh and shank both at 0.35 rad: drop = 0.6535 (1 - cos 0.35)
  EXPECT_NEAR(d->qpos[2], kInitWaistZ - 0.6535 * (1 - std::cos(0.35)), 1e-6);
  mj_forward(m, d);
  for (const char* sole : {"RLEG_SOLE", "LLEG_SOLE"}) {
    int g = Id(m, mjOBJ_GEOM, sole);
    EXPECT_NEAR(BoxBottom(m, d, g), 0.0, 1e-3) << sole;
    const mjtNum* R = d->geom_xmat + 9 * g;
    EXPECT_NEAR(R[8], 1.0, 1e-6) << sole << " not flat";
  }
}

// Hold a pose for 1 s with PD (kp 5000, kd 100) at 1 ms Euler steps; the robot must neither
// sink nor float, and the ankle force sensors must carry its weight.
void StandStill(const char* scene, const char* keyname) {
  SCOPED_TRACE(std::string(scene) + " / " + keyname);
  Model mm(kDir + scene);
  ASSERT_NE(mm.m, nullptr) << mm.error;
  mjModel* m = mm.m;
  mjData* d = mm.d;
  ASSERT_EQ(m->opt.timestep, 0.001);
  ASSERT_EQ(m->opt.integrator, mjINT_EULER);
  int key = Id(m, mjOBJ_KEY, keyname);
  ASSERT_GE(key, 0);
  mj_resetDataKeyframe(m, d, key);
  std::vector<double> qref(m->nu);
  for (int i = 0; i < m->nu; ++i) qref[i] = d->qpos[m->jnt_qposadr[m->actuator_trnid[2 * i]]];
  const double z0 = d->qpos[2];
  const int steps = 1000;
  for (int k = 0; k < steps; ++k) {
    for (int i = 0; i < m->nu; ++i) {
      int j = m->actuator_trnid[2 * i];
      d->ctrl[i] = 5000.0 * (qref[i] - d->qpos[m->jnt_qposadr[j]]) -
                   100.0 * d->qvel[m->jnt_dofadr[j]];
    }
    mj_step(m, d);
  }
  mj_forward(m, d);  // sensors consistent with the final state
  EXPECT_NEAR(d->time, 1.0, 1e-9);
  EXPECT_LT(std::fabs(d->qpos[2] - z0), 0.02) << "root z " << z0 << " -> " << d->qpos[2];
  // still upright and in place
  EXPECT_GT(d->qpos[3], 0.999);
  EXPECT_LT(std::hypot(d->qpos[0], d->qpos[1]), 0.02);

  // every contact is sole-vs-environment
  int rs = Id(m, mjOBJ_GEOM, "RLEG_SOLE"), ls = Id(m, mjOBJ_GEOM, "LLEG_SOLE");
  EXPECT_GT(d->ncon, 0);
  for (int c = 0; c < d->ncon; ++c) {
    int g1 = d->contact[c].geom1, g2 = d->contact[c].geom2;
    bool sole1 = g1 == rs || g1 == ls, sole2 = g2 == rs || g2 == ls;
    EXPECT_TRUE(sole1 != sole2) << "contact " << g1 << "-" << g2;
    EXPECT_EQ(m->geom_bodyid[sole1 ? g2 : g1], 0);
  }

  // MuJoCo's <force> sensor reads cfrc_int of the sensor's body (RLEG_ANKLE_R): the force the
  // parent (ankle-pitch link) exerts on the foot link, in the site frame. Standing, the
  // parent pushes the foot DOWN onto the floor, so the world-z component is negative, and
  // its size is the weight above the sensor: the total weight minus the two foot links
  // below the sensors (the foot's own weight goes straight from the foot into the floor).
  const double g = -m->opt.gravity[2];
  auto fr = SensorWorld(m, d, "rfsensor_f");
  auto fl = SensorWorld(m, d, "lfsensor_f");
  const double fz = fr[2] + fl[2];
  const double expected = (kTotalMass - 2 * kFootLinkMass) * g;  // 127.0 kg * g
  EXPECT_LT(fz, 0.0) << "sign convention changed";
  EXPECT_NEAR(-fz, expected, 0.03 * expected) << "ankle force sum " << fz;
  // the same check with the ground reaction: sensors + foot weights = m g
  EXPECT_NEAR(-fz + 2 * kFootLinkMass * g, kTotalMass * g, 0.03 * kTotalMass * g);
  // both feet carry load
  EXPECT_LT(fr[2], -0.2 * expected);
  EXPECT_LT(fl[2], -0.2 * expected);

  // the IMU reads +g along its z (site axes = CHEST axes) and an identity orientation
  int acc = Id(m, mjOBJ_SENSOR, "gsensor");
  const mjtNum* a = d->sensordata + m->sensor_adr[acc];
  EXPECT_NEAR(a[2], g, 0.05 * g);
  EXPECT_LT(std::hypot(a[0], a[1]), 0.05 * g);
  const mjtNum* qimu = d->sensordata + m->sensor_adr[Id(m, mjOBJ_SENSOR, "imu_quat")];
  EXPECT_GT(std::fabs(qimu[0]), 0.999);
  EXPECT_EQ(g_warnings, "");
}

TEST_F(HrpModel, StandsStillOnFlatFloorInInitPose) { StandStill("scene_flat.xml", "init"); }
TEST_F(HrpModel, StandsStillOnFlatFloorInHalfsit) { StandStill("scene_flat.xml", "halfsit"); }
TEST_F(HrpModel, StandsStillAtTheStartOfTheOtherScenes) {
  StandStill("scene_slope.xml", "init");
  StandStill("scene_rough.xml", "init");
  StandStill("scene_stairs.xml", "init");
}

}  // namespace
