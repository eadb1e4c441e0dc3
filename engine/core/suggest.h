// Messages that help: the nearest valid name for a misspelt one ("did you mean"), and user tokens
// quoted short enough that a 10 MB argument never ends up echoed in a one-line message.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace kfw {

// Longest user token quoted in a message, in characters (bytes of UTF-8, cut at a character).
inline constexpr std::size_t kMaxQuotedToken = 80;

// Damerau–Levenshtein distance (optimal string alignment: insert, delete, substitute, swap two
// neighbours).
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate nearest to `word`, when near enough to be a likely misspelling: at most one edit
// per three characters (case differences are free, one at least), or a prefix of at least three
// characters either way ("sim" -> "simulate", "rmse_pos" -> "rmse"). Ties: the first candidate.
std::optional<std::string> nearest(std::string_view word,
                                   const std::vector<std::string>& candidates);

// " (did you mean 'X'?)" for the nearest candidate, or "" when none is near.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

// "unknown WHAT 'word' (did you mean 'X'?)": one line, the word quoted short.
std::string unknown_message(std::string_view what, std::string_view word,
                            const std::vector<std::string>& candidates);

// `token` cut to at most `max` characters with "…" appended when cut (never inside a UTF-8
// character).
std::string truncate_token(std::string_view token, std::size_t max = kMaxQuotedToken);
// 'token' for a message, truncated.
std::string quote_token(std::string_view token);
// A cell, column name or other field of a data file as its messages show it: at most 40
// characters (then "…"), printable.
inline std::string shown_field(std::string_view s) {
  return truncate_token(s, 41);
}

// A message as one line: newlines become spaces, and any word longer than 160 characters keeps
// its first 100 and last 40 around "…" (so FILE:LINE:COL at the end of a long path survives),
// and control bytes are written as \xNN (a NUL from a file never reaches a terminal raw).
std::string one_line(std::string_view message);

}  // namespace kfw
