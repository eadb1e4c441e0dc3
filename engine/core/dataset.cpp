#include "core/dataset.h"

#include "core/import.h"
#include "core/output.h"
#include "core/suggest.h"
#include "core/table.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

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

namespace {

bool is_missing_word(std::string_view s) {
  return s.empty() || s == "nan" || s == "NaN" || s == "NAN" || s == "-nan" || s == "NA";
}

}  // namespace

Expected<double> parse_cell(std::string_view f) {
  if (is_missing_word(f)) return kNoSample;
  const char* b = f.data();
  const char* e = f.data() + f.size();
  if (*b == '+') ++b;
  double v = 0.0;
  auto [ptr, ec] = fast_float::from_chars(b, e, v);
  if (ec != std::errc() || ptr != e) {
    std::ostringstream os;
    os << '\'' << shown_field(f) << "' is not a number";
    return Error{os.str()};
  }
  if (std::isnan(v)) return kNoSample;
  if (std::isinf(v)) {
    if (f.find_first_of("iI") != std::string_view::npos) return Error{"infinite value"};
    std::ostringstream os;
    os << '\'' << shown_field(f) << "' overflows a double";
    return Error{os.str()};
  }
  return v;
}

namespace {
Expected<Dataset> parse_csv_text(std::string text, const std::string& source,
                                 const CsvOptions& opt) {
  TableOptions topt;
  topt.progress = opt.progress;
  auto t = parse_table(std::move(text), source, topt);
  if (!t) return t.err();
  if (!t->has_header()) {  // kfw's own format names its columns
    return Error{source_position(source, t->line_of(0), 1) +
                 ": the first row must be a header row of column names, found the number '" +
                 t->cell(0, 0) + "'"};
  }
  if (t->index(opt.time_column) < 0) {
    return Error{source + ":" + std::to_string(t->header_line) + ": no time column '" +
                 opt.time_column + "' in the header"};
  }
  // Every validated column is a role of its own name; the time column is the role "t".
  Mapping m;
  m["t"].column = opt.time_column;
  std::vector<ColumnSpec> roles;
  for (const auto& n : opt.validate.empty() ? t->names : opt.validate) {
    if (n != opt.time_column && t->index(n) >= 0) roles.push_back({n, "", "", false});
  }
  auto d = import_table(*t, m, roles);
  if (!d) return d;
  if (opt.time_column != "t") d->names.front() = opt.time_column;
  return d;
}
}  // namespace

Expected<Dataset> parse_csv(std::istream& in, const std::string& source, const CsvOptions& opt) {
  std::ostringstream os;
  os << in.rdbuf();
  return parse_csv_text(std::move(os).str(), source, opt);
}

Expected<Dataset> read_csv(const std::string& path, const CsvOptions& opt) {
  auto bytes = read_file_bytes(path, kMaxCsvLineBytes);
  if (!bytes) return bytes.err();
  return parse_csv_text(std::move(*bytes), path, opt);
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

void write_csv(std::ostream& out, const Dataset& d) {
  for (std::size_t c = 0; c < d.names.size(); ++c)
    out << (c ? "," : "") << d.names[c];
  out << '\n';
  char buf[64];
  for (std::size_t r = 0; r < d.rows(); ++r) {
    for (std::size_t c = 0; c < d.columns.size(); ++c) {
      if (c) out << ',';
      const double v = d.columns[c][r];
      if (std::isfinite(v)) {
        auto res = std::to_chars(buf, buf + sizeof buf, v);
        out.write(buf, res.ptr - buf);
      }
    }
    out << '\n';
  }
}

Status write_text_file_atomic(const std::string& path, const std::string& text) {
  return write_file_atomic(path, text);  // unique temporary beside the target (output.h)
}

Status write_csv_file(const std::string& path, const Dataset& d) {
  std::ostringstream os;
  write_csv(os, d);
  return write_text_file_atomic(path, os.str());
}

}  // namespace kfw
