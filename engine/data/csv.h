// kfw's own CSV format: reading and writing Datasets (a header row, a time column, NaN as an
// empty cell).
#pragma once

#include <cstddef>
#include <functional>
#include <istream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/limits.h"
#include "data/output.h"

namespace kfw {

// Limits (README "Missing and invalid data"; docs/hardening.md "Limits"): refused at once with a
// message, in bounded time and memory.
inline constexpr std::size_t kMaxCsvLineBytes = limits::kMaxCsvLineBytes;
inline constexpr std::size_t kMaxCsvColumns = limits::kMaxCsvColumns;

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
// Streams the columns row by row into a staged output: the same bytes as write_csv of a Dataset
// with these columns, in O(1) memory.
Status write_csv_stream(OutputStream& out, const std::vector<TableColumn>& columns,
                        std::size_t rows);
// Writes to path atomically (temporary file, then rename); the old file survives a failure.
Status write_csv_file(const std::string& path, const Dataset& d);
Status write_text_file_atomic(const std::string& path, const std::string& text);

}  // namespace kfw
