// One writer for every output file. A command declares its outputs before any work (each path is
// checked: not an input of the command, not a directory, FIFO or device, its directory exists and
// is writable — exit 2, nothing written), stages their content while it works, and commits only
// after it succeeded: each file goes to a uniquely named temporary beside its target
// (".NAME.kfw-XXXXXX"), is fsynced and renamed into place. A symlink is written through to its
// target. A failed commit removes its temporaries and returns a failure (exit 1).
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace kfw {

// Test hook: milliseconds to sleep after the temporaries are written and before the renames.
inline constexpr const char* kPauseBeforeRenameEnv = "KFW_TEST_PAUSE_BEFORE_RENAME";

// A streamed output's bytes on their way to the staged temporary: a 1 MiB buffer written out
// as it fills, so an output costs its formatting and O(1) memory whatever its length.
class OutputStream {
 public:
  explicit OutputStream(int fd);
  OutputStream(const OutputStream&) = delete;
  OutputStream& operator=(const OutputStream&) = delete;
  void write(std::string_view bytes);
  // Room for `n` bytes (n ≤ kBuffer) at the end of the buffer; then wrote(k) for the k used.
  char* reserve(std::size_t n);
  void wrote(std::size_t k) { used_ += k; }
  // Writes the buffer out; false (errno kept in error()) once a write failed.
  bool flush();
  int error() const { return error_; }
  static constexpr std::size_t kBuffer = std::size_t{1} << 20;

 private:
  int fd_;
  int error_ = 0;
  std::size_t used_ = 0;
  std::unique_ptr<char[]> buf_;
};

// A std::ostream over an OutputStream (nlohmann::json and other stream writers).
class OutputStreamBuf : public std::streambuf {
 public:
  explicit OutputStreamBuf(OutputStream& out) : out_(out) {}

 protected:
  int_type overflow(int_type c) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;

 private:
  OutputStream& out_;
};

// Writes a streamed output's content; an Error stops the commit (nothing is replaced).
using OutputWriter = std::function<Status(OutputStream&)>;

class OutputSet {
 public:
  // A file the command reads; an output that is the same file is refused.
  void add_input(const std::string& path);
  // Declares an output (before any work). `option` names it in messages ("--out").
  Status add(const std::string& path, std::string_view option = {});
  // The content of a declared output.
  Status stage(const std::string& path, std::string text);
  // The content of a declared output, written at commit straight into its temporary; what the
  // writer reads must live until commit() returns.
  Status stage_stream(const std::string& path, OutputWriter writer);
  // Writes every staged output (unstaged ones are left alone). Exit 1 on failure.
  Status commit();

  // Where `path` is written: the final target of a symlink chain, else the path itself.
  static Expected<std::filesystem::path> target_of(const std::string& path);

 private:
  struct Entry {
    std::string path;  // as given
    std::string option;
    std::filesystem::path target;  // what is replaced
    std::optional<std::string> text;
    OutputWriter writer;  // a streamed output (text empty)
  };
  std::vector<std::filesystem::path> inputs_;
  std::vector<Entry> entries_;
};

// Writes one file the same way (check, unique temporary, fsync, rename); for the GUI's presets
// and sessions.
Status write_file_atomic(const std::string& path, std::string text);

}  // namespace kfw
