#include "common/scratch.h"

#include <errno.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace ohrp::testing {

namespace fs = std::filesystem;

namespace {

// the folder and the process that made it; removed by that process's static destruction,
// unless a test of the process failed
struct Scratch {
  std::string dir;
  pid_t owner = -1;
  int next = 0;
  ~Scratch() {
    if (owner != getpid() || dir.empty()) return;
    if (::testing::UnitTest::GetInstance()->Failed()) {
      std::fprintf(stderr, "a test failed: its scratch folder %s is kept for a look\n",
                   dir.c_str());
      return;
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

Scratch& TheScratch() {
  static Scratch s;
  if (s.dir.empty()) {
    const char* program = program_invocation_short_name;
    std::string name = (fs::temp_directory_path() /
                        ("ohrp_test_" + std::string(program ? program : "test") + "_XXXXXX"))
                           .string();
    if (mkdtemp(name.data()) == nullptr)
      throw std::runtime_error("cannot make a scratch folder '" + name +
                               "': " + std::strerror(errno));
    s.dir = name;
    s.owner = getpid();
  }
  return s;
}

}  // namespace

const std::string& ScratchDir() { return TheScratch().dir; }

std::string ScratchPath(const std::string& tag, const std::string& suffix) {
  Scratch& s = TheScratch();
  return s.dir + "/" + tag + "_" + std::to_string(s.next++) + suffix;
}

std::string ScratchFile(const std::string& tag, const std::string& text,
                        const std::string& suffix) {
  const std::string p = ScratchPath(tag, suffix);
  std::ofstream out(p);
  out << text;
  if (!out.flush()) throw std::runtime_error("cannot write the scratch file '" + p + "'");
  return p;
}

std::string ScratchFolder(const std::string& tag) {
  const std::string p = ScratchPath(tag);
  fs::create_directory(p);
  return p;
}

ScratchTmpfs::ScratchTmpfs(const std::string& size) {
  const std::string dir = ScratchFolder("tmpfs");
  if (mount("ohrp_test", dir.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0) {
    dir_ = dir;
  } else {
    why_ = std::string("cannot mount a tmpfs here: ") + std::strerror(errno);
  }
}

ScratchTmpfs::~ScratchTmpfs() {
  if (!dir_.empty()) umount2(dir_.c_str(), MNT_DETACH);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace ohrp::testing
