// From a read table to a scenario's dataset: a mapping assigns each role (time is the role "t")
// to a column; each value is converted from the column's unit to the role's, then scaled, offset
// and its sign flipped. The guesser proposes a mapping from the column names and their units.
#pragma once

#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "data/mapping.h"
#include "data/table.h"

namespace kfw {

// The time role's unit for an ISO-8601 date-time column ("2024-05-01T10:00:00.5+02:00").
inline constexpr const char* kIsoTime = "iso";

// The roles of a scenario with time first: "t" in seconds is always a role.
std::vector<ColumnSpec> roles_with_time(const std::vector<ColumnSpec>& columns);

// A unit stated by a column's name: "omega_dps" -> "deg/s", "time_ms" -> "ms", "gyro [rad/s]"
// -> "rad/s"; empty when the name states none.
std::string unit_from_name(const std::string& name);

// The mapping a user most likely means: each role to the column whose name matches it best (its
// own name, then words such as time/timestamp/zeit for t, gyro/omega/rate for a rate, angle/roll
// for an angle, truth/ref for a reference), each column used once; the unit each name states
// when it is of the role's kind; an ISO date-time column as time. Roles with no match are absent.
Mapping guess_mapping(const Table& t, const std::vector<ColumnSpec>& roles);

// Where a role reads from: the mapped column, else the column of the role's own name; -1 when
// neither is in the table.
int role_column(const Table& t, const Mapping& m, const std::string& role);

// The dataset: time first as "t" (seconds; an ISO column rebased to start at 0, its origin in
// Dataset::time_origin), each mapped role under its name, converted; other columns kept under
// their own names (renamed "NAME.unmapped" when a role takes their name). Errors name the file
// and line (and column): a cell that is not a number in a column bound to a role, an empty,
// duplicate or decreasing time, a mapped column absent from the file, a column bound to two
// roles, a unit of the wrong kind.
Expected<Dataset> import_table(const Table& t, const Mapping& m,
                               const std::vector<ColumnSpec>& roles);

// ISO-8601 date-time to nanoseconds since 1970-01-01 UTC: date, 'T' or ' ', time with optional
// fraction, then 'Z', +hh:mm, +hhmm or nothing: UTC, or a local time in `zone` (an IANA name,
// from the system's time zone database) when one is given. Error text for a cell that is not
// one, or a local time the zone skips (the clocks jump forward); of a repeated local time (the
// clocks go back) the earlier.
Expected<long long> parse_iso_time_ns(std::string_view s, const std::string& zone = {});
// Ok when `zone` names a time zone of the system's database; else an Error naming it.
Status check_time_zone(const std::string& zone);
std::string format_iso_time_ns(long long ns);

}  // namespace kfw
