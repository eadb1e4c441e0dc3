#include "core/dataset.h"
#include "data/csv.h"

#include <gtest/gtest.h>

#include <cmath>

#include <fstream>
#include <sstream>

namespace kfw {
namespace {

Expected<Dataset> parse(const std::string& text) {
  std::istringstream in(text);
  return parse_csv(in, "f.csv");
}

void expect_csv_error(const std::string& text, const std::string& fragment) {
  auto d = parse(text);
  ASSERT_FALSE(d.ok()) << "accepted: " << text;
  EXPECT_NE(d.error().find(fragment), std::string::npos) << d.error();
}

TEST(Csv, ReadsHeaderColumnsAndMissingSamples) {
  auto d = parse("t,gyro,angle\n0,1.5,\n0.01,NaN,2\r\n0.02, 3 ,-4e-1\n");
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->names, (std::vector<std::string>{"t", "gyro", "angle"}));
  ASSERT_EQ(d->rows(), 3u);
  EXPECT_TRUE(std::isnan(d->col("angle")[0]));
  EXPECT_TRUE(std::isnan(d->col("gyro")[1]));
  EXPECT_DOUBLE_EQ(d->col("angle")[2], -0.4);
  EXPECT_DOUBLE_EQ(d->col("gyro")[2], 3.0);
  EXPECT_NEAR(d->median_dt(), 0.01, 1e-15);
}

TEST(Csv, ErrorsNameFileLineAndColumn) {
  expect_csv_error("", "f.csv: empty file");
  expect_csv_error("t,a\n0,1\n0.1,x1\n", "f.csv:3:5: column 'a': 'x1' is not a number");
  expect_csv_error("t,a\n0,1\n0.1,1,2\n", "f.csv:3: expected 2 fields as in the header, found 3");
  expect_csv_error("t,a\n0,1\n0,2\n", "f.csv:3:1: time is not increasing");
  expect_csv_error("t,a\n0,1\n-1,2\n", "f.csv:3:1: time is not increasing");
  expect_csv_error("time,a\n0,1\n", "no time column 't'");
  expect_csv_error("t,a\n0,1\n,2\n", "f.csv:3:1: column 't' is empty");
  expect_csv_error("t,a\n0,inf\n", "f.csv:2:3: column 'a': infinite value");
  expect_csv_error("t,a,a\n0,1,2\n", "duplicate column 'a'");
  expect_csv_error("t,,a\n0,1,2\n", "column 2 has an empty header name");
  expect_csv_error("0,1\n1,2\n", "must be a header row");
  expect_csv_error("t,a\n", "no data rows");
  expect_csv_error("t,a\n0,1e999\n", "f.csv:2:3: column 'a': '1e999' overflows a double");
  expect_csv_error("# only a comment\n", "f.csv: empty file");
  expect_csv_error("t,a\n0,1\n1e308,2\n-1e308,3\n", "f.csv:4:1: time is not increasing");
  expect_csv_error(std::string("t,a\n0,\0\n", 8), "f.csv:2: not a text file");
  expect_csv_error("t,a\n0," + std::string(2 * 1024 * 1024, '1') + "\n",
                   "f.csv:2: line longer than 1 MB");
  std::string wide = "t";
  for (int c = 0; c < 10001; ++c)
    wide += ",c" + std::to_string(c);
  expect_csv_error(wide + "\n", "f.csv:1: 10002 columns: more than the limit of 10000");
}

TEST(Csv, WriteReadRoundTripIsExact) {
  Dataset d;
  d.add("t", 3);
  d.add("x", 3);
  d.columns[0] = {0.0, 0.1, 0.30000000000000004};
  d.columns[1] = {1.0 / 3.0, kNoSample, -2.5e-300};
  std::ostringstream os;
  write_csv(os, d);
  std::istringstream in(os.str());
  auto back = parse_csv(in, "mem");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->col("t"), d.col("t"));
  EXPECT_DOUBLE_EQ(back->col("x")[0], d.col("x")[0]);
  EXPECT_TRUE(std::isnan(back->col("x")[1]));
  EXPECT_EQ(back->col("x")[2], d.col("x")[2]);
}

TEST(Csv, RequireColumnsNamesTheMissingOne) {
  Dataset d;
  d.source = "log.csv";
  d.add("t", 1);
  auto st = require_columns(d, {{"t", "s", "time"}, {"gyro", "deg/s", "rate gyro"}});
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("log.csv: missing required column 'gyro' (rate gyro, deg/s)"),
            std::string::npos)
      << st.error();
  EXPECT_TRUE(require_columns(d, {{"t"}, {"opt", "", "", false}}).ok());
}

TEST(Csv, AtomicWriteKeepsOldFileOnFailure) {
  const std::string path = ::testing::TempDir() + "kfw_atomic.csv";
  ASSERT_TRUE(write_text_file_atomic(path, "old").ok());
  EXPECT_FALSE(write_text_file_atomic("/nonexistent-dir/x.csv", "new").ok());
  std::ifstream in(path);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "old");
}

}  // namespace
}  // namespace kfw
