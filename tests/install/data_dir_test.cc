// cli/data_dir.h: where programs find the data. OHRP_DATA_DIR wins; else <program>/../share/ohrp,
// which in the build tree is the link to the checkout (cmake/OhrpData.cmake), so the libraries'
// defaults (controllers' pose and self-collision files) are the checkout's files here and the
// prefix's files when installed.
#include "cli/data_dir.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>

#include "controllers/posture.h"
#include "controllers/runner.h"

namespace fs = std::filesystem;

namespace {

// sets OHRP_DATA_DIR for one test, restores it after
class DataDirEnv {
 public:
  explicit DataDirEnv(const char* value) {
    if (const char* old = std::getenv("OHRP_DATA_DIR")) old_ = old, had_ = true;
    if (value) setenv("OHRP_DATA_DIR", value, 1); else unsetenv("OHRP_DATA_DIR");
  }
  ~DataDirEnv() {
    if (had_) setenv("OHRP_DATA_DIR", old_.c_str(), 1); else unsetenv("OHRP_DATA_DIR");
  }

 private:
  std::string old_;
  bool had_ = false;
};

TEST(DataDir, EnvironmentWins) {
  DataDirEnv env("/opt/elsewhere/share/ohrp");
  EXPECT_EQ(ohrp::cli::DataDir(), "/opt/elsewhere/share/ohrp");
  EXPECT_EQ(ohrp::cli::DataPath("mjcf/hrp1s/hrp1s.xml"), "/opt/elsewhere/share/ohrp/mjcf/hrp1s/hrp1s.xml");
  EXPECT_EQ(ohrp::controllers::DefaultPoseFile(),
            "/opt/elsewhere/share/ohrp/controllers/poses/hrp1s_halfsit.yaml");
  EXPECT_EQ(ohrp::controllers::DefaultSelfCollisionFile(),
            "/opt/elsewhere/share/ohrp/mjcf/hrp1s/selfcollision.yaml");
}

TEST(DataDir, EmptyEnvironmentIsUnset) {
  DataDirEnv empty("");
  const std::string from_empty = ohrp::cli::DataDir();
  DataDirEnv unset(nullptr);
  EXPECT_EQ(from_empty, ohrp::cli::DataDir());
}

TEST(DataDir, BesideTheProgram) {
  DataDirEnv unset(nullptr);
  const fs::path exe = fs::canonical("/proc/self/exe");
  EXPECT_TRUE(fs::equivalent(ohrp::cli::DataDir(), exe.parent_path().parent_path() / "share" / "ohrp"));
}

// the link resolved: a scenario's "../shared/..." (the runner joins and normalizes lexically)
// names the folder beside the checkout, as it did when the checkout's path was compiled in
TEST(DataDir, ParentIsTheCheckoutsParent) {
  DataDirEnv unset(nullptr);
  EXPECT_EQ((fs::path(ohrp::cli::DataDir()) / "..").lexically_normal(),
            (fs::canonical(OHRP_SOURCE_DIR) / "..").lexically_normal());
}

TEST(DataDir, BuildTreeReadsTheCheckout) {
  DataDirEnv unset(nullptr);
  for (const char* file : {"mjcf/hrp1s/hrp1s.xml", "scenarios/stand.yaml", "tools/view/web/index.html",
                           "controllers/poses/hrp1s_halfsit.yaml"}) {
    const std::string found = ohrp::cli::DataPath(file);
    ASSERT_TRUE(fs::exists(found)) << found;
    EXPECT_TRUE(fs::equivalent(found, fs::path(OHRP_SOURCE_DIR) / file)) << found;
  }
  EXPECT_TRUE(fs::equivalent(ohrp::controllers::DefaultPoseFile(),
                             fs::path(OHRP_SOURCE_DIR) / "controllers/poses/hrp1s_halfsit.yaml"));
  EXPECT_TRUE(fs::equivalent(ohrp::controllers::DefaultSelfCollisionFile(),
                             fs::path(OHRP_SOURCE_DIR) / "mjcf/hrp1s/selfcollision.yaml"));
}

}  // namespace
