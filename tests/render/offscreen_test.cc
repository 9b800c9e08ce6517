// Tests the offscreen renderer (render/offscreen.h) against closed forms: a camera above a floor
// sees the floor's distance along its optical axis in every pixel when it looks straight down,
// and the pinhole ray's distance when it looks 30 deg down; rows come top first.
#include "common/scratch.h"
#include "render/offscreen.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace ohrp::render {
namespace {

constexpr int kW = 160, kH = 120;

struct Frame {
  std::vector<uint8_t> rgb = std::vector<uint8_t>(3 * kW * kH);
  std::vector<float> depth = std::vector<float>(kW * kH);
};

// renders the scene's camera 0 (a camera at height `z` with axes `xyaxes` above a plane)
Frame Render(double z, const std::string& xyaxes, int samples = 0) {
  const std::string path = ohrp::testing::ScratchPath("offscreen", ".xml");
  std::ofstream(path) << "<mujoco><worldbody><geom type='plane' size='20 20 0.1' rgba='0.2 0.8 0.2 1'/>"
                         "<camera pos='0 0 " << z << "' xyaxes='" << xyaxes << "' fovy='45'/>"
                         "</worldbody></mujoco>";
  char error[500] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  std::filesystem::remove(path);
  EXPECT_NE(m, nullptr) << error;
  Frame f;
  if (m == nullptr) return f;
  mjData* d = mj_makeData(m);
  mj_forward(m, d);
  {
    OffscreenOptions o;
    o.width = kW;
    o.height = kH;
    o.samples = samples;
    std::string why;
    std::unique_ptr<Offscreen> r = Offscreen::Create(m, o, &why);
    EXPECT_TRUE(r) << why;
    if (r) {
      mjvCamera cam;
      mjv_defaultCamera(&cam);
      cam.type = mjCAMERA_FIXED;
      cam.fixedcamid = 0;
      r->Draw(m, d, &cam, kW, kH);
      r->Read(kW, kH, f.rgb.data(), f.depth.data());
    }
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return f;
}

TEST(Offscreen, LookingStraightDownEveryPixelIsTheHeight) {
  for (double z : {1.0, 3.0, 10.0}) {
    const Frame f = Render(z, "1 0 0 0 1 0");
    for (int i : {0, kW - 1, (kH / 2) * kW + kW / 2, kW * kH - 1}) {
      EXPECT_NEAR(f.depth[i], z, 2e-4 * z * z) << "height " << z << ", pixel " << i;
    }
    EXPECT_GT(f.rgb[3 * (kW * kH / 2) + 1], 100) << "the green floor";
  }
}

TEST(Offscreen, LookingDownAtThirtyDegreesEachRowIsItsPinholeRay) {
  // optical axis (cos 30, 0, -sin 30) from height 2. Pixel row v's ray in the camera frame is
  // (0, -y, -1) with y = (v + 0.5 - H/2) / f, f = (H/2) / tan(fovy/2); in the world its
  // vertical component is -(sin 30 + y cos 30), so it meets the floor at the axial distance
  // 2 / (sin 30 + y cos 30)
  const double s = std::sin(M_PI / 6), c = std::cos(M_PI / 6);
  const Frame f = Render(2.0, "0 -1 0 0.5 0 0.8660254");
  const double focal = 0.5 * kH / std::tan(M_PI / 8);
  for (int v : {0, 30, 59, 60, 90, kH - 1}) {
    const double y = (v + 0.5 - 0.5 * kH) / focal;  // downwards in the image
    const double expected = 2.0 / (s + y * c);
    EXPECT_NEAR(f.depth[v * kW + kW / 2], expected, 2e-4 * expected * expected) << "row " << v;
  }
  // with multisampling the depth is a sample's, off the pixel centre: the reason for samples 0
  const Frame ms = Render(2.0, "0 -1 0 0.5 0 0.8660254", 4);
  const double centre = 2.0 / (s + (0.5 / focal) * c);
  EXPECT_GT(std::fabs(ms.depth[60 * kW + kW / 2] - centre), 2e-4 * centre * centre);
}

}  // namespace
}  // namespace ohrp::render
