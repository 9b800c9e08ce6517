// The tests' scratch folder (scratch.h): unique per process, removed at the exit of the process
// that made it and only of that one.
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

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// runs `body` in a forked child that ends with exit() (static destruction runs, as at the end of
// a test program); returns what the child wrote to the pipe
std::string InChild(const std::function<std::string()>& body) {
  int fds[2];
  EXPECT_EQ(pipe(fds), 0);
  const pid_t child = Spawn([&] {
    const std::string said = body();
    if (write(fds[1], said.data(), said.size()) != static_cast<ssize_t>(said.size())) _exit(3);
    std::exit(0);
    return 0;
  });
  close(fds[1]);
  std::string said;
  char buf[512];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) said.append(buf, n);
  close(fds[0]);
  EXPECT_EQ(WaitExit(child), 0);
  return said;
}

TEST(Scratch, TheFolderIsRemovedWithItsFilesWhenTheProcessThatMadeItExits) {
  // this process has not made its folder yet: the child makes its own
  const std::string dir = InChild([] {
    ScratchFile("inside", "text");
    ScratchFolder("sub");
    return ScratchDir();
  });
  ASSERT_FALSE(dir.empty());
  EXPECT_FALSE(fs::exists(dir)) << dir;
  EXPECT_NE(dir, ScratchDir()) << "a second process gets a folder of its own";
}

TEST(Scratch, AForkedChildsExitLeavesTheFolderOfTheProcessThatMadeIt) {
  const std::string dir = ScratchDir();
  const std::string file = InChild([] { return ScratchFile("from_child", "written by the child"); });
  EXPECT_EQ(fs::path(file).parent_path(), fs::path(dir));
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_EQ(Read(file), "written by the child");
}

TEST(Scratch, EveryPathIsFreshAndInTheFolder) {
  const std::string a = ScratchPath("log", ".csv"), b = ScratchPath("log", ".csv");
  EXPECT_NE(a, b);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_EQ(fs::path(a).parent_path(), fs::path(ScratchDir()));
  EXPECT_EQ(fs::path(a).extension(), ".csv");
  const std::string f = ScratchFile("scenario", "name: x\n", ".yaml");
  EXPECT_EQ(Read(f), "name: x\n");
  const std::string d = ScratchFolder("out");
  EXPECT_TRUE(fs::is_directory(d));
  EXPECT_TRUE(fs::is_empty(d));
}

}  // namespace
}  // namespace ohrp::testing
