// Internal to the C export (c_export.cpp, c_filter.cpp, c_example.cpp): what every part of the
// generator reads — the model, the values, the options — and the writers they share.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "codegen/c_export.h"
#include "codegen/c_expr.h"
#include "model/model_eval.h"
#include "model/model_filter.h"
#include "model/model_spec.h"

namespace kfw::codegen::detail {

struct Gen {
  const model::ModelSpec& spec;
  const ParamValues& values;
  const ParamTable& table;  // the preset's parameters (the header comment formats values with it)
  model::FilterOptions filter;
  CExportOptions opt;
  model::ModelEval& ev;           // at the values (every, gates, the steady state's matrices)
  std::string P;                  // the prefix, NAME
  std::string real;               // "double" or "float"
  std::set<std::string> runtime;  // the runtime pieces the functions call
  std::set<std::string> params;   // the parameters the expressions read (their constants)
  std::string defs;               // constants the runtime reads (the UKF's weights, angles)
  int n = 0, nu = 0, mx = 1;

  bool ukf() const { return filter.kind == model::FilterKind::kUkf; }
  bool steady() const { return opt.steady; }
  std::string lit(double v) const { return c_number(v, opt.single); }
  // The C text of a model symbol in a generated function: par_NAME, x[i], u[j], dt, t.
  std::string symbol(const std::string& name);
  // A set of expressions whose symbols map through symbol().
  CExprSet exprs() {
    return CExprSet(opt.single, [this](const std::string& s) { return symbol(s); });
  }
};

// A channel's or column's name as a C identifier (anything else replaced by '_').
std::string c_name(const std::string& name);
// Upper case of c_name (macro names).
std::string c_macro(const std::string& name);
// Text for inside a C comment: "*/" and "/*" broken up, no control characters.
std::string comment_text(const std::string& text);
// The angle kind of the runtime's wrap_angle: 0 none, 1 rad, 2 deg.
int angle_kind(Angle a);

// The model's functions and the API's bodies (c_filter.cpp): appended to the .c text.
Expected<std::string> filter_functions(Gen& g);
// The process's matrices as C: assignments into F, B, Q (or fx, the process f) at x, u, t, dt.
Expected<std::string> process_functions(Gen& g);
// The measurement channels' functions: ẑ, H and R at x, u, t.
Expected<std::string> channel_functions(Gen& g);
// The example program (c_example.cpp).
std::string example_program(const Gen& g);
// The header's declarations of the API (c_export.cpp); the example calls them.
std::string update_signature(const Gen& g, std::size_t c);
bool channel_reads_step(const model::ChannelSpec& c);  // h, H or R read t or an input

}  // namespace kfw::codegen::detail
