// Paths inside a file that names other files (a preset's data, a session's preset and logs):
// written relative to the file's own folder, read back from there, so a folder of presets,
// sessions and logs can be copied or moved whole.
#pragma once

#include <string>

namespace kfw {

// `target` as written into `file`: relative to file's folder when both are on one root, else
// absolute. A relative `target` is taken from the current folder. Empty stays empty.
std::string path_for_file(const std::string& target, const std::string& file);
// A path read from `file`: a relative one is taken from file's folder. `cwd_fallback`: a
// relative path that names nothing there but names something from the current folder (a session
// written before paths were relative to it), or a bare name (a preset's), is kept as written.
std::string path_from_file(const std::string& written, const std::string& file,
                           bool cwd_fallback = false);

}  // namespace kfw
