// Datasets: a table of named numeric columns with a time column `t`. NaN means "no sample".
#pragma once

#include <cstddef>
#include <functional>
#include <istream>
#include <limits>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace kfw {

inline constexpr double kNoSample = std::numeric_limits<double>::quiet_NaN();

struct Dataset {
  std::string source;  // file path, or "simulated <scenario> seed N"
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;  // columns[i] belongs to names[i]
  std::string time_origin;  // an ISO-8601 time column's first instant (t = 0), UTC; else empty

  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  bool has(std::string_view name) const { return index(name) >= 0; }
  int index(std::string_view name) const;
  // The column by name; throws std::logic_error when absent (check with has() or require()).
  const std::vector<double>& col(std::string_view name) const;
  // Appends a column of NaN; the reference is invalidated by the next add().
  std::vector<double>& add(std::string name, std::size_t rows = 0);
  // Median sample period of `t`, the filter's Ts when a dataset is loaded.
  double median_dt() const;
};

// What a scenario needs from a dataset.
struct ColumnSpec {
  std::string name;
  std::string unit;
  std::string meaning;
  bool required = true;
};

// Names the first required column that is missing, with the file.
Status require_columns(const Dataset& d, const std::vector<ColumnSpec>& spec);

// Required columns that are present but hold no finite value at all are invalid (column named).
Status require_some_value(const Dataset& d, const std::vector<ColumnSpec>& spec);

// Limits (README "Limits"): refused at once with a message, in bounded time and memory.
inline constexpr std::size_t kMaxCsvLineBytes = 1024u * 1024u;
inline constexpr std::size_t kMaxCsvColumns = 10000;

struct CsvOptions {
  std::string time_column = "t";
  // Columns bound to a role: only these (and time) are validated; a bad cell elsewhere reads as
  // no sample. Empty: every column is validated.
  std::vector<std::string> validate;
  std::function<bool(double)> progress;  // fraction read; return false to cancel
};

// One cell: empty, NaN, nan, NA -> no sample (kNoSample); a finite number; else an Error
// (text, inf, a number that overflows a double).
Expected<double> parse_cell(std::string_view text);

// Parses CSV with a header row (the data policy, README "Missing and invalid data"): an empty
// cell or NaN/nan/NA is a missing sample; inf, a number that overflows a double or text in a
// validated column is invalid. Errors name FILE:LINE:COL: malformed numbers, ragged rows,
// duplicate or empty header names, a missing, empty or non-increasing time, binary files, the
// line-length and column-count limits.
Expected<Dataset> parse_csv(std::istream& in, const std::string& source,
                            const CsvOptions& opt = {});
Expected<Dataset> read_csv(const std::string& path, const CsvOptions& opt = {});

// Writes with full precision; NaN as an empty cell.
void write_csv(std::ostream& out, const Dataset& d);
// Writes to path atomically (temporary file, then rename); the old file survives a failure.
Status write_csv_file(const std::string& path, const Dataset& d);
Status write_text_file_atomic(const std::string& path, const std::string& text);

}  // namespace kfw
