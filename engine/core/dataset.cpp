#include "core/dataset.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kfw {

int Dataset::index(std::string_view name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

const std::vector<double>& Dataset::col(std::string_view name) const {
  const int i = index(name);
  if (i < 0) throw std::logic_error("kfw: dataset has no column '" + std::string(name) + "'");
  return columns[static_cast<std::size_t>(i)];
}

std::vector<TableColumn> table_columns(const Dataset& d) {
  std::vector<TableColumn> out;
  out.reserve(d.names.size());
  for (std::size_t c = 0; c < d.names.size(); ++c)
    out.push_back(TableColumn{d.names[c], d.columns[c].data(), {}, {}});
  return out;
}

std::vector<double>& Dataset::add(std::string name, std::size_t n) {
  names.push_back(std::move(name));
  columns.emplace_back(n, kNoSample);
  return columns.back();
}

double Dataset::median_dt() const {
  const int i = index("t");
  if (i < 0 || rows() < 2) return kNoSample;
  const auto& t = columns[static_cast<std::size_t>(i)];
  std::vector<double> dt(t.size() - 1);
  for (std::size_t k = 1; k < t.size(); ++k)
    dt[k - 1] = t[k] - t[k - 1];
  auto mid = dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2);
  std::nth_element(dt.begin(), mid, dt.end());
  return *mid;
}

Status require_columns(const Dataset& d, const std::vector<ColumnSpec>& spec) {
  for (const auto& c : spec) {
    if (c.required && !d.has(c.name)) {
      std::string msg = d.source + ": missing required column '" + c.name + "'";
      if (!c.meaning.empty()) msg += " (" + c.meaning + (c.unit.empty() ? "" : ", " + c.unit) + ")";
      msg += "; columns present:";
      for (const auto& n : d.names)
        msg += " " + n;
      return Error{msg};
    }
  }
  return Ok{};
}

Status require_some_value(const Dataset& d, const std::vector<ColumnSpec>& spec) {
  for (const auto& c : spec) {
    if (!c.required || !d.has(c.name)) continue;
    const auto& col = d.col(c.name);
    const bool any = std::any_of(col.begin(), col.end(), [](double v) { return std::isfinite(v); });
    if (!any) {
      return Error{d.source + ": column '" + c.name +
                   "' has no value (every cell is empty or NaN)"};
    }
  }
  return Ok{};
}

}  // namespace kfw
