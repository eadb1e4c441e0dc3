// The command lines that reproduce a document outside the window: `kfw-cli run` and
// `kfw --export` with its preset, the values that differ from the preset's, its data and the
// data's mapping. What they leave out: pinned snapshots, zoom, the replay cursor, presentation.
#pragma once

#include <string>
#include <vector>

#include "document/document.h"

namespace kfw {

// The arguments after the program and its command: PRESET [--data F] [mapping options]
// [--set KEY=VALUE]... (values written so they read back exactly).
std::vector<std::string> document_args(const Document& doc);
// A mapping as the import options that say it (--time, --map, --unit, --scale, --offset, --flip,
// --sep, --header), numbers in their shortest exact text.
std::vector<std::string> mapping_args(const Mapping& m);
// One argument as a POSIX shell reads it back (single-quoted when it needs to be).
std::string shell_quote(const std::string& arg);
// "kfw-cli run ARGS" and "kfw --export plots ARGS", one per line.
std::string command_lines(const Document& doc);

}  // namespace kfw
