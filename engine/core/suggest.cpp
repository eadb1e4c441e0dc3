#include "core/suggest.h"

#include <algorithm>
#include <cctype>
#include <numeric>

namespace kfw {

namespace {

// Words longer than this are not misspellings of a name; skipping them keeps the distance cheap.
constexpr std::size_t kMaxSuggestWord = 100;

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

bool is_continuation(char c) {
  return (static_cast<unsigned char>(c) & 0xC0) == 0x80;
}

// Cuts `s` to at most `n` bytes without splitting a UTF-8 character.
std::string_view cut(std::string_view s, std::size_t n) {
  if (s.size() <= n) return s;
  while (n > 0 && is_continuation(s[n]))
    --n;
  return s.substr(0, n);
}

// The last at most `n` bytes of `s`, starting on a character boundary.
std::string_view tail(std::string_view s, std::size_t n) {
  if (s.size() <= n) return s;
  std::size_t from = s.size() - n;
  while (from < s.size() && is_continuation(s[from]))
    ++from;
  return s.substr(from);
}

}  // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Rows i-2, i-1, i of the optimal-string-alignment table.
  std::vector<std::size_t> two(b.size() + 1), one(b.size() + 1), cur(b.size() + 1);
  std::iota(one.begin(), one.end(), std::size_t{0});
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      cur[j] = std::min({one[j] + 1, cur[j - 1] + 1, one[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        cur[j] = std::min(cur[j], two[j - 2] + 1);
      }
    }
    two.swap(one);
    one.swap(cur);
  }
  return one[b.size()];
}

std::optional<std::string> nearest(std::string_view word,
                                   const std::vector<std::string>& candidates) {
  if (word.empty() || word.size() > kMaxSuggestWord) return std::nullopt;
  const std::string w = lower(word);
  const std::size_t allowed = std::max<std::size_t>(1, w.size() / 3);
  std::optional<std::string> best;
  std::size_t best_score = 0;
  for (const auto& cand : candidates) {
    if (cand.empty() || cand.size() > kMaxSuggestWord) continue;
    const std::string c = lower(cand);
    std::size_t d = edit_distance(w, c);
    bool near = true;
    if (d == 0) {
      d = cand == word ? 0 : 1;  // the same, or differs in case only
    } else {
      near = d <= allowed && d < w.size();
    }
    const std::size_t shorter = std::min(w.size(), c.size());
    if (!near && shorter >= 3 && (w.compare(0, shorter, c, 0, shorter) == 0)) {
      near = true;
      d = std::max(w.size(), c.size()) - shorter;
    }
    if (near && (!best || d < best_score)) {
      best = cand;
      best_score = d;
    }
  }
  return best;
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  auto n = nearest(word, candidates);
  return n ? " (did you mean '" + *n + "'?)" : std::string();
}

std::string unknown_message(std::string_view what, std::string_view word,
                            const std::vector<std::string>& candidates) {
  return "unknown " + std::string(what) + " " + quote_token(word) + did_you_mean(word, candidates);
}

namespace {
// Control characters written as \n, \r, \t or \xNN: an echoed token keeps a message on one line
// (truncate_token and quote_token apply it).
std::string printable(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      static const char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[u >> 4];
      out += hex[u & 0xf];
    }
  }
  return out;
}
}  // namespace

// Cut, and control characters made printable (see printable).
std::string truncate_token(std::string_view token, std::size_t max) {
  if (token.size() <= max) return printable(token);
  return printable(cut(token, max > 0 ? max - 1 : 0)) + "…";
}

std::string quote_token(std::string_view token) {
  return "'" + truncate_token(token) + "'";
}

std::string one_line(std::string_view message) {
  constexpr std::size_t kLong = 160, kHead = 100, kTail = 40;
  std::string flat(message);
  while (!flat.empty() && (flat.back() == '\n' || flat.back() == '\r'))
    flat.pop_back();
  std::replace(flat.begin(), flat.end(), '\n', ' ');
  std::replace(flat.begin(), flat.end(), '\r', ' ');
  std::string out;
  std::size_t i = 0;
  while (i < flat.size()) {
    const std::size_t space = flat.find(' ', i);
    const std::size_t end = space == std::string::npos ? flat.size() : space;
    const std::string_view w = std::string_view(flat).substr(i, end - i);
    if (w.size() > kLong) {
      out += std::string(cut(w, kHead)) + "…" + std::string(tail(w, kTail));
    } else {
      out += w;
    }
    if (space == std::string::npos) break;
    out += ' ';
    i = space + 1;
  }
  // A control byte that reached the message untruncated (a NUL in a preset's "format", a
  // mapping's column, a part's scenario) is written as \xNN, as everywhere else.
  return printable(out);
}

}  // namespace kfw
