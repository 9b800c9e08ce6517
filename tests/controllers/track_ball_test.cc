// Tests track_ball's vision (FindBall) on drawn images against the closed forms: the centroid
// of a red disc is its centre, the bearing atan((cx - W/2) / f) with f = (H/2) / tan(fovy/2);
// the same convention as the runner's pinhole projection (ProjectPinhole is its inverse along
// the image's x); other colours are not the ball; too few red pixels are no ball.
#include "controllers/track_ball.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ohrp::controllers {
namespace {

constexpr int kW = 320, kH = 240;

// a grey-blue image (the floor's colours) with a disc of colour (r, g, b) at (x0, y0), radius
// `radius` [pixel]: pixel (x, y) is in the disc when its centre (x + 0.5, y + 0.5) is
std::vector<uint8_t> Image(double x0, double y0, double radius, uint8_t r, uint8_t g, uint8_t b) {
  std::vector<uint8_t> rgb(3 * kW * kH);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      uint8_t* p = &rgb[3 * (y * kW + x)];
      const bool in = std::hypot(x + 0.5 - x0, y + 0.5 - y0) <= radius;
      p[0] = in ? r : 70;
      p[1] = in ? g : 80;
      p[2] = in ? b : 100;
    }
  }
  return rgb;
}

TEST(FindBall, TheCentroidOfARedDiscIsItsCentreAndGivesItsBearing) {
  const TrackBallOptions o;
  const double fovy = 45.0, f = 0.5 * kH / std::tan(M_PI / 8);
  for (const auto& [x0, y0] : {std::pair{160.0, 120.0}, std::pair{64.3, 129.9}, std::pair{290.5, 20.25}}) {
    BallSighting s;
    FindBall(Image(x0, y0, 11.0, 200, 30, 25).data(), kW, kH, fovy, o, &s);
    ASSERT_TRUE(s.seen);
    EXPECT_NEAR(s.pixels, M_PI * 11.0 * 11.0, 0.1 * M_PI * 121.0);
    // a digitised disc's centroid: within a quarter pixel of the centre (its edge pixels are
    // in or out whole; the scenario's tolerance is 10 px)
    EXPECT_NEAR(s.cx, x0, 0.25);
    EXPECT_NEAR(s.cy, y0, 0.25);
    EXPECT_NEAR(s.bearing, std::atan((s.cx - 0.5 * kW) / f), 1e-12);
  }
}

TEST(FindBall, OtherColoursAndTooFewPixelsAreNoBall) {
  TrackBallOptions o;
  BallSighting s;
  FindBall(Image(100, 100, 11.0, 200, 150, 40).data(), kW, kH, 45.0, o, &s);  // orange: green too high
  EXPECT_FALSE(s.seen);
  EXPECT_EQ(s.pixels, 0);
  FindBall(Image(100, 100, 11.0, 60, 10, 10).data(), kW, kH, 45.0, o, &s);  // too dark
  EXPECT_FALSE(s.seen);
  FindBall(Image(100, 100, 1.5, 200, 30, 25).data(), kW, kH, 45.0, o, &s);  // 7 pixels < 12
  EXPECT_FALSE(s.seen);
  EXPECT_GT(s.pixels, 0);
}

}  // namespace
}  // namespace ohrp::controllers
