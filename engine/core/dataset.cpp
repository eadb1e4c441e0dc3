#include "core/dataset.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
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

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

void split(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      out.push_back(trim(line.substr(start)));
      return;
    }
    out.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

bool is_nan_word(std::string_view s) {
  return s == "nan" || s == "NaN" || s == "NAN" || s == "-nan" || s == "NA";
}

}  // namespace

Expected<Dataset> parse_csv(std::istream& in, const std::string& source, const CsvOptions& opt) {
  Dataset d;
  d.source = source;
  std::string line;
  std::size_t line_no = 0;
  std::vector<std::string_view> fields;
  // Header: the first non-empty line.
  while (std::getline(in, line)) {
    ++line_no;
    if (!trim(line).empty()) break;
  }
  if (trim(line).empty()) return Error{source + ": empty file (expected a header row)"};
  if (line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEF) line.erase(0, 3);  // BOM
  split(line, fields);
  for (std::size_t c = 0; c < fields.size(); ++c) {
    std::string name(fields[c]);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') {
      name = name.substr(1, name.size() - 2);
    }
    double dummy = 0.0;
    if (name.empty()) {
      return Error{source + ":" + std::to_string(line_no) + ": column " + std::to_string(c + 1) +
                   " has an empty header name"};
    }
    if (c == 0 &&
        std::from_chars(name.data(), name.data() + name.size(), dummy).ec == std::errc()) {
      return Error{source + ":" + std::to_string(line_no) +
                   ": the first row must be a header row of column names, found the number '" +
                   name + "'"};
    }
    if (d.has(name)) {
      return Error{source + ":" + std::to_string(line_no) + ": duplicate column '" + name + "'"};
    }
    d.add(name);
  }
  const int ti = d.index(opt.time_column);
  if (ti < 0) {
    return Error{source + ":" + std::to_string(line_no) + ": no time column '" + opt.time_column +
                 "' in the header"};
  }
  const std::size_t ncols = d.names.size();
  std::size_t rows = 0;
  double last_t = -std::numeric_limits<double>::infinity();
  const auto tcol = static_cast<std::size_t>(ti);
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view lv = trim(line);
    if (lv.empty()) continue;
    if (lv.front() == '#') continue;
    split(lv, fields);
    if (fields.size() != ncols) {
      return Error{source + ":" + std::to_string(line_no) + ": expected " + std::to_string(ncols) +
                   " fields as in the header, found " + std::to_string(fields.size())};
    }
    for (std::size_t c = 0; c < ncols; ++c) {
      const std::string_view f = fields[c];
      double v = kNoSample;
      if (!f.empty() && !is_nan_word(f)) {
        const char* b = f.data();
        if (*b == '+') ++b;
        auto [ptr, ec] = std::from_chars(b, f.data() + f.size(), v);
        if (ec != std::errc() || ptr != f.data() + f.size()) {
          return Error{source + ":" + std::to_string(line_no) + ": column '" + d.names[c] + "': '" +
                       std::string(f) + "' is not a number"};
        }
        if (!std::isfinite(v)) {
          return Error{source + ":" + std::to_string(line_no) + ": column '" + d.names[c] +
                       "': infinite value"};
        }
      }
      d.columns[c].push_back(v);
    }
    const double t = d.columns[tcol].back();
    if (std::isnan(t)) {
      return Error{source + ":" + std::to_string(line_no) + ": column '" + opt.time_column +
                   "' is empty (every row needs a time)"};
    }
    if (!(t > last_t)) {
      return Error{source + ":" + std::to_string(line_no) + ": time is not increasing (" +
                   opt.time_column + " = " + std::string(fields[tcol]) + " after " +
                   std::to_string(last_t) + ")"};
    }
    last_t = t;
    ++rows;
    if (opt.progress && (rows % 8192) == 0 && !opt.progress(0.0)) {
      return Error{source + ": reading cancelled"};
    }
  }
  if (rows == 0) return Error{source + ": no data rows after the header"};
  return d;
}

Expected<Dataset> read_csv(const std::string& path, const CsvOptions& opt) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open file"};
  return parse_csv(in, path, opt);
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
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return Error{path + ": cannot write (cannot create " + tmp + ")"};
    out << text;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      return Error{path + ": write failed"};
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    return Error{path + ": cannot replace the file"};
  }
  return Ok{};
}

Status write_csv_file(const std::string& path, const Dataset& d) {
  std::ostringstream os;
  write_csv(os, d);
  return write_text_file_atomic(path, os.str());
}

}  // namespace kfw
