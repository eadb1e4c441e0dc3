#include "data/json_check.h"

#include <cmath>
#include <sstream>

#include "core/suggest.h"
#include "data/json_io.h"

namespace kfw::json_check {

namespace {

Error expected(const std::string& where, const std::string& what, const Json& got) {
  return Error{where + ": expected " + what + ", found " + type_of(got)};
}

}  // namespace

std::string type_of(const Json& j) {
  std::string found = json_type_name(j);
  if (j.is_number() || j.is_boolean()) found += " (" + truncate_token(j.dump()) + ")";
  return found;
}

std::string at(const std::string& where, const std::string& key) {
  // "FILE: runs[3]" + "seed" -> "FILE: runs[3].seed"; "FILE" + "seeds" -> "FILE: seeds".
  const bool file_only = where.find(": ") == std::string::npos;
  return where + (file_only ? ": " : ".") + truncate_token(key);
}

Status object(const Json& j, const std::string& where) {
  return j.is_object() ? Status(Ok{}) : expected(where, "an object", j);
}

Status string(const Json& j, const std::string& where) {
  return j.is_string() ? Status(Ok{}) : expected(where, "a string", j);
}

Status boolean(const Json& j, const std::string& where) {
  return j.is_boolean() ? Status(Ok{}) : expected(where, "true or false", j);
}

Status integer(const Json& j, const std::string& where, double lo, double hi) {
  if (!j.is_number()) return expected(where, "a whole number", j);
  const double v = j.get<double>();
  if (!std::isfinite(v) || v != std::round(v)) return expected(where, "a whole number", j);
  const auto text = [](double x) {
    std::ostringstream os;
    os << x;
    return os.str();
  };
  if (v < lo) {
    return Error{where + ": " + truncate_token(j.dump()) +
                 (lo == 0.0 ? " must not be negative" : " is less than " + text(lo))};
  }
  if (v > hi) return Error{where + ": " + truncate_token(j.dump()) + " is more than " + text(hi)};
  return Ok{};
}

Status finite(const Json& j, const std::string& where, double lo) {
  if (!j.is_number()) return expected(where, "a number", j);
  const double v = j.get<double>();
  if (!std::isfinite(v)) return expected(where, "a finite number", j);
  if (v < lo) return Error{where + ": " + truncate_token(j.dump()) + " must not be negative"};
  return Ok{};
}

Status finite_array(const Json& j, const std::string& where, double lo) {
  if (!j.is_array()) return expected(where, "an array of numbers", j);
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (auto st = finite(j[i], index_path(where, i), lo); !st) return st;
  }
  return Ok{};
}

Status count_array(const Json& j, const std::string& where) {
  if (!j.is_array()) return expected(where, "an array of counts", j);
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (auto st = integer(j[i], index_path(where, i), 0.0); !st) return st;
  }
  return Ok{};
}

Status increasing_array(const Json& j, const std::string& where) {
  if (auto st = finite_array(j, where); !st) return st;
  for (std::size_t i = 1; i < j.size(); ++i) {
    if (!(j[i].get<double>() > j[i - 1].get<double>())) {
      return Error{index_path(where, i) + ": " + truncate_token(j[i].dump()) +
                   " does not increase from the value before it"};
    }
  }
  return Ok{};
}

Status number_map(const Json& j, const std::string& where, bool nulls) {
  if (!j.is_object()) return expected(where, "an object of numbers", j);
  for (const auto& [k, v] : j.items()) {
    if (nulls && v.is_null()) continue;
    if (auto st = finite(v, at(where, k)); !st) return st;
  }
  return Ok{};
}

Status string_map(const Json& j, const std::string& where) {
  if (!j.is_object()) return expected(where, "an object of strings", j);
  for (const auto& [k, v] : j.items()) {
    if (auto st = string(v, at(where, k)); !st) return st;
  }
  return Ok{};
}

}  // namespace kfw::json_check
