// The "expressions" block of a model file (version 2): named sub-expressions, usable in every
// expression of the model, each other's included, in any order of declaration.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "core/expected.h"
#include "core/limits.h"
#include "model/expression.h"

namespace kfw::model {

// At most this many sub-expressions in one model (each is compiled once, by both libraries).
inline constexpr std::size_t kMaxSubExpressions = limits::kMaxSubExpressions;
// At most this deep a chain of sub-expressions that use each other (each link is compiled with
// the whole chain expanded: the load time grows with the cube of the depth — 0.13 s at 100,
// 41 s at 1000).
inline constexpr std::size_t kMaxSubExpressionDepth = limits::kMaxSubExpressionDepth;

// Adds each sub-expression of `block` to `symbols` (after the parameters, dt, t, the states and
// the inputs), a sub-expression that others use before them; a cycle is refused with the chain.
// Errors read "PATH: model.expressions.NAME: what".
Status parse_expressions(const nlohmann::json& block, const std::string& path, Symbols& symbols);

}  // namespace kfw::model
