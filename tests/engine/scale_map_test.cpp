// Memory-mapped reads (issue 33, data/input_file.h InputBytes): a large regular file is mapped,
// not copied, and gives the same table as the read path; a file truncated under the mapping
// (another program rewriting it) is an error naming the file, never a SIGBUS; small files, and
// text given in memory, are read as before.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "data/csv.h"
#include "data/input_file.h"
#include "data/table.h"

namespace kfw {
namespace scale_map_test {
namespace {

namespace fs = std::filesystem;

struct BigCsv {
  fs::path path;
  std::string text;
  explicit BigCsv(std::size_t rows) {
    path = fs::temp_directory_path() / ("kfw_scale_map_" + std::to_string(::getpid()) + ".csv");
    text = "t,a,b\n";
    for (std::size_t k = 0; k < rows; ++k) {
      text += std::to_string(0.01 * static_cast<double>(k)) + "," +
              std::to_string(std::sin(static_cast<double>(k))) + "," + (k % 9 ? "1.5" : "") + "\n";
    }
    std::ofstream(path, std::ios::binary) << text;
  }
  ~BigCsv() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

TEST(ScaleMap, ALargeFileIsMappedAndReadsAsTheText) {
  BigCsv f(60000);
  ASSERT_GT(f.text.size(), InputBytes::kMapMinBytes);
  auto bytes = InputBytes::open(f.path.string(), limits::Input::kData);
  ASSERT_TRUE(bytes) << bytes.error();
  EXPECT_TRUE((*bytes)->mapped());
  EXPECT_EQ((*bytes)->view(), f.text);
  auto mapped = read_table(f.path.string());
  auto copied = parse_table(f.text, f.path.string());
  ASSERT_TRUE(mapped) << mapped.error();
  ASSERT_TRUE(copied) << copied.error();
  ASSERT_EQ(mapped->rows(), 60000u);
  for (std::size_t c = 0; c < 3; ++c) {
    ASSERT_EQ(mapped->values[c].size(), copied->values[c].size());
    for (std::size_t k = 0; k < mapped->rows(); ++k) {
      const double a = mapped->values[c][k], b = copied->values[c][k];
      ASSERT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << c << " " << k;
    }
  }
  EXPECT_EQ(mapped->cell(59999, 0), copied->cell(59999, 0));  // re-read from the mapping
  auto d = read_csv(f.path.string());
  ASSERT_TRUE(d) << d.error();
  EXPECT_EQ(d->rows(), 60000u);
}

// Truncated after mapping and before parsing: the pages past the new end read as zeros (the
// guard), and the parse says the file was truncated, naming it.
TEST(ScaleMap, AFileTruncatedUnderTheMappingIsAnErrorNotASigbus) {
  BigCsv f(60000);
  auto bytes = InputBytes::open(f.path.string(), limits::Input::kData);
  ASSERT_TRUE(bytes) << bytes.error();
  ASSERT_TRUE((*bytes)->mapped());
  ASSERT_EQ(::truncate(f.path.c_str(), 4096), 0);
  auto t = parse_table(*bytes, f.path.string());
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().find(f.path.string()), std::string::npos) << t.error();
  EXPECT_NE(t.error().find("truncated while being read"), std::string::npos) << t.error();
  EXPECT_TRUE((*bytes)->changed());
  // A later table over the same, now shorter, file reads normally.
  auto again = read_table(f.path.string());
  EXPECT_FALSE(again);  // 4096 bytes end inside a row: the ragged last row is named
  EXPECT_NE(again.error().find(f.path.string() + ":"), std::string::npos) << again.error();
}

TEST(ScaleMap, SmallFilesAndTextAreRead) {
  BigCsv f(10);
  auto bytes = InputBytes::open(f.path.string(), limits::Input::kData);
  ASSERT_TRUE(bytes) << bytes.error();
  EXPECT_FALSE((*bytes)->mapped());
  EXPECT_EQ((*bytes)->view(), f.text);
  EXPECT_FALSE(InputBytes::of("t\n1\n")->mapped());
  EXPECT_FALSE((*bytes)->changed());
}

}  // namespace
}  // namespace scale_map_test
}  // namespace kfw
