// A delimited text file read into named columns, before any role is assigned: the first step of
// an import, which never refuses a file for its header names. The separator (comma, semicolon,
// tab, whitespace) is detected unless given; `#` lines are comments; fields may be quoted; a UTF-8
// BOM and CRLF line ends are accepted; in a `;` file a decimal comma is accepted. Numbers are read
// with fast_float (exact, locale-free). A cell that is not a number is kept as no sample and
// remembered (first such cell per column) so that a role bound to the column can name it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "data/input_file.h"

namespace kfw {

inline constexpr char kWhitespaceSeparator = ' ';  // runs of blanks

// Whether the first row (not a comment) names the columns. Detected: a row whose every cell is
// a number (or a missing-value word, at least one a number) is data, and the columns are named
// by position: col1, col2, ...; any other first row is the header.
enum class HeaderRow { detect, first, none };

struct TableOptions {
  char separator = 0;                    // 0: detect; ',' ';' '\t' or kWhitespaceSeparator
  HeaderRow header = HeaderRow::detect;  // first: names even if numeric; none: col1, col2, ...
  std::function<bool(double)> progress;  // fraction read; return false to cancel
};

// The first cell of a column that is not a number (text, inf, overflow).
struct CellIssue {
  std::size_t line = 0;  // 1-based line in the file
  std::size_t col = 0;   // 1-based character column
  std::string message;   // "'x' is not a number", "infinite value", ...
};

struct Table {
  std::string source;
  char separator = ',';
  bool decimal_comma = false;  // `;` files: "1,5" reads as 1.5
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;  // NaN: no sample or not a number
  std::vector<std::size_t> invalid;         // per column: cells that are not numbers
  std::vector<CellIssue> first_invalid;     // per column, when invalid > 0
  std::size_t header_line = 0;              // 0: no header row (columns named col1, col2, ...)

  std::size_t rows() const { return row_line_.size(); }
  std::size_t columns() const { return names.size(); }
  int index(std::string_view name) const;
  std::size_t line_of(std::size_t row) const { return row_line_[row]; }
  // A cell's text as written (unquoted, trimmed) and its 1-based character column.
  std::string cell(std::size_t row, std::size_t col) const;
  std::size_t cell_column(std::size_t row, std::size_t col) const;
  // "comma", "semicolon", "tab", "whitespace".
  std::string separator_name() const;
  bool has_header() const { return header_line > 0; }

  // Filled by the reader: the file's bytes (mapped or read, data/input_file.h) and where each row
  // starts (cells are re-read on demand).
  std::shared_ptr<const InputBytes> bytes_;
  std::string_view text_;
  std::vector<std::size_t> row_start_;
  std::vector<std::uint32_t> row_line_;
};

// "FILE:LINE" or "FILE:LINE:COL" (col 0: none), where a data file's messages point.
std::string source_position(const std::string& source, std::size_t line, std::size_t col = 0);

// A separator by name or character: "," ";" "tab" "\t" "space" "whitespace" "comma" "semicolon".
Expected<char> parse_separator(const std::string& s);
// The separator's name as parse_separator reads it ("comma", ...); "" for 0 (detected).
std::string separator_key(char sep);
// "detect" (or "auto"), "first", "none"; and back.
Expected<HeaderRow> parse_header_row(const std::string& s);
std::string header_row_name(HeaderRow h);
// The name a column gets in a file without a header: "col" + its 1-based position.
std::string positional_name(std::size_t index0);

// Errors name FILE:LINE[:COL]: an empty file, a header only, a binary file (NUL byte), ragged
// rows, an empty or duplicate header name, an unterminated quote, the line and column limits.
Expected<Table> parse_table(std::string text, const std::string& source,
                            const TableOptions& opt = {});
// The same over a file's bytes (a mapped file is never copied; one truncated while it was read
// is an error naming it).
Expected<Table> parse_table(std::shared_ptr<const InputBytes> bytes, const std::string& source,
                            const TableOptions& opt = {});
Expected<Table> read_table(const std::string& path, const TableOptions& opt = {});

// The file's bytes (a directory or an unreadable file is an error naming the path). With
// max_line > 0, reading stops (memory bounded) once a line is longer than max_line bytes: the text
// then ends inside that line, which parse_table refuses as too long, naming its line.
Expected<std::string> read_file_bytes(const std::string& path, std::size_t max_line = 0);

}  // namespace kfw
