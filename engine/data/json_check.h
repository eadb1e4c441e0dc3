// Checks for readers that must not trust a JSON document (merge parts, written by another run,
// copied, edited): each check names the place ("FILE: runs[3].seed") and says what was expected
// and what was found. A reader validates the whole document with these before it reads a value,
// so a type-confused or out-of-range node is an Error (exit 2), never a library exception.
#pragma once

#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "core/expected.h"

namespace kfw::json_check {

using Json = nlohmann::json;

// The member `key` of object `j` (at `where`): present (unless optional) and of the right kind.
// `at(where, key)` is the place of a member in messages.
std::string at(const std::string& where, const std::string& key);
// "a number (2.5)", "a string", … for messages.
std::string type_of(const Json& j);
Status object(const Json& j, const std::string& where);
Status string(const Json& j, const std::string& where);
Status boolean(const Json& j, const std::string& where);
// A whole number in [lo, hi] (a float with an integral value is one; true/false are not).
Status integer(const Json& j, const std::string& where, double lo = -9.007199254740992e15,
               double hi = 9.007199254740992e15);
// A finite number ≥ lo.
Status finite(const Json& j, const std::string& where,
              double lo = -std::numeric_limits<double>::max());
// Arrays: of finite numbers (≥ lo), of whole numbers ≥ 0, strictly increasing finite numbers.
Status finite_array(const Json& j, const std::string& where,
                    double lo = -std::numeric_limits<double>::max());
Status count_array(const Json& j, const std::string& where);
Status increasing_array(const Json& j, const std::string& where);
// An object of finite numbers (metrics: key → value); null values allowed when `nulls`.
Status number_map(const Json& j, const std::string& where, bool nulls = false);
// An object of strings.
Status string_map(const Json& j, const std::string& where);

// Member `key` of object `j` (at `where`), checked by `check`; absent is an error unless
// `optional`.
template <class Check>
Status member(const Json& j, const std::string& where, const std::string& key, Check check,
              bool optional = false) {
  const auto it = j.find(key);
  if (it == j.end()) {
    if (optional) return Ok{};
    return Error{at(where, key) + ": missing"};
  }
  return check(*it, at(where, key));
}

// An array each of whose elements passes `check` (at "where[i]").
template <class Check>
Status each(const Json& j, const std::string& where, Check check) {
  if (!j.is_array()) return Error{where + ": expected an array, found " + type_of(j)};
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (Status st = check(j[i], where + "[" + std::to_string(i) + "]"); !st) return st;
  }
  return Ok{};
}
// A check of each element as a callable: each_of(check)(j, where).
template <class Check>
auto each_of(Check check) {
  return [check](const Json& j, const std::string& where) { return each(j, where, check); };
}

}  // namespace kfw::json_check
