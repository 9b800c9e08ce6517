// The tests' scratch folder (scratch.h): unique per process, removed at the exit of the process
// that made it and only of that one, kept when a test of that process failed.
#include "common/scratch.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/process.h"

namespace ohrp::testing {
namespace {

namespace fs = std::filesystem;

// The two test programs below, each run alone as a process of its own by the tests that follow
// (disabled: they do not run in the suite themselves). Each writes into its scratch folder and
// prints the folder's path; the second fails on purpose.
TEST(DISABLED_ScratchProgram, Passes) {
  ScratchFile("inside", "text");
  ScratchFolder("sub");
  std::printf("SCRATCH %s\n", ScratchDir().c_str());
}

TEST(DISABLED_ScratchProgram, Fails) {
  ScratchFile("evidence", "what the failed test wrote");
  std::printf("SCRATCH %s\n", ScratchDir().c_str());
  ADD_FAILURE() << "on purpose: a failed test's scratch folder is kept";
}

struct ProgramRun {
  int code = -1;
  std::string dir;  // the folder it printed
};

// runs one of the programs above in a new process of this test binary
ProgramRun RunProgram(const std::string& test) {
  const std::string out = ScratchPath("program", ".out");
  const pid_t pid = Spawn({fs::read_symlink("/proc/self/exe").string(),
                           "--gtest_also_run_disabled_tests",
                           "--gtest_filter=DISABLED_ScratchProgram." + test},
                          ToFile(out));
  ProgramRun r;
  r.code = WaitExit(pid, 30.0);
  const std::string text = ReadFile(out);
  const std::size_t at = text.find("SCRATCH ");
  if (at != std::string::npos) r.dir = text.substr(at + 8, text.find('\n', at) - at - 8);
  return r;
}

TEST(Scratch, TheFolderIsRemovedWithItsFilesWhenTheProgramsTestsPassed) {
  const ProgramRun r = RunProgram("Passes");
  EXPECT_EQ(r.code, 0);
  ASSERT_FALSE(r.dir.empty());
  EXPECT_FALSE(fs::exists(r.dir)) << r.dir;
  EXPECT_NE(r.dir, ScratchDir()) << "each process has a folder of its own";
}

TEST(Scratch, AProgramWhoseTestFailedKeepsItsFolderForALook) {
  const ProgramRun r = RunProgram("Fails");
  EXPECT_EQ(r.code, 1);
  ASSERT_FALSE(r.dir.empty());
  EXPECT_TRUE(fs::is_directory(r.dir)) << r.dir;
  EXPECT_EQ(ReadFile(r.dir + "/evidence_0"), "what the failed test wrote");
  fs::remove_all(r.dir);
}

TEST(Scratch, AForkedChildsExitLeavesTheFolderOfTheProcessThatMadeIt) {
  const std::string dir = ScratchDir();
  const std::string file = ScratchPath("from_child");
  // a forked child shares this process's folder; its exit() runs the static destructors
  const pid_t child = Spawn([&] {
    std::ofstream(file) << "written by the child";
    std::exit(0);
    return 0;
  });
  EXPECT_EQ(WaitExit(child), 0);
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_EQ(ReadFile(file), "written by the child");
}

TEST(Scratch, EveryPathIsFreshAndInTheFolder) {
  const std::string a = ScratchPath("log", ".csv"), b = ScratchPath("log", ".csv");
  EXPECT_NE(a, b);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_EQ(fs::path(a).parent_path(), fs::path(ScratchDir()));
  EXPECT_EQ(fs::path(a).extension(), ".csv");
  const std::string f = ScratchFile("scenario", "name: x\n", ".yaml");
  EXPECT_EQ(ReadFile(f), "name: x\n");
  const std::string d = ScratchFolder("out");
  EXPECT_TRUE(fs::is_directory(d));
  EXPECT_TRUE(fs::is_empty(d));
}

}  // namespace
}  // namespace ohrp::testing
