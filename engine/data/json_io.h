// Reading JSON documents (presets, sessions, mappings) with messages that name the file, the
// line and column, and the dotted key: "p.json:12:18: parameters.Q.value: number overflows a
// double". Limits: 10 MB and 256 levels of nesting, refused before any parsing of values.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/expected.h"
#include "core/limits.h"
#include "data/output.h"

namespace kfw {

inline constexpr std::size_t kMaxJsonBytes = limits::kJsonBytes;
inline constexpr std::size_t kMaxJsonDepth = limits::kMaxJsonDepth;

// Parses `text` (from `path`). Errors: invalid syntax, a number that overflows a double, a file
// over 10 MB, nesting deeper than 256 — each with line:column and the key path where known.
Expected<nlohmann::json> parse_json_document(const std::string& text, const std::string& path);
// Reads a file under the input policy (data/input_file.h: regular files only, 10 MB) and parses
// it. `what` names the kind in messages: "preset", "model", "mapping", "session", "part".
Expected<nlohmann::json> read_json_document(const std::string& path, const char* what);
// The same, every object's keys kept in the file's order (a model file's parameters are listed,
// and its sliders laid out, in the order the file declares them).
Expected<nlohmann::ordered_json> parse_ordered_json_document(const std::string& text,
                                                             const std::string& path);
Expected<nlohmann::ordered_json> read_ordered_json_document(const std::string& path,
                                                            const char* what);

// Stages `doc` as the content of a declared output, streamed at commit (no text copy in memory):
// the bytes of doc.dump(indent) followed by a newline.
Status stage_json(OutputSet& outs, const std::string& path, nlohmann::json doc, int indent);
Status stage_json(OutputSet& outs, const std::string& path, nlohmann::ordered_json doc, int indent);

// "parameters.Q.value", "model.h[0]": a child key appended to a dotted path, for messages (the
// key printable: control bytes as \xNN, a long key cut).
std::string key_path(std::string_view parent, std::string_view key);
std::string index_path(std::string_view parent, std::size_t index);
// The JSON type of a value in words ("a string", "an object", ...), for messages.
std::string json_type_name(const nlohmann::json& j);

}  // namespace kfw
