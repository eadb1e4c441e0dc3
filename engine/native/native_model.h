// The native path (issue 33): a model's expressions compiled to machine code by the system's C
// compiler instead of evaluated by muparser. Every expression group of a model evaluator
// (model/expression.h ExprGroup) becomes one C function written by the C export's expression
// writer (codegen/c_expr.h), compiled once with `cc -O2 -ffp-contract=off -fPIC -shared`, cached
// under $XDG_CACHE_HOME/kfw (else ~/.cache/kfw; mode 0700) by the content hash of its C source,
// and loaded with dlopen after its bytes are checked against the hash recorded when it was built.
// A group that cannot be compiled (no compiler, a compile error, an unusable cache) stays with
// muparser, which is also the test oracle: both agree to 1e-9 (tests/engine/scale_native_test.cpp).
// Turned on by KFW_NATIVE=1 for kfw-cli and kfw (docs/speed.md "Native path").
#pragma once

#include <cstddef>
#include <string>

#include "core/expected.h"

namespace kfw::native {

struct NativeOptions {
  std::string cache_dir;  // empty: $XDG_CACHE_HOME/kfw, else $HOME/.cache/kfw
  std::string compiler;   // empty: $CC, else cc
};

// Installs the native path for every model evaluator created from now on; an Error when the
// cache folder cannot be made private or no compiler runs (muparser stays).
Status enable(const NativeOptions& options = {});
// Back to muparser for evaluators created from now on (compiled code stays loaded).
void disable();

struct NativeStats {
  std::size_t groups_native = 0;    // groups given a compiled function
  std::size_t groups_fallback = 0;  // groups left with muparser (a compile failed)
  std::size_t compiles = 0;         // shared objects built
  std::size_t cache_loads = 0;      // loaded from the cache folder (built by an earlier run)
  std::string last_error;           // why the last fallback happened
};
NativeStats stats();
// Forgets which models were compiled in this process (their code stays loaded): the next run of
// each goes to the cache folder again, as a new process would. For tests.
void forget();

// KFW_NATIVE=1 in the environment: enable(); a failure is a one-line notice (muparser stays).
// Returns the notice, empty when there is none.
std::string enable_from_environment();

}  // namespace kfw::native
