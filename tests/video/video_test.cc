// ohrp_video: renders a log through a scene offscreen. A red bar on a hinge, logged at two
// angles, must appear where the angle puts it; bad inputs are clear errors; an MP4 is written.
#include <gtest/gtest.h>
#include <png.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/process.h"
#include "common/scratch.h"

namespace {

namespace fs = std::filesystem;
const std::string kBin = std::string(OHRP_BIN_DIR) + "/ohrp_video";

// a camera-facing scene: a red bar hinged at the origin about y, lying along +x at q = 0 and
// pointing up at q = pi/2; grey floor far below, no lights needed beyond the headlight
const char* kScene = R"(<mujoco><compiler angle="radian"/>
  <worldbody>
    <geom type="plane" size="5 5 0.1" pos="0 0 -2" rgba="0.5 0.5 0.5 1"/>
    <body name="bar"><joint name="hinge" type="hinge" axis="0 -1 0"/>
      <geom type="capsule" fromto="0 0 0 0.8 0 0" size="0.08" rgba="1 0 0 1"/></body>
  </worldbody></mujoco>)";

struct Result {
  int code;
  std::string err;
};
Result Exec(const std::string& args) {
  const std::string err_file = ohrp::testing::ScratchPath("video_stderr");
  const int status = std::system((kBin + " " + args + " >/dev/null 2>" + err_file).c_str());
  std::ifstream in(err_file);
  std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fs::remove(err_file);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, err};
}

// red pixels' mean position (x right, y down) and count
struct Blob {
  double x = 0, y = 0;
  int n = 0;
};
Blob RedBlob(const std::string& png_path) {
  Blob b;
  FILE* f = std::fopen(png_path.c_str(), "rb");
  if (!f) return b;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_read_png(png, info, PNG_TRANSFORM_STRIP_ALPHA, nullptr);
  const int w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  png_bytepp rows = png_get_rows(png, info);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const png_bytep p = rows[y] + 3 * x;
      if (p[0] > 120 && p[1] < 60 && p[2] < 60) {
        b.x += x;
        b.y += y;
        ++b.n;
      }
    }
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  if (b.n) {
    b.x /= b.n;
    b.y /= b.n;
  }
  return b;
}

class Video : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ohrp::testing::ScratchFolder("video");
    std::ofstream(dir_ / "scene.xml") << kScene;
    std::ofstream log(dir_ / "log.csv");
    log << "time,q_hinge\n0,0\n1,1.5707963\n2,1.5707963\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(Video, StillsShowTheLoggedPose) {
  const Result r = Exec(dir_.string() + " --scene " + (dir_ / "scene.xml").string() +
                     " --still 0,1 --azimuth 90 --elevation 0 --distance 2.5 --width 320 --height 240");
  ASSERT_EQ(r.code, 0) << r.err;
  const Blob flat = RedBlob((dir_ / "still_0.00.png").string());
  const Blob up = RedBlob((dir_ / "still_1.00.png").string());
  std::printf("bar at q=0: %d red px at (%.0f, %.0f); q=pi/2: %d px at (%.0f, %.0f)\n", flat.n,
              flat.x, flat.y, up.n, up.x, up.y);
  ASSERT_GT(flat.n, 150);
  ASSERT_GT(up.n, 150);
  // lying along x (seen from the side) the bar is wider than tall, pointing up it is above
  EXPECT_LT(up.y, flat.y - 20);        // higher in the image
  EXPECT_LT(std::abs(up.x - 160), 25); // over the hinge, which the camera centres
  EXPECT_GT(flat.x, up.x + 20);        // the flat bar reaches out to one side
}

TEST_F(Video, WritesAnMp4) {
  const fs::path out = dir_ / "v.mp4";
  const Result r = Exec(dir_.string() + " --scene " + (dir_ / "scene.xml").string() +
                     " --out " + out.string() + " --fps 10 --width 160 --height 120");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out));
  EXPECT_GT(fs::file_size(out), 1000u);
}

// the output path is a file name, never a command: ffmpeg gets an argument vector (today's main
// put it in single quotes into `sh -c`, so a quote in it ran the rest as a command)
TEST_F(Video, AnOutputPathWithQuotesIsAFileNameNotACommand) {
  const std::string marker = "pwned_by_ohrp_video";  // what the injected command would create
  fs::remove(marker);
  const fs::path out = dir_ / ("v';touch${IFS}" + marker + ";'.mp4");
  const std::string err = (dir_ / "stderr.txt").string();
  const int code = ohrp::testing::WaitExit(
      ohrp::testing::Spawn({kBin, dir_.string(), "--scene", (dir_ / "scene.xml").string(), "--out",
                            out.string(), "--fps", "2", "--width", "32", "--height", "32"},
                           ohrp::testing::ToFile(err)),
      60.0);
  EXPECT_FALSE(fs::exists(marker)) << "the path ran as a command";
  fs::remove(marker);
  ASSERT_EQ(code, 0) << ohrp::testing::ReadFile(err);
  EXPECT_TRUE(fs::exists(out)) << ohrp::testing::ReadFile(err);
}

TEST_F(Video, BadInputsAreClearErrors) {
  Result r = Exec((dir_ / "nothing").string() + " --scene " + (dir_ / "scene.xml").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("cannot read the data log"), std::string::npos) << r.err;

  r = Exec(dir_.string());  // no sim_summary.json beside the log
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--scene"), std::string::npos) << r.err;

  std::ofstream(dir_ / "other.csv") << "time,q_elbow\n0,0\n1,1\n";
  r = Exec((dir_ / "other.csv").string() + " --scene " + (dir_ / "scene.xml").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no q_<joint> column names a joint"), std::string::npos) << r.err;

  r = Exec(dir_.string() + " --scene " + (dir_ / "scene.xml").string() + " --still 7");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("outside the log"), std::string::npos) << r.err;

  std::ofstream(dir_ / "bad.xml") << "<mujoco><worldbody><geom type=\"nonsense\"/></worldbody></mujoco>";
  r = Exec(dir_.string() + " --scene " + (dir_ / "bad.xml").string() + " --still 0");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bad.xml"), std::string::npos) << r.err;
}

}  // namespace
