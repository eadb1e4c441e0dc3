// The import path (table.h, import.h): separators, comments, quotes, BOM, CRLF, decimal comma;
// the guesser; unit conversion, scale, offset, flip; ISO-8601 time; the errors with FILE:LINE:COL.
#include "data/import.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/table_text.h"
#include "core/scenario.h"

namespace kfw {
namespace {

using testing::table;

const std::vector<ColumnSpec> kHeli = {{"t", "s", "time", true},
                                       {"gyro", "deg/s", "rate gyro", true},
                                       {"angle", "deg", "angle", true},
                                       {"truth", "deg", "true angle", false}};

TEST(Table, DetectsEachSeparator) {
  EXPECT_EQ(table("a,b\n1,2\n").separator, ',');
  EXPECT_EQ(table("a;b\n1,5;2\n").separator, ';');
  EXPECT_EQ(table("a\tb\n1\t2\n").separator, '\t');
  EXPECT_EQ(table("a  b\n 1   2\n").separator, kWhitespaceSeparator);
  // A decimal comma does not make a `;` file look like a comma file.
  const Table t = table("Zeit;Drehrate;Winkel\n0,5;1,25;-3\n1,5;2;4,75\n");
  EXPECT_EQ(t.separator, ';');
  EXPECT_TRUE(t.decimal_comma);
  EXPECT_EQ(t.values[0], (std::vector<double>{0.5, 1.5}));
  EXPECT_EQ(t.values[1], (std::vector<double>{1.25, 2.0}));
  EXPECT_EQ(t.values[2], (std::vector<double>{-3.0, 4.75}));
  TableOptions semicolon;
  semicolon.separator = ';';
  EXPECT_EQ(table("a,b;c\n1;2\n", semicolon).names, (std::vector<std::string>{"a,b", "c"}));
}

TEST(Table, CommentsQuotesBomAndCrlf) {
  const Table t = table(
      "\xEF\xBB\xBF# a comment\r\n\"time, s\",\"say \"\"hi\"\"\"\r\n# "
      "more\r\n1,\"2.5\"\r\n\r\n3,4\r\n");
  EXPECT_EQ(t.names, (std::vector<std::string>{"time, s", "say \"hi\""}));
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.values[1], (std::vector<double>{2.5, 4.0}));
  EXPECT_EQ(t.line_of(0), 4u);
  EXPECT_EQ(t.line_of(1), 6u);
  EXPECT_EQ(t.cell(1, 1), "4");
  const Table w = table("# c\nt gyro\n  0  1\n\t1 2\n");
  EXPECT_EQ(w.names, (std::vector<std::string>{"t", "gyro"}));
  EXPECT_EQ(w.values[1], (std::vector<double>{1.0, 2.0}));
}

TEST(Table, TextCellsAreRememberedNotRefused) {
  const Table t = table("t,notes\n0,hello\n1,2\n2,x\n");
  EXPECT_EQ(t.invalid[1], 2u);
  EXPECT_EQ(t.first_invalid[1].line, 2u);
  EXPECT_EQ(t.first_invalid[1].col, 3u);
  EXPECT_TRUE(std::isnan(t.values[1][0]));
  EXPECT_EQ(t.values[1][1], 2.0);
}

TEST(Table, BadFilesNameFileAndLine) {
  auto err = [](const std::string& text) {
    auto t = parse_table(text, "f.csv");
    EXPECT_FALSE(t.ok()) << text;
    return t.ok() ? std::string() : t.error();
  };
  EXPECT_EQ(err(""), "f.csv: empty file (expected a header row)");
  EXPECT_EQ(err("a,b\n"), "f.csv: no data rows after the header");
  EXPECT_EQ(err(std::string("a,b\n1,2\n\x01\x00\x02", 11)), "f.csv:3: not a text file (NUL byte)");
  EXPECT_EQ(err("a,b\n1,\"2\n"), "f.csv:2:3: unterminated quote");
  EXPECT_EQ(err("a,b\n1,2\n3\n"), "f.csv:3: expected 2 fields as in the header, found 1");
}

TEST(Guess, NamesThatStateTheirUnitsGiveACompleteMapping) {
  const Table t = table("time_ms,omega_rads,acc_roll_deg\n0,1,2\n10,1,2\n");
  const Mapping m = guess_mapping(t, kHeli);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m.at("t"), (RoleMapping{"time_ms", "ms"}));
  EXPECT_EQ(m.at("gyro"), (RoleMapping{"omega_rads", "rad/s"}));
  EXPECT_EQ(m.at("angle"), (RoleMapping{"acc_roll_deg", "deg"}));
}

TEST(Guess, WordsAndUnits) {
  EXPECT_EQ(unit_from_name("omega_dps"), "deg/s");
  EXPECT_EQ(unit_from_name("gyroRateDegS"), "deg/s");
  EXPECT_EQ(unit_from_name("gyro [rad/s]"), "rad/s");
  EXPECT_EQ(unit_from_name("t_us"), "us");
  EXPECT_EQ(unit_from_name("acc_g"), "g");
  EXPECT_EQ(unit_from_name("g"), "");
  EXPECT_EQ(unit_from_name("Drehrate"), "");
  const Table t = table("timestamp,ref_angle,gyro_x,roll\n0,1,2,3\n1,1,2,3\n");
  const Mapping m = guess_mapping(t, kHeli);
  EXPECT_EQ(m.at("t").column, "timestamp");
  EXPECT_EQ(m.at("truth").column, "ref_angle");
  EXPECT_EQ(m.at("gyro").column, "gyro_x");
  EXPECT_EQ(m.at("angle").column, "roll");
  // Two columns that name the role as well: the one with fewer other words.
  EXPECT_EQ(
      guess_mapping(table("t,c_bias_truth,c_truth\n0,1,2\n1,1,2\n"), kHeli).at("truth").column,
      "c_truth");
  // No time word: the first column, because it increases.
  EXPECT_EQ(guess_mapping(table("k,gyro\n1,0\n2,0\n"), kHeli).at("t").column, "k");
  EXPECT_EQ(guess_mapping(table("k,gyro\n2,0\n1,0\n"), kHeli).count("t"), 0u);
}

TEST(Import, ConvertsScalesOffsetsAndFlipsInThatOrder) {
  const Table t = table("time_ms,w,a\n0,1,10\n20,2,20\n");
  Mapping m;
  m["t"] = {"time_ms", "ms"};
  m["gyro"] = {"w", "rad/s", 2.0, 1.0, true};
  m["angle"].column = "a";
  auto d = import_table(t, m, kHeli);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->names.front(), "t");
  EXPECT_EQ(d->col("t")[0], 0.0);
  EXPECT_DOUBLE_EQ(d->col("t")[1], 0.02);
  const double k = 180.0 / 3.14159265358979323846;
  EXPECT_DOUBLE_EQ(d->col("gyro")[0], -(2.0 * (1.0 * k) + 1.0));
  EXPECT_DOUBLE_EQ(d->col("gyro")[1], -(2.0 * (2.0 * k) + 1.0));
  EXPECT_EQ(d->col("angle"), (std::vector<double>{10.0, 20.0}));
}

TEST(Import, IsoTimeIsRebasedWithTheOriginAndZonesHonoured) {
  const Table t = table(
      "when,gyro,angle\n2024-05-01T12:00:00.5+02:00,1,2\n2024-05-01 10:00:00.75Z,1,2\n"
      "2024-05-01T10:00:01.000000001,1,2\n");
  const Mapping g = guess_mapping(t, kHeli);
  ASSERT_EQ(g.at("t"), (RoleMapping{"when", kIsoTime}));
  auto d = import_table(t, g, kHeli);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->time_origin, "2024-05-01T10:00:00.500000000Z");
  EXPECT_EQ(d->col("t")[0], 0.0);
  EXPECT_EQ(d->col("t")[1], 0.25);
  EXPECT_DOUBLE_EQ(d->col("t")[2], 0.500000001);
  EXPECT_FALSE(parse_iso_time_ns("2024-13-01T00:00:00").ok());
  EXPECT_FALSE(parse_iso_time_ns("yesterday").ok());
}

// iso@ZONE: a date-time without an offset is a local time in the zone, daylight saving included;
// an explicit offset or Z still wins.
TEST(Import, NamedTimeZonesReadLocalTimes) {
  // Berlin is UTC+1 in winter and UTC+2 in summer; the clocks went forward at 2024-03-31 02:00.
  auto ns = [](const char* text) {
    auto v = parse_iso_time_ns(text, "Europe/Berlin");
    EXPECT_TRUE(v.ok()) << text << ": " << (v.ok() ? "" : v.error());
    return v.ok() ? *v : 0LL;
  };
  EXPECT_EQ(ns("2024-01-15T13:00:00"), *parse_iso_time_ns("2024-01-15T12:00:00Z"));
  EXPECT_EQ(ns("2024-07-15T14:00:00"), *parse_iso_time_ns("2024-07-15T12:00:00Z"));
  EXPECT_EQ(ns("2024-07-15T14:00:00+00:00"), *parse_iso_time_ns("2024-07-15T14:00:00Z"));
  // Across the change the local clock jumps 01:59:59 → 03:00:00: one second of real time.
  EXPECT_EQ(ns("2024-03-31T03:00:00") - ns("2024-03-31T01:59:59"), 1'000'000'000LL);
  auto gap = parse_iso_time_ns("2024-03-31T02:30:00", "Europe/Berlin");
  ASSERT_FALSE(gap.ok());
  EXPECT_NE(gap.error().find("does not exist in Europe/Berlin"), std::string::npos);
  EXPECT_FALSE(check_time_zone("Europe/Berlln").ok());
  EXPECT_TRUE(check_time_zone("America/New_York").ok());
  // Through a mapping: rebased time, and an unknown zone names the mapping key.
  const Table t = table("when,gyro,angle\n2024-03-31T01:59:59,1,2\n2024-03-31T03:00:00.5,1,2\n");
  auto d = import_table(t, {{"t", {"when", "iso@Europe/Berlin"}}}, kHeli);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->time_origin, "2024-03-31T00:59:59.000000000Z");  // CET, UTC+1
  EXPECT_DOUBLE_EQ(d->col("t")[1], 1.5);
  auto bad = import_table(t, {{"t", {"when", "iso@Mars/Olympus"}}}, kHeli);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().rfind("f.csv: mapping.t.unit: unknown time zone 'Mars/Olympus'", 0), 0u)
      << bad.error();
}

TEST(Import, TimeErrorsNameTheLine) {
  auto err = [](const std::string& text, const Mapping& m = {}) {
    auto d = import_table(table(text), m, kHeli);
    EXPECT_FALSE(d.ok()) << text;
    return d.ok() ? std::string() : d.error();
  };
  EXPECT_EQ(err("t,gyro,angle\n0,1,2\n1,1,2\n1,1,2\n"),
            "f.csv:4:1: time is not increasing (t = 1 after 1, a duplicate)");
  EXPECT_EQ(err("t,gyro,angle\n0,1,2\n2,1,2\n1,1,2\n"),
            "f.csv:4:1: time is not increasing (t = 1 after 2)");
  EXPECT_EQ(err("t,gyro,angle\n0,1,2\n1,x,2\n"), "f.csv:3:3: column 'gyro': 'x' is not a number");
  EXPECT_EQ(err("t,gyro,angle\n0,1,2\nnoon,1,2\n"),
            "f.csv:3:1: column 't': 'noon' is not a number");
  EXPECT_EQ(err("when,gyro,angle\n2024-05-01T00:00:00,1,2\nlater,1,2\n", {{"t", {"when", "iso"}}}),
            "f.csv:3:1: column 'when': 'later' is not an ISO-8601 date-time");
  EXPECT_EQ(err("a,b,gyro\n0,1,2\n", {{"t", {"a"}}, {"angle", {"a"}}}),
            "f.csv: column 'a' is mapped to both 't' and 'angle'");
  EXPECT_EQ(err("a,gyro,angle\n0,1,2\n", {{"t", {"a"}}, {"gyro", {"gyro", "m"}}}),
            "f.csv: mapping.gyro.unit: cannot convert 'm' to 'deg/s' (a length and a rate)");
}

TEST(Import, UnboundColumnsKeepTheirNames) {
  auto d = import_table(table("time,gyro,angle,t,notes\n0,1,2,3,x\n1,1,2,3,y\n"), {{"t", {"time"}}},
                        kHeli);
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->names, (std::vector<std::string>{"t", "gyro", "angle", "t.unmapped", "notes"}));
}

}  // namespace
}  // namespace kfw
