// The producers' outputs (robot_model/output_file.h): a summary or stats file checked writable
// before the run and written whole; the byte sizes of --log-max.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>

#include "common/scratch.h"
#include "robot_model/output_file.h"

namespace ohrp::model {
namespace {

using ohrp::testing::ReadFile;
using ohrp::testing::ScratchPath;

TEST(OutputFile, PrepareRefusesWhatCannotBeWrittenAndLeavesTheProvisionalText) {
  std::string error;
  const std::string ok = ScratchPath("summary", ".json");
  ASSERT_TRUE(PrepareOutputFile(ok, "{\"outcome\": \"running\"}\n", &error)) << error;
  EXPECT_EQ(ReadFile(ok), "{\"outcome\": \"running\"}\n");
  for (const std::string path : {"/nonexistent/x", "/proc/version", "/dev/full"}) {
    EXPECT_FALSE(PrepareOutputFile(path, "{}\n", &error)) << path;
    EXPECT_EQ(error.rfind("cannot write '" + path + "': ", 0), 0u) << error;
  }
  EXPECT_FALSE(WriteWholeFile("/dev/full", "{}\n", &error));
  EXPECT_NE(error.find("No space left on device"), std::string::npos) << error;
}

TEST(OutputFile, ByteSizes) {
  std::string error;
  uint64_t b = 0;
  const std::pair<const char*, uint64_t> good[] = {{"500000", 500000}, {"500k", 500000}, {"20M", 20000000},
                                                   {"1.5G", 1500000000}, {"1KiB", 1024}, {"2MiB", 2097152},
                                                   {"3MB", 3000000}};
  for (const auto& [text, bytes] : good) {
    EXPECT_TRUE(ParseByteSize(text, &b, &error)) << text << ": " << error;
    EXPECT_EQ(b, bytes) << text;
  }
  for (const char* bad : {"", "x", "0", "-5", "5X", "1e300", "nan", "0.1"}) {
    EXPECT_FALSE(ParseByteSize(bad, &b, &error)) << bad;
    EXPECT_NE(error.find("500k"), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace ohrp::model
