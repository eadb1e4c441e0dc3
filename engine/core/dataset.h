// Datasets: a table of named numeric columns with a time column `t`. NaN means "no sample".
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
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

// A column of a table that is written without being copied (a streamed --out): a run's array
// (`data`, `rows` values) or values computed per row (`at`, e.g. an IMM's mode probabilities).
// `keep` holds whatever the pointer lives in when the table was built for the write.
struct TableColumn {
  std::string name;
  const double* data = nullptr;
  std::function<double(std::size_t)> at;
  std::shared_ptr<const void> keep;
  double value(std::size_t r) const { return data ? data[r] : at(r); }
};

// Every column of `d` by pointer (d outlives the columns).
std::vector<TableColumn> table_columns(const Dataset& d);

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

}  // namespace kfw
