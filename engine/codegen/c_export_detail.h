// Internal to the C export (c_export.cpp, c_filter.cpp, c_example.cpp): what every part of the
// generator reads — the model, the values, the options — and the writers they share.
#pragma once

#include <map>
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
  std::map<std::string, double> consts;  // the parameters read: par_NAME (par_NAME_mJ) -> value
  std::string defs;                      // constants the runtime reads (the UKF's weights, angles)
  int n = 0, nu = 0, mx = 1;
  // The filter being written: the model's, or an IMM mode's (its model, values and evaluator).
  const model::ModelSpec* ms = nullptr;
  const ParamValues* mv = nullptr;
  model::ModelEval* me = nullptr;
  int mode = -1;          // the IMM mode, or -1
  std::string const_sfx;  // a mode's own parameter values: par_NAME + this ("_mJ", "_centre")
  int chan = -1;          // the channel being written: its roles read as zr[j]
  std::string sfx;        // its functions' suffix: "" or "_mJ"
  std::string ft;         // the struct a filter's functions take: NAME_state, or NAME_filter (IMM)
  int modes = 0;          // an IMM's modes; 0: none
  std::vector<std::string> mode_names;
  bool cache = false;  // a continuous process (in the model or a mode): Van Loan's cache
  // An IMM's block structure (model.modes.structure) at the values: per state its block, per
  // channel and component the block its H row reads; `approximate` drops Q's and R's cross terms.
  std::vector<int> block_of;
  std::vector<std::vector<int>> component_block;
  bool approximate = false;
  int roles_max = 1;  // the most roles of a channel (the raw sample's size)
  bool ages = false;  // an input declares an age: u holds NU inputs, then NU ages
  // Per channel: its missing-sample flag in force (model.measurements.C.missing, `when` ≠ 0), and
  // the value that flags a sample (the caller skips such an update; the example does).
  std::vector<char> missing_on;
  std::vector<double> missing_equals;

  bool ukf() const { return filter.kind == model::FilterKind::kUkf; }
  // Parameters in a runtime struct (CExportOptions::runtime_params): every function that reads
  // one has `pp`, the NAME_params in force — from its struct (pp_decl), as a parameter
  // (pp_param), passed on (pp_arg); par_KEY is a macro for pp->par_KEY.
  bool rt() const { return opt.runtime_params; }
  std::string pp_decl() const {
    return rt() ? "  const " + P + "_params *pp = &s->par;\n  (void)pp;\n" : "";
  }
  std::string pp_param() const { return rt() ? ", const " + P + "_params *pp" : ""; }
  std::string pp_arg() const { return rt() ? ", pp" : ""; }
  std::string pp_void() const { return rt() ? "  (void)pp;\n" : ""; }
  std::string ctx_arg() const { return rt() ? "pp" : "0"; }  // rk4's context
  bool steady() const { return opt.steady; }
  std::string lit(double v) const { return c_number(v, opt.single); }
  // The C text of a model symbol in a generated function: par_NAME, x[i], u[j], dt, t.
  std::string symbol(const std::string& name);
  // A set of expressions whose symbols map through symbol().
  CExprSet exprs() {
    return CExprSet(opt.single, [this](const std::string& s) { return symbol(s); });
  }
};

// One generated assignment: `target` = the expression, `key` naming it in messages.
struct Assign {
  std::string target;
  const model::Expr* e;
  std::string key;
};

// The model's matrices as C (c_parts.cpp): "target = expression;" lines with the common
// sub-expressions computed once before; "[i][j]"; the entries of a matrix whose class is of a
// step (t, inputs, state) or not; an IMM's approximate structure's zeroed R and Q entries; the
// process's functions (process_dt, process_at, process_step, process_f, or ẋ's); a channel's
// (channel_C, channel_C_h, preprocess_C); the RK4 sub-steps over dt.
Expected<std::string> assignments(Gen& g, const std::vector<Assign>& list,
                                  const std::string& indent = "  ");
std::string ij(int i, int j);
void matrix(std::vector<Assign>& out, const model::MatrixSpec& m, const std::string& target,
            bool step);
std::string drop_R(const Gen& g, std::size_t c);
std::string drop_Q(const Gen& g);
Expected<std::string> process_parts(Gen& g);
Expected<std::string> channel_parts(Gen& g, std::size_t c);
Expected<std::string> preprocess_text(Gen& g, std::size_t c, const std::string& sfx);
std::string rk4_steps(Gen& g);

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
// One filter's static functions (the model's, or mode g.mode's): its process and channels, and
// filter_predict<sfx>(FT *s, u, t, dt), filter_update_<channel><sfx>(FT *s, z, u, t, nis,
// logdet), filter_init<sfx>(FT *s) (c_filter.cpp).
Expected<std::string> one_filter(Gen& g);
// The IMM over the modes (c_imm.cpp): every mode's filter, the mixing, the probabilities and the
// combination, and the API.
Expected<std::string> imm_functions(Gen& g);
// NAME_init_from_CHANNEL's head, its sample pre-processed by preprocess_CHANNEL<sfx> into zp (a
// raw channel copied), and the lines setting `x`[i] from it.
std::string start_head(const Gen& g, const std::string& sfx);
std::string start_lines(const Gen& g, const std::string& x);
// preprocess_CHANNEL<sfx>(zr, u, t, z) of g.ms's channel c.
Expected<std::string> preprocess_part(Gen& g, std::size_t c, const std::string& sfx);
// Channel groups (c_groups.cpp): a stacked group's update (its signature; whether a member reads t
// or the inputs), and every stacked group's function.
std::string group_signature(const Gen& g, std::size_t k);
bool group_reads_step(const Gen& g, std::size_t k);
std::string group_functions(Gen& g);
// A block computing out = F in + B u (the engine's order: F's row, then each input), F and B
// named with `m` before them ("s->" or "" for --steady's constants).
std::string linear_mean(const Gen& g, const std::string& m, const std::string& in,
                        const std::string& out, const std::string& indent);
// y[j] = wrap_angle(...) lines for the channel's angle components.
std::string wrap_innovation(Gen& g, const model::ChannelSpec& ch);
// s->x[i] = wrap_angle(...) lines for the angle states.
std::string wrap_state_lines(Gen& g, const std::string& indent);
// --steady: NAME_predict and NAME_update_CHANNEL of the fixed DARE gain (c_steady.cpp).
Expected<std::string> steady_functions(Gen& g);
// The UKF's weights and angle tables (once, before the runtime).
void ukf_defs(Gen& g);
// `name`(FT *s) setting x0 and P0 (and the process unset): "void NAME_init" or an IMM's
// "static void filter_init".
Expected<std::string> filter_init(Gen& g, const std::string& name);
// The example program (c_example.cpp).
std::string example_program(const Gen& g);
// NAME_init_from_CHANNEL(s, z, [u, t]): x0 from the start channel's sample (model.x0 entries
// "CHANNEL.COMPONENT"); empty when the model has none.
std::string init_channel_signature(const Gen& g);
// The header's declarations of the API (c_export.cpp); the example calls them.
std::string update_signature(const Gen& g, std::size_t c);
bool channel_reads_step(const model::ChannelSpec& c);  // h, H or R read t or an input

}  // namespace kfw::codegen::detail
