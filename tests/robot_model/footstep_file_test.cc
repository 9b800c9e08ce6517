// Tests of the footstep files (robot_model/src/walking/footstep_file.cc): the shipped example
// keeps the limits from HRP-1S's half-sitting stance, YAML and CSV agree, and each kind of error
// names the file, the line and the key.
#include "walking/footstep_file.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "../integration/temp_file.h"
#include "stances.h"

namespace ohrp::walking {
namespace {

const std::string kExample = std::string(OHRP_SOURCE_DIR) + "/scenarios/steps/mixed.yaml";

// HRP-1S's soles in the half-sitting keyframe of the MJCF: the centre of each sole's bottom
// face and its yaw; the soles' half size in `*half`
FeetPose Hrp1sHalfSitting(Eigen::Vector2d* half) {
  char err[512] = "";
  mjModel* m = mj_loadXML((std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml").c_str(),
                          nullptr, err, sizeof(err));
  EXPECT_NE(m, nullptr) << err;
  FeetPose f;
  if (!m) return f;
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, mj_name2id(m, mjOBJ_KEY, "halfsit"));
  mj_forward(m, d);
  for (int s : {kLeft, kRight}) {
    const int g = mj_name2id(m, mjOBJ_GEOM, s == kLeft ? "LLEG_SOLE" : "RLEG_SOLE");
    const double* x = d->geom_xpos + 3 * g;
    const double* r = d->geom_xmat + 9 * g;
    f.p[s] = Eigen::Vector3d(x[0], x[1], x[2] - m->geom_size[3 * g + 2]);
    f.yaw[s] = std::atan2(r[3], r[0]);
    *half = Eigen::Vector2d(m->geom_size[3 * g], m->geom_size[3 * g + 1]);
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return f;
}

// the error of parsing `text`, named "steps.yaml" or "steps.csv"; "" when it parses
std::string ErrorOf(const std::string& text, FootstepFormat format = FootstepFormat::kYaml) {
  const StepLimits l;
  std::vector<Footstep> steps;
  std::string error;
  const std::string name = format == FootstepFormat::kYaml ? "steps.yaml" : "steps.csv";
  if (ParseFootstepText(text, format, name, Stance(l.width), l, &steps, &error)) return "";
  EXPECT_TRUE(steps.empty());
  return error;
}

// the error holds the place and every piece given
void ExpectError(const std::string& text, const std::string& at,
                 std::initializer_list<const char*> pieces,
                 FootstepFormat format = FootstepFormat::kYaml) {
  const std::string e = ErrorOf(text, format);
  EXPECT_EQ(e.rfind(at, 0), 0u) << "expected it to start with '" << at << "': " << e;
  for (const char* p : pieces)
    EXPECT_NE(e.find(p), std::string::npos) << "no '" << p << "' in: " << e;
}

//---------------- the example ----------------

TEST(FootstepFile, TheExampleKeepsTheDefaultLimitsFromHrp1sHalfSitting) {
  Eigen::Vector2d half;
  const FeetPose start = Hrp1sHalfSitting(&half);
  ASSERT_NEAR(start.p[kLeft].y() - start.p[kRight].y(), 0.18, 1e-9);  // hips at y = +-0.09
  StepLimits hrp1s;
  hrp1s.sole_half_size = half;  // 0.125 x 0.07
  for (const StepLimits& l : {StepLimits(), hrp1s}) {
    std::vector<Footstep> steps;
    std::string error;
    ASSERT_TRUE(ReadFootstepFile(kExample, start, l, &steps, &error)) << error;
    EXPECT_EQ(CheckSteps(start, steps, l), "");
    ASSERT_EQ(steps.size(), 12u);
    // relative to the start's mid frame, the defaults where a step gives none
    const Frame2 mid = MidFrame(start);
    EXPECT_NEAR(steps[0].p.x(), mid.p.x() + 0.2, 1e-12);
    EXPECT_NEAR(steps[0].p.y(), mid.p.y() + 0.09, 1e-12);
    EXPECT_NEAR(steps[0].p.z(), mid.p.z(), 1e-12);
    EXPECT_NEAR(steps[6].yaw, mid.yaw + 15 * M_PI / 180, 1e-12);
    EXPECT_EQ(steps[0].height, 0.04);
    EXPECT_EQ(steps[8].height, 0.06);
    EXPECT_EQ(steps[0].duration, 0.8);
    EXPECT_EQ(steps[3].duration, 1.0);
    // mixed: a step forward, one to the side, a turn and one back (in the stance foot's frame)
    bool forward = false, side = false, turn = false, back = false;
    FeetPose feet = start;
    for (const auto& s : steps) {
      const int o = 1 - s.foot;
      const double c = std::cos(feet.yaw[o]), sn = std::sin(feet.yaw[o]);
      const Eigen::Vector3d d = s.p - feet.p[o];
      const double ahead = c * d.x() + sn * d.y();
      forward |= ahead > 0.15;
      back |= ahead < -0.05;
      side |= std::abs(-sn * d.x() + c * d.y()) > 0.2;
      turn |= std::abs(s.yaw - feet.yaw[o]) > 0.2;
      feet = After(feet, s);
    }
    EXPECT_TRUE(forward && side && turn && back);
  }
}

TEST(FootstepFile, CsvAndYamlAgree) {
  const StepLimits l;
  const FeetPose start = Stance(l.width, 0.3, -0.2, 0.4, 0.05);
  const std::string yaml =
      "defaults: {duration: 0.9}\n"
      "steps:\n"
      "  - {foot: left, x: 0.2, y: 0.08, yaw_deg: 0}\n"
      "  - {foot: right, x: 0.4, y: -0.08, z: 0.02, yaw_deg: 5, height: 0.05}\n"
      "  - {foot: left, x: 0.4, y: 0.1, yaw_deg: 10, duration: 1.2}\n";
  const std::string csv =
      "# the same steps\n"
      "foot, x, y, z, yaw_deg, height, duration\n"
      "left, 0.2, 0.08, , 0, , 0.9\n"
      "right, 0.4, -0.08, 0.02, 5, 0.05, 0.9\n"
      "\n"
      "left, 0.4, 0.1, , 10, , 1.2\r\n";
  std::vector<Footstep> a, b;
  std::string error;
  ASSERT_TRUE(ParseFootstepText(yaml, FootstepFormat::kYaml, "a.yaml", start, l, &a, &error))
      << error;
  ASSERT_TRUE(ParseFootstepText(csv, FootstepFormat::kCsv, "a.csv", start, l, &b, &error)) << error;
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].foot, b[k].foot);
    EXPECT_EQ(a[k].p, b[k].p);
    EXPECT_EQ(a[k].yaw, b[k].yaw);
    EXPECT_EQ(a[k].height, b[k].height);
    EXPECT_EQ(a[k].duration, b[k].duration);
  }
  // relative to the start: the turned mid frame, z on the start's height
  EXPECT_NEAR(a[1].p.x(), 0.3 + 0.4 * std::cos(0.4) + 0.08 * std::sin(0.4), 1e-12);
  EXPECT_NEAR(a[1].p.z(), 0.05 + 0.02, 1e-12);
  EXPECT_NEAR(a[1].yaw, 0.4 + 5 * M_PI / 180, 1e-12);
  EXPECT_EQ(a[0].height, -1);  // the generator's default
}

TEST(FootstepFile, WorldFrameTakesThePosesAsWritten) {
  const StepLimits l;
  const FeetPose start = Stance(l.width, 1.0, 2.0);
  std::vector<Footstep> steps;
  std::string error;
  ASSERT_TRUE(
      ParseFootstepText("frame: world\nsteps:\n  - {foot: left, x: 1.2, y: 2.08, yaw_deg: 5}\n",
                        FootstepFormat::kYaml, "w.yaml", start, l, &steps, &error))
      << error;
  EXPECT_EQ(steps[0].p, Eigen::Vector3d(1.2, 2.08, 0));
  EXPECT_NEAR(steps[0].yaw, 5 * M_PI / 180, 1e-15);
}

TEST(FootstepFile, ReadsAFileByItsExtension) {
  const StepLimits l;
  std::vector<Footstep> steps;
  std::string error;
  const std::string csv = runner::Temp("foot,x,y,yaw_deg\nleft,0.1,0.08,0\n", ".csv");
  EXPECT_TRUE(ReadFootstepFile(csv, Stance(l.width), l, &steps, &error)) << error;
  EXPECT_EQ(steps.size(), 1u);
  const std::string txt = runner::Temp("foot,x,y,yaw_deg\n", ".txt");
  EXPECT_FALSE(ReadFootstepFile(txt, Stance(l.width), l, &steps, &error));
  EXPECT_NE(error.find(".yaml, .yml or .csv"), std::string::npos) << error;
  EXPECT_FALSE(ReadFootstepFile("/nonexistent/steps.yaml", Stance(l.width), l, &steps, &error));
  EXPECT_NE(error.find("/nonexistent/steps.yaml: cannot be read"), std::string::npos) << error;
  std::remove(csv.c_str());
  std::remove(txt.c_str());
}

// the YAML and CSV examples of docs/footsteps.md read, and give the same steps
TEST(FootstepFile, TheDocsExamplesRead) {
  std::ifstream in(std::string(OHRP_SOURCE_DIR) + "/docs/footsteps.md");
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  auto block = [&](const std::string& section, const std::string& fence) {
    const size_t at = text.find(fence, text.find(section));
    const size_t from = text.find('\n', at) + 1;
    return text.substr(from, text.find("```", from) - from);
  };
  const std::string yaml = block("### YAML", "```yaml"), csv = block("### CSV", "```");
  const StepLimits l;
  const FeetPose start = Stance(0.18);
  std::vector<Footstep> a, b;
  std::string error;
  ASSERT_TRUE(ParseFootstepText(yaml, FootstepFormat::kYaml, "doc.yaml", start, l, &a, &error))
      << error << "\n"
      << yaml;
  ASSERT_TRUE(ParseFootstepText(csv, FootstepFormat::kCsv, "doc.csv", start, l, &b, &error))
      << error << "\n"
      << csv;
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].p, b[k].p);
    EXPECT_EQ(a[k].height, b[k].height);
    EXPECT_EQ(a[k].duration, b[k].duration);
  }
}

//---------------- errors: file, line, key ----------------

const char kHead[] = "steps:\n  - {foot: left, x: 0.2, y: 0.08, yaw_deg: 0}\n";  // lines 1-2

TEST(FootstepFileErrors, UnknownKeys) {
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.4, y: -0.08, yawdeg: 0}\n",
              "steps.yaml:3: ", {"unknown key 'yawdeg'", "yaw_deg"});
  ExpectError("speed: 2\n" + std::string(kHead),
              "steps.yaml:1: ", {"unknown key 'speed'", "steps"});
  ExpectError("defaults: {height: 0.05, width: 0.2}\n" + std::string(kHead),
              "steps.yaml:1: ", {"defaults: unknown key 'width'", "height"});
  ExpectError("foot,x,y,yaw,yaw_deg\n", "steps.csv:1: ", {"unknown column 'yaw'", "yaw_deg"},
              FootstepFormat::kCsv);
}

TEST(FootstepFileErrors, WrongTypes) {
  ExpectError(std::string(kHead) + "  - foot: right\n    x: far\n    y: -0.08\n    yaw_deg: 0\n",
              "steps.yaml:4: ", {"x: must be a finite number", "'far'"});
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.4, y: [0], yaw_deg: 0}\n",
              "steps.yaml:3: ", {"y: must be a single value"});
  ExpectError(std::string(kHead) + "  - {foot: l, x: 0.4, y: -0.08, yaw_deg: 0}\n",
              "steps.yaml:3: ", {"foot: must be left or right", "'l'"});
  ExpectError("frame: robot\n" + std::string(kHead),
              "steps.yaml:1: ", {"frame: must be start or world"});
  ExpectError("steps: 3\n", "steps.yaml:1: ", {"steps: must be a list"});
  ExpectError("foot,x,y,yaw_deg\nleft,0.1,0.08,.nan\n",
              "steps.csv:2: ", {"yaw_deg: must be a finite number"}, FootstepFormat::kCsv);
  ExpectError("foot,x,y,yaw_deg\nleft,0.1,0.08\n",
              "steps.csv:2: ", {"row: 3 cells", "header has 4"}, FootstepFormat::kCsv);
}

TEST(FootstepFileErrors, MissingKeys) {
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.4, yaw_deg: 0}\n",
              "steps.yaml:3: ", {"missing key 'y'"});
  ExpectError("frame: start\n", "steps.yaml:1: ", {"steps: missing"});
  ExpectError("steps: []\n", "steps.yaml:1: ", {"steps: the file holds no step"});
  ExpectError("foot,x,yaw_deg\n", "steps.csv:1: ", {"header: missing key 'y'"},
              FootstepFormat::kCsv);
  ExpectError("foot,x,y,yaw_deg\nleft,,0.08,0\n", "steps.csv:2: ", {"x: empty"},
              FootstepFormat::kCsv);
}

TEST(FootstepFileErrors, ValuesOutOfRange) {
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.4, y: -0.08, yaw_deg: 0, height: 0.8}\n",
              "steps.yaml:3: ", {"height: ", "0 .. 0.5 m"});
  ExpectError("defaults:\n  duration: 0\n" + std::string(kHead),
              "steps.yaml:2: ", {"duration: ", "above 0 .. 10 s"});
}

TEST(FootstepFileErrors, TheSameFootTwiceOnlyWhenTheStepSaysSo) {
  ExpectError(std::string(kHead) + "  - {foot: left, x: 0.3, y: 0.1, yaw_deg: 0}\n",
              "steps.yaml:3: ", {"foot: left again", "same_foot: true"});
  EXPECT_EQ(ErrorOf(std::string(kHead) +
                    "  - {foot: left, x: 0.25, y: 0.1, yaw_deg: 0, same_foot: true}\n"),
            "");
  ExpectError(
      std::string(kHead) + "  - {foot: right, x: 0.3, y: -0.08, yaw_deg: 0, same_foot: true}\n",
      "steps.yaml:3: ", {"same_foot: ", "by the left foot"});
}

TEST(FootstepFileErrors, FeetThatCrossAndStepsBeyondTheLimits) {
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.4, y: 0.2, yaw_deg: 0}\n",
              "steps.yaml:3: ", {"y: step 2 (right)", "cross"});
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.6, y: -0.08, yaw_deg: 0}\n",
              "steps.yaml:3: ", {"x: step 2 (right)", "max_forward", "0.400 m ahead"});
  ExpectError("foot,x,y,yaw_deg\nleft,0,0.08,30\n",
              "steps.csv:2: ", {"yaw_deg: step 1 (left)", "max_turn"}, FootstepFormat::kCsv);
}

TEST(FootstepFileErrors, KeysGivenTwice) {
  ExpectError(std::string(kHead) + "  - {foot: right, x: 0.4, x: 0.3, y: -0.08, yaw_deg: 0}\n",
              "steps.yaml:3: ", {"x: given twice"});
  ExpectError("frame: start\n" + std::string(kHead) + "frame: world\n",
              "steps.yaml:4: ", {"frame: given twice"});
  ExpectError("foot,x,y,x,yaw_deg\n", "steps.csv:1: ", {"x: column given twice"},
              FootstepFormat::kCsv);
}

TEST(FootstepFileErrors, YamlThatDoesNotParse) {
  ExpectError("steps:\n  - {foot: left, x: 0.2\n", "steps.yaml:", {"not valid YAML"});
  ExpectError("- 1\n- 2\n", "steps.yaml:1: ", {"must be a mapping"});
}

// every prefix and random byte changes of the example: an answer, never a crash
TEST(FootstepFileErrors, DamagedFilesGetAnAnswer) {
  std::ifstream in(kExample);
  std::stringstream text;
  text << in.rdbuf();
  const std::string example = text.str();
  for (size_t cut = 0; cut < example.size(); cut += 7) {
    const std::string e = ErrorOf(example.substr(0, cut));
    if (!e.empty()) {
      EXPECT_EQ(e.rfind("steps.yaml:", 0), 0u) << e;
    }
  }
  std::mt19937 random(3);
  const std::string bytes = "{}[]:,-# \n\"'&*!|>%@`0123456789.abcxyz\t\xff";
  for (int i = 0; i < 300; ++i) {
    std::string t = example;
    for (int k = 0; k < 4; ++k)
      t[std::uniform_int_distribution<size_t>(0, t.size() - 1)(random)] =
          bytes[std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(random)];
    const std::string e = ErrorOf(t);
    if (!e.empty()) {
      EXPECT_EQ(e.rfind("steps.yaml:", 0), 0u) << e;
    }
    const std::string c = ErrorOf(t, FootstepFormat::kCsv);
    EXPECT_FALSE(c.empty());  // YAML is not CSV
  }
}

}  // namespace
}  // namespace ohrp::walking
