// ohrp view's replay of the cameras' images recorded in a run folder (sim_host --record-images;
// tools/view/src/replay_images.cc, web/recorded.js): a replayed HRP-1S log beside images/ with
// three frames of one camera at 0, 1 and 2 s (tiny PNGs of three colours, written here); at each
// time shown the page shows the camera's latest frame at or before it, the server hands out the
// files the index names and nothing else (a path out of the folder, a file not indexed: 404);
// without images/ the page says there are none.
#include <gtest/gtest.h>

#include <fstream>

#include "browser.h"
#include "common/scratch.h"
#include "render/png.h"
#include "view_process.h"
#include "viewer_page.h"

namespace ohrp::view::testing {
namespace {

// the log: 401 rows, 10 ms apart, the robot standing upright (joints at 0)
void WriteLog(const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "sim_summary.json") << "{\"scene\": \"" << kScene << "\"}\n";
  std::ofstream log(dir / "log.csv");
  log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_RLEG_KNEE\n";
  for (int i = 0; i <= 400; ++i) log << 0.01 * i << ",0,0,0.7235,1,0,0,0,0\n";
}

// images/: LeftCamera frames at 0, 1, 2 s, 4 x 3 pixels of red, green, blue
void WriteImages(const fs::path& dir) {
  fs::create_directories(dir / "images" / "LeftCamera");
  std::ofstream index(dir / "images" / "images.csv");
  index << "time,camera,rgb,depth\n";
  const uint8_t colours[3][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  for (int k = 0; k < 3; ++k) {
    std::vector<uint8_t> rgb(4 * 3 * 3);
    for (size_t p = 0; p < rgb.size(); ++p) rgb[p] = colours[k][p % 3];
    const std::string name = "LeftCamera/00000" + std::to_string(k) + ".png";
    std::string error;
    ASSERT_TRUE(render::WritePngRgb((dir / "images" / name).string(), rgb.data(), 4, 3, false, &error)) << error;
    index << k << ".000000,LeftCamera," << name << ",\n";
  }
}

// the page at time t: the recorded frame's time and file it shows
std::pair<double, std::string> At(Browser* b, double t) {
  const std::string ts = std::to_string(t);
  b->Eval("(() => { replay.playing = false; seek(" + ts + "); })()");
  EXPECT_TRUE(b->WaitTrue("Math.abs(document.getElementById('state').dataset.t - " + ts + ") < 1e-6"));
  return {std::stod(b->Eval("document.getElementById('state').dataset.recordedT").get<std::string>()),
          b->Eval("document.getElementById('state').dataset.recordedSrc").get<std::string>()};
}

// the HTTP status of GET `path` from the page's own server
int Status(Browser* b, const std::string& path) {
  b->Eval("window.status_ = 0; fetch('" + path + "').then((r) => { window.status_ = r.status; })");
  EXPECT_TRUE(b->WaitTrue("window.status_ > 0"));
  return b->Eval("window.status_").get<int>();
}

class RecordedPage : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = ohrp::testing::ScratchFolder("recorded_page"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(RecordedPage, TheLatestFrameAtOrBeforeTheTimeShownAndOnlyIndexedFilesServed) {
  WriteLog(dir_ / "run");
  WriteImages(dir_ / "run");
  ASSERT_FALSE(HasFatalFailure());
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  EXPECT_NE(browser.Eval("document.getElementById('cameras').textContent").get<std::string>().find("1 camera(s) recorded"),
            std::string::npos);
  for (const auto& [t, want_t, want] : std::vector<std::tuple<double, double, std::string>>{
           {0.5, 0.0, "LeftCamera/000000.png"}, {1.0, 1.0, "LeftCamera/000001.png"},
           {1.99, 1.0, "LeftCamera/000001.png"}, {3.5, 2.0, "LeftCamera/000002.png"},
           {0.2, 0.0, "LeftCamera/000000.png"}}) {
    const auto [got_t, src] = At(&browser, t);
    EXPECT_EQ(got_t, want_t) << "at t = " << t;
    EXPECT_EQ(src, "/recorded/" + want) << "at t = " << t;
  }
  // the image shown is the file's (the browser decoded it: 4 x 3, the third frame's blue)
  At(&browser, 2.5);
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('recimg0').complete && "
                               "document.getElementById('recimg0').naturalWidth === 4"));
  const std::string blue = browser.Eval(
      "(() => { const i = document.getElementById('recimg0'), c = document.createElement('canvas');"
      " c.width = 4; c.height = 3; const g = c.getContext('2d'); g.drawImage(i, 0, 0);"
      " return Array.from(g.getImageData(1, 1, 1, 1).data).join(','); })()").get<std::string>();
  EXPECT_EQ(blue, "0,0,255,255");
  EXPECT_EQ(Status(&browser, "/recorded/LeftCamera/000001.png"), 200);
  EXPECT_EQ(Status(&browser, "/recorded/LeftCamera/000009.png"), 404);  // not in the index
  EXPECT_EQ(Status(&browser, "/recorded/images.csv"), 404);
  EXPECT_EQ(Status(&browser, "/recorded/..%2Flog.csv"), 404);
  EXPECT_EQ(Status(&browser, "/recorded/../log.csv"), 404);
}

TEST_F(RecordedPage, WithoutRecordedImagesThePageSaysSo) {
  WriteLog(dir_ / "run");
  ViewerPage page;
  OpenPage(&page, {(dir_ / "run").string(), "--port", "0"}, (dir_ / "viewer.txt").string(), "?t=0");
  ASSERT_FALSE(HasFatalFailure());
  Browser& browser = *page.browser;
  ASSERT_TRUE(browser.WaitTrue("document.getElementById('state').dataset.frames > 0"));
  const std::string note = browser.Eval("document.getElementById('cameras').textContent").get<std::string>();
  EXPECT_NE(note.find("no recorded images"), std::string::npos) << note;
}

}  // namespace
}  // namespace ohrp::view::testing
