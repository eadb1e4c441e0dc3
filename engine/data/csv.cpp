#include "data/csv.h"

#include "core/cores.h"
#include "core/suggest.h"
#include "data/import.h"
#include "data/output.h"
#include "data/table.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <deque>
#include <future>
#include <sstream>

namespace kfw {

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
Expected<Dataset> parse_csv_text(std::shared_ptr<const InputBytes> text, const std::string& source,
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
  return parse_csv_text(InputBytes::of(std::move(os).str()), source, opt);
}

Expected<Dataset> read_csv(const std::string& path, const CsvOptions& opt) {
  auto bytes = InputBytes::open(path, limits::Input::kData, kMaxCsvLineBytes);
  if (!bytes) return bytes.err();
  return parse_csv_text(std::move(*bytes), path, opt);
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

namespace {

constexpr std::size_t kCell = 32;  // a shortest double is at most 24 characters

// Rows [first, last) as CSV text, appended to `text`.
void format_rows(const std::vector<TableColumn>& columns, std::size_t first, std::size_t last,
                 std::string& text) {
  text.resize(text.size() + (last - first) * (columns.size() * kCell + 1));
  char* p = text.data() + text.size() - (last - first) * (columns.size() * kCell + 1);
  for (std::size_t r = first; r < last; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) *p++ = ',';
      const double v = columns[c].value(r);
      if (std::isfinite(v)) p = std::to_chars(p, p + kCell, v).ptr;
    }
    *p++ = '\n';
  }
  text.resize(static_cast<std::size_t>(p - text.data()));
}

// The cores this process may run on (its affinity), at most 8: formatting more in parallel than
// the disk takes gains nothing.
std::size_t format_threads() {
  return static_cast<std::size_t>(std::clamp(usable_cores(), 1, 8));
}

}  // namespace

Status write_csv_stream(OutputStream& out, const std::vector<TableColumn>& columns,
                        std::size_t rows) {
  std::string header;
  for (std::size_t c = 0; c < columns.size(); ++c)
    header += (c ? "," : "") + columns[c].name;
  out.write(header + "\n");
  // Blocks of rows are formatted on every core while the blocks before them are written, in
  // order: the same bytes as one thread, in O(threads · block) memory.
  const std::size_t block =
      std::max<std::size_t>(1, (std::size_t{1} << 20) / (columns.size() * kCell + 1));
  const std::size_t blocks = (rows + block - 1) / block;
  const std::size_t threads = blocks > 2 ? format_threads() : 1;
  std::deque<std::future<std::string>> pending;
  std::size_t next = 0;
  auto launch = [&] {
    const std::size_t first = next * block, last = std::min(rows, first + block);
    ++next;
    pending.push_back(std::async(threads > 1 ? std::launch::async : std::launch::deferred,
                                 [&columns, first, last] {
                                   std::string text;
                                   format_rows(columns, first, last, text);
                                   return text;
                                 }));
  };
  while (next < blocks && pending.size() < 2 * threads)
    launch();
  while (!pending.empty()) {
    const std::string text = pending.front().get();
    pending.pop_front();
    if (next < blocks) launch();
    out.write(text);
    if (out.error()) {
      for (auto& f : pending)
        f.wait();
      return failure(std::string("write failed: ") + std::strerror(out.error()));
    }
  }
  return Ok{};
}

Status write_text_file_atomic(const std::string& path, const std::string& text) {
  return write_file_atomic(path, text);  // unique temporary beside the target (output.h)
}

Status write_csv_file(const std::string& path, const Dataset& d) {
  OutputSet out;
  if (auto st = out.add(path); !st) return st;
  const auto columns = table_columns(d);
  auto st = out.stage_stream(
      path, [&](OutputStream& os) { return write_csv_stream(os, columns, d.rows()); });
  if (!st) return st;
  return out.commit();
}

}  // namespace kfw
