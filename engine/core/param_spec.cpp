#include "core/param_spec.h"

#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/suggest.h"

namespace kfw {

const ParamSpec* ParamTable::find(std::string_view key) const {
  for (const auto& s : specs_) {
    if (s.key == key) return &s;
  }
  return nullptr;
}

ParamValues ParamTable::defaults() const {
  ParamValues v;
  for (const auto& s : specs_)
    v[s.key] = s.def;
  return v;
}

// Every key, for "did you mean".
static std::vector<std::string> keys_of(const std::vector<ParamSpec>& specs) {
  std::vector<std::string> keys;
  keys.reserve(specs.size());
  for (const auto& s : specs)
    keys.push_back(s.key);
  return keys;
}

static std::string number(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

Status ParamTable::check(std::string_view key, double value) const {
  const ParamSpec* s = find(key);
  if (!s) return Error{unknown_message("parameter", key, keys_of(specs_))};
  if (!std::isfinite(value)) {
    return Error{"parameter '" + s->key + "': value must be a finite number"};
  }
  if (value < s->min || value > s->max) {
    return Error{"parameter '" + s->key + "' = " + number(value) + " is out of range [" +
                 number(s->min) + ", " + number(s->max) + "]" +
                 (s->unit.empty() ? "" : " " + s->unit)};
  }
  const bool whole =
      s->scale == Scale::kInteger || s->scale == Scale::kChoice || s->scale == Scale::kToggle;
  if (whole && value != std::round(value)) {
    return Error{"parameter '" + s->key + "' = " + number(value) + " must be a whole number"};
  }
  return Ok{};
}

Status ParamTable::check(const ParamValues& values) const {
  for (const auto& [key, value] : values) {
    if (auto st = check(key, value); !st) return st;
  }
  for (const auto& s : specs_) {
    if (!values.count(s.key)) return Error{"parameter '" + s.key + "' has no value"};
  }
  return Ok{};
}

bool parse_double(std::string_view text, double& out) {
  while (!text.empty() && text.front() == ' ')
    text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ')
    text.remove_suffix(1);
  if (text.empty()) return false;
  if (text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

Status ParamTable::apply_assignment(std::string_view assignment, ParamValues& values) const {
  const auto eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    return Error{"--set expects key=value, got " + quote_token(assignment)};
  }
  const std::string_view key = assignment.substr(0, eq);
  const std::string_view text = assignment.substr(eq + 1);
  const ParamSpec* s = find(key);
  if (!s) return Error{unknown_message("parameter", key, keys_of(specs_))};
  double value = 0.0;
  bool parsed = false;
  if (s->scale == Scale::kChoice) {
    for (std::size_t i = 0; i < s->choices.size(); ++i) {
      if (s->choices[i] == text) {
        value = static_cast<double>(i);
        parsed = true;
      }
    }
  }
  if (!parsed && !parse_double(text, value)) {
    std::string msg = "parameter '" + s->key + "': " + quote_token(text) + " is not a number";
    if (s->scale == Scale::kChoice) {
      msg += " or one of";
      for (const auto& c : s->choices)
        msg += " " + c;
      msg += did_you_mean(text, s->choices);
    }
    return Error{msg};
  }
  if (auto st = check(key, value); !st) return st;
  values[s->key] = value;
  return Ok{};
}

std::string ParamTable::format(std::string_view key, double value) const {
  const ParamSpec* s = find(key);
  if (s && s->scale == Scale::kChoice) {
    const auto i = static_cast<std::size_t>(value);
    if (value >= 0 && i < s->choices.size()) return s->choices[i];
  }
  if (s && (s->scale == Scale::kInteger || s->scale == Scale::kToggle)) {
    return std::to_string(static_cast<long long>(std::llround(value)));
  }
  return number(value);
}

double param(const ParamValues& values, std::string_view key) {
  auto it = values.find(key);
  if (it == values.end()) throw std::logic_error("kfw: parameter '" + std::string(key) + "' unset");
  return it->second;
}

}  // namespace kfw
