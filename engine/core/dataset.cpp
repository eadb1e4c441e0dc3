#include "core/dataset.h"

#include "core/output.h"

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

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

// Fields of a line with their 1-based character columns (for FILE:LINE:COL messages).
struct Field {
  std::string_view text;
  std::size_t col = 1;
};

void split(std::string_view line, std::vector<Field>& out) {
  out.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    const std::string_view raw = line.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    const std::string_view f = trim(raw);
    const std::size_t lead = f.empty() ? 0 : static_cast<std::size_t>(f.data() - raw.data());
    out.push_back({f, start + lead + 1});
    if (comma == std::string_view::npos) return;
    start = comma + 1;
  }
}

bool is_missing_word(std::string_view s) {
  return s.empty() || s == "nan" || s == "NaN" || s == "NAN" || s == "-nan" || s == "NA";
}

// A token as it may appear in a message: at most 40 characters.
std::string shown(std::string_view s) {
  if (s.size() <= 40) return std::string(s);
  return std::string(s.substr(0, 40)) + "…";
}

std::string at(const std::string& source, std::size_t line, std::size_t col = 0) {
  std::ostringstream os;
  os << source << ':' << line;
  if (col) os << ':' << col;
  return os.str();
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
    os << '\'' << shown(f) << "' is not a number";
    return Error{os.str()};
  }
  if (std::isnan(v)) return kNoSample;
  if (std::isinf(v)) {
    if (f.find_first_of("iI") != std::string_view::npos) return Error{"infinite value"};
    std::ostringstream os;
    os << '\'' << shown(f) << "' overflows a double";
    return Error{os.str()};
  }
  return v;
}

Expected<Dataset> parse_csv(std::istream& in, const std::string& source, const CsvOptions& opt) {
  Dataset d;
  d.source = source;
  std::string line;
  std::size_t line_no = 0;
  std::vector<Field> fields;
  auto too_long = [&] {
    return Error{at(source, line_no) + ": line longer than " +
                 std::to_string(kMaxCsvLineBytes / (1024 * 1024)) + " MB"};
  };
  auto binary = [&] { return Error{at(source, line_no) + ": not a text file (NUL byte)"}; };
  // Header: the first non-empty line that is not a comment.
  while (std::getline(in, line)) {
    ++line_no;
    if (line.size() > kMaxCsvLineBytes) return too_long();
    if (line.find('\0') != std::string::npos) return binary();
    const std::string_view lv = trim(line);
    if (!lv.empty() && lv.front() != '#') break;
  }
  if (line_no == 0 || trim(line).empty() || trim(line).front() == '#')
    return Error{source + ": empty file (expected a header row)"};
  if (line.size() >= 3 && static_cast<unsigned char>(line[0]) == 0xEF &&
      static_cast<unsigned char>(line[1]) == 0xBB && static_cast<unsigned char>(line[2]) == 0xBF)
    line.erase(0, 3);  // BOM
  split(line, fields);
  if (fields.size() > kMaxCsvColumns) {
    return Error{at(source, line_no) + ": " + std::to_string(fields.size()) +
                 " columns: more than the limit of " + std::to_string(kMaxCsvColumns)};
  }
  std::unordered_set<std::string> seen;
  for (std::size_t c = 0; c < fields.size(); ++c) {
    std::string name(fields[c].text);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') {
      name = name.substr(1, name.size() - 2);
    }
    double dummy = 0.0;
    if (name.empty()) {
      return Error{at(source, line_no, fields[c].col) + ": column " + std::to_string(c + 1) +
                   " has an empty header name"};
    }
    if (c == 0 &&
        fast_float::from_chars(name.data(), name.data() + name.size(), dummy).ec == std::errc()) {
      return Error{at(source, line_no, 1) +
                   ": the first row must be a header row of column names, found the number '" +
                   shown(name) + "'"};
    }
    if (!seen.insert(name).second) {
      return Error{at(source, line_no, fields[c].col) + ": duplicate column '" + shown(name) + "'"};
    }
    d.names.push_back(std::move(name));
    d.columns.emplace_back();
  }
  const auto ti = std::find(d.names.begin(), d.names.end(), opt.time_column);
  if (ti == d.names.end()) {
    return Error{at(source, line_no) + ": no time column '" + opt.time_column + "' in the header"};
  }
  const auto tcol = static_cast<std::size_t>(ti - d.names.begin());
  const std::size_t ncols = d.names.size();
  // Only columns bound to a role are validated (all of them when none are named).
  std::vector<char> checked(ncols, opt.validate.empty() ? 1 : 0);
  for (const auto& name : opt.validate) {
    auto it = std::find(d.names.begin(), d.names.end(), name);
    if (it != d.names.end()) checked[static_cast<std::size_t>(it - d.names.begin())] = 1;
  }
  checked[tcol] = 1;
  std::size_t rows = 0;
  double last_t = -std::numeric_limits<double>::infinity();
  std::string last_t_text;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.size() > kMaxCsvLineBytes) return too_long();
    const std::string_view lv = trim(line);
    if (lv.empty()) continue;
    if (lv.front() == '#') continue;
    if (lv.find('\0') != std::string_view::npos) return binary();
    split(line, fields);
    if (fields.size() != ncols) {
      return Error{at(source, line_no) + ": expected " + std::to_string(ncols) +
                   " fields as in the header, found " + std::to_string(fields.size())};
    }
    for (std::size_t c = 0; c < ncols; ++c) {
      auto v = parse_cell(fields[c].text);
      if (!v) {
        if (checked[c]) {
          return Error{at(source, line_no, fields[c].col) + ": column '" + shown(d.names[c]) +
                       "': " + v.error()};
        }
        d.columns[c].push_back(kNoSample);
        continue;
      }
      d.columns[c].push_back(*v);
    }
    const double t = d.columns[tcol].back();
    if (std::isnan(t)) {
      return Error{at(source, line_no, fields[tcol].col) + ": column '" + opt.time_column +
                   "' is empty (every row needs a time)"};
    }
    if (!(t > last_t)) {
      return Error{at(source, line_no, fields[tcol].col) + ": time is not increasing (" +
                   opt.time_column + " = " + shown(fields[tcol].text) + " after " + last_t_text +
                   ")"};
    }
    if (rows > 0 && !std::isfinite(t - last_t)) {
      return Error{at(source, line_no, fields[tcol].col) + ": the step from " + last_t_text +
                   " to " + shown(fields[tcol].text) + " overflows a double"};
    }
    last_t = t;
    last_t_text = shown(fields[tcol].text);
    ++rows;
    if (opt.progress && (rows % 8192) == 0 && !opt.progress(0.0)) {
      return Error{source + ": reading cancelled"};
    }
  }
  if (rows == 0) return Error{source + ": no data rows after the header"};
  return d;
}

Expected<Dataset> read_csv(const std::string& path, const CsvOptions& opt) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return Error{path + ": is a directory, not a CSV file"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open file"};
  return parse_csv(in, path, opt);
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
