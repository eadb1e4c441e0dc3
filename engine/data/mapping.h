// How a log's columns become a scenario's roles: role -> column, the unit the column is in, then
// a scale, an offset and a sign flip. The preset's (and the session's) "mapping" block; the time
// role is "t". By default a role reads the column of the same name, in the role's own unit.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "data/table.h"

namespace kfw {

struct RoleMapping {
  std::string column;  // the file's column; empty: the role's own name
  std::string unit;    // the unit the column is in; empty: already the role's unit
  double scale = 1.0;  // applied after unit conversion: v' = ±(scale·v + offset)
  double offset = 0.0;
  bool flip = false;
  bool operator==(const RoleMapping&) const = default;
};

// role -> mapping ("t" is the time column), and how the file is read: its separator and whether
// its first row is a header (the block's "sep" and "header" keys; by default both are detected).
struct Mapping : std::map<std::string, RoleMapping> {
  using std::map<std::string, RoleMapping>::map;
  char separator = 0;                    // 0: detected; else ',' ';' '\t' kWhitespaceSeparator
  HeaderRow header = HeaderRow::detect;  // first row: detected, the header, or data
  bool operator==(const Mapping&) const = default;

  // Nothing given: no role and the file's format detected.
  bool blank() const { return empty() && separator == 0 && header == HeaderRow::detect; }
  // `over`'s roles replace these, and its separator and header replace these where given.
  void override_with(const Mapping& over);
  TableOptions table_options() const;
  bool same_format(const Mapping& o) const {
    return separator == o.separator && header == o.header;
  }
};

// A dataset by path, with the mapping that reads it.
struct DataRef {
  std::string path;
  Mapping mapping;
  bool operator==(const DataRef&) const = default;
};

// The units kfw converts between (README "Importing logs"): s ms us ns; deg rad; deg/s rad/s; m/s^2
// g; m mm. Factor to multiply a value in `from` by to get `to`; an Error when they are not of one
// kind or unknown.
Expected<double> unit_factor(const std::string& from, const std::string& to);
// The time role's unit for an ISO-8601 date-time column: "iso" (a date-time without an offset
// is UTC), or "iso@ZONE" with an IANA zone ("iso@Europe/Berlin": such a date-time is a local
// time there, daylight saving included). iso_zone() is ZONE, or "" for plain "iso".
bool is_iso_unit(const std::string& unit);
std::string iso_zone(const std::string& unit);
const std::vector<std::string>& known_units();

// The "mapping" block: {"gyro": "omega_dps"} or {"gyro": {"column": ..., "unit": ..., "scale":
// ..., "offset": ..., "flip": ...}}, plus "sep" (comma, semicolon, tab, whitespace) and "header"
// (first, none; detected when absent): these two keys are not roles. `where` is the dotted key
// path for messages.
Expected<Mapping> mapping_from_json(const nlohmann::json& j, const std::string& where);
nlohmann::ordered_json mapping_to_json(const Mapping& m);

}  // namespace kfw
