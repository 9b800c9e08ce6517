// Tests the VRML reader (vrml/vrml.h): OpenHRP's sample1.wrl gives the robot of
// mjcf/hrp1s/hrp1s.xml (bodies, joints, inertias, actuators, sensors, sites, cameras, keyframes,
// the model hash), sample1_bush.wrl its bush joints as spring-dampers, the other samples and the
// floors load, a scene Inlines a robot and a floor, and malformed text gets file:line:column.
#include "common/scratch.h"
#include "vrml/vrml.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>

#include "robot_model/kinematics.h"
#include "robot_model/model.h"
#include "robot_model/model_hash.h"

namespace ohrp::vrml {
namespace {

// OpenHRP's samples beside the repository, as the other tests reach them
const std::string kSamples = std::string(OHRP_SOURCE_DIR) + "/../shared/external/openhrp3-sample/";
const std::string kRobotDir = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/";

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

ModelPtr LoadVrml(const std::string& path) {
  std::string error;
  ModelPtr m(LoadModel(path, &error));
  EXPECT_TRUE(m) << error;
  return m;
}

ModelPtr LoadMjcf(const std::string& path) {
  char err[1024] = "";
  ModelPtr m(mj_loadXML(path.c_str(), nullptr, err, sizeof err));
  EXPECT_TRUE(m) << err;
  return m;
}

using ohrp::testing::ReadFile;

std::string Name(const mjModel* m, int type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : "";
}

// element-wise comparison of two arrays of n numbers
void ExpectNear(const mjtNum* a, const mjtNum* b, int n, double tol, const std::string& what) {
  for (int k = 0; k < n; ++k) EXPECT_NEAR(a[k], b[k], tol) << what << "[" << k << "]";
}

// a quaternion and its negative are the same rotation
void ExpectSameRotation(const mjtNum* a, const mjtNum* b, double tol, const std::string& what) {
  const double dot = std::fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  EXPECT_NEAR(dot, 1.0, tol) << what;
}

// stated tolerances: positions and inertias are written with 9 significant digits by both
constexpr double kLength = 1e-9;    // [m]
constexpr double kMass = 1e-9;      // [kg]
constexpr double kInertia = 1e-9;   // [kg m^2]
constexpr double kRotation = 1e-9;  // |q1.q2| against 1
constexpr double kAngle = 1e-6;     // keyframe joint angles and heights [rad, m]

//---------------- sample1.wrl is hrp1s.xml ----------------

class Sample1 : public ::testing::Test {
 protected:
  void SetUp() override {
    vrml_ = LoadVrml(kSamples + "sample1.wrl");
    mjcf_ = LoadMjcf(kRobotDir + "hrp1s.xml");
    ASSERT_TRUE(vrml_ && mjcf_);
  }
  ModelPtr vrml_, mjcf_;
};

TEST_F(Sample1, BodiesHaveTheSameTreePosesAndInertias) {
  const mjModel* a = vrml_.get();
  const mjModel* b = mjcf_.get();
  ASSERT_EQ(a->nbody, b->nbody);
  for (int i = 1; i < a->nbody; ++i) {
    const std::string name = Name(a, mjOBJ_BODY, i);
    SCOPED_TRACE(name);
    EXPECT_EQ(name, Name(b, mjOBJ_BODY, i));
    EXPECT_EQ(Name(a, mjOBJ_BODY, a->body_parentid[i]), Name(b, mjOBJ_BODY, b->body_parentid[i]));
    ExpectNear(a->body_pos + 3 * i, b->body_pos + 3 * i, 3, kLength, "pos");
    ExpectSameRotation(a->body_quat + 4 * i, b->body_quat + 4 * i, kRotation, "quat");
    EXPECT_NEAR(a->body_mass[i], b->body_mass[i], kMass);
    ExpectNear(a->body_ipos + 3 * i, b->body_ipos + 3 * i, 3, kLength, "ipos");
    ExpectNear(a->body_inertia + 3 * i, b->body_inertia + 3 * i, 3, kInertia, "inertia");
  }
}

TEST_F(Sample1, JointsHaveTheSameOrderAxesLimitsAndArmature) {
  const mjModel* a = vrml_.get();
  const mjModel* b = mjcf_.get();
  ASSERT_EQ(a->njnt, b->njnt);
  ASSERT_EQ(a->nq, b->nq);
  for (int j = 0; j < a->njnt; ++j) {
    const std::string name = Name(a, mjOBJ_JOINT, j);
    SCOPED_TRACE(name);
    EXPECT_EQ(name, Name(b, mjOBJ_JOINT, j));
    EXPECT_EQ(a->jnt_type[j], b->jnt_type[j]);
    EXPECT_EQ(a->jnt_qposadr[j], b->jnt_qposadr[j]);
    EXPECT_EQ(a->jnt_limited[j], b->jnt_limited[j]);
    ExpectNear(a->jnt_axis + 3 * j, b->jnt_axis + 3 * j, 3, 1e-12, "axis");
    ExpectNear(a->jnt_range + 2 * j, b->jnt_range + 2 * j, 2, 1e-12, "range");
    const int da = a->jnt_dofadr[j], db = b->jnt_dofadr[j];
    EXPECT_NEAR(a->dof_armature[da], b->dof_armature[db], 1e-12);
    EXPECT_NEAR(a->dof_damping[da], b->dof_damping[db], 1e-12);
  }
}

TEST_F(Sample1, MotorsAreInJointIdOrderWithTheSameTorqueLimits) {
  const mjModel* a = vrml_.get();
  const mjModel* b = mjcf_.get();
  ASSERT_EQ(a->nu, 29);
  ASSERT_EQ(a->nu, b->nu);
  for (int u = 0; u < a->nu; ++u) {
    SCOPED_TRACE(Name(b, mjOBJ_ACTUATOR, u));
    EXPECT_EQ(Name(a, mjOBJ_ACTUATOR, u), Name(b, mjOBJ_ACTUATOR, u));
    EXPECT_EQ(Name(a, mjOBJ_JOINT, a->actuator_trnid[2 * u]),
              Name(b, mjOBJ_JOINT, b->actuator_trnid[2 * u]));
    EXPECT_EQ(a->actuator_gear[6 * u], 1.0);
    ExpectNear(a->actuator_ctrlrange + 2 * u, b->actuator_ctrlrange + 2 * u, 2, 0, "ctrlrange");
    ExpectNear(a->actuator_forcerange + 2 * u, b->actuator_forcerange + 2 * u, 2, 0, "forcerange");
  }
}

TEST_F(Sample1, SensorsSitesAndCamerasMatch) {
  const mjModel* a = vrml_.get();
  const mjModel* b = mjcf_.get();
  ASSERT_EQ(a->nsensor, b->nsensor);
  for (int s = 0; s < a->nsensor; ++s) {
    SCOPED_TRACE(Name(b, mjOBJ_SENSOR, s));
    EXPECT_EQ(Name(a, mjOBJ_SENSOR, s), Name(b, mjOBJ_SENSOR, s));
    EXPECT_EQ(a->sensor_type[s], b->sensor_type[s]);
    EXPECT_EQ(a->sensor_adr[s], b->sensor_adr[s]);
    EXPECT_EQ(Name(a, a->sensor_objtype[s], a->sensor_objid[s]),
              Name(b, b->sensor_objtype[s], b->sensor_objid[s]));
  }
  ASSERT_EQ(a->nsite, b->nsite);
  for (int s = 0; s < a->nsite; ++s) {
    SCOPED_TRACE(Name(b, mjOBJ_SITE, s));
    EXPECT_EQ(Name(a, mjOBJ_SITE, s), Name(b, mjOBJ_SITE, s));
    EXPECT_EQ(a->site_bodyid[s], b->site_bodyid[s]);
    ExpectNear(a->site_pos + 3 * s, b->site_pos + 3 * s, 3, kLength, "site pos");
    ExpectSameRotation(a->site_quat + 4 * s, b->site_quat + 4 * s, kRotation, "site quat");
  }
  ASSERT_EQ(a->ncam, b->ncam);
  for (int c = 0; c < a->ncam; ++c) {
    SCOPED_TRACE(Name(b, mjOBJ_CAMERA, c));
    EXPECT_EQ(Name(a, mjOBJ_CAMERA, c), Name(b, mjOBJ_CAMERA, c));
    ExpectNear(a->cam_pos + 3 * c, b->cam_pos + 3 * c, 3, kLength, "camera pos");
    ExpectSameRotation(a->cam_quat + 4 * c, b->cam_quat + 4 * c, 1e-6, "camera quat");
    EXPECT_NEAR(a->cam_fovy[c], b->cam_fovy[c], 1e-6);
  }
}

TEST_F(Sample1, OnlyTheSolesCollideAndGeomsMatch) {
  const mjModel* a = vrml_.get();
  const mjModel* b = mjcf_.get();
  ASSERT_EQ(a->ngeom, b->ngeom);
  for (int g = 0; g < a->ngeom; ++g) {
    SCOPED_TRACE("geom " + std::to_string(g) + " " + Name(b, mjOBJ_GEOM, g));
    EXPECT_EQ(Name(a, mjOBJ_GEOM, g), Name(b, mjOBJ_GEOM, g));
    EXPECT_EQ(a->geom_type[g], b->geom_type[g]);
    EXPECT_EQ(a->geom_bodyid[g], b->geom_bodyid[g]);
    EXPECT_EQ(a->geom_contype[g], b->geom_contype[g]);
    EXPECT_EQ(a->geom_conaffinity[g], b->geom_conaffinity[g]);
    ExpectNear(a->geom_size + 3 * g, b->geom_size + 3 * g, 3, kLength, "size");
    ExpectNear(a->geom_pos + 3 * g, b->geom_pos + 3 * g, 3, kLength, "pos");
    ExpectSameRotation(a->geom_quat + 4 * g, b->geom_quat + 4 * g, 1e-6, "quat");
  }
  EXPECT_EQ(a->nexclude, b->nexclude);
}

TEST_F(Sample1, KeyframesPutTheSolesOnTheFloor) {
  const mjModel* a = vrml_.get();
  const mjModel* b = mjcf_.get();
  ASSERT_EQ(a->nkey, 2);
  ASSERT_EQ(a->nkey, b->nkey);
  for (int k = 0; k < a->nkey; ++k) {
    EXPECT_EQ(Name(a, mjOBJ_KEY, k), Name(b, mjOBJ_KEY, k));
    ExpectNear(a->key_qpos + k * a->nq, b->key_qpos + k * b->nq, a->nq, kAngle, Name(b, mjOBJ_KEY, k));
  }
  ExpectNear(a->qpos0, b->qpos0, a->nq, kAngle, "qpos0");
}

TEST_F(Sample1, HasTheModelHashOfHrp1s) {
  model::RobotMap ra, rb;
  std::string error;
  ASSERT_TRUE(model::MapRobot(vrml_.get(), &ra, &error)) << error;
  ASSERT_TRUE(model::MapRobot(mjcf_.get(), &rb, &error)) << error;
  EXPECT_EQ(ra.joints.size(), 29u);
  EXPECT_EQ(ra.forces.size(), 4u);
  EXPECT_EQ(ra.imus.size(), 1u);
  EXPECT_NEAR(ra.total_mass, 130.8, 1e-9);
  EXPECT_EQ(model::ModelHash(vrml_.get(), ra), model::ModelHash(mjcf_.get(), rb));
}

//---------------- the bushes ----------------

TEST(Bush, BushJointsArePassiveSpringDampers) {
  ModelPtr m = LoadVrml(kSamples + "sample1_bush.wrl");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->nu, 29);  // the bushes have no motor
  int bushes = 0;
  for (int j = 0; j < m->njnt; ++j) {
    const std::string name = Name(m.get(), mjOBJ_JOINT, j);
    if (name.find("BUSH") == std::string::npos) continue;
    SCOPED_TRACE(name);
    ++bushes;
    for (int u = 0; u < m->nu; ++u) EXPECT_NE(m->actuator_trnid[2 * u], j);
    const int dof = m->jnt_dofadr[j];
    if (m->jnt_type[j] == mjJNT_SLIDE) {
      EXPECT_EQ(m->jnt_stiffness[j], 1.0e6);  // [N/m]
      EXPECT_EQ(m->dof_damping[dof], 1.0e3);  // [N s/m]
      EXPECT_NEAR(m->dof_armature[dof], 0.1, 1e-12);  // rotorInertia, gearRatio 1
    } else {
      EXPECT_EQ(m->jnt_type[j], mjJNT_HINGE);
      EXPECT_EQ(m->jnt_stiffness[j], 2.5e3);  // [N m/rad]
      EXPECT_EQ(m->dof_damping[dof], 2.5);    // [N m s/rad]
      EXPECT_NEAR(m->dof_armature[dof], 0.014, 1e-12);
    }
  }
  EXPECT_EQ(bushes, 18);  // 3 per sole, 6 per wrist
  // the masses moved below the bushes, none lost (the massless links weigh 1e-6 kg each)
  double mass = 0;
  for (int b = 1; b < m->nbody; ++b) mass += m->body_mass[b];
  EXPECT_NEAR(mass, 130.8, 1e-4);
}

TEST(Bush, SolesAreTheBoxesBelowTheBushes) {
  ModelPtr m = LoadVrml(kSamples + "sample1_bush.wrl");
  ASSERT_TRUE(m);
  for (const char* sole : {"RLEG_SOLE", "LLEG_SOLE"}) {
    const int g = mj_name2id(m.get(), mjOBJ_GEOM, sole);
    ASSERT_GE(g, 0) << sole;
    EXPECT_NE(Name(m.get(), mjOBJ_BODY, m->geom_bodyid[g]).find("BUSH_PITCH"), std::string::npos);
    EXPECT_EQ(m->geom_contype[g], 1);
  }
  // standing straight, the soles' bottoms are at z = 0
  const int key = mj_name2id(m.get(), mjOBJ_KEY, "init");
  ASSERT_GE(key, 0);
  mjData* d = mj_makeData(m.get());
  mj_resetDataKeyframe(m.get(), d, key);
  mj_forward(m.get(), d);
  const int g = mj_name2id(m.get(), mjOBJ_GEOM, "RLEG_SOLE");
  EXPECT_NEAR(d->geom_xpos[3 * g + 2] - m->geom_size[3 * g + 2], 0.0, 1e-9);
  mj_deleteData(d);
}

//---------------- other samples, floors, scenes ----------------

TEST(Samples, SampleAndTheFloorsLoad) {
  ModelPtr sample = LoadVrml(kSamples + "sample.wrl");
  ASSERT_TRUE(sample);
  EXPECT_EQ(sample->nu, 29);
  for (const char* floor : {"floor.wrl", "longfloor.wrl", "box.wrl"}) {
    SCOPED_TRACE(floor);
    ModelPtr m = LoadVrml(kSamples + floor);
    ASSERT_TRUE(m);
    EXPECT_EQ(m->njnt, 0);  // fixed: scenery
    EXPECT_EQ(m->ngeom, 1);
    EXPECT_EQ(m->geom_contype[0], 1);
    EXPECT_EQ(m->geom_conaffinity[0], 1);
  }
  ModelPtr ball = LoadVrml(kSamples + "ball.wrl");
  ASSERT_TRUE(ball);
  EXPECT_EQ(ball->njnt, 1);
  EXPECT_EQ(ball->jnt_type[0], mjJNT_FREE);
  EXPECT_NEAR(ball->body_mass[1], 5.0, 1e-12);
  EXPECT_EQ(ball->geom_type[0], mjGEOM_SPHERE);
}

TEST(Samples, FloorTopIsAtZeroAndTheLongFloorMeshSpansIt) {
  ModelPtr floor = LoadVrml(kSamples + "floor.wrl");
  ModelPtr longfloor = LoadVrml(kSamples + "longfloor.wrl");
  ASSERT_TRUE(floor && longfloor);
  mjData* d = mj_makeData(floor.get());
  mj_forward(floor.get(), d);
  EXPECT_NEAR(d->geom_xpos[2] + floor->geom_size[2], 0.0, 1e-12);
  mj_deleteData(d);
  ASSERT_EQ(longfloor->geom_type[0], mjGEOM_MESH);
  d = mj_makeData(longfloor.get());
  mj_forward(longfloor.get(), d);
  // the mesh's bounding box: x from -2 to 5, top at z = 0 (0.1 above the body at z = -0.1)
  const int mesh = longfloor->geom_dataid[0];
  double top = -1e9, xmin = 1e9, xmax = -1e9;
  for (int v = 0; v < longfloor->mesh_vertnum[mesh]; ++v) {
    const float* p = longfloor->mesh_vert + 3 * (longfloor->mesh_vertadr[mesh] + v);
    double w[3];
    const double local[3] = {p[0], p[1], p[2]};
    mju_rotVecMat(w, local, d->geom_xmat);
    top = std::max(top, w[2] + d->geom_xpos[2]);
    xmin = std::min(xmin, w[0] + d->geom_xpos[0]);
    xmax = std::max(xmax, w[0] + d->geom_xpos[0]);
  }
  EXPECT_NEAR(top, 0.0, 1e-6);
  EXPECT_NEAR(xmin, -2.0, 1e-6);
  EXPECT_NEAR(xmax, 5.0, 1e-6);
  mj_deleteData(d);
}

TEST(Scenes, AnInlineSceneHoldsTheRobotAndTheFloor) {
  ModelPtr m = LoadVrml(kRobotDir + "scene_bush.wrl");
  ASSERT_TRUE(m);
  const int floor = mj_name2id(m.get(), mjOBJ_GEOM, "floor");  // in the world body
  ASSERT_GE(floor, 0);
  EXPECT_EQ(m->geom_bodyid[floor], 0);
  EXPECT_GE(mj_name2id(m.get(), mjOBJ_JOINT, "RLEG_BUSH_Z"), 0);
  EXPECT_EQ(m->nu, 29);
  EXPECT_EQ(m->nkey, 2);
}

TEST(Scenes, SceneLoadAndKinematicsLoadAcceptVrml) {
  std::string error;
  auto scene = model::Scene::Load(kRobotDir + "scene_sample1.wrl", &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  EXPECT_EQ(robot.joints.size(), 29u);
  EXPECT_TRUE(scene->Reset("halfsit", &error)) << error;
  auto kin = model::Kinematics::Load(kSamples + "sample1.wrl", &error);
  EXPECT_TRUE(kin) << error;
}

TEST(Scenes, AMissingInlineNamesTheIncludingFileAndLine) {
  std::string mjcf, error;
  EXPECT_FALSE(ConvertText("#VRML V2.0 utf8\n\nInline { url \"missing.wrl\" }\n", "scene.wrl",
                           &mjcf, &error));
  EXPECT_TRUE(std::regex_search(error, std::regex("^scene\\.wrl:3:1: "))) << error;
}

//---------------- malformed input ----------------

// the message of a conversion that must fail
std::string ErrorOf(const std::string& text) {
  std::string mjcf, error;
  EXPECT_FALSE(ConvertText(text, "bad.wrl", &mjcf, &error));
  return error;
}

TEST(Malformed, TruncatedFileNamesWhereItEnds) {
  const std::string text = ReadFile(kSamples + "sample1.wrl");
  ASSERT_GT(text.size(), 1000u);
  for (size_t cut : {text.size() / 3, text.size() / 2, text.size() - 10}) {
    const std::string error = ErrorOf(text.substr(0, cut));
    EXPECT_TRUE(std::regex_search(error, std::regex("^bad\\.wrl:[0-9]+:[0-9]+: "))) << error;
  }
}

TEST(Malformed, BadTokenGivesLineAndColumn) {
  EXPECT_EQ(ErrorOf("#VRML V2.0 utf8\nTransform {\n  translation 0 1.2.3 0\n}\n"),
            "bad.wrl:3:17: '1.2.3' is not a number (numbers look like 1, -0.5, 2e-3)");
  EXPECT_EQ(ErrorOf("Transform { children [ Shape { geometry Box { size 1 1 1 } } } ]"),
            "bad.wrl:1:62: expected a value (numbers, a string, TRUE/FALSE or a node), found '}'");
  EXPECT_EQ(ErrorOf("Group { children [ ] }\n\"unterminated"),
            "bad.wrl:2:1: string not terminated: a '\"' is missing");
}

TEST(Malformed, UnknownProtoFieldNamesTheFieldAndTheKnownOnes) {
  const std::string text =
      "PROTO Joint [\n"
      "  exposedField SFVec3f translation 0 0 0\n"
      "  exposedField MFNode children []\n"
      "  exposedField SFString jointType \"\"\n"
      "] { Transform { translation IS translation children IS children } }\n"
      "DEF WAIST Joint {\n"
      "  jointType \"free\"\n"
      "  jointAxsi 0 0 1\n"
      "}\n";
  EXPECT_EQ(ErrorOf(text),
            "bad.wrl:8:3: Joint has no field 'jointAxsi' (its fields: children jointType "
            "translation)");
}

TEST(Malformed, ModelErrorsNameTheNode) {
  const std::string proto =
      "PROTO Joint [ exposedField SFString jointType \"\" exposedField SFInt32 jointId -1\n"
      "  exposedField MFNode children [] exposedField SFVec3f jointAxis 0 0 1 ] { Group {} }\n";
  EXPECT_EQ(ErrorOf(proto + "DEF A Joint { jointType \"spin\" }\n"),
            "bad.wrl:3:25: jointType \"spin\" of Joint A is not one of free, rotate, slide, fixed");
  EXPECT_EQ(ErrorOf(proto + "DEF A Joint { jointType \"free\" children [ DEF B Joint {\n"
                            "  jointType \"rotate\" jointId 1 } ] }\n"),
            "bad.wrl:3:49: jointIds must be 0..n-1: jointId 0 is missing (Joint B has 1)");
  EXPECT_EQ(ErrorOf(proto + "DEF A Joint { jointType \"free\" children [ Shape { geometry Box {\n"
                            "  size 1 0 1 } } ] }\n"),
            "bad.wrl:3:60: Box has a size that is not positive");
  EXPECT_EQ(ErrorOf("PROTO Segment [ exposedField SFFloat mass 0 exposedField MFFloat "
                    "momentsOfInertia [ 0 0 0 0 0 0 0 0 0 ] ] { Group {} }\n"
                    "Group { children Segment { mass 1 momentsOfInertia [ 1 0 0 0 -1 0 0 0 1 ] } }"),
            "bad.wrl:2:52: momentsOfInertia of Segment is not an inertia tensor (symmetric, no "
            "negative eigenvalue)");
  EXPECT_EQ(ErrorOf("Group { children [ USE X ] }"),
            "bad.wrl:1:24: USE X: no node was defined as DEF X before this point");
}

TEST(Malformed, NamesCannotInjectMjcf) {
  // a name with XML in it stays a name: no <include> of a file from the disk
  const std::string text = R"(
PROTO Humanoid [ exposedField SFString name "" exposedField MFNode humanoidBody [] ] { Group {} }
PROTO Joint [ exposedField SFString jointType "" ] { Group {} }
Humanoid { name "x\"><include file=\"/etc/passwd\"/><b " humanoidBody [ DEF W Joint { jointType "free" } ] }
)";
  std::string mjcf, error;
  ASSERT_TRUE(ConvertText(text, "names.wrl", &mjcf, &error)) << error;
  EXPECT_EQ(mjcf.find("<include"), std::string::npos) << mjcf;
  EXPECT_NE(mjcf.find("<mujoco model=\"x___include file=_/etc/passwd_/__b \">"), std::string::npos)
      << mjcf;
}

TEST(Malformed, SceneLoadReportsTheVrmlPositionAndNoSceneIsMade) {
  std::string error;
  auto scene = model::Scene::Load(kRobotDir + "no_such_scene.wrl", &error);
  EXPECT_FALSE(scene);
  EXPECT_NE(error.find("cannot read VRML file"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::vrml
