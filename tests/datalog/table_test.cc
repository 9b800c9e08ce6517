// datalog::Table, the one reader of the data log: columns by name, CRLF and blank lines taken,
// every malformed row refused naming the file, the line and the column.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "common/scratch.h"
#include "datalog/table.h"

namespace ohrp::datalog {
namespace {

std::string Write(const std::string& tag, const std::string& text) {
  const std::string path = ohrp::testing::ScratchPath(tag, ".csv");
  std::ofstream(path) << text;
  return path;
}

TEST(Table, ReadsColumnsByName) {
  const std::string path = Write("ok", "time,q_A,tau_A\r\n0.0,1.5,-2\r\n\r\n0.005, 1.25 ,nan\n");
  Table t;
  std::string error;
  ASSERT_TRUE(t.Load(path, &error)) << error;
  EXPECT_EQ(t.rows(), 2u);
  ASSERT_EQ(t.Column("q_A"), 1);
  EXPECT_EQ(t.Column("tau_A"), 2);  // the header's '\r' is not part of the name
  EXPECT_EQ(t.Column("q_B"), -1);
  EXPECT_DOUBLE_EQ(t.col(0)[1], 0.005);
  EXPECT_DOUBLE_EQ(t.col(1)[1], 1.25);
  EXPECT_TRUE(std::isnan(t.col(2)[1]));
  EXPECT_EQ(t.line(0), 2u);
  EXPECT_EQ(t.line(1), 4u);  // after the blank line
}

TEST(Table, MalformedRowsAreRefusedNamingTheLineAndColumn) {
  Table t;
  std::string error;
  EXPECT_FALSE(t.Load("/nonexistent/log.csv", &error));
  EXPECT_EQ(error, "cannot read the data log '/nonexistent/log.csv'");
  const std::string empty = Write("empty", "");
  EXPECT_FALSE(t.Load(empty, &error));
  EXPECT_EQ(error, "the data log '" + empty + "' is empty (expected a header line of column names)");
  const std::string short_row = Write("short", "time,q_A\n0,1\n0.005\n");
  EXPECT_FALSE(t.Load(short_row, &error));
  EXPECT_EQ(error, short_row + ":3: 1 fields, the header has 2");
  const std::string long_row = Write("long", "time,q_A\n0,1,2\n");
  EXPECT_FALSE(t.Load(long_row, &error));
  EXPECT_EQ(error, long_row + ":2: 3 fields, the header has 2");
  const std::string word = Write("word", "time,q_A\n0,1\n0.005,1.0x\n");
  EXPECT_FALSE(t.Load(word, &error));
  EXPECT_EQ(error, word + ":3: '1.0x' in column 'q_A' is not a number");
}

}  // namespace
}  // namespace ohrp::datalog
