#include "data/import.h"

#include <date/date.h>
#include <date/tz.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <locale>
#include <map>
#include <optional>
#include <sstream>

#include "core/suggest.h"

namespace kfw {

namespace {

// Lower-case words of a name: "accRoll_deg [x]" -> acc, roll, deg, x.
std::vector<std::string> words(const std::string& name) {
  std::vector<std::string> w;
  std::string cur;
  auto flush = [&] {
    if (!cur.empty()) w.push_back(cur);
    cur.clear();
  };
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (!std::isalnum(c) && c < 0x80) {
      flush();
      continue;
    }
    if (std::isupper(c) && i > 0 && std::islower(static_cast<unsigned char>(name[i - 1]))) flush();
    cur += static_cast<char>(std::tolower(c));
  }
  flush();
  return w;
}

std::string lower(std::string s) {
  for (auto& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Words that name a role. A reference word outweighs the role's own name among the words
// ("ref_angle" is truth, not angle); the exact name outweighs everything.
struct Synonyms {
  const char* role;
  std::vector<std::string> words;
  int weight;
};
const std::vector<Synonyms>& synonyms() {
  static const std::vector<Synonyms> s = {
      {"t", {"t", "time", "timestamp", "zeit", "ts", "datetime", "date", "sec", "seconds"}, 3},
      {"gyro", {"gyro", "gyr", "omega", "rate", "drehrate", "angular", "gx", "gy", "gz", "w"}, 3},
      {"angle", {"angle", "roll", "pitch", "yaw", "phi", "theta", "winkel", "tilt", "incl"}, 3},
      {"truth", {"truth", "true", "ref", "reference", "gt", "groundtruth", "soll"}, 6},
  };
  return s;
}

// A unit word or pair of words ("deg", "s") -> a known unit.
std::string unit_of_words(const std::string& a, const std::string& b) {
  static const std::map<std::string, std::string> one = {
      {"s", "s"},        {"sec", "s"},       {"ms", "ms"},      {"us", "us"},
      {"ns", "ns"},      {"deg", "deg"},     {"degree", "deg"}, {"degrees", "deg"},
      {"rad", "rad"},    {"dps", "deg/s"},   {"degs", "deg/s"}, {"degps", "deg/s"},
      {"rads", "rad/s"}, {"radps", "rad/s"}, {"g", "g"},        {"mss", "m/s^2"},
      {"ms2", "m/s^2"},  {"mps2", "m/s^2"},  {"m", "m"},        {"mm", "mm"}};
  if ((a == "deg" || a == "rad") && (b == "s" || b == "sec")) return a + "/s";
  if (a == "m" && (b == "s2" || b == "s")) return b == "s2" ? "m/s^2" : "";
  auto it = one.find(b);
  return it == one.end() ? "" : it->second;
}

int name_score(const std::string& column, const std::string& role) {
  const auto w = words(column);
  if (lower(column) == lower(role)) return 10 * 16;
  int best = 0;
  for (const auto& x : w) {
    if (x == lower(role)) best = std::max(best, 5);
  }
  for (const auto& s : synonyms()) {
    if (role != s.role) continue;
    for (const auto& x : w) {
      if (std::find(s.words.begin(), s.words.end(), x) != s.words.end())
        best = std::max(best, s.weight);
    }
  }
  // Between columns that match as well, the one with fewer other words ("c_truth" before
  // "c_bias_truth" for truth).
  const int extra = std::min(15, static_cast<int>(w.size()) - 1);
  return best > 0 ? best * 16 - std::max(0, extra) : 0;
}

bool looks_iso(const Table& t, std::size_t col) {
  return t.invalid[col] > 0 && t.rows() > 0 && parse_iso_time_ns(t.cell(0, col)).ok();
}

}  // namespace

std::vector<ColumnSpec> roles_with_time(const std::vector<ColumnSpec>& columns) {
  std::vector<ColumnSpec> r;
  r.push_back({"t", "s", "time", true});
  for (const auto& c : columns) {
    if (c.name != "t") r.push_back(c);
  }
  return r;
}

std::string unit_from_name(const std::string& name) {
  const auto open = name.find_first_of("[(");
  if (open != std::string::npos) {
    const auto close = name.find_first_of("])", open);
    std::string u =
        name.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1);
    u.erase(std::remove(u.begin(), u.end(), ' '), u.end());
    if (u == "m/s2" || u == "m/s²") u = "m/s^2";
    const auto& known = known_units();
    if (std::find(known.begin(), known.end(), u) != known.end()) return u;
    const auto w = words(u);
    if (!w.empty()) return unit_of_words(w.size() > 1 ? w[w.size() - 2] : "", w.back());
  }
  const auto w = words(name);
  if (w.size() < 2) return "";  // a one-word name ("g", "s") is not a unit
  return unit_of_words(w[w.size() - 2], w.back());
}

int role_column(const Table& t, const Mapping& m, const std::string& role) {
  auto it = m.find(role);
  const std::string col = it == m.end() || it->second.column.empty() ? role : it->second.column;
  return t.index(col);
}

Mapping guess_mapping(const Table& t, const std::vector<ColumnSpec>& spec) {
  const auto roles = roles_with_time(spec);
  struct Candidate {
    int score;
    std::size_t role, col;
  };
  std::vector<Candidate> cands;
  for (std::size_t r = 0; r < roles.size(); ++r) {
    for (std::size_t c = 0; c < t.columns(); ++c) {
      const int s = name_score(t.names[c], roles[r].name);
      if (s > 0) cands.push_back({s, r, c});
    }
  }
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  std::vector<int> role_col(roles.size(), -1);
  std::vector<char> used(t.columns(), 0);
  for (const auto& c : cands) {
    if (role_col[c.role] >= 0 || used[c.col]) continue;
    role_col[c.role] = static_cast<int>(c.col);
    used[c.col] = 1;
  }
  // No time by name: the first column, when it is an ISO date-time or increases.
  if (role_col[0] < 0 && t.columns() > 0 && !used[0]) {
    const auto& v = t.values[0];
    bool increasing = t.invalid[0] == 0;
    for (std::size_t i = 1; i < v.size() && increasing; ++i)
      increasing = v[i] > v[i - 1];
    if (increasing || looks_iso(t, 0)) role_col[0] = 0;
  }
  Mapping m;
  for (std::size_t r = 0; r < roles.size(); ++r) {
    if (role_col[r] < 0) continue;
    const auto c = static_cast<std::size_t>(role_col[r]);
    RoleMapping rm;
    rm.column = t.names[c];
    if (r == 0 && looks_iso(t, c)) {
      rm.unit = kIsoTime;
    } else if (const std::string u = unit_from_name(t.names[c]);
               !u.empty() && !roles[r].unit.empty() && unit_factor(u, roles[r].unit).ok()) {
      rm.unit = u;
    }
    m[roles[r].name] = rm;
  }
  return m;
}

// GCC 12 reports a false -Wmaybe-uninitialized inside date.h's parser (inlined here); clang has
// no such warning (and -Werror refuses the unknown name).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
Expected<long long> parse_iso_time_ns(std::string_view text, const std::string& zone) {
  std::string s(text);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
    s.pop_back();
  const auto bad = Error{"'" + shown_field(text) + "' is not an ISO-8601 date-time"};
  if (s.size() < 10) return bad;
  if (s.size() > 10 && s[10] == ' ') s[10] = 'T';
  bool utc = false;
  if (s.back() == 'Z' || s.back() == 'z') {
    s.pop_back();
    utc = true;
  }
  // An offset is a sign after the time of day.
  const auto sign = s.size() > 11 ? s.find_first_of("+-", 11) : std::string::npos;
  std::string fmt = s.size() == 10 ? "%Y-%m-%d" : "%Y-%m-%dT%H:%M:%S";
  std::istringstream in(s);
  in.imbue(std::locale::classic());
  if (sign == std::string::npos && !utc && !zone.empty()) {
    // A local time in `zone`.
    date::local_time<std::chrono::nanoseconds> lt;
    in >> date::parse(fmt, lt);
    if (in.fail() || in.peek() != std::char_traits<char>::eof()) return bad;
    const date::time_zone* z = nullptr;
    try {
      z = date::locate_zone(zone);
    } catch (const std::exception&) {
      return Error{"unknown time zone '" + shown_field(zone) + "'"};
    }
    try {
      return static_cast<long long>(z->to_sys(lt).time_since_epoch().count());
    } catch (const date::ambiguous_local_time&) {
      return static_cast<long long>(
          z->to_sys(lt, date::choose::earliest).time_since_epoch().count());
    } catch (const date::nonexistent_local_time&) {
      return Error{"'" + shown_field(text) + "' does not exist in " + zone +
                   " (the clocks jump forward then)"};
    }
  }
  // A leap second (…T23:59:60Z) has no place on a time axis counted without them (POSIX time).
  if (s.size() >= 19 && s[10] == 'T' && s.compare(16, 3, ":60") == 0) {
    return Error{"'" + shown_field(text) + "' is a leap second (seconds = 60), which a time axis " +
                 "in seconds since 1970 does not have; write it as the next second"};
  }
  if (sign != std::string::npos) {
    // date.h reads any hh:mm offset; a real one is −12:00 … +14:00 (hours ≤ 14, minutes < 60).
    const std::string off = s.substr(sign + 1);
    const bool colon = off.find(':') != std::string::npos;
    const int hh = off.size() >= 2 ? std::atoi(off.substr(0, 2).c_str()) : -1;
    const int mm =
        off.size() >= (colon ? 5u : 4u) ? std::atoi(off.substr(colon ? 3 : 2, 2).c_str()) : 0;
    if (hh > 14 || mm > 59) {
      return Error{"'" + shown_field(text) + "': the UTC offset " + s.substr(sign) +
                   " is out of range (-12:00 to +14:00)"};
    }
    fmt += colon ? "%Ez" : "%z";
  }
  date::sys_time<std::chrono::nanoseconds> tp;
  in >> date::parse(fmt, tp);
  if (in.fail() || in.peek() != std::char_traits<char>::eof()) return bad;
  return static_cast<long long>(tp.time_since_epoch().count());
}

Status check_time_zone(const std::string& zone) {
  try {
    date::locate_zone(zone);
  } catch (const std::exception&) {
    return Error{"unknown time zone '" + shown_field(zone) +
                 "' (an IANA name such as Europe/Berlin)"};
  }
  return Ok{};
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

std::string format_iso_time_ns(long long ns) {
  const date::sys_time<std::chrono::nanoseconds> tp{std::chrono::nanoseconds(ns)};
  return date::format("%FT%TZ", tp);
}

Expected<Dataset> import_table(const Table& t, const Mapping& m,
                               const std::vector<ColumnSpec>& spec) {
  const auto roles = roles_with_time(spec);
  std::map<std::string, std::string> role_unit;
  for (const auto& r : roles)
    role_unit[r.name] = r.unit;
  struct Bound {
    std::string role;
    std::size_t col = 0;
    RoleMapping map;
    double factor = 1.0;
  };
  std::vector<Bound> bound;
  std::vector<int> owner(t.columns(), -1);
  auto bind = [&](const std::string& role) -> Status {
    auto it = m.find(role);
    const RoleMapping rm = it == m.end() ? RoleMapping{} : it->second;
    const int c = role_column(t, m, role);
    if (c < 0) {
      if (rm.column.empty()) return Ok{};  // not in the file: require_columns names it
      std::string msg = t.source + ": mapped column '" + rm.column + "' (for '" + role +
                        "') is not in the file; columns:";
      for (const auto& n : t.names)
        msg += " " + n;
      return Error{msg};
    }
    const auto col = static_cast<std::size_t>(c);
    if (owner[col] >= 0) {
      return Error{t.source + ": column '" + t.names[col] + "' is mapped to both '" +
                   bound[static_cast<std::size_t>(owner[col])].role + "' and '" + role + "'"};
    }
    Bound b{role, col, rm, 1.0};
    if (!rm.unit.empty() && !is_iso_unit(rm.unit)) {
      auto ru = role_unit.find(role);
      auto f =
          unit_factor(rm.unit, ru == role_unit.end() || ru->second.empty() ? rm.unit : ru->second);
      if (!f) return Error{t.source + ": mapping." + role + ".unit: " + f.error()};
      b.factor = *f;
    }
    if (is_iso_unit(rm.unit) && role != "t") {
      return Error{t.source + ": mapping." + role + ".unit: 'iso' is for the time role 't' only"};
    }
    if (const std::string zone = iso_zone(rm.unit); !zone.empty()) {
      if (auto st = check_time_zone(zone); !st) {
        return Error{t.source + ": mapping." + role + ".unit: " + st.error()};
      }
    }
    owner[col] = static_cast<int>(bound.size());
    bound.push_back(std::move(b));
    return Ok{};
  };
  for (const auto& r : roles) {
    if (auto st = bind(r.name); !st) return st.err();
  }
  for (const auto& [role, rm] : m) {
    if (role_unit.count(role)) continue;
    if (auto st = bind(role); !st) return st.err();
  }
  if (bound.empty() || bound.front().role != "t") {
    std::string msg =
        t.source + ": no time column 't' in the header (map one: --time COLUMN); columns:";
    for (const auto& n : t.names)
      msg += " " + n;
    return Error{msg};
  }
  // The first cell that is not a number in a column bound to a role.
  std::optional<Error> cell_error;
  std::size_t cell_line = std::numeric_limits<std::size_t>::max();
  for (const auto& b : bound) {
    if (is_iso_unit(b.map.unit) || t.invalid[b.col] == 0) continue;
    const auto& i = t.first_invalid[b.col];
    if (i.line < cell_line) {
      cell_line = i.line;
      cell_error = Error{source_position(t.source, i.line, i.col) + ": column '" +
                         shown_field(t.names[b.col]) + "': " + i.message};
    }
  }
  Dataset d;
  d.source = t.source;
  const Bound& tb = bound.front();
  const std::string tname = shown_field(t.names[tb.col]);
  auto& time = d.add("t", t.rows());
  if (is_iso_unit(tb.map.unit)) {
    const std::string zone = iso_zone(tb.map.unit);
    long long origin = 0;
    for (std::size_t r = 0; r < t.rows(); ++r) {
      const std::string text = t.cell(r, tb.col);
      if (text.empty()) break;  // reported below as an empty time
      auto ns = parse_iso_time_ns(text, zone);
      if (!ns) {
        if (t.line_of(r) >= cell_line) break;  // a cell that is not a number comes first
        return Error{source_position(t.source, t.line_of(r), t.cell_column(r, tb.col)) +
                     ": column '" + tname + "': " + ns.error()};
      }
      if (r == 0) origin = *ns;
      time[r] = static_cast<double>(*ns - origin) * 1e-9;
    }
    d.time_origin = format_iso_time_ns(origin);
  } else {
    const auto& v = t.values[tb.col];
    for (std::size_t r = 0; r < t.rows(); ++r)
      time[r] = tb.map.scale * (tb.factor * v[r]) + tb.map.offset;
  }
  if (tb.map.flip) {
    for (double& x : time)
      x = -x;
  }
  for (std::size_t r = 0; r < t.rows(); ++r) {
    if (t.line_of(r) >= cell_line) break;  // a cell that is not a number comes first
    const double x = time[r];
    const std::size_t line = t.line_of(r);
    if (std::isnan(x)) {
      return Error{source_position(t.source, line, t.cell_column(r, tb.col)) + ": column '" +
                   tname + "' is empty (every row needs a time)"};
    }
    if (r == 0) continue;
    const double prev = time[r - 1];
    if (!(x > prev)) {
      return Error{source_position(t.source, line, t.cell_column(r, tb.col)) +
                   ": time is not increasing (" + tname + " = " + shown_field(t.cell(r, tb.col)) +
                   " after " + shown_field(t.cell(r - 1, tb.col)) +
                   (x == prev ? ", a duplicate" : "") + ")"};
    }
    if (!std::isfinite(x - prev)) {
      return Error{source_position(t.source, line, t.cell_column(r, tb.col)) + ": the step from " +
                   shown_field(t.cell(r - 1, tb.col)) + " to " + shown_field(t.cell(r, tb.col)) +
                   " overflows a double"};
    }
  }
  if (cell_error) return *cell_error;
  for (std::size_t c = 0; c < t.columns(); ++c) {
    if (c == tb.col) continue;
    if (owner[c] < 0) {
      std::string name = t.names[c];
      if (role_unit.count(name) || m.count(name)) name += ".unmapped";
      d.names.push_back(name);
      d.columns.push_back(t.values[c]);
      continue;
    }
    const Bound& b = bound[static_cast<std::size_t>(owner[c])];
    d.names.push_back(b.role);
    d.columns.push_back(t.values[c]);
    auto& col = d.columns.back();
    const double k = b.factor * b.map.scale, off = b.map.offset;
    if (k == 1.0 && off == 0.0 && !b.map.flip) continue;
    const double sign = b.map.flip ? -1.0 : 1.0;
    if (b.factor == 1.0 || b.map.scale == 1.0) {
      for (double& x : col)
        x = sign * (k * x + off);
    } else {
      for (double& x : col)
        x = sign * (b.map.scale * (b.factor * x) + off);
    }
  }
  return d;
}

}  // namespace kfw
