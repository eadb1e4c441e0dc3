// The one input policy for every file the programs read (data, preset, model, mapping, session,
// Monte Carlo and sweep parts), CLI and GUI alike: regular files only — a FIFO, device, socket or
// directory is refused at once, without blocking on it — and at most the kind's byte cap
// (core/limits.h), checked before reading and while reading.
#pragma once

#include <string>

#include "core/expected.h"
#include "core/limits.h"

namespace kfw {

// The whole file. `max_line` > 0: stops early once a line is longer (the parser refuses it).
Expected<std::string> read_input_file(const std::string& path, limits::Input kind,
                                      std::size_t max_line = 0);

// Opens the file for reading under the policy (not the byte cap): a descriptor the caller closes.
Expected<int> open_input_file(const std::string& path, limits::Input kind);

}  // namespace kfw
