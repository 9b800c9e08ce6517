// sim_host's outputs as a process (issue 28 item 3): the data log and the summary are checked
// writable before anything runs (exit 2 naming the path and the reason), a full disk under the
// log is a failed run (exit 9, the file and the error named, the summary's log_rows = the rows
// in the file, an event), and --log-max bounds the log and says what it left out.

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>

#include "common/scratch.h"
#include "host_process.h"

namespace ohrp::sim {
namespace {

namespace fs = std::filesystem;
using testing::SimHostProcess;

nlohmann::json ReadJson(const std::string& path) {
  try {
    return nlohmann::json::parse(ohrp::testing::ReadFile(path));
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": " << e.what();
    return nlohmann::json::object();
  }
}

// data rows of a CSV log (lines after the header), and whether it ends with a whole line
size_t DataRows(const std::string& path, bool* whole) {
  const std::string text = ohrp::testing::ReadFile(path);
  *whole = !text.empty() && text.back() == '\n';
  const size_t lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  return lines > 0 ? lines - 1 : 0;
}

bool HasEvent(const nlohmann::json& summary, const std::string& kind) {
  for (const auto& e : summary.value("events", nlohmann::json::array()))
    if (e.value("event", std::string()) == kind) return true;
  return false;
}

TEST_F(SimHostProcess, OutputsThatCannotBeWrittenAreRefusedBeforeTheRun) {
  const std::string summary = ohrp::testing::ScratchPath("summary", ".json");
  for (const auto& [option, path, reason] :
       {std::tuple<std::string, std::string, std::string>{"--log", "/proc/version", ""},
        {"--log", "/nonexistent/log.csv", "No such file or directory"},
        {"--log", "/dev/full", "No space left on device"},
        {"--summary", "/nonexistent/x", "No such file or directory"},
        {"--summary", "/proc/version", ""}}) {
    Start({"--duration", "0.1", "--wait-controller", "0", option, path});
    EXPECT_EQ(Wait(), 2) << option << " " << path << ": " << Stderr();
    EXPECT_NE(Stderr().find(option + ": cannot write"), std::string::npos) << Stderr();
    EXPECT_NE(Stderr().find("'" + path + "'"), std::string::npos) << Stderr();
    EXPECT_NE(Stderr().find(reason), std::string::npos) << Stderr();
    EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_))) << "no segment made";
  }
}

TEST_F(SimHostProcess, TheSummarySaysRunningUntilTheEnd) {
  const std::string summary = ohrp::testing::ScratchPath("summary", ".json");
  Start({"--duration", "1", "--wait-controller", "30", "--summary", summary});
  ASSERT_TRUE(WaitSegment());
  // written just after the segment is made, before the run (waiting for its controller)
  for (int i = 0; i < 500 && ohrp::testing::ReadFile(summary).empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_EQ(ReadJson(summary).value("outcome", std::string()), "running");
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130);
  EXPECT_EQ(ReadJson(summary).value("outcome", std::string()), "interrupted");
}

// the figures: with the disk full, sim_host wrote 161 of 2001 rows and said 2001, exit 0
TEST_F(SimHostProcess, AFullDiskUnderTheLogIsAFailedRunWithTheRowsOnDiskCounted) {
  const ohrp::testing::ScratchTmpfs disk("64k");
  if (disk.dir().empty())
    GTEST_SKIP() << disk.why() << "; robot_model_recorder_test fails a write with a file size "
                 << "limit instead";
  const std::string& dir = disk.dir();
  const std::string log = dir + "/log.csv";
  const std::string summary = ohrp::testing::ScratchPath("summary", ".json");
  // paced to the wall clock: the tmpfs fills in about 1 s, and the run must end there, not at 20 s
  Start({"--duration", "20", "--realtime", "--wait-controller", "0", "--log", log, "--summary", summary});
  EXPECT_EQ(Wait(20), 9) << Stderr();
  EXPECT_NE(Stderr().find(log), std::string::npos) << Stderr();
  EXPECT_NE(Stderr().find("No space left on device"), std::string::npos) << Stderr();
  const nlohmann::json s = ReadJson(summary);
  EXPECT_EQ(s.value("outcome", std::string()), "log_failed");
  EXPECT_EQ(s.value("exit_code", 0), 9);
  EXPECT_NE(s.value("log_error", std::string()).find("No space left on device"), std::string::npos);
  EXPECT_TRUE(HasEvent(s, "log_write_failed")) << s.dump(2);
  bool whole = false;
  const size_t rows = DataRows(log, &whole);
  EXPECT_TRUE(whole) << "the last row cut in the middle";
  EXPECT_GT(rows, 10u);
  EXPECT_EQ(s.value("log_rows", 0ul), rows) << "the summary counts the rows on disk";
  EXPECT_LT(s.value("sim_time", 99.0), 5.0) << "the run ended at the failure";
}

TEST_F(SimHostProcess, LogMaxBoundsTheLogAndSaysHowManyRowsItLeftOut) {
  const std::string log = ohrp::testing::ScratchPath("bounded", ".csv");
  const std::string summary = ohrp::testing::ScratchPath("summary", ".json");
  Start({"--duration", "2", "--wait-controller", "0", "--log", log, "--log-max", "20k",
         "--summary", summary});
  EXPECT_EQ(Wait(20), 0) << Stderr();
  EXPECT_LE(fs::file_size(log), 20000u);
  const nlohmann::json s = ReadJson(summary);
  bool whole = false;
  const size_t rows = DataRows(log, &whole);
  EXPECT_TRUE(whole);
  EXPECT_EQ(s.value("log_rows", 0ul), rows);
  // 2 s at 2 ms: 1001 rows published (the first at t = 0), those not on disk counted
  EXPECT_EQ(rows + s.value("log_rows_over_limit", 0ul) + s.value("log_dropped", 0ul), 1001u) << s.dump(2);
  EXPECT_GT(s.value("log_rows_over_limit", 0ul), 0u);
  EXPECT_EQ(s.value("log_max_bytes", 0ul), 20000u);
  EXPECT_TRUE(HasEvent(s, "log_limit_reached"));
  EXPECT_NE(Stderr().find("later rows not written"), std::string::npos) << Stderr();
  // a bad size is refused before the run
  Start({"--duration", "2", "--wait-controller", "0", "--log", log, "--log-max", "20X"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("--log-max: '20X'"), std::string::npos) << Stderr();
}

// --contact-file: the soles of a file (as `ohrp identify` writes DIR/soles.yaml) reach the run
// (the summary's contact_params); a --contact-* option given as well wins; a bad file exits 2
// naming the file, the line and the key, before anything runs
TEST_F(SimHostProcess, AContactFileSetsTheSolesAndAnOptionGivenAsWellWins) {
  scene_ = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  const std::string file = ohrp::testing::ScratchPath("soles", ".yaml");
  std::ofstream(file) << "# identified\ncontact_params:\n  stiffness: 2.0e6\n  damping: 45\n"
                         "identified: {stiffness_se: 1.0e4, recording: robot.csv}\n";
  const std::string summary = ohrp::testing::ScratchPath("summary", ".json");
  Start({"--contact", "soft", "--contact-file", file, "--contact-damping", "50", "--duration", "0.02",
         "--wait-controller", "0", "--summary", summary});
  ASSERT_EQ(Wait(30), 0) << Stderr();
  const nlohmann::json j = ReadJson(summary);
  EXPECT_EQ(j["contact_params"]["stiffness"].get<double>(), 2.0e6) << j.dump();
  EXPECT_EQ(j["contact_params"]["damping"].get<double>(), 50.0);  // the option wins
  EXPECT_EQ(j["contact_file"].get<std::string>(), file);

  std::ofstream(file) << "contact_params:\n  stiffness: 2.0e6\n  damping: -45\n";
  Start({"--contact", "soft", "--contact-file", file, "--duration", "0.02", "--wait-controller", "0"});
  EXPECT_EQ(Wait(30), 2);
  EXPECT_NE(Stderr().find(file + ":3: contact_params: damping: must be a number > 0, not -45"), std::string::npos)
      << Stderr();
  std::ofstream(file) << "contact_params:\n  stifness: 2.0e6\n";
  Start({"--contact", "soft", "--contact-file", file, "--duration", "0.02", "--wait-controller", "0"});
  EXPECT_EQ(Wait(30), 2);
  EXPECT_NE(Stderr().find(file + ":2: contact_params: stifness: unknown key"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

// a robot profile's contact_file (relative to the profile) is the --contact-file by default; a
// --contact-file given wins; a profile naming a file that is not there is refused (exit 2)
TEST_F(SimHostProcess, AProfilesContactFileSetsTheSoles) {
  const std::string dir = ohrp::testing::ScratchFolder("profile_soles");
  std::ofstream(dir + "/soles.yaml") << "contact_params:\n  stiffness: 3.0e6\n  damping: 40\n";
  const std::string head = "model: " + std::string(OHRP_SOURCE_DIR) +
                           "/mjcf/hrp1s/scene_flat.xml\nfeet:\n  left: {body: LLEG_ANKLE_R}\n"
                           "  right: {body: RLEG_ANKLE_R}\nforce_torque: none\nimu: none\n";
  std::ofstream(dir + "/robot.yaml") << head << "contact_file: soles.yaml\n";
  scene_ = dir + "/robot.yaml";
  const std::string summary = ohrp::testing::ScratchPath("summary", ".json");
  Start({"--contact", "soft", "--duration", "0.02", "--wait-controller", "0", "--summary", summary});
  ASSERT_EQ(Wait(30), 0) << Stderr();
  nlohmann::json j = ReadJson(summary);
  EXPECT_EQ(j["contact_params"]["stiffness"].get<double>(), 3.0e6) << j.dump();
  EXPECT_EQ(j["contact_params"]["damping"].get<double>(), 40.0);
  EXPECT_EQ(j["contact_file"].get<std::string>(), dir + "/soles.yaml");
  // a --contact-file given wins over the profile's
  const std::string other = ohrp::testing::ScratchPath("other_soles", ".yaml");
  std::ofstream(other) << "contact_params:\n  stiffness: 1.5e6\n";
  Start({"--contact", "soft", "--contact-file", other, "--duration", "0.02", "--wait-controller",
         "0", "--summary", summary});
  ASSERT_EQ(Wait(30), 0) << Stderr();
  j = ReadJson(summary);
  EXPECT_EQ(j["contact_params"]["stiffness"].get<double>(), 1.5e6) << j.dump();
  // a profile naming a file that is not there
  std::ofstream(dir + "/robot.yaml") << head << "contact_file: nosuch.yaml\n";
  Start({"--contact", "soft", "--duration", "0.02", "--wait-controller", "0"});
  EXPECT_EQ(Wait(30), 2);
  EXPECT_NE(Stderr().find("robot.yaml:7: contact_file: no such file"), std::string::npos) << Stderr();
}

}  // namespace
}  // namespace ohrp::sim
