// The C export (c_export.h): what can be exported, the header, the .c file's prelude and
// constants, and writing the three files. The model's functions are c_filter.cpp's, the example
// c_example.cpp's.
#include "codegen/c_export.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

#include "codegen/c_export_detail.h"
#include "codegen/c_runtime.h"
#include "data/output.h"
#include "model/imm/imm_spec.h"
#include "model/model_filter_view.h"
#include "model/world/model_world_noise.h"

namespace kfw::codegen {

namespace detail {

std::string c_name(const std::string& name) {
  std::string s;
  for (char c : name)
    s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "_" + s;
  return s;
}

std::string c_macro(const std::string& name) {
  std::string s = c_name(name);
  for (char& c : s)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string comment_text(const std::string& text) {
  std::string s;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (static_cast<unsigned char>(c) < 0x20) {
      s += ' ';
    } else if ((c == '*' && i + 1 < text.size() && text[i + 1] == '/') ||
               (c == '/' && i + 1 < text.size() && text[i + 1] == '*')) {
      s += c;
      s += ' ';
    } else {
      s += c;
    }
  }
  return s;
}

int angle_kind(Angle a) {
  return a == Angle::kRad ? 1 : a == Angle::kDeg ? 2 : 0;
}

std::string Gen::symbol(const std::string& name) {
  const model::ModelSpec& m = ms ? *ms : spec;
  const ParamValues& vals = mv ? *mv : values;
  const int slot = m.symbols.find(name);
  if (slot < 0) throw std::runtime_error("unknown symbol '" + name + "'");
  const auto in = [&](const std::vector<int>& slots) {
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (slots[i] == slot) return static_cast<int>(i);
    }
    return -1;
  };
  switch (m.symbols.kinds[static_cast<std::size_t>(slot)]) {
    case model::kParamSymbol: {
      const int i = in(m.param_slots);
      const auto it = i < 0 ? vals.end() : vals.find(m.param_keys[static_cast<std::size_t>(i)]);
      if (it == vals.end()) throw std::runtime_error("the parameter '" + name + "' has no value");
      std::string c = "par_" + name;
      // A mode's own value (an IMM's mode sets it) gets a constant of its own.
      const auto base = values.find(it->first);
      if (mode >= 0 && (base == values.end() || base->second != it->second))
        c += const_sfx.empty() ? "_m" + std::to_string(mode) : const_sfx;
      consts[c] = it->second;
      return c;
    }
    case model::kDtSymbol:
      return "dt";
    case model::kTimeSymbol:
      return "t";
    case model::kStateSymbol:
      return "x[" + std::to_string(in(m.state_slots)) + "]";
    case model::kInputSymbol:
      if (const int i = in(m.input_slots); i >= 0) return "u[" + std::to_string(i) + "]";
      if (const int i = in(m.input_age_slots); i >= 0)  // an input's age follows the inputs
        return "u[" + std::to_string(nu + i) + "]";
      throw std::runtime_error("the input symbol '" + name + "' is not exported");
    case model::kMeasuredSymbol:  // a pre-processed channel's role: the raw sample
      if (chan >= 0) {
        const auto& cols = m.channels[static_cast<std::size_t>(chan)].column_slots;
        if (const int i = in(cols); i >= 0) return "zr[" + std::to_string(i) + "]";
      }
      throw std::runtime_error("the column '" + name + "' outside its channel");
    default:
      throw std::runtime_error("the symbol '" + name + "' is not exported");
  }
}

bool channel_reads_step(const model::ChannelSpec& c) {
  const auto reads = [](const model::Expr& e) {
    return (e.uses & (model::kTimeSymbol | model::kInputSymbol)) != 0;
  };
  for (const auto& e : c.h)
    if (reads(e)) return true;
  for (const auto& e : c.H.e)
    if (reads(e)) return true;
  for (const auto& e : c.R.e)
    if (reads(e)) return true;
  for (const auto& e : c.z)
    if (reads(e)) return true;
  return false;
}

std::string init_channel_signature(const Gen& g) {
  if (g.spec.start_channel < 0) return {};
  const auto& ch = g.spec.channels[static_cast<std::size_t>(g.spec.start_channel)];
  std::string s = "int " + g.P + "_init_from_" + c_name(ch.name) + "(" + g.P + "_state *s, const " +
                  g.P + "_real z[" + std::to_string(ch.roles.size()) + "]";
  if (channel_reads_step(ch)) s += ", const " + g.P + "_real *u, " + g.P + "_real t";
  return s + ")";
}

std::string update_signature(const Gen& g, std::size_t c) {
  const auto& ch = g.spec.channels[c];
  std::string s = "int " + g.P + "_update_" + c_name(ch.name) + "(" + g.P + "_state *s, const " +
                  g.P + "_real z[" + std::to_string(ch.roles.size()) + "], ";
  if (channel_reads_step(ch)) s += "const " + g.P + "_real *u, " + g.P + "_real t, ";
  return s + g.P + "_real *nis)";
}

}  // namespace detail

using detail::c_macro;
using detail::c_name;
using detail::comment_text;
using detail::Gen;

namespace {

// Why a model's filter cannot be exported (one line), or empty.
std::string refusal(const model::ModelSpec& s, const ParamValues& values, const CExportOptions& o,
                    const model::FilterOptions& f) {
  if (s.modes) {
    if (o.steady || f.kind == model::FilterKind::kSteady)
      return "--steady: an IMM over modes has no single steady state";
    if (s.modes->renewal && s.modes->renewal->gain.at(values) != 0.0)
      return "an IMM's renewal (model.modes.renewal, " + s.modes->renewal->gain.key +
             " ≠ 0) is not exported";
  }
  for (const auto& c : s.channels) {
    const std::string key = "model.measurements." + c.name;
    if (c.size() > model::kMaxChannelSize) return key + ": too many components";
    auto reads_dt = [](const model::Expr& e) { return (e.uses & model::kDtSymbol) != 0; };
    for (const auto* m : {&c.H, &c.R}) {
      for (const auto& e : m->e)
        if (reads_dt(e)) return key + ": a channel that reads dt is not exported";
    }
    for (const auto& e : c.h)
      if (reads_dt(e)) return key + ": a channel that reads dt is not exported";
  }
  if ((o.steady || f.kind == model::FilterKind::kSteady) && o.runtime_params)
    return "--steady bakes its gain: no runtime parameters (--params-struct)";
  if (o.steady || f.kind == model::FilterKind::kSteady) {
    if (!s.time_invariant())
      return "--steady needs a linear time-invariant model (F, B, Q, H and R of parameters and "
             "dt only)";
    if (s.channels.size() != 1) return "--steady needs exactly one measurement channel";
  } else if (f.kind == model::FilterKind::kKf && !s.linear()) {
    return "filter 'kf' needs a linear model; use ekf or ukf";
  }
  return {};
}

std::string header_comment(const Gen& g, const std::string& file) {
  const model::ModelSpec& s = g.spec;
  const char* kind = g.steady()                                 ? "steady-state (fixed DARE gain)"
                     : g.filter.kind == model::FilterKind::kUkf ? "unscented Kalman filter"
                     : g.filter.kind == model::FilterKind::kEkf ? "extended Kalman filter"
                                                                : "Kalman filter (Joseph form)";
  std::string c = "/* " + file + ": the filter of " + comment_text(g.opt.preset) +
                  ", exported by kfw " KFW_VERSION " (kfw-cli export-c).\n";
  c += " *\n * Filter: " + std::string(kind) + ", " + (g.opt.single ? "single" : "double") +
       " precision.\n";
  if (g.steady()) c += " * Fixed interval: dt = " + g.lit(g.opt.steady_dt) + " s.\n";
  c += " * Parameter values:\n";
  for (const auto& [k, v] : g.values)
    c += " *   " + comment_text(k) + " = " + comment_text(g.table.format(k, v)) + "\n";
  std::vector<std::string> left;
  if (s.world) left.push_back("the world block");
  if (s.controller) left.push_back("the controller");
  if (!s.derived.empty()) left.push_back("derived quantities");
  if (!s.stat_metrics.empty()) left.push_back("statistics");
  if (!left.empty()) {
    c += " * Not exported (kfw only):";
    for (std::size_t i = 0; i < left.size(); ++i)
      c += std::string(i ? "," : "") + " " + left[i];
    c += ".\n";
  }
  return c + " */\n";
}

std::string state_struct(const Gen& g) {
  const std::string R = g.P + "_real", N = c_macro(g.P) + "_N";
  std::string s = "typedef struct {\n  " + R + " x[" + N + "]; /* the estimate */\n";
  if (g.steady()) return s + "} " + g.P + "_state;\n";
  const std::string name = g.modes > 0 ? g.P + "_filter" : g.P + "_state";
  if (g.modes > 0) s = "/* One mode's filter. */\n" + s;
  s += "  " + R + " P[" + N + "][" + N + "]; /* its covariance */\n";
  if (g.rt()) s += "  " + g.P + "_params par; /* the parameters in force (NAME_init) */\n";
  s += "  " + R + " dt; /* the interval F, B and Q hold the process for (NaN: none yet) */\n";
  s += "  " + R + " F[" + N + "][" + N + "], Q[" + N + "][" + N + "];\n";
  if (g.nu > 0) s += "  " + R + " B[" + N + "][" + c_macro(g.P) + "_NU];\n";
  if (g.cache) {
    // A log's intervals differ in their last bits (0.3 − 0.2 ≠ 0.1): Van Loan's exponential is
    // kept for the last few, as the engine keeps 64.
    const std::string C = c_macro(g.P) + "_DT_CACHE";
    s += "  /* F, Q (and B) of the last " + C +
         " intervals (NaN: empty), next the slot to fill */\n";
    s += "  " + R + " cache_dt[" + C + "], cache_F[" + C + "][" + N + "][" + N + "], cache_Q[" + C +
         "][" + N + "][" + N + "];\n";
    if (g.nu > 0) s += "  " + R + " cache_B[" + C + "][" + N + "][" + c_macro(g.P) + "_NU];\n";
    s += "  int next;\n";
  }
  s += "} " + name + ";\n";
  if (g.modes == 0) return s;
  const std::string NM = c_macro(g.P) + "_MODES";
  s += "\n/* The IMM: the combined estimate, the mode probabilities and each mode's filter. */\n";
  s += "typedef struct {\n  " + R + " x[" + N + "];\n  " + R + " P[" + N + "][" + N + "];\n";
  if (g.rt()) s += "  " + g.P + "_params par;\n";
  s += "  " + R + " mu[" + NM + "]; /* mode probabilities:";
  for (std::size_t j = 0; j < g.mode_names.size(); ++j)
    s += std::string(j ? "," : "") + " " + std::to_string(j) + " " + comment_text(g.mode_names[j]);
  s += " */\n  " + R + " log_mu[" + NM + "];\n  " + g.P + "_filter mode[" + NM + "];\n} " + g.P +
       "_state;\n";
  return s;
}

std::string header_text(const Gen& g) {
  const model::ModelSpec& s = g.spec;
  const std::string M = c_macro(g.P), R = g.P + "_real";
  std::string h = header_comment(g, g.P + ".h");
  h += "#ifndef " + M + "_H\n#define " + M + "_H\n\n#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n";
  h += "typedef " + g.real + " " + R + ";\n\n";
  h += "#define " + M + "_N " + std::to_string(g.n) + " /* states:";
  for (int i = 0; i < g.n; ++i) {
    const auto& st = s.states[static_cast<std::size_t>(i)];
    h += " x[" + std::to_string(i) + "] " + comment_text(st.name) +
         (st.unit.empty() ? "" : " (" + comment_text(st.unit) + ")") + (i + 1 < g.n ? "," : "");
  }
  h += " */\n#define " + M + "_NU " + std::to_string(g.nu) + " /* inputs";
  for (int i = 0; i < g.nu; ++i) {
    const auto& in = s.inputs[static_cast<std::size_t>(i)];
    h += std::string(i ? "," : ":") + " u[" + std::to_string(i) + "] " + comment_text(in.name);
  }
  h += " */\n";
  if (g.ages) {
    h += "#define " + M + "_U_SIZE (2 * " + M +
         "_NU) /* u: the inputs held, then each one's age "
         "(s since its last sample) */\n";
  } else {
    h += "#define " + M + "_U_SIZE " + M + "_NU /* u: the inputs held */\n";
  }
  if (g.modes > 0)
    h += "#define " + M + "_MODES " + std::to_string(g.modes) + " /* the IMM's modes */\n";
  if (g.cache)
    h += "#define " + M + "_DT_CACHE 8 /* Van Loan's results kept for this many intervals */\n";
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const auto& ch = s.channels[c];
    const int every = g.ev.channel(c).every;
    h += "#define " + M + "_EVERY_" + c_macro(ch.name) + " " + std::to_string(every) +
         " /* channel " + comment_text(ch.name) + " updates on rows k with k % " +
         std::to_string(every) + " == 0 */\n";
  }
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    if (!g.missing_on[c]) continue;
    const auto& ch = s.channels[c];
    h += "#define " + M + "_MISSING_" + c_macro(ch.name) + " " +
         c_number(g.missing_equals[c], false) + " /* channel " + comment_text(ch.name) +
         ": a sample is missing (no update) where column " + comment_text(ch.missing.column) +
         " reads this */\n";
  }
  h += "\n/* What an update returns. */\nenum { " + M + "_APPLIED = 1, " + M + "_GATED = 0, " + M +
       "_SKIPPED = -1, " + M + "_DIVERGED = -2 };\n\n";
  if (g.rt()) {
    h += "/* The parameters the filter reads, set at NAME_init (NAME_params_default: the exported\n"
         "   values; par_KEY_mJ: an IMM mode's own, par_KEY_centre: a grid's centre). */\n"
         "typedef struct {\n";
    for (const auto& [name, v] : g.consts)
      h += "  " + R + " " + name + ";\n";
    h += "} " + g.P + "_params;\nvoid " + g.P + "_params_default(" + g.P + "_params *p);\n\n";
  }
  h += state_struct(g) + "\n";
  h += "/* x and P (x alone in a steady-state export) at their initial values. */\nvoid " + g.P +
       "_init(" + g.P + "_state *s" + (g.rt() ? ", const " + g.P + "_params *p" : "") + ");\n";
  std::set<std::string> cols;
  for (const auto& x0 : s.x0) {
    if (!x0.first_column.empty() && cols.insert(x0.first_column).second) {
      h += "/* The states that start from column " + comment_text(x0.first_column) +
           "'s first finite sample. */\nvoid " + g.P + "_init_from_" + c_name(x0.first_column) +
           "(" + g.P + "_state *s, " + R + " value);\n";
    }
  }
  if (const std::string sig = detail::init_channel_signature(g); !sig.empty()) {
    h += "/* x0 from the first sample of channel " +
         comment_text(s.channels[static_cast<std::size_t>(s.start_channel)].name) +
         " (raw, its roles): the filter starts at that row, which is not also an update. 0 when "
         "a component is not finite. */\n" +
         sig + ";\n";
  }
  for (std::size_t k = 0; k < s.groups.size(); ++k) {
    const auto scheme = g.ev.group(k).scheme;
    if (scheme == model::GroupScheme::kEach) continue;
    const auto& gs = s.groups[k];
    std::string members;
    for (std::size_t j = 0; j < gs.members.size(); ++j)
      members += std::string(j ? ", " : "") + std::to_string(j) + " " +
                 comment_text(s.channels[static_cast<std::size_t>(gs.members[j])].name);
    if (scheme == model::GroupScheme::kSequential) {
      h += "/* Group " + comment_text(gs.name) + " (sequential; members " + members +
           "): its samples wait for their instant, then go through the members' updates in the "
           "order they came (see the example). */\n";
      continue;
    }
    h += "/* Group " + comment_text(gs.name) + " (stacked; members " + members +
         "): the samples waiting for the instant, member[a] and z[a] for a < count, in one "
         "update at the prior; nis[a] each member's NIS (NaN: not usable). */\n" +
         detail::group_signature(g, k) + ";\n";
  }
  h += "/* x(k|k-1) and P(k|k-1) from row k-1: u the inputs held at row k-1 (their last finite\n"
       "   values), t = t(k-1), dt = t(k) - t(k-1). " +
       M + "_DIVERGED when x or P stops being finite. */\n";
  h += "int " + g.P + "_predict(" + g.P + "_state *s, const " + R + " *u, " + R + " t, " + R +
       " dt);\n";
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const auto& ch = s.channels[c];
    h += "/* Channel " + comment_text(ch.name) + ": z = [";
    for (std::size_t j = 0; j < ch.comps.size(); ++j)
      h += (j ? ", " : "") + comment_text(ch.comps[j].name);
    h += "]";
    if (detail::channel_reads_step(ch)) h += "; u the inputs held at row k, t = t(k)";
    h += ". *nis: the NIS (NaN when not computed). */\n" + detail::update_signature(g, c) + ";\n";
  }
  h += "\n#ifdef __cplusplus\n}\n#endif\n\n#endif\n";
  return h;
}

// The .c file's prelude: the type, the sizes, the math functions of the precision.
std::string source_prelude(const Gen& g) {
  const std::string M = c_macro(g.P);
  std::string s = header_comment(g, g.P + ".c");
  s += "#include <math.h>\n\n#include \"" + g.P + ".h\"\n\n";
  s += "typedef " + g.P + "_real real;\n";
  s += c_math_macros(g.opt.single);
  s += "#define NX " + M + "_N\n#define MX " + std::to_string(g.mx) + "\n";
  if (g.nu > 0) s += "#define NU " + M + "_NU\n";
  s += "#define NS (2 * NX + 1)\n";
  if (g.modes > 0) {
    s += "#define NM " + M + "_MODES\n#define LOG_2PI LIT(" +
         c_number(std::log(2.0 * std::numbers::pi), false) + ")\n";
  }
  s += "#define EM " + std::to_string(std::max(2 * g.n, g.n + g.nu)) + "\n\n";
  return s;
}

std::string constants(const Gen& g) {
  if (g.rt()) {  // the defaults, then par_KEY as the field of the struct being stepped
    std::string s = "void " + g.P + "_params_default(" + g.P + "_params *p) {\n";
    for (const auto& [name, v] : g.consts)
      s += "  p->" + name + " = " + g.lit(v) + ";\n";
    s += "}\n\n/* par_KEY: the parameter in force, pp the NAME_params of the struct being stepped. "
         "*/\n";
    for (const auto& [name, v] : g.consts)
      s += "#define " + name + " (pp->" + name + ")\n";
    return s + "\n";
  }
  std::string s = "/* The tuned parameters (par_NAME_mJ: mode J's own value). */\n";
  for (const auto& [name, v] : g.consts)
    s += "static const real " + name + " = " + g.lit(v) + ";\n";
  return s + "\n";
}

}  // namespace

bool is_c_identifier(const std::string& name) {
  static const std::set<std::string> kKeywords = {
      "auto",     "break",  "case",   "char",     "const",      "continue", "default",  "do",
      "double",   "else",   "enum",   "extern",   "float",      "for",      "goto",     "if",
      "inline",   "int",    "long",   "register", "restrict",   "return",   "short",    "signed",
      "sizeof",   "static", "struct", "switch",   "typedef",    "union",    "unsigned", "void",
      "volatile", "while",  "_Bool",  "_Complex", "_Imaginary", "main"};
  return model::is_identifier(name) && !kKeywords.count(name);
}

bool exports_steady(const Scenario& s, const ParamValues& values, bool flag) {
  if (flag) return true;
  auto view = model_filter_view(s, values);
  return view && view->options.kind == model::FilterKind::kSteady;
}

Expected<double> steady_interval(const Scenario& s, const ParamValues& values,
                                 std::optional<double> dt, const Dataset* data) {
  auto view = model_filter_view(s, values);
  if (!view) return view.err();
  std::string where = "--dt";
  if (!dt && data && data->rows() >= 2) {
    dt = data->median_dt();
    where = "the median interval of " + data->source;
  } else if (!dt) {
    dt = param(view->values, view->spec->sim_dt_key);
    where = view->spec->sim_dt_key;
  }
  if (!(*dt > 0.0) || !std::isfinite(*dt))
    return Error{where + ": " + model::number(*dt) + " s: --steady needs a positive interval"};
  return *dt;
}

CExportOptions default_options(const std::string& preset_path) {
  CExportOptions o;
  o.prefix = default_prefix(preset_path);
  o.preset = std::filesystem::path(preset_path).filename().string();
  return o;
}

std::string default_prefix(const std::string& preset_path) {
  std::string stem = std::filesystem::path(preset_path).stem().string();
  return c_name(stem.empty() ? "filter" : stem);
}

Expected<CExport> export_c(const Scenario& scenario, const ParamValues& values,
                           const CExportOptions& options) {
  auto view = model_filter_view(scenario, values);
  if (!view) return view.err();
  const model::ModelSpec& spec = *view->spec;
  const std::string what = "cannot export " + spec.path + " as C: ";
  if (!is_c_identifier(options.prefix))
    return Error{"--prefix '" + options.prefix + "': not a C identifier"};
  if (auto why = refusal(spec, view->values, options, view->options); !why.empty())
    return Error{what + why};
  auto ev = model::ModelEval::create(spec, view->values);
  if (!ev) return ev.err();
  Gen g{spec,
        view->values,
        scenario.params(),
        view->options,
        options,
        **ev,
        options.prefix,
        options.single ? "float" : "double",
        {},
        {},
        {},
        spec.n(),
        static_cast<int>(spec.inputs.size()),
        1};
  if (view->options.kind == model::FilterKind::kSteady) g.opt.steady = true;
  if (g.opt.steady && !(g.opt.steady_dt > 0.0)) {
    auto dt = steady_interval(scenario, values, std::nullopt, nullptr);
    if (!dt) return dt.err();
    g.opt.steady_dt = *dt;
  }
  g.cache = spec.process.form == model::ProcessForm::kContinuous;
  for (std::size_t k = 0; k < spec.groups.size(); ++k) {
    const auto scheme = g.ev.group(k).scheme;
    if (scheme == model::GroupScheme::kEach) continue;
    const std::string key = "model.groups." + spec.groups[k].name;
    if (spec.modes) return Error{what + key + ": a group's instants in an IMM are not exported"};
    if (scheme == model::GroupScheme::kStacked && view->options.kind == model::FilterKind::kUkf)
      return Error{what + key + ": the stacked scheme runs in the kf or the ekf, not the ukf"};
    if (scheme == model::GroupScheme::kStacked)
      g.mx = std::max(g.mx, static_cast<int>(spec.groups[k].members.size()));
  }
  for (int slot : spec.input_age_slots)
    g.ages = g.ages || slot >= 0;
  std::vector<double> vars = g.ev.vars();
  for (const auto& c : spec.channels) {
    const std::string key = "model.measurements." + c.name + ".missing";
    double when = 0.0, equals = 0.0;
    if (c.missing.on()) {
      auto w = model::detail::param_value(c.missing.when, spec, vars, key + ".when");
      if (!w) return w.err();
      auto e = model::detail::param_value(c.missing.equals, spec, vars, key + ".equals");
      if (!e) return e.err();
      when = *w;
      equals = *e;
    }
    g.missing_on.push_back(when != 0.0);
    g.missing_equals.push_back(equals);
  }
  if (spec.modes) {
    auto modes = spec.modes->modes(spec, view->values);
    if (!modes) return modes.err();
    g.modes = static_cast<int>(modes->size());
    if (const model::StructureSpec* st = spec.modes->structure.at(view->values)) {
      g.block_of = st->block_of;
      g.component_block = st->component_block;
      g.approximate = st->approximate;
    }
    for (const auto& m : *modes) {
      g.mode_names.push_back(m.name);
      if (m.model && m.model->process.form == model::ProcessForm::kContinuous) g.cache = true;
      if (m.model)
        for (const auto& c : m.model->channels)
          g.mx = std::max(g.mx, c.size());
    }
  }
  for (const auto& c : spec.channels) {
    g.mx = std::max(g.mx, c.size());
    g.roles_max = std::max(g.roles_max, static_cast<int>(c.roles.size()));
  }
  auto functions = detail::filter_functions(g);
  if (!functions) return Error{what + functions.error()};
  CExport out;
  out.header = header_text(g);
  out.source = source_prelude(g) + constants(g) + g.defs + c_runtime(g.runtime) + *functions;
  out.example = detail::example_program(g);
  return out;
}

Status write_c_export(const std::string& dir, const std::string& prefix, const CExport& files,
                      const std::vector<std::string>& inputs) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Error{"--out-dir " + dir + ": not a directory"};
  const std::filesystem::path base(dir);
  const std::string names[3] = {(base / (prefix + ".h")).string(),
                                (base / (prefix + ".c")).string(),
                                (base / (prefix + "_example.c")).string()};
  OutputSet outs;
  for (const auto& in : inputs)
    outs.add_input(in);
  for (const auto& n : names) {
    if (auto st = outs.add(n, "--out-dir"); !st) return st;
  }
  if (auto st = outs.stage(names[0], files.header); !st) return st;
  if (auto st = outs.stage(names[1], files.source); !st) return st;
  if (auto st = outs.stage(names[2], files.example); !st) return st;
  return outs.commit();
}

}  // namespace kfw::codegen
