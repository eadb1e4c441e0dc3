// Streamed outputs (issue 33): `--out` is written row by row into the staged temporary
// (data/output.h OutputStream, data/csv.h write_csv_stream) instead of being built in memory.
// The bytes equal the old writer's (write_csv of the whole table into a string) on every shipped
// preset, for a table larger than the stream's buffer, and for JSON documents; a writer that fails
// leaves the old file in place.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/scenario.h"
#include "data/csv.h"
#include "data/json_io.h"
#include "data/output.h"
#include "document/workspace.h"

namespace kfw {
namespace scale_stream_test {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string old_writer(const Dataset& d) {
  std::ostringstream os;
  write_csv(os, d);
  return os.str();
}

// Streams `columns` into `path` through an OutputSet, as kfw-cli does.
std::string streamed(const fs::path& path, const std::vector<TableColumn>& columns,
                     std::size_t rows) {
  OutputSet outs;
  EXPECT_TRUE(outs.add(path.string(), "--out").ok());
  EXPECT_TRUE(
      outs.stage_stream(path.string(),
                        [&](OutputStream& os) { return write_csv_stream(os, columns, rows); })
          .ok());
  EXPECT_TRUE(outs.commit().ok());
  return slurp(path);
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("kfw_scale_stream_" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::vector<std::string> every_preset() {
  std::vector<std::string> out;
  for (const char* dir : {"/presets", "/presets/models"}) {
    for (const auto& e : fs::directory_iterator(std::string(KFW_SOURCE_DIR) + dir)) {
      if (e.path().extension() == ".json") out.push_back(e.path().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Every preset's run: the streamed estimates equal the old writer's bytes, and so does the
// simulated dataset `kfw-cli simulate` writes.
TEST(ScaleStream, RunOutEqualsTheOldWriterOnEveryPreset) {
  TempDir tmp;
  const auto presets = every_preset();
  ASSERT_GE(presets.size(), 15u);
  for (const auto& p : presets) {
    SCOPED_TRACE(p);
    auto ws = open_workspace(p, std::nullopt, {});
    ASSERT_TRUE(ws) << ws.error();
    if (ws->data_path && !fs::exists(*ws->data_path)) continue;  // ../shared absent (a bare clone)
    auto d = load_dataset(*ws);
    ASSERT_TRUE(d) << d.error();
    auto r = ws->scenario->run(*d, ws->values);
    ASSERT_TRUE(r) << r.error();
    const RunResult& res = **r;
    const std::string expected = old_writer(res.table());
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(streamed(tmp.path / "est.csv", res.table_view(), res.steps()), expected);
    EXPECT_EQ(streamed(tmp.path / "data.csv", table_columns(*d), d->rows()), old_writer(*d));
  }
}

// Several buffers' worth (the stream flushes at 1 MiB) with missing cells, negative zero,
// subnormals and extremes: byte for byte.
TEST(ScaleStream, LongTableAcrossBufferBoundaries) {
  TempDir tmp;
  Dataset d;
  const std::size_t rows = 120000;
  d.add("t", rows);
  d.add("a", rows);
  d.add("b.long.name", rows);
  auto& t = d.columns[0];
  auto& a = d.columns[1];
  auto& b = d.columns[2];
  for (std::size_t k = 0; k < rows; ++k) {
    t[k] = 0.001 * static_cast<double>(k);
    a[k] = k % 7 == 0 ? kNoSample : std::sin(static_cast<double>(k)) * 1e300;
    b[k] = k % 5 == 0 ? -0.0 : k % 11 == 0 ? 4.9e-324 : 1.0 / (1.0 + static_cast<double>(k));
  }
  const std::string expected = old_writer(d);
  ASSERT_GT(expected.size(), 3 * OutputStream::kBuffer);
  EXPECT_EQ(streamed(tmp.path / "long.csv", table_columns(d), rows), expected);
  ASSERT_TRUE(write_csv_file((tmp.path / "file.csv").string(), d).ok());
  EXPECT_EQ(slurp(tmp.path / "file.csv"), expected);
}

// A JSON output streams the bytes of dump(indent) and a newline, for both json kinds.
TEST(ScaleStream, JsonEqualsDump) {
  TempDir tmp;
  nlohmann::ordered_json j;
  j["z"] = 1.5;
  j["a"] = {1, 2, 3};
  j["nested"]["k"] = "text with \"quotes\"";
  for (int indent : {1, 2}) {
    const fs::path p = tmp.path / ("doc" + std::to_string(indent) + ".json");
    OutputSet outs;
    ASSERT_TRUE(outs.add(p.string()).ok());
    ASSERT_TRUE(stage_json(outs, p.string(), j, indent).ok());
    ASSERT_TRUE(outs.commit().ok());
    EXPECT_EQ(slurp(p), j.dump(indent) + "\n");
    const nlohmann::json plain = nlohmann::json::parse(j.dump());
    OutputSet outs2;
    ASSERT_TRUE(outs2.add(p.string()).ok());
    ASSERT_TRUE(stage_json(outs2, p.string(), plain, indent).ok());
    ASSERT_TRUE(outs2.commit().ok());
    EXPECT_EQ(slurp(p), plain.dump(indent) + "\n");
  }
}

// A writer that fails half way: the old file is untouched and no temporary is left.
TEST(ScaleStream, FailingWriterKeepsTheOldFile) {
  TempDir tmp;
  const fs::path p = tmp.path / "keep.csv";
  std::ofstream(p) << "old\n";
  OutputSet outs;
  ASSERT_TRUE(outs.add(p.string(), "--out").ok());
  ASSERT_TRUE(outs.stage_stream(p.string(),
                                [](OutputStream& os) -> Status {
                                  for (int i = 0; i < 300000; ++i)
                                    os.write("0123456789");
                                  return failure("the run broke down");
                                })
                  .ok());
  const auto st = outs.commit();
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("the run broke down"), std::string::npos) << st.error();
  EXPECT_EQ(slurp(p), "old\n");
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(tmp.path))
    files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1u);
}

}  // namespace
}  // namespace scale_stream_test
}  // namespace kfw
