// The hand-written reader behind every CSV kfw opens (docs/architecture.md says why no library):

// one pass over the file's bytes, fields split with memchr, numbers read with fast_float.
#include "data/table.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <limits>
#include <unordered_set>

#include "core/dataset.h"
#include "core/suggest.h"
#include "data/csv.h"
#include "data/input_file.h"

namespace kfw {

namespace {

struct Field {
  std::string_view text;
  std::size_t col = 1;  // 1-based character column
};

bool blank(char c) {
  return c == ' ' || c == '\t';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && blank(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && (blank(s.back()) || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

void push_trimmed(std::string_view line, const char* b, const char* e, std::vector<Field>& out) {
  const std::string_view f = trim(std::string_view(b, static_cast<std::size_t>(e - b)));
  const char* start = f.empty() ? b : f.data();
  out.push_back({f, static_cast<std::size_t>(start - line.data()) + 1});
}

// Splits one line (no line end) into fields. Quoted fields may hold the separator and "" for a
// quote; their text lives in `scratch`. Returns the 1-based column of an unterminated quote, or 0.
std::size_t split(std::string_view line, char sep, std::vector<Field>& out,
                  std::deque<std::string>& scratch) {
  out.clear();
  const char* b = line.data();
  const char* end = b + line.size();
  if (sep == kWhitespaceSeparator) {
    const char* p = b;
    for (;;) {
      while (p < end && blank(*p))
        ++p;
      if (p == end) return 0;
      const char* s = p;
      while (p < end && !blank(*p))
        ++p;
      out.push_back({std::string_view(s, static_cast<std::size_t>(p - s)),
                     static_cast<std::size_t>(s - b) + 1});
    }
  }
  if (!std::memchr(b, '"', line.size())) {
    const char* p = b;
    for (;;) {
      const auto* q =
          static_cast<const char*>(std::memchr(p, sep, static_cast<std::size_t>(end - p)));
      const char* fe = q ? q : end;
      push_trimmed(line, p, fe, out);
      if (!q) return 0;
      p = q + 1;
    }
  }
  const char* p = b;
  for (;;) {
    const char* s = p;
    while (p < end && blank(*p) && *p != sep)
      ++p;
    if (p < end && *p == '"') {
      const char* open = p;
      std::string text;
      ++p;
      for (;;) {
        if (p == end) return static_cast<std::size_t>(open - b) + 1;
        if (*p == '"') {
          if (p + 1 < end && p[1] == '"') {
            text += '"';
            p += 2;
            continue;
          }
          ++p;
          break;
        }
        text += *p++;
      }
      while (p < end && *p != sep)
        ++p;  // anything after the closing quote up to the separator is dropped
      scratch.push_back(std::move(text));
      out.push_back({scratch.back(), static_cast<std::size_t>(open - b) + 1});
    } else {
      while (p < end && *p != sep)
        ++p;
      push_trimmed(line, s, p, out);
    }
    if (p == end) return 0;
    ++p;
  }
}

// Separators counted outside quotes.
std::size_t count_outside_quotes(std::string_view line, char c) {
  std::size_t n = 0;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"')
      quoted = !quoted;
    else if (ch == c && !quoted)
      ++n;
  }
  return n;
}

// The separator that splits the header and the sample rows into the same number of fields (tab,
// then semicolon, then comma); else the one most frequent in the header; else whitespace.
char detect_separator(const std::vector<std::string_view>& sample) {
  const char candidates[] = {'\t', ';', ','};
  for (char c : candidates) {
    const std::size_t n = count_outside_quotes(sample.front(), c);
    if (n == 0) continue;
    bool same = true;
    for (std::size_t i = 1; i < sample.size() && same; ++i)
      same = count_outside_quotes(sample[i], c) == n;
    if (same) return c;
  }
  char best = 0;
  std::size_t most = 0;
  for (char c : candidates) {
    const std::size_t n = count_outside_quotes(sample.front(), c);
    if (n > most) {
      most = n;
      best = c;
    }
  }
  if (best) return best;
  const std::string_view h = trim(sample.front());
  if (std::find_if(h.begin(), h.end(), blank) != h.end()) return kWhitespaceSeparator;
  return ',';
}

// A number, fast: fast_float on the whole cell; false for anything needing a closer look.
inline bool fast_number(const char* b, const char* e, double& v, bool decimal_comma) {
  auto r = fast_float::from_chars(b, e, v);
  if (r.ec == std::errc() && r.ptr == e) return std::isfinite(v);
  if (decimal_comma && r.ptr != e && *r.ptr == ',') {
    r = fast_float::from_chars_advanced(
        b, e, v, fast_float::parse_options(fast_float::chars_format::general, ','));
    return r.ec == std::errc() && r.ptr == e && std::isfinite(v);
  }
  return false;
}

// The slow path: missing words, a sign, the decimal comma, and the message for an invalid cell.
Expected<double> slow_number(std::string_view f, bool decimal_comma) {
  if (decimal_comma && f.find(',') != std::string_view::npos) {
    std::string s(f);
    std::replace(s.begin(), s.end(), ',', '.');
    auto v = parse_cell(s);
    if (!v) return Error{"'" + shown_field(f) + "' is not a number"};
    return v;
  }
  return parse_cell(f);
}

struct Line {
  std::string_view text;
  std::size_t start = 0;  // offset in the file
  std::size_t number = 0;
};

}  // namespace

int Table::index(std::string_view name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::string Table::separator_name() const {
  return separator_key(separator ? separator : ',');
}

namespace {
std::vector<Field> row_fields(const Table& t, std::size_t row, std::deque<std::string>& scratch) {
  const std::size_t s = t.row_start_[row];
  const char* b = t.text_.data() + s;
  const auto* nl = static_cast<const char*>(std::memchr(b, '\n', t.text_.size() - s));
  std::string_view line(b, nl ? static_cast<std::size_t>(nl - b) : t.text_.size() - s);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<Field> f;
  split(line, t.separator, f, scratch);
  return f;
}
}  // namespace

std::string Table::cell(std::size_t row, std::size_t col) const {
  std::deque<std::string> scratch;
  const auto f = row_fields(*this, row, scratch);
  return col < f.size() ? std::string(f[col].text) : std::string();
}

std::size_t Table::cell_column(std::size_t row, std::size_t col) const {
  std::deque<std::string> scratch;
  const auto f = row_fields(*this, row, scratch);
  return col < f.size() ? f[col].col : 0;
}

std::string source_position(const std::string& source, std::size_t line, std::size_t col) {
  std::string s = source + ":" + std::to_string(line);
  if (col) s += ":" + std::to_string(col);
  return s;
}

Expected<char> parse_separator(const std::string& s) {
  if (s == "," || s == "comma") return ',';
  if (s == ";" || s == "semicolon") return ';';
  if (s == "\t" || s == "\\t" || s == "tab") return '\t';
  if (s == " " || s == "space" || s == "whitespace") return kWhitespaceSeparator;
  return Error{"unknown separator '" + s + "' (comma, semicolon, tab, whitespace)"};
}

std::string separator_key(char sep) {
  switch (sep) {
    case 0:
      return "";
    case ';':
      return "semicolon";
    case '\t':
      return "tab";
    case kWhitespaceSeparator:
      return "whitespace";
    default:
      return "comma";
  }
}

Expected<HeaderRow> parse_header_row(const std::string& s) {
  if (s == "detect" || s == "auto") return HeaderRow::detect;
  if (s == "first") return HeaderRow::first;
  if (s == "none") return HeaderRow::none;
  return Error{"unknown header '" + s + "' (detect, first, none)"};
}

std::string header_row_name(HeaderRow h) {
  return h == HeaderRow::first ? "first" : h == HeaderRow::none ? "none" : "detect";
}

std::string positional_name(std::size_t index0) {
  return "col" + std::to_string(index0 + 1);
}

Expected<Table> parse_table(std::string text, const std::string& source, const TableOptions& opt) {
  return parse_table(InputBytes::of(std::move(text)), source, opt);
}

namespace {
Expected<Table> parse_table_text(std::shared_ptr<const InputBytes> bytes, const std::string& source,
                                 const TableOptions& opt) {
  const std::string_view text = bytes->view();
  Table t;
  t.source = source;
  if (const void* nul = std::memchr(text.data(), '\0', text.size())) {
    const auto pos = static_cast<std::size_t>(static_cast<const char*>(nul) - text.data());
    const auto line = 1 + static_cast<std::size_t>(std::count(
                              text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
    return Error{source_position(source, line) + ": not a text file (NUL byte)"};
  }
  std::size_t pos = 0;
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) pos = 3;  // UTF-8 BOM
  std::size_t line_no = 0;
  // The next non-empty, non-comment line; false at the end.
  auto next = [&](Line& out) -> Expected<bool> {
    while (pos < text.size()) {
      const char* b = text.data() + pos;
      const auto* nl = static_cast<const char*>(std::memchr(b, '\n', text.size() - pos));
      const std::size_t len = nl ? static_cast<std::size_t>(nl - b) : text.size() - pos;
      ++line_no;
      const std::size_t start = pos;
      pos += len + (nl ? 1 : 0);
      if (len > kMaxCsvLineBytes) {
        return Error{source_position(source, line_no) + ": line longer than " +
                     std::to_string(kMaxCsvLineBytes / (1024 * 1024)) + " MB"};
      }
      std::string_view line(b, len);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      std::size_t i = 0;
      while (i < line.size() && blank(line[i]))
        ++i;
      if (i == line.size() || line[i] == '#') continue;
      out = {line, start, line_no};
      return true;
    }
    return false;
  };
  Line header;
  auto got = next(header);
  if (!got) return got.err();
  if (!*got) return Error{source + ": empty file (expected a header row)"};
  // Detection looks at the header and up to 50 rows after it.
  t.separator = opt.separator;
  if (!t.separator) {
    std::vector<std::string_view> sample{header.text};
    const std::size_t save_pos = pos, save_line = line_no;
    Line l;
    while (sample.size() < 51) {
      auto more = next(l);
      if (!more) return more.err();
      if (!*more) break;
      sample.push_back(l.text);
    }
    pos = save_pos;
    line_no = save_line;
    t.separator = detect_separator(sample);
  }
  t.decimal_comma = t.separator == ';';
  std::vector<Field> fields;
  std::deque<std::string> scratch;
  if (std::size_t q = split(header.text, t.separator, fields, scratch)) {
    return Error{source_position(source, header.number, q) + ": unterminated quote"};
  }
  if (fields.size() > kMaxCsvColumns) {
    return Error{source_position(source, header.number) + ": " + std::to_string(fields.size()) +
                 " columns: more than the limit of " + std::to_string(kMaxCsvColumns)};
  }
  auto is_number = [&](std::string_view f) {
    double v = 0.0;
    return !f.empty() && fast_number(f.data(), f.data() + f.size(), v, t.decimal_comma);
  };
  HeaderRow mode = opt.header;
  if (mode == HeaderRow::detect) {
    // Data, not names: every cell a number or a missing-value word, at least one a number.
    bool numbers = false, all = true;
    for (const auto& f : fields) {
      if (is_number(f.text))
        numbers = true;
      else if (!slow_number(f.text, t.decimal_comma))
        all = false;
    }
    mode = numbers && all ? HeaderRow::none : HeaderRow::first;
  }
  if (mode == HeaderRow::none) {
    for (std::size_t c = 0; c < fields.size(); ++c)
      t.names.push_back(positional_name(c));
    pos = header.start;  // the first row is data: read it again below
    line_no = header.number - 1;
  } else {
    t.header_line = header.number;
    std::unordered_set<std::string_view> seen;
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const std::string_view name = fields[c].text;
      if (name.empty()) {
        return Error{source_position(source, header.number, fields[c].col) + ": column " +
                     std::to_string(c + 1) + " has an empty header name"};
      }
      if (c == 0 && opt.header == HeaderRow::detect && is_number(name)) {
        return Error{source_position(source, header.number, 1) +
                     ": the first row must be a header row of column names, found the number '" +
                     shown_field(name) + "' next to text (a file without a header: all numbers)"};
      }
      if (!seen.insert(name).second) {
        return Error{source_position(source, header.number, fields[c].col) +
                     ": duplicate column '" + shown_field(name) + "'"};
      }
      t.names.emplace_back(name);
    }
  }
  const std::size_t ncols = t.names.size();
  t.values.resize(ncols);
  t.invalid.assign(ncols, 0);
  t.first_invalid.resize(ncols);
  const std::size_t estimate =
      (text.size() - pos) / std::max<std::size_t>(header.text.size(), 8) + 16;
  for (auto& v : t.values)
    v.reserve(estimate);
  t.row_start_.reserve(estimate);
  t.row_line_.reserve(estimate);
  const bool dc = t.decimal_comma;
  Line l;
  for (;;) {
    auto more = next(l);
    if (!more) return more.err();
    if (!*more) break;
    scratch.clear();
    if (std::size_t q = split(l.text, t.separator, fields, scratch)) {
      return Error{source_position(source, l.number, q) + ": unterminated quote"};
    }
    if (fields.size() != ncols) {
      return Error{source_position(source, l.number) + ": expected " + std::to_string(ncols) +
                   " fields as in the " + (t.has_header() ? "header" : "first row") + ", found " +
                   std::to_string(fields.size())};
    }
    for (std::size_t c = 0; c < ncols; ++c) {
      const std::string_view f = fields[c].text;
      double v = 0.0;
      if (!f.empty() && fast_number(f.data(), f.data() + f.size(), v, dc)) {
        t.values[c].push_back(v);
        continue;
      }
      auto slow = slow_number(f, dc);
      if (slow) {
        t.values[c].push_back(*slow);
        continue;
      }
      t.values[c].push_back(kNoSample);
      if (t.invalid[c]++ == 0) t.first_invalid[c] = {l.number, fields[c].col, slow.error()};
    }
    t.row_start_.push_back(l.start);
    t.row_line_.push_back(static_cast<std::uint32_t>(l.number));
    if (opt.progress && (t.row_line_.size() % 8192) == 0 &&
        !opt.progress(static_cast<double>(pos) / static_cast<double>(text.size()))) {
      return Error{source + ": reading cancelled"};
    }
  }
  if (t.rows() == 0) return Error{source + ": no data rows after the header"};  // header only
  t.bytes_ = std::move(bytes);
  t.text_ = text;
  return t;
}
}  // namespace

Expected<Table> parse_table(std::shared_ptr<const InputBytes> bytes, const std::string& source,
                            const TableOptions& opt) {
  auto t = parse_table_text(bytes, source, opt);
  if (bytes->changed()) {
    return Error{source +
                 ": the file was truncated while being read (another program is writing "
                 "it?); read it again when it is complete"};
  }
  return t;
}

Expected<std::string> read_file_bytes(const std::string& path, std::size_t max_line) {
  return read_input_file(path, limits::Input::kData, max_line);
}

Expected<Table> read_table(const std::string& path, const TableOptions& opt) {
  auto bytes = InputBytes::open(path, limits::Input::kData, kMaxCsvLineBytes);
  if (!bytes) return bytes.err();
  return parse_table(std::move(*bytes), path, opt);
}

}  // namespace kfw
