// Every limit on what an input can make large, in one place; docs/limits.md is its table (a
// test reads both and checks they agree). A limit is refused up front with a message naming the
// input, the value and the limit — never an allocation failure, a hang or a silent cut.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace kfw::limits {

inline constexpr std::uint64_t kMiB = 1024u * 1024u;
inline constexpr std::uint64_t kGiB = 1024u * kMiB;

// The files the programs read, each kind with its byte cap (checked before reading, and again
// while reading a file that grows).
enum class Input { kData, kPreset, kModel, kMapping, kSession, kPart };
// A data file: 10 M rows of the widest seed preset's CSV (radome, ≈ 245 bytes a row) fit.
inline constexpr std::uint64_t kDataBytes = 4 * kGiB;
// Presets, model files, mappings, sessions: JSON written by hand or by kfw.
inline constexpr std::uint64_t kJsonBytes = 10 * kMiB;
// Monte Carlo and sweep parts: JSON too, under the same cap for now (≈ 100 000 sweep points).
inline constexpr std::uint64_t kPartBytes = kJsonBytes;
std::uint64_t max_bytes(Input kind);
// "data file", "preset", ... for messages.
const char* input_name(Input kind);

// A model file: states, measurement channels, characters of one expression.
inline constexpr std::size_t kMaxStates = 1000;
inline constexpr std::size_t kMaxChannels = 1000;
inline constexpr std::size_t kMaxExpressionChars = 100'000;
// A name the model declares (state, input, parameter, channel, sub-expression).
inline constexpr std::size_t kMaxNameChars = 100;
// A channel's `every` (an m-step model raises F to this power by squaring).
inline constexpr double kMaxEvery = 1'000'000;
// An exported plot: pixels of one image (a 40 in × 40 in figure at 1 200 dpi is 2.3 G).
inline constexpr std::uint64_t kMaxExportPixels = 100'000'000;

// Data files: one CSV line (reading stops there), columns of a table.
inline constexpr std::size_t kMaxCsvLineBytes = 1024u * 1024u;
inline constexpr std::size_t kMaxCsvColumns = 10000;
// JSON documents: levels of nesting.
inline constexpr std::size_t kMaxJsonDepth = 256;
// Grammars: points n of one grid axis lo:hi:n, members of a set of integers (--seeds).
inline constexpr std::size_t kMaxGridPoints = 1'000'000;
inline constexpr std::size_t kMaxSetMembers = 1'000'000;
// Model files: components of one channel, sub-expressions and their nesting, a sub-expression's
// expanded text.
inline constexpr int kMaxChannelSize = 8;
inline constexpr std::size_t kMaxSubExpressions = 1000;
inline constexpr std::size_t kMaxSubExpressionDepth = 100;
inline constexpr std::size_t kMaxExpandedText = 100'000;
// Model files' modes (an IMM): modes, and mode probabilities kept (rows × modes).
inline constexpr std::size_t kMaxModes = 400;
inline constexpr std::size_t kMaxModeValues = 100'000'000;

// The memory a run may plan for: the smallest of the machine's, the cgroup's limit (memory.max,
// v2; memory.limit_in_bytes, v1) and the address-space limit (ulimit -v); KFW_MEMORY_LIMIT
// (bytes) overrides them (tests). Read once per process.
inline constexpr const char* kMemoryLimitEnv = "KFW_MEMORY_LIMIT";
std::uint64_t memory_bytes();
// Rows of a model simulation whose run (dataset and filter results) holds `columns` doubles a
// row: a quarter of memory_bytes() (copies, output and the window take the rest), at most
// kMaxSimRows.
inline constexpr std::size_t kMaxSimRows = 50'000'000;
std::size_t max_sim_rows(std::size_t columns);
// "10 MB", "23.5 GB" (of 2^20 and 2^30 bytes), for messages.
std::string bytes_text(std::uint64_t bytes);

}  // namespace kfw::limits
