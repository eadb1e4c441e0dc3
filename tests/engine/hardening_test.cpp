// Issue 16 follow-ups: the CSV reader stops reading at the line limit (bounded memory), and the
// covariance check the debug builds and the fuzz harnesses use.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/dataset.h"
#include "data/csv.h"
#include "data/table.h"
#include "filter/covariance_check.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;

class LongLine : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("kfw_longline_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A header, one good row, then a 16 MB line with no line end.
  std::string write_file() {
    const std::string path = (dir_ / "long.csv").string();
    std::ofstream out(path, std::ios::binary);
    out << "t,a\n0,1\n0.1,";
    const std::string chunk(1 << 20, '7');
    for (int i = 0; i < 16; ++i)
      out << chunk;
    return path;
  }
  fs::path dir_;
};

TEST_F(LongLine, ReadingStopsAtTheLimit) {
  const std::string path = write_file();
  ASSERT_GT(fs::file_size(path), 16u * kMaxCsvLineBytes);
  auto bytes = read_file_bytes(path, kMaxCsvLineBytes);
  ASSERT_TRUE(bytes.ok()) << bytes.error();
  // Read up to the limit plus one read buffer (64 KB), not the 16 MB.
  EXPECT_GT(bytes->size(), kMaxCsvLineBytes);
  EXPECT_LE(bytes->size(), kMaxCsvLineBytes + 2 * 65536);
  // Without a limit, everything.
  auto all = read_file_bytes(path);
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all->size(), fs::file_size(path));
}

TEST_F(LongLine, TheLoadersNameTheLine) {
  const std::string path = write_file();
  auto t = read_table(path);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error(), path + ":3: line longer than 1 MB");
  auto d = read_csv(path);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error(), path + ":3: line longer than 1 MB");
}

TEST(LongLineLimit, ALineAtTheLimitIsRead) {
  const fs::path path = fs::temp_directory_path() / ("kfw_atlimit_" + std::to_string(::getpid()));
  {
    std::ofstream out(path, std::ios::binary);
    // Line 2 is exactly kMaxCsvLineBytes long (allowed); no line end after it.
    const std::string first = "0,";
    out << "t,a\n" << first << std::string(kMaxCsvLineBytes - first.size(), '1');
  }
  auto bytes = read_file_bytes(path.string(), kMaxCsvLineBytes);
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(bytes->size(), fs::file_size(path));
  fs::remove(path);
}

TEST(CovarianceCheck, SymmetricPsdAndNot) {
  Eigen::Matrix2d P;
  P << 2.0, 1.0, 1.0, 2.0;  // eigenvalues 1, 3
  EXPECT_TRUE(is_symmetric_psd(P));
  P << 1.0, 1.0, 1.0, 1.0;  // singular: eigenvalues 0, 2
  EXPECT_TRUE(is_symmetric_psd(P));
  P << 1.0, 2.0, 2.0, 1.0;  // eigenvalues −1, 3
  EXPECT_FALSE(is_symmetric_psd(P));
  P << 2.0, 1.0, 0.0, 2.0;  // not symmetric
  EXPECT_FALSE(is_symmetric_psd(P));
  P << 1.0, 0.0, 0.0, -1e-20;  // rounding below the tolerance
  EXPECT_TRUE(is_symmetric_psd(P));
  Eigen::Matrix3d Z = Eigen::Matrix3d::Zero();
  EXPECT_TRUE(is_symmetric_psd(Z));
}

}  // namespace
}  // namespace kfw
