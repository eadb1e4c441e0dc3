// How a file is read, stored with its mapping (issue 13): the separator and the header row
// ("sep", "header" in the mapping block) round-trip through the preset, the session and a mapping
// file, old blocks stay valid; a file whose first row is all numbers has no header and its columns
// are named col1, col2, ...; the header choice can be forced either way.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/table_text.h"
#include "core/scenario.h"
#include "data/csv.h"
#include "data/import.h"
#include "document/preset.h"
#include "document/session.h"
#include "document/workspace.h"

namespace kfw {
namespace {

using testing::table;

std::string err(const std::string& text, const TableOptions& opt = {}) {
  auto t = parse_table(text, "f.csv", opt);
  EXPECT_FALSE(t.ok()) << text;
  return t.ok() ? std::string() : t.error();
}

TEST(Headerless, AFirstRowOfNumbersIsDataNamedByPosition) {
  const Table t = table("# logger v2\n0,1.5,-2\n0.01,1.25,NA\n0.02,1,-1.5\n");
  EXPECT_FALSE(t.has_header());
  EXPECT_EQ(t.header_line, 0u);
  EXPECT_EQ(t.names, (std::vector<std::string>{"col1", "col2", "col3"}));
  ASSERT_EQ(t.rows(), 3u);
  EXPECT_EQ(t.line_of(0), 2u);  // the first row is data, on its own line
  EXPECT_EQ(t.values[1], (std::vector<double>{1.5, 1.25, 1.0}));
  EXPECT_TRUE(std::isnan(t.values[2][1]));
  // Semicolons with decimal commas, tabs and whitespace alike.
  const Table g = table("0,5;1,25\n1,5;2\n");
  EXPECT_FALSE(g.has_header());
  EXPECT_EQ(g.values[0], (std::vector<double>{0.5, 1.5}));
  EXPECT_EQ(table("0\t1\n1\t2\n").names, (std::vector<std::string>{"col1", "col2"}));
  EXPECT_EQ(table("  0   1\n  1   2\n").values[1], (std::vector<double>{1.0, 2.0}));
  // A first row with a missing value but a number is still data; one with a word is a header.
  EXPECT_FALSE(table("0,,2\n1,3,4\n").has_header());
  EXPECT_TRUE(table("t,gyro\n0,1\n").has_header());
  EXPECT_EQ(table("t,gyro\n0,1\n").header_line, 1u);
}

TEST(Headerless, TheHeaderChoiceOverridesDetection) {
  TableOptions first;
  first.header = HeaderRow::first;
  const Table f = table("1,2\n3,4\n5,6\n", first);  // numbers as names, when the user says so
  EXPECT_EQ(f.names, (std::vector<std::string>{"1", "2"}));
  EXPECT_EQ(f.rows(), 2u);
  TableOptions none;
  none.header = HeaderRow::none;
  const Table n = table("t,gyro\n0,1\n1,2\n", none);  // a header read as data: text cells
  EXPECT_EQ(n.names, (std::vector<std::string>{"col1", "col2"}));
  EXPECT_EQ(n.rows(), 3u);
  EXPECT_EQ(n.invalid[0], 1u);
  EXPECT_EQ(n.first_invalid[0].line, 1u);
}

TEST(Headerless, BadHeaderlessFilesNameLineAndColumn) {
  // Ragged rows are counted against the first row.
  EXPECT_EQ(err("0,1,2\n1,2\n"), "f.csv:2: expected 3 fields as in the first row, found 2");
  // A number next to text in the first row: neither a header nor data.
  EXPECT_NE(err("0,gyro\n1,2\n").find("f.csv:1:1: the first row must be a header row"),
            std::string::npos);
  EXPECT_EQ(err("# only a comment\n"), "f.csv: empty file (expected a header row)");
  // A text cell in a bound column of a headerless file: the usual FILE:LINE:COL.
  const Table t = table("0,1\n0.5,2\n1,x2\n");
  const std::vector<ColumnSpec> roles = {{"gyro", "", "rate", true}};
  Mapping m;
  m["t"].column = "col1";
  m["gyro"].column = "col2";
  auto d = import_table(t, m, roles);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().rfind("f.csv:3:3: ", 0), 0u) << d.error();
  EXPECT_NE(d.error().find("'x2' is not a number"), std::string::npos) << d.error();
  // kfw's own format still names its columns.
  std::istringstream own_text("0,1\n1,2\n");
  auto own = parse_csv(own_text, "k.csv");
  ASSERT_FALSE(own.ok());
  EXPECT_EQ(own.error().rfind("k.csv:1:1: the first row must be a header row", 0), 0u)
      << own.error();
}

TEST(Headerless, TheGuessTakesAnIncreasingFirstColumnAsTime) {
  const Table t = table("0,1.5,2\n0.01,1.25,3\n0.02,1,4\n");
  const std::vector<ColumnSpec> roles = {{"gyro", "deg/s", "rate", true}};
  const Mapping g = guess_mapping(t, roles);
  ASSERT_TRUE(g.count("t"));
  EXPECT_EQ(g.at("t").column, "col1");
}

TEST(MappingFormat, SepAndHeaderRoundTripAndOldBlocksStayValid) {
  auto m =
      mapping_from_json(nlohmann::json::parse(R"({"sep": "semicolon", "header": "none", "t": "col1",
                                 "gyro": {"column": "col2", "unit": "rad/s"}})"),
                        "mapping");
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->separator, ';');
  EXPECT_EQ(m->header, HeaderRow::none);
  EXPECT_EQ(m->size(), 2u);  // "sep" and "header" are not roles
  EXPECT_FALSE(m->count("sep"));
  auto back = mapping_from_json(nlohmann::json::parse(mapping_to_json(*m).dump()), "mapping");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(*back, *m);
  // Each separator by name and by character; detection writes nothing.
  for (const char* s : {"comma", ",", "semicolon", ";", "tab", "\t", "whitespace", " "}) {
    auto one = mapping_from_json({{"sep", s}}, "mapping");
    ASSERT_TRUE(one.ok()) << s;
    EXPECT_EQ(mapping_to_json(*one).at("sep"), separator_key(one->separator));
  }
  EXPECT_FALSE(mapping_to_json(Mapping{}).contains("sep"));
  EXPECT_FALSE(mapping_to_json(Mapping{}).contains("header"));
  // Old blocks (roles only) read as detected.
  auto old = mapping_from_json({{"t", "time_s"}}, "mapping");
  ASSERT_TRUE(old.ok());
  EXPECT_EQ(old->separator, 0);
  EXPECT_EQ(old->header, HeaderRow::detect);
  // Bad values name the key.
  EXPECT_EQ(mapping_from_json({{"sep", "pipe"}}, "mapping").error(),
            "mapping.sep: unknown separator 'pipe' (comma, semicolon, tab, whitespace)");
  EXPECT_EQ(mapping_from_json({{"header", "yes"}}, "mapping").error(),
            "mapping.header: unknown header 'yes' (detect, first, none)");
  EXPECT_EQ(mapping_from_json({{"sep", 1}}, "mapping").error(),
            "mapping.sep: must be a string, not a number");
}

TEST(MappingFormat, OverridingReplacesOnlyWhatIsGiven) {
  Mapping base;
  base.separator = ';';
  base["gyro"].column = "g";
  Mapping over;
  over["angle"].column = "a";
  base.override_with(over);
  EXPECT_EQ(base.separator, ';');  // not given: kept
  EXPECT_EQ(base.at("gyro").column, "g");
  over.separator = '\t';
  over.header = HeaderRow::none;
  base.override_with(over);
  EXPECT_EQ(base.separator, '\t');
  EXPECT_EQ(base.header, HeaderRow::none);
  EXPECT_EQ(mapping_options(base), "--map angle=a --map gyro=g --sep tab --header none");
}

TEST(MappingFormat, PresetAndSessionCarryTheFormat) {
  const std::string text = R"({"format": "kfw-preset", "version": 2, "scenario": "helicopter",
    "mapping": {"sep": "tab", "header": "none", "t": "col1", "gyro": "col2", "angle": "col3"}})";
  auto p = parse_preset(text, "m.json");
  ASSERT_TRUE(p.ok()) << p.error();
  EXPECT_EQ(p->mapping.separator, '\t');
  EXPECT_EQ(p->mapping.header, HeaderRow::none);
  auto back = parse_preset(preset_to_json(*p), "m.json");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->mapping, p->mapping);
  // A mapping of the format alone is written too.
  Preset only = *p;
  only.mapping = Mapping{};
  only.mapping.separator = ';';
  auto b2 = parse_preset(preset_to_json(only), "m.json");
  ASSERT_TRUE(b2.ok()) << b2.error();
  EXPECT_EQ(b2->mapping.separator, ';');

  Session s;
  s.preset_path = "presets/helicopter.json";
  s.scenario = "helicopter";
  s.data_path = "/data/log.tsv";
  s.mapping = p->mapping;
  Mapping other;
  other.separator = kWhitespaceSeparator;
  s.tuning_set = {{"/data/a.txt", other}};
  auto sb = parse_session(session_to_json(s), "s.json");
  ASSERT_TRUE(sb.ok()) << sb.error();
  EXPECT_EQ(sb->mapping, s.mapping);
  EXPECT_EQ(sb->tuning_set, s.tuning_set);
}

// The stored format is what reads the file: a tab file read as comma is one column and fails; the
// same mapping with "sep": "tab" loads; a headerless file loads through col names.
TEST(MappingFormat, LoadingReadsWithTheMappingsFormat) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "kfw_import_format";
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "log.tsv").string();
  std::ofstream(file) << "0\t1.5\t2\t2.1\n0.01\t1.25\t3\t3.1\n0.02\t1\t4\t4.1\n";
  auto p = load_preset(KFW_SOURCE_DIR "/presets/helicopter.json");
  ASSERT_TRUE(p.ok()) << p.error();
  const Scenario& s = *p->instance;
  Mapping m;
  m["t"].column = "col1";
  m["gyro"].column = "col2";
  m["angle"].column = "col3";
  m["truth"].column = "col4";
  auto d = load_dataset_file(s, file, m);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->col("angle"), (std::vector<double>{2, 3, 4}));
  m.separator = ',';
  auto wrong = load_dataset_file(s, file, m);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().find("mapped column 'col"), std::string::npos) << wrong.error();
  m.separator = '\t';
  m.header = HeaderRow::first;  // the first row as names: col1 .. col4 are gone
  EXPECT_FALSE(load_dataset_file(s, file, m).ok());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace kfw
