// The producers' data log (datalog/recorder.h) when the disk says no: a failed write (a file
// size limit, a full tmpfs, /dev/full, /proc/version) is detected, the rows ON DISK are counted
// (the file is read back: its whole lines), no half row is left, and --log-max bounds the file.
// Also the output files' checks (robot_model/output_file.h) and --log-max's sizes.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "common/scratch.h"
#include "datalog/recorder.h"

namespace ohrp::datalog {
namespace {

namespace fs = std::filesystem;
using ohrp::testing::ReadFile;
using ohrp::testing::ScratchFolder;
using ohrp::testing::ScratchPath;

const LogNames kNames{{"HIP", "KNEE", "ANKLE"}, {"rfsensor"}, {"gsensor"}, {}};

// row k of a run: numbers of every length, as a real log has
shm::SensorBlock Row(uint64_t k, shm::JointCommand* refs) {
  shm::SensorBlock s{};
  s.cycle = k;
  s.time = 0.005 * static_cast<double>(k + 1);
  for (int i = 0; i < 3; ++i) {
    s.q[i] = std::sin(0.01 * k + i);
    s.tau[i] = 40 * std::cos(0.02 * k + i);
    refs[i].q_ref = s.q[i] + 1e-4;
  }
  for (int i = 0; i < 3; ++i) {
    s.force[0].force[i] = 300 + 10 * i + 0.1 * k;
    s.force[0].torque[i] = 0.5 * i;
  }
  s.imu[0].accel[2] = 9.81;
  s.imu[0].quat_WI[0] = 1;
  s.status = 1;
  return s;
}

// pushes `n` rows, letting the writer keep up; returns the rows the ring took
uint64_t PushRows(Recorder* r, uint64_t n) {
  shm::JointCommand refs[3] = {};
  uint64_t taken = 0;
  for (uint64_t k = 0; k < n; ++k) {
    taken += r->Push(Row(k, refs), refs);
    if (k % 1000 == 999) r->Flush();
  }
  return taken;
}

size_t Lines(const std::string& text) { return static_cast<size_t>(std::count(text.begin(), text.end(), '\n')); }

// the file holds exactly the header and rows_on_disk() whole rows, bytes_on_disk() bytes
void ExpectFileMatchesCounts(const Recorder& r, const std::string& path) {
  const std::string text = ReadFile(path);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "a half row at the end";
  EXPECT_EQ(Lines(text), r.rows_on_disk() + 1) << "header + the rows counted on disk";
  EXPECT_EQ(text.size(), r.bytes_on_disk());
  EXPECT_EQ(fs::file_size(path), r.bytes_on_disk());
}

TEST(Recorder, ACompleteLogCountsEveryRowOnDisk) {
  const std::string path = ScratchPath("complete", ".csv");
  std::string error;
  auto r = Recorder::Open(path, kNames, &error, 4096);
  ASSERT_TRUE(r) << error;
  EXPECT_EQ(PushRows(r.get(), 3000), 3000u);
  EXPECT_TRUE(r->Close());
  EXPECT_FALSE(r->failed());
  EXPECT_EQ(r->rows_on_disk(), 3000u);
  EXPECT_EQ(r->lost(), 0u);
  ExpectFileMatchesCounts(*r, path);
}

// the last column is the controller's guard record (issue 29): 1 in the rows whose commands
// the self-collision guard held, 0 elsewhere (and by default)
TEST(Recorder, TheLastColumnSaysWhetherTheGuardHeld) {
  const std::string path = ScratchPath("guard", ".csv");
  std::string error;
  auto r = Recorder::Open(path, kNames, &error, 16);
  ASSERT_TRUE(r) << error;
  shm::JointCommand refs[3] = {};
  EXPECT_TRUE(r->Push(Row(0, refs), refs));
  EXPECT_TRUE(r->Push(Row(1, refs), refs, 1));
  EXPECT_TRUE(r->Push(Row(2, refs), refs, 0));
  EXPECT_TRUE(r->Close());
  const std::string text = ReadFile(path);
  std::vector<std::string> lines;
  for (size_t a = 0, b; (b = text.find('\n', a)) != std::string::npos; a = b + 1)
    lines.push_back(text.substr(a, b - a));
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0].substr(lines[0].rfind(',')), ",guard_holding") << lines[0];
  const auto last = [](const std::string& l) { return l.substr(l.rfind(',') + 1); };
  EXPECT_EQ(last(lines[1]), "0");
  EXPECT_EQ(last(lines[2]), "1");
  EXPECT_EQ(last(lines[3]), "0");
  // as many numbers in a row as names in the header
  EXPECT_EQ(std::count(lines[0].begin(), lines[0].end(), ','), std::count(lines[2].begin(), lines[2].end(), ','));
}

// the passive joints (issue 31: read-only, e.g. Cassie's shins) are logged as the driven ones
// are: q_<passive>, then dq_<passive>, after the driven joints' columns, with the values of the
// sensor block
TEST(Recorder, PassiveJointsAreLoggedWithTheirPositionAndVelocity) {
  const std::string path = ScratchPath("passive", ".csv");
  const LogNames names{{"HIP"}, {}, {}, {"SHIN", "TARSUS"}};
  std::string error;
  auto r = Recorder::Open(path, names, &error, 16, RecorderChannels{false, true, true, true});
  ASSERT_TRUE(r) << error;
  shm::SensorBlock s{};
  s.time = 0.25;
  s.q[0] = 0.5;
  s.passive_q[0] = -0.125;
  s.passive_q[1] = 1.5;
  s.passive_dq[0] = 2.0;
  s.passive_dq[1] = -3.0;
  shm::JointCommand refs[1] = {};
  EXPECT_TRUE(r->Push(s, refs));
  EXPECT_TRUE(r->Close());
  const std::string text = ReadFile(path);
  EXPECT_EQ(text,
            "time,q_HIP,qref_HIP,tau_HIP,q_SHIN,q_TARSUS,dq_SHIN,dq_TARSUS,status,rejected,"
            "guard_holding\n0.25,0.5,0,0,-0.125,1.5,2,-3,0,0,0\n");
}

// --log-dq (issue 35: the velocity's noise is identified from the log): dq_<joint> after tau_,
// before the passive joints' columns; off by default (the header above has none)
TEST(Recorder, JointVelocitiesAreLoggedWhenAsked) {
  const std::string path = ScratchPath("dq", ".csv");
  const LogNames names{{"HIP", "KNEE"}, {}, {}, {"SHIN"}};
  std::string error;
  RecorderChannels channels{false, true, true, true};
  channels.joint_velocities = true;
  auto r = Recorder::Open(path, names, &error, 16, channels);
  ASSERT_TRUE(r) << error;
  shm::SensorBlock s{};
  s.time = 0.5;
  s.dq[0] = 0.25;
  s.dq[1] = -1.5;
  s.passive_dq[0] = 2.0;
  shm::JointCommand refs[2] = {};
  EXPECT_TRUE(r->Push(s, refs));
  EXPECT_TRUE(r->Close());
  EXPECT_EQ(ReadFile(path),
            "time,q_HIP,q_KNEE,qref_HIP,qref_KNEE,tau_HIP,tau_KNEE,dq_HIP,dq_KNEE,q_SHIN,dq_SHIN,"
            "status,rejected,guard_holding\n0.5,0,0,0,0,0,0,0.25,-1.5,0,2,0,0,0\n");
}

// RLIMIT_FSIZE (SIGXFSZ ignored, as sim_host and hw_driver do): write(2) writes up to the limit,
// mid-row, then fails with EFBIG; the file is cut back to its last whole row
TEST(Recorder, AWriteStoppedByTheFileSizeLimitIsAFailureAndNoHalfRowStays) {
  const std::string path = ScratchPath("fsize", ".csv");
  std::string error;
  auto r = Recorder::Open(path, kNames, &error, 4096);
  ASSERT_TRUE(r) << error;
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  auto* previous = signal(SIGXFSZ, SIG_IGN);
  rlimit small = old;
  small.rlim_cur = 50000;  // bytes; rows are about 200 bytes
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const uint64_t pushed = PushRows(r.get(), 2000);
  const bool complete = r->Close();
  setrlimit(RLIMIT_FSIZE, &old);
  signal(SIGXFSZ, previous);

  EXPECT_FALSE(complete);
  EXPECT_TRUE(r->failed());
  EXPECT_NE(r->error().find(std::strerror(EFBIG)), std::string::npos) << r->error();
  EXPECT_GT(r->rows_on_disk(), 100u);
  EXPECT_LT(r->rows_on_disk(), 2000u);
  EXPECT_EQ(r->rows_on_disk() + r->lost(), pushed) << "every row taken is on disk or lost";
  EXPECT_LE(r->bytes_on_disk(), 50000u);
  ExpectFileMatchesCounts(*r, path);
  // the first row not on disk is the one after the last row of the file
  EXPECT_EQ(r->failure_cycle(), r->rows_on_disk());
  EXPECT_DOUBLE_EQ(r->failure_time(), 0.005 * static_cast<double>(r->rows_on_disk() + 1));
  EXPECT_NE(r->Describe().find("INCOMPLETE"), std::string::npos) << r->Describe();
}

// a small tmpfs filled by the log: ENOSPC, the "disk full" (root only: skipped without)
TEST(Recorder, AFullDiskIsAFailureNamingItAndTheRowsOnDiskAreCounted) {
  const ohrp::testing::ScratchTmpfs disk("64k");
  if (disk.dir().empty())
    GTEST_SKIP() << disk.why() << ": the file size limit test covers the failed write";
  const std::string& dir = disk.dir();
  const std::string path = dir + "/log.csv";
  std::string error;
  auto r = Recorder::Open(path, kNames, &error, 4096);
  ASSERT_TRUE(r) << error;
  const uint64_t pushed = PushRows(r.get(), 2000);
  EXPECT_FALSE(r->Close());
  EXPECT_NE(r->error().find("No space left on device"), std::string::npos) << r->error();
  EXPECT_EQ(r->rows_on_disk() + r->lost(), pushed);
  EXPECT_GT(r->rows_on_disk(), 100u);
  EXPECT_LT(r->rows_on_disk(), 2000u);
  ExpectFileMatchesCounts(*r, path);
}

TEST(Recorder, FilesThatTakeNoDataAreRefusedAtOpen) {
  for (const auto& [path, reason] :
       {std::pair<std::string, std::string>{"/dev/full", "No space left on device"},
        {"/proc/version", ""},  // EIO as root, EACCES otherwise
        {"/nonexistent/log.csv", "No such file or directory"},
        {ScratchFolder("a_folder"), "Is a directory"}}) {
    std::string error;
    EXPECT_FALSE(Recorder::Open(path, kNames, &error)) << path;
    EXPECT_NE(error.find("'" + path + "'"), std::string::npos) << error;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
  }
}

TEST(Recorder, MaxBytesBoundsTheFileAndCountsTheRowsPastIt) {
  const std::string path = ScratchPath("bounded", ".csv");
  std::string error;
  const uint64_t max = 30000;
  auto r = Recorder::Open(path, kNames, &error, 4096, {}, max);
  ASSERT_TRUE(r) << error;
  const uint64_t pushed = PushRows(r.get(), 2000);
  EXPECT_TRUE(r->Close()) << "a bound is no failure";
  EXPECT_TRUE(r->limit_reached());
  EXPECT_LE(fs::file_size(path), max);
  EXPECT_EQ(r->rows_on_disk() + r->over_limit(), pushed);
  ExpectFileMatchesCounts(*r, path);
  // it stopped at the first row that did not fit: less than two rows' room is left
  const double row = static_cast<double>(r->bytes_on_disk()) / static_cast<double>(r->rows_on_disk() + 1);
  EXPECT_LT(static_cast<double>(max - r->bytes_on_disk()), 2 * row);
  EXPECT_EQ(r->limit_cycle(), r->rows_on_disk());
  EXPECT_NE(r->Describe().find(std::to_string(r->over_limit()) + " later rows not written"),
            std::string::npos) << r->Describe();
}

TEST(Recorder, ABoundTooSmallForTheHeaderAndOneRowIsRefused) {
  std::string error;
  EXPECT_FALSE(Recorder::Open(ScratchPath("tiny", ".csv"), kNames, &error, 16, {}, 100));
  EXPECT_NE(error.find("cannot hold"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::datalog
