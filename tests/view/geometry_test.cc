// The viewer's scene geometry (tools/view/src/geometry.cc): the description of HRP-1S's flat
// scene, the geoms' world poses by forward kinematics, the ZMP from the sole sensors against
// closed forms, and the meshes (an inline cube, menagerie's H1).
#include "common/scratch.h"
#include "view/geometry.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

namespace ohrp::view {
namespace {

const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";

class Geometry : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    geometry_ = SceneGeometry::Load(kScene, &error);
    ASSERT_TRUE(geometry_) << error;
    state_.q.assign(geometry_->robot().joints.size(), 0.0);
    state_.p_WB[2] = 0.7235;
    state_.ft.assign(geometry_->robot().forces.size(), shm::ForceTorque{});
  }
  int Sensor(const std::string& name) const {
    const auto& f = geometry_->robot().forces;
    for (size_t i = 0; i < f.size(); ++i)
      if (f[i].name == name) return static_cast<int>(i);
    return -1;
  }
  std::unique_ptr<SceneGeometry> geometry_;
  RobotState state_;
};

TEST_F(Geometry, DescribesTheFloorAndTheRobotsGeoms) {
  const nlohmann::json& d = geometry_->Describe();
  ASSERT_EQ(d["static"].size(), 1u);
  EXPECT_EQ(d["static"][0]["type"], "plane");
  EXPECT_GT(d["moving"].size(), 40u);
  EXPECT_EQ(d["joints"].size(), 29u);
  EXPECT_EQ(geometry_->Poses(state_).size(), d["moving"].size());
}

// RFC 4648's test vectors
TEST(GeometryMeshes, Base64IsRfc4648s) {
  for (const auto& [in, out] : std::vector<std::pair<std::string, std::string>>{
           {"", ""}, {"f", "Zg=="}, {"fo", "Zm8="}, {"foo", "Zm9v"}, {"foob", "Zm9vYg=="},
           {"fooba", "Zm9vYmE="}, {"foobar", "Zm9vYmFy"}})
    EXPECT_EQ(Base64(in.data(), in.size()), out) << in;
  const unsigned char high[3] = {0xfb, 0xff, 0xbf};
  EXPECT_EQ(Base64(high, 3), "+/+/");
}

// each triangle of the compact mesh is the same triangle of MuJoCo's, its positions unrepeated
void ExpectSameTriangles(const mjModel* m, int mesh, const MeshData& c) {
  const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
  const int* f = m->mesh_face + 3 * m->mesh_faceadr[mesh];
  ASSERT_EQ(c.faces.size(), 3u * m->mesh_facenum[mesh]);
  const size_t n = c.vertices.size() / 3;
  std::set<std::array<float, 3>> unique;
  for (size_t k = 0; k < n; ++k)
    unique.insert({c.vertices[3 * k], c.vertices[3 * k + 1], c.vertices[3 * k + 2]});
  EXPECT_EQ(unique.size(), n) << "a position is repeated";
  for (size_t k = 0; k < c.faces.size(); ++k) {
    ASSERT_LT(c.faces[k], n);
    for (int x = 0; x < 3; ++x) ASSERT_EQ(c.vertices[3 * c.faces[k] + x], v[3 * f[k] + x]);
  }
}

// meshes: sent once with their vertices and triangles, each mesh geom naming its mesh
TEST(GeometryMeshes, EachMeshIsSentOnceWithItsTriangles) {
  const std::string path = ohrp::testing::ScratchDir() + "/view_meshes.xml";
  std::ofstream(path) << R"(<mujoco model="meshes">
    <asset><mesh name="cube" vertex="-1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1"
                 scale="0.1 0.1 0.1"/></asset>
    <worldbody><geom type="plane" size="5 5 0.1"/>
      <body name="base" pos="0 0 0.6"><freejoint/><geom type="mesh" mesh="cube"/>
        <body name="arm" pos="0 0.3 0"><joint name="j1" axis="0 1 0"/>
          <geom type="mesh" mesh="cube"/><geom type="sphere" size="0.05"/></body></body>
    </worldbody><actuator><motor joint="j1"/></actuator></mujoco>)";
  std::string error;
  const auto g = SceneGeometry::Load(path, &error);
  ASSERT_TRUE(g) << error;
  const nlohmann::json& d = g->Describe();
  ASSERT_EQ(d["meshes"].size(), 1u);
  const nlohmann::json& mesh = d["meshes"][0];
  EXPECT_EQ(mesh["name"], "cube");
  // a cube's hull: 8 corners at 0.1 sqrt(3) m from its centre (MuJoCo turns it to its inertia
  // axes, which a cube leaves free), 12 triangles
  const MeshData c = CompactMesh(g->model(), 0);
  ASSERT_EQ(c.vertices.size(), 8u * 3);
  for (int k = 0; k < 8; ++k)
    EXPECT_NEAR(Eigen::Vector3f(c.vertices.data() + 3 * k).norm(), 0.1 * std::sqrt(3.0), 1e-6);
  ExpectSameTriangles(g->model(), 0, c);
  EXPECT_EQ(mesh["nvert"], 8);
  EXPECT_EQ(mesh["nface"], 12);
  EXPECT_EQ(mesh["vertices"], Base64(c.vertices.data(), c.vertices.size() * sizeof(float)));
  EXPECT_EQ(mesh["faces"], Base64(c.faces.data(), c.faces.size() * sizeof(uint32_t)));
  ASSERT_EQ(d["moving"].size(), 3u);
  EXPECT_EQ(d["moving"][0]["type"], "mesh");
  EXPECT_EQ(d["moving"][0]["mesh"], 0);
  EXPECT_EQ(d["moving"][1]["mesh"], 0);
  EXPECT_FALSE(d["moving"][2].contains("mesh"));
}

// HRP-1S's uneven scene stands on a height field: the description carries it once, its
// elevations in metres (MuJoCo's 0..1 samples times the top height), and the floor geom points
// at it
TEST(GeometryHfields, TheUnevenFloorIsSentWithItsElevations) {
  std::string error;
  const auto g =
      SceneGeometry::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_uneven.xml", &error);
  ASSERT_TRUE(g) << error;
  const mjModel* m = g->model();
  ASSERT_EQ(m->nhfield, 1);
  const nlohmann::json& d = g->Describe();
  ASSERT_EQ(d["hfields"].size(), 1u);
  const nlohmann::json& h = d["hfields"][0];
  EXPECT_EQ(h["name"], "waves");
  EXPECT_EQ(h["nrow"], m->hfield_nrow[0]);
  EXPECT_EQ(h["ncol"], m->hfield_ncol[0]);
  ASSERT_EQ(h["size"].size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(h["size"][i].get<double>(), m->hfield_size[i]);
  const std::vector<float> z = HfieldHeights(m, 0);
  ASSERT_EQ(z.size(), static_cast<size_t>(m->hfield_nrow[0] * m->hfield_ncol[0]));
  float lo = z[0], hi = z[0];
  for (size_t i = 0; i < z.size(); ++i) {
    // size="1 1 0.006 0.05": the top height is 0.006 m
    EXPECT_FLOAT_EQ(z[i], static_cast<float>(0.006 * m->hfield_data[i])) << i;
    lo = std::min(lo, z[i]);
    hi = std::max(hi, z[i]);
  }
  EXPECT_GT(hi - lo, 0.003f) << "the waves are +-3 mm";
  EXPECT_EQ(h["heights"], Base64(z.data(), z.size() * sizeof(float)));
  int floors = 0;
  for (const auto& s : d["static"]) {
    if (s["type"] != "hfield") continue;
    ++floors;
    EXPECT_EQ(s["hfield"], 0);
    EXPECT_EQ(s["name"], "floor");
  }
  EXPECT_EQ(floors, 1);
}

// menagerie's H1 and Cassie (../shared/external beside the repository), whose visual geoms are
// all meshes; Cassie's repeat each corner in every triangle
TEST(GeometryMeshes, H1AndCassieAreDrawnByTheirVisualMeshes) {
  for (const std::string robot : {"unitree_h1", "agility_cassie"}) {
    const std::string path =
        std::string(OHRP_SOURCE_DIR) + "/../shared/external/menagerie/" + robot + "/scene.xml";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
    std::string error;
    const auto g = SceneGeometry::Load(path, &error);
    ASSERT_TRUE(g) << error;
    const nlohmann::json& d = g->Describe();
    const mjModel* m = g->model();
    size_t mesh_geoms = 0, vertices = 0, merged = 0;
    for (const auto& geom : d["moving"]) {
      if (geom["type"] != "mesh") continue;
      ++mesh_geoms;
      ASSERT_LT(geom["mesh"].get<size_t>(), d["meshes"].size());
    }
    EXPECT_GE(mesh_geoms, 20u) << robot << ": one visual mesh a link";
    for (const auto& mesh : d["meshes"]) {
      const int id = mj_name2id(m, mjOBJ_MESH, mesh["name"].get<std::string>().c_str());
      ASSERT_GE(id, 0) << mesh["name"];
      const MeshData c = CompactMesh(m, id);
      ExpectSameTriangles(m, id, c);
      EXPECT_EQ(mesh["nvert"].get<size_t>(), c.vertices.size() / 3);
      EXPECT_EQ(mesh["vertices"].get<std::string>().size(), (c.vertices.size() * 4 + 2) / 3 * 4);
      vertices += m->mesh_vertnum[id];
      merged += c.vertices.size() / 3;
    }
    std::printf("%s: %zu mesh geoms drawn, %zu meshes, %zu vertices (%zu merged), description "
                "%.1f MB\n", robot.c_str(), mesh_geoms, d["meshes"].size(), vertices, merged,
                d.dump().size() / 1e6);
  }
}

TEST_F(Geometry, PosesFollowTheBase) {
  const nlohmann::json a = geometry_->Poses(state_);
  state_.p_WB[0] += 1.0;
  const nlohmann::json b = geometry_->Poses(state_);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(b[i][0].get<double>() - a[i][0].get<double>(), 1.0, 1e-9);
    EXPECT_NEAR(b[i][2].get<double>(), a[i][2].get<double>(), 1e-9);
  }
}

// two ankles carrying 300 N each, straight up, no moment: the ZMP is midway between the
// sensors; a moment -6 N m about each sensor's y moves it 2 cm forward (x = -M_y / F_z); a
// wrist sensor's force is not a foot's and changes nothing
TEST_F(Geometry, ZmpFromTheSoleSensorsMatchesTheClosedForm) {
  const int r = Sensor("rfsensor"), l = Sensor("lfsensor"), h = Sensor("rhsensor");
  ASSERT_GE(r, 0);
  ASSERT_GE(l, 0);
  ASSERT_GE(h, 0);
  geometry_->Poses(state_);
  const mjModel* m = geometry_->model();
  // the sensors' positions, from a fresh kinematics of the same state
  mjData* d = mj_makeData(m);
  for (int k = 0; k < 3; ++k) d->qpos[geometry_->robot().base_qpos + k] = state_.p_WB[k];
  mj_kinematics(m, d);
  const double* pr = d->site_xpos + 3 * geometry_->robot().forces[r].site_id;
  const double* pl = d->site_xpos + 3 * geometry_->robot().forces[l].site_id;
  const double mid_x = 0.5 * (pr[0] + pl[0]), mid_y = 0.5 * (pr[1] + pl[1]);
  state_.ft[r].force[2] = state_.ft[l].force[2] = 300;
  state_.ft[h].force[2] = 500;
  double zmp[2];
  ASSERT_TRUE(geometry_->Zmp(state_, zmp));
  EXPECT_NEAR(zmp[0], mid_x, 1e-9);
  EXPECT_NEAR(zmp[1], mid_y, 1e-9);
  state_.ft[r].torque[1] = state_.ft[l].torque[1] = -6;
  ASSERT_TRUE(geometry_->Zmp(state_, zmp));
  EXPECT_NEAR(zmp[0], mid_x + 0.02, 1e-9);
  // in the air: no ZMP
  state_.ft[r].force[2] = state_.ft[l].force[2] = 5;
  EXPECT_FALSE(geometry_->Zmp(state_, zmp));
  mj_deleteData(d);
}

// the balance overlays' data (balance.cc): the CoM is the bodies' mass-weighted mean (a fresh
// kinematics of the same state); a sole's centre of pressure is its sensor moved by
// (-ty, tx) / fz; its corners are the MJCF's sole box (0.25 x 0.14 m, 0.055 m ahead of the
// sensor, its bottom face on the sensor's plane); a foot with 5 N is not loaded
TEST_F(Geometry, BalanceMatchesTheClosedForms) {
  const int r = Sensor("rfsensor"), l = Sensor("lfsensor");
  ASSERT_GE(r, 0);
  ASSERT_GE(l, 0);
  state_.p_WB[0] = 0.3;
  geometry_->Poses(state_);
  const mjModel* m = geometry_->model();
  mjData* d = mj_makeData(m);
  for (int k = 0; k < 3; ++k) d->qpos[geometry_->robot().base_qpos + k] = state_.p_WB[k];
  mj_kinematics(m, d);
  double mass = 0, com[3] = {0, 0, 0};
  for (int b = 1; b < m->nbody; ++b) {
    mass += m->body_mass[b];
    for (int k = 0; k < 3; ++k) com[k] += m->body_mass[b] * d->xipos[3 * b + k];
  }
  state_.ft[r].force[2] = 300;
  state_.ft[r].torque[0] = 3;   // cop 1 cm to +y
  state_.ft[r].torque[1] = -6;  // cop 2 cm to +x
  state_.ft[l].force[2] = 5;
  const nlohmann::json b = geometry_->Balance(state_);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(b["com"][k].get<double>(), com[k] / mass, 1e-9) << k;
  ASSERT_EQ(b["feet"].size(), 2u) << b;  // the sole sensors only, not the wrists'
  for (const auto& foot : b["feet"]) {
    const bool right = foot["sensor"] == "rfsensor";
    const double* p = d->site_xpos + 3 * geometry_->robot().forces[right ? r : l].site_id;
    EXPECT_EQ(foot["loaded"].get<bool>(), right);
    EXPECT_NEAR(foot["f"][2].get<double>(), right ? 300 : 5, 1e-9);
    EXPECT_NEAR(foot["cop"][0].get<double>(), p[0] + (right ? 0.02 : 0), 1e-9);
    EXPECT_NEAR(foot["cop"][1].get<double>(), p[1] + (right ? 0.01 : 0), 1e-9);
    ASSERT_EQ(foot["corners"].size(), 4u);
    for (const auto& c : foot["corners"]) {
      EXPECT_NEAR(std::abs(c[0].get<double>() - p[0] - 0.055), 0.125, 1e-9);
      EXPECT_NEAR(std::abs(c[1].get<double>() - p[1]), 0.07, 1e-9);
      EXPECT_NEAR(c[2].get<double>(), p[2], 1e-9);
    }
  }
  mj_deleteData(d);
  // its cost beside the poses' (printed, not checked: the machine is shared)
  auto seconds = [](auto f) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < 2000; ++i) f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 2000;
  };
  const double poses = seconds([&] { geometry_->Poses(state_); });
  const double balance = seconds([&] { geometry_->Balance(state_); });
  std::printf("per frame: Poses %.1f us, Balance %.1f us, %zu bytes of JSON\n", 1e6 * poses, 1e6 * balance, b.dump().size());
}

}  // namespace
}  // namespace ohrp::view
