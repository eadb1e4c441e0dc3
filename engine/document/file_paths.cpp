#include "document/file_paths.h"

#include <filesystem>
#include <system_error>

namespace kfw {

namespace fs = std::filesystem;

namespace {
fs::path folder_of(const std::string& file) {
  std::error_code ec;
  fs::path dir = fs::path(file).parent_path();
  // A file named without a folder ("p.json") is in the current one (absolute("") throws).
  if (dir.empty()) dir = fs::current_path(ec);
  return ec ? fs::path() : fs::absolute(dir, ec).lexically_normal();
}
}  // namespace

std::string path_for_file(const std::string& target, const std::string& file) {
  if (target.empty() || file.empty()) return target;
  std::error_code ec;
  const fs::path dir = folder_of(file);
  const fs::path abs = fs::absolute(fs::path(target), ec).lexically_normal();
  if (ec || dir.empty()) return target;
  const fs::path rel = abs.lexically_relative(dir);
  return rel.empty() ? abs.string() : rel.string();
}

std::string path_from_file(const std::string& written, const std::string& file, bool cwd_fallback) {
  const fs::path p(written);
  if (written.empty() || p.is_absolute() || file.empty()) return written;
  const fs::path beside = (fs::path(file).parent_path() / p).lexically_normal();
  std::error_code ec;
  // Nothing beside the file: a path from the current folder (an older session) or a bare name (a
  // preset named by its name) is kept as written.
  if (cwd_fallback && !fs::exists(beside, ec) && (fs::exists(p, ec) || !p.has_parent_path()))
    return written;
  return beside.string();
}

}  // namespace kfw
