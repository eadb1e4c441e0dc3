// The fixed C of an exported filter (c_export.h): small static functions — the expression
// helpers, angle wrapping, the covariance prediction, the scalar and vector measurement updates
// (filter/measurement_update.h), the matrix exponential and Van Loan's discretisation
// (filter/discretize.h), the unscented transform (filter/ukf.h) — written once in C99 over the
// sizes NX (states), MX (the largest channel), NU (inputs) and EM (the exponential's size) and
// the type `real`, which the generated file defines. Only the pieces a filter calls are emitted
// (an unused static function is a warning, and the exports compile with -Werror).
#pragma once

#include <set>
#include <string>

namespace kfw::codegen {

// LIT(v) and the math functions the runtime calls (SQRT, SIN, …) for the precision: the
// `#define` lines a file that includes c_runtime() puts after its `real` typedef.
std::string c_math_macros(bool single);

// The pieces named in `wanted` and those they call, in one fixed order.
std::string c_runtime(std::set<std::string> wanted);

}  // namespace kfw::codegen
