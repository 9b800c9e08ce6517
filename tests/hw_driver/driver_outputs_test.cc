// hw_driver's outputs (issue 28 item 3, the few lines in hw_driver/driver/src/program.cc): --log,
// --summary and --stats checked writable before anything runs (exit 2, path and reason), a full
// disk under the log is exit 9 with the rows ON DISK reported (the issue: "4103 rows" said, 189 on
// disk), and --log-max bounds the log.

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <regex>

#include "driver_process.h"

namespace ohrp::hw {
namespace {

namespace fs = std::filesystem;
using testing::HwDriverProcess;

// data rows of a CSV log, and whether it ends with a whole line
size_t DataRows(const std::string& path, bool* whole) {
  const std::string text = ohrp::testing::ReadFile(path);
  *whole = !text.empty() && text.back() == '\n';
  const size_t lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  return lines > 0 ? lines - 1 : 0;
}

// the rows the driver's report says are on disk ("data log PATH: N rows on disk")
long ReportedRows(const std::string& err) {
  std::smatch m;
  return std::regex_search(err, m, std::regex(R"(: (\d+) rows on disk)")) ? std::stol(m[1]) : -1;
}

TEST_F(HwDriverProcess, OutputsThatCannotBeWrittenAreRefusedBeforeTheRun) {
  for (const auto& [option, path] : {std::pair<std::string, std::string>{"--log", "/proc/version"},
                                     {"--log", "/dev/full"},
                                     {"--summary", "/nonexistent/x"},
                                     {"--stats", "/proc/version"}}) {
    if (option == "--summary") {  // the fixture's Start gives one
      pid_ = Exec({std::string(OHRP_BIN_DIR) + "/hw_driver", "--model", model_, "--segment", segment_,
                   "--io", FAKE_IO_PATH, "--duration", "0.2", option, path},
                  Path("driver.stderr"));
    } else {
      Start({"--duration", "0.2", option, path});
    }
    EXPECT_EQ(Wait(), 2) << option << " " << path << ": " << Stderr();
    EXPECT_NE(Stderr().find("'" + path + "'"), std::string::npos) << Stderr();
    EXPECT_FALSE(fs::exists(ShmPath())) << "no segment made";
  }
}

TEST_F(HwDriverProcess, AFullDiskUnderTheLogIsExit9WithTheRowsOnDisk) {
  const ohrp::testing::ScratchTmpfs disk("32k");
  if (disk.dir().empty())
    GTEST_SKIP() << disk.why() << "; robot_model_recorder_test fails a write with a file size "
                 << "limit instead";
  const std::string& dir = disk.dir();
  const std::string log = dir + "/log.csv";
  Start({"--duration", "1", "--log", log});
  EXPECT_EQ(Wait(), 9) << Stderr();
  EXPECT_NE(Stderr().find("data log " + log), std::string::npos) << Stderr();
  EXPECT_NE(Stderr().find("No space left on device"), std::string::npos) << Stderr();
  bool whole = false;
  const size_t rows = DataRows(log, &whole);
  EXPECT_TRUE(whole) << "a half row at the end";
  EXPECT_GT(rows, 10u);
  EXPECT_EQ(ReportedRows(Stderr()), static_cast<long>(rows)) << Stderr();
}

TEST_F(HwDriverProcess, LogMaxBoundsTheLog) {
  Start({"--duration", "1", "--log", Path("log.csv"), "--log-max", "20k"});
  EXPECT_EQ(Wait(), 0) << Stderr();
  EXPECT_LE(fs::file_size(Path("log.csv")), 20000u);
  bool whole = false;
  const size_t rows = DataRows(Path("log.csv"), &whole);
  EXPECT_TRUE(whole);
  EXPECT_EQ(ReportedRows(Stderr()), static_cast<long>(rows)) << Stderr();
  EXPECT_NE(Stderr().find("later rows not written"), std::string::npos) << Stderr();
}

}  // namespace
}  // namespace ohrp::hw
