// One writer for every output file. A command declares its outputs before any work (each path is
// checked: not an input of the command, not a directory, FIFO or device, its directory exists and
// is writable — exit 2, nothing written), stages their content while it works, and commits only
// after it succeeded: each file goes to a uniquely named temporary beside its target
// (".NAME.kfw-XXXXXX"), is fsynced and renamed into place. A symlink is written through to its
// target. A failed commit removes its temporaries and returns a failure (exit 1).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"

namespace kfw {

// Test hook: milliseconds to sleep after the temporaries are written and before the renames.
inline constexpr const char* kPauseBeforeRenameEnv = "KFW_TEST_PAUSE_BEFORE_RENAME";

class OutputSet {
 public:
  // A file the command reads; an output that is the same file is refused.
  void add_input(const std::string& path);
  // Declares an output (before any work). `option` names it in messages ("--out").
  Status add(const std::string& path, std::string_view option = {});
  // The content of a declared output.
  Status stage(const std::string& path, std::string text);
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
  };
  std::vector<std::filesystem::path> inputs_;
  std::vector<Entry> entries_;
};

// Writes one file the same way (check, unique temporary, fsync, rename); for the GUI's presets
// and sessions.
Status write_file_atomic(const std::string& path, std::string text);

}  // namespace kfw
