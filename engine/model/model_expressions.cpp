#include "model/model_expressions.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/suggest.h"

namespace kfw::model {

using nlohmann::json;

namespace {

class SubReader {
 public:
  SubReader(const json& block, const std::string& path, Symbols& symbols)
      : block_(block), path_(path), symbols_(symbols) {}

  Error error(const std::string& name, const std::string& what) const {
    return Error{path_ + ": model.expressions." + name + ": " + what};
  }

  // Defines `name` after the sub-expressions it uses.
  Status define(const std::string& name) {
    if (symbols_.find(name) >= 0) return Ok{};
    if (auto it = std::find(stack_.begin(), stack_.end(), name); it != stack_.end()) {
      std::string chain;
      for (; it != stack_.end(); ++it)
        chain += *it + " → ";
      return error(name, "defined in terms of itself (" + chain + name + ")");
    }
    const json& j = block_.at(name);
    std::string text;
    if (j.is_string()) {
      text = j.get<std::string>();
    } else if (j.is_number()) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.17g", j.get<double>());
      text = buf;
    } else {
      return error(name, "expected an expression (a string or a number), got " + j.dump());
    }
    stack_.push_back(name);
    std::size_t depth = 1;
    for (const auto& id : identifiers(text)) {
      if (id != name && block_.contains(id)) {
        if (auto st = define(id); !st) return st;
        depth = std::max(depth, depth_[id] + 1);
      } else if (id == name) {
        return error(name, "defined in terms of itself (" + name + " → " + name + ")");
      }
    }
    if (depth > kMaxSubExpressionDepth) {
      return error(name, "sub-expressions nested more than " +
                             std::to_string(kMaxSubExpressionDepth) + " deep");
    }
    depth_[name] = depth;
    auto e = compile_expr(text, "model.expressions." + name, symbols_,
                          kAllSymbols | kMeasuredSymbol, "");
    if (!e) return Error{path_ + ": " + e.error()};
    symbols_.add_sub(name, *e);
    stack_.pop_back();
    return Ok{};
  }

 private:
  const json& block_;
  const std::string& path_;
  Symbols& symbols_;
  std::vector<std::string> stack_;
  std::map<std::string, std::size_t> depth_;  // 1 + the deepest sub-expression each one uses
};

}  // namespace

Status parse_expressions(const json& block, const std::string& path, Symbols& symbols) {
  if (!block.is_object()) {
    return Error{path + ": model.expressions: expected {\"name\": \"expression\", ...}"};
  }
  if (block.size() > kMaxSubExpressions) {
    return Error{path + ": model.expressions: " + std::to_string(block.size()) +
                 " sub-expressions (at most " + std::to_string(kMaxSubExpressions) + ")"};
  }
  SubReader r(block, path, symbols);
  for (auto it = block.begin(); it != block.end(); ++it) {
    const std::string& name = it.key();
    if (!is_identifier(name)) {
      return r.error(
          name, quote_token(name) + " is not a name (letters, digits and _, not first a digit)");
    }
    if (is_reserved_name(name)) return r.error(name, quote_token(name) + " is reserved");
    if (symbols.find(name) >= 0) {
      return r.error(name, quote_token(name) + " is already a parameter, state or input");
    }
  }
  for (auto it = block.begin(); it != block.end(); ++it) {
    if (auto st = r.define(it.key()); !st) return st;
  }
  return Ok{};
}

}  // namespace kfw::model
