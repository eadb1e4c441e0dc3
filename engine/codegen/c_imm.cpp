// An IMM over a model's modes as C (c_export_detail.h): one filter per mode (c_filter.cpp's, with
// the mode's model and values, its functions suffixed _mJ), and the cycle of
// model/imm/imm_run.cpp over them — mixing with spread terms (filter/imm.h, the uniform chain's
// O(r) form or the dense matrix), each mode's prediction, each channel's update in every mode with
// the probabilities updated in the log domain, and the combination after each step.
#include <cmath>
#include <memory>
#include <numbers>

#include "codegen/c_export_detail.h"
#include "model/imm/imm_spec.h"

namespace kfw::codegen::detail {

namespace {

// The chain as constants: the uniform chain's stay and off probabilities, or the matrix.
std::string chain_constants(const Gen& g, const model::ModesSpec& ms, int r) {
  if (ms.matrix.empty()) {
    const double stay = r == 1 ? 1.0 : ms.stay.at(g.values);
    const double off = r == 1 ? 0.0 : (1.0 - stay) / static_cast<double>(r - 1);
    return "static const real MARKOV_STAY = " + g.lit(stay) + ", MARKOV_OFF = " + g.lit(off) +
           ";\n";
  }
  std::string s = "static const real MARKOV[NM][NM] = {";
  for (int i = 0; i < r; ++i) {
    s += std::string(i ? ", " : "") + "{";
    for (int j = 0; j < r; ++j)
      s += (j ? ", " : "") +
           g.lit(ms.matrix[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
    s += "}";
  }
  return s + "};\n";
}

const char* kLogSumExp = R"C(/* mu = exp(log mu), below e^-700 flushed to 0 (filter/imm.cpp). */
static real mode_prob(real log_mu) { return log_mu < -LIT(700.0) ? LIT(0.0) : EXP(log_mu); }

/* log sum exp(v), -inf when every entry is -inf. */
static real log_sum_exp(const real v[NM]) {
  real m = NEG_INF, s = LIT(0.0);
  int j;
  for (j = 0; j < NM; ++j) {
    if (v[j] > m) m = v[j];
  }
  if (!isfinite(m)) return NEG_INF;
  for (j = 0; j < NM; ++j) s += EXP(v[j] - m);
  return m + LOG(s);
}

/* x = sum mu_j x_j, P = sum mu_j (P_j + (x_j - x)(x_j - x)') (seed 001, Table 2). */
static void combine(STATE *s) {
  int i, j, k;
  for (j = 0; j < NM; ++j) s->mu[j] = mode_prob(s->log_mu[j]);
  for (i = 0; i < NX; ++i) {
    real v = LIT(0.0);
    for (j = 0; j < NM; ++j) v += s->mu[j] * s->mode[j].x[i];
    s->x[i] = v;
    for (k = 0; k < NX; ++k) s->P[i][k] = LIT(0.0);
  }
  for (j = 0; j < NM; ++j) {
    real d[NX];
    if (s->mu[j] == LIT(0.0)) continue;
    for (i = 0; i < NX; ++i) d[i] = s->mode[j].x[i] - s->x[i];
    for (i = 0; i < NX; ++i) {
      for (k = 0; k < NX; ++k) s->P[i][k] += s->mu[j] * s->mode[j].P[i][k] + (s->mu[j] * d[i]) * d[k];
    }
  }
}

)C";

const char* kMixUniform =
    R"C(/* Mixing (seed 001, Table 2) for the uniform chain: c_j = off + (stay - off) mu_j, each mode's
   prior (1 - b_j) times the mu-weighted moments plus b_j times its own, b_j = (stay - off) mu_j / c_j
   (0 below 1e-16); log mu becomes log c (filter/imm.cpp, filter/imm.h). */
static void mix(STATE *s) {
  real mean[NX], M[NX][NX], own[NM], mu[NM];
  int i, j, k;
  for (j = 0; j < NM; ++j) {
    const real c = MARKOV_OFF + (MARKOV_STAY - MARKOV_OFF) * (mu[j] = mode_prob(s->log_mu[j]));
    if (c > LIT(0.0)) {
      const real b = (MARKOV_STAY - MARKOV_OFF) * mu[j] / c;
      own[j] = FABS(b) < LIT(1e-16) ? LIT(0.0) : b;
      s->log_mu[j] = LOG(c);
    } else {
      own[j] = LIT(1.0);
      s->log_mu[j] = NEG_INF;
    }
  }
  for (i = 0; i < NX; ++i) {
    real v = LIT(0.0);
    for (j = 0; j < NM; ++j) v += mu[j] * s->mode[j].x[i];
    mean[i] = v;
    for (k = 0; k < NX; ++k) M[i][k] = LIT(0.0);
  }
  for (j = 0; j < NM; ++j) {
    real d[NX];
    if (mu[j] == LIT(0.0)) continue;
    for (i = 0; i < NX; ++i) d[i] = s->mode[j].x[i] - mean[i];
    for (i = 0; i < NX; ++i) {
      for (k = 0; k < NX; ++k) M[i][k] += mu[j] * s->mode[j].P[i][k] + (mu[j] * d[i]) * d[k];
    }
  }
  for (j = 0; j < NM; ++j) {
    const real b = own[j];
    real d[NX];
    if (b == LIT(0.0)) {
      for (i = 0; i < NX; ++i) {
        s->mode[j].x[i] = mean[i];
        for (k = 0; k < NX; ++k) s->mode[j].P[i][k] = M[i][k];
      }
      continue;
    }
    for (i = 0; i < NX; ++i) d[i] = s->mode[j].x[i] - mean[i];
    for (i = 0; i < NX; ++i) {
      s->mode[j].x[i] = mean[i] + b * d[i];
      for (k = 0; k < NX; ++k) {
        s->mode[j].P[i][k] = (LIT(1.0) - b) * M[i][k] + b * s->mode[j].P[i][k] +
                             (b * (LIT(1.0) - b) * d[i]) * d[k];
      }
    }
  }
}

)C";

const char* kMixDense =
    R"C(/* Mixing (seed 001, Table 2) for a Markov matrix: c_j = sum_i p_ij mu_i, mu_i|j = p_ij mu_i / c_j,
   each mode's prior the mu_i|j-weighted moments with spread terms; log mu becomes log c. */
static void mix(STATE *s) {
  real w[NM][NM], x[NM][NX], P[NM][NX][NX], mu[NM];
  int i, j, k, a;
  for (j = 0; j < NM; ++j) mu[j] = mode_prob(s->log_mu[j]);
  for (j = 0; j < NM; ++j) {
    real c = LIT(0.0);
    for (i = 0; i < NM; ++i) c += MARKOV[i][j] * mu[i];
    if (c > LIT(0.0)) {
      s->log_mu[j] = LOG(c);
      for (i = 0; i < NM; ++i) w[i][j] = MARKOV[i][j] * mu[i] / c;
    } else {
      s->log_mu[j] = NEG_INF;
      for (i = 0; i < NM; ++i) w[i][j] = i == j ? LIT(1.0) : LIT(0.0);
    }
  }
  for (j = 0; j < NM; ++j) {
    for (a = 0; a < NX; ++a) {
      real v = LIT(0.0);
      for (i = 0; i < NM; ++i) v += w[i][j] * s->mode[i].x[a];
      x[j][a] = v;
      for (k = 0; k < NX; ++k) P[j][a][k] = LIT(0.0);
    }
    for (i = 0; i < NM; ++i) {
      real d[NX];
      if (w[i][j] == LIT(0.0)) continue;
      for (a = 0; a < NX; ++a) d[a] = s->mode[i].x[a] - x[j][a];
      for (a = 0; a < NX; ++a) {
        for (k = 0; k < NX; ++k) P[j][a][k] += w[i][j] * s->mode[i].P[a][k] + (w[i][j] * d[a]) * d[k];
      }
    }
  }
  for (j = 0; j < NM; ++j) {
    for (a = 0; a < NX; ++a) {
      s->mode[j].x[a] = x[j][a];
      for (k = 0; k < NX; ++k) s->mode[j].P[a][k] = P[j][a][k];
    }
  }
}

)C";

// The API over the modes: NAME_init (every mode at x0, P0; mu0), NAME_init_from_COLUMN,
// NAME_predict (mixing, each mode's prediction) and NAME_update_CHANNEL (every mode, then mu).
std::string imm_api(Gen& g, const model::ModesSpec& ms, int r) {
  const std::string M = c_macro(g.P);
  std::string s;
  // NAME_init: every mode at x0, P0; μ0.
  s += "void " + g.P + "_init(" + g.P + "_state *s" +
       (g.rt() ? ", const " + g.P + "_params *p) {\n  s->par = *p;\n" : ") {\n");
  for (int j = 0; j < r; ++j) {
    const double mu0 = ms.mu0.empty() ? 1.0 / r : ms.mu0[static_cast<std::size_t>(j)];
    if (g.rt()) s += "  s->mode[" + std::to_string(j) + "].par = *p;\n";
    s += "  filter_init(&s->mode[" + std::to_string(j) + "]);\n  s->log_mu[" + std::to_string(j) +
         "] = " + (mu0 > 0.0 ? g.lit(std::log(mu0)) : std::string("NEG_INF")) + ";\n";
    if (!g.block_of.empty()) s += "  drop_cross(s->mode[" + std::to_string(j) + "].P);\n";
  }
  s += "  combine(s);\n}\n\n";
  std::set<std::string> cols;
  for (const auto& x0 : g.spec.x0) {
    if (x0.first_column.empty() || !cols.insert(x0.first_column).second) continue;
    s += "void " + g.P + "_init_from_" + c_name(x0.first_column) + "(" + g.P + "_state *s, " + g.P +
         "_real value) {\n  int j;\n  for (j = 0; j < NM; ++j) {\n";
    for (int i = 0; i < g.n; ++i) {
      if (g.spec.x0[static_cast<std::size_t>(i)].first_column == x0.first_column)
        s += "    s->mode[j].x[" + std::to_string(i) + "] = value;\n";
    }
    s += "  }\n  combine(s);\n}\n\n";
  }
  if (g.spec.start_channel >= 0) {  // from the sample at the grid's centre, into every mode
    s += start_head(g, "_centre") + "  {\n    int j;\n    for (j = 0; j < NM; ++j) {\n" +
         start_lines(g, "  s->mode[j].x") + "    }\n  }\n  combine(s);\n" +
         wrap_state_lines(g, "  ") + "  return 1;\n}\n\n";
  }
  // NAME_predict: mixing, then each mode's prediction.
  s += "int " + g.P + "_predict(" + g.P + "_state *s, const " + g.P + "_real *u, " + g.P +
       "_real t, " + g.P + "_real dt) {\n  mix(s);\n";
  if (!g.block_of.empty()) {  // mixing block by block: the spread terms between blocks dropped
    s += "  {\n    int j;\n    for (j = 0; j < NM; ++j) drop_cross(s->mode[j].P);\n  }\n";
  }
  for (int j = 0; j < r; ++j) {
    const std::string jj = std::to_string(j);
    s += "  if (filter_predict_m" + jj + "(&s->mode[" + jj + "], u, t, dt) < 0) return " + M +
         "_DIVERGED;\n";
  }
  s += "  combine(s);\n" + wrap_state_lines(g, "  ") + "  return 0;\n}\n\n";
  // NAME_update_CHANNEL: the channel in every mode, then μ_j ∝ Λ_j μ_j (log domain).
  for (std::size_t c = 0; c < g.spec.channels.size(); ++c) {
    const auto& ch = g.spec.channels[c];
    const std::string name = c_name(ch.name);
    s += update_signature(g, c) +
         " {\n  real ll[NM], n[NM], ld[NM], v[NM], lc, zp[MX];\n  int j, r, best;\n" + g.pp_decl();
    if (!channel_reads_step(ch)) s += "  const real *u = 0;\n  const real t = LIT(0.0);\n";
    for (int j = 0; j < r; ++j) {
      const std::string jj = std::to_string(j);
      if (ch.preprocessed()) {  // each mode's own pseudo-measurement (seed 001)
        s += "  if (!preprocess_" + name + "_m" + jj + "(z, u, t, zp" + g.pp_arg() +
             ")) {\n    ll[" + jj + "] = NEG_INF;\n    n[" + jj + "] = NAN;\n  } else {\n";
      } else {
        s += "  {\n    for (j = 0; j < " + std::to_string(ch.size()) + "; ++j) zp[j] = z[j];\n";
      }
      s += "  r = filter_update_" + name + "_m" + jj + "(&s->mode[" + jj + "], zp, z, u, t, &n[" +
           jj + "], &ld[" + jj + "]);\n  if (r == " + M + "_DIVERGED) return r;\n  ll[" + jj +
           "] = r == " + M + "_APPLIED ? -LIT(0.5) * (LIT(" + std::to_string(ch.size()) +
           ".0) * LOG_2PI + ld[" + jj + "] + n[" + jj + "]) : NEG_INF;\n  }\n";
    }
    s += "  for (j = 0; j < NM; ++j) {\n    v[j] = s->log_mu[j] + (isnan(ll[j]) ? NEG_INF : "
         "ll[j]);\n"
         "    if (isnan(v[j])) v[j] = NEG_INF;\n  }\n  lc = log_sum_exp(v);\n"
         "  if (!isfinite(lc)) { /* no mode explains it: mu stays */\n    if (nis) *nis = NAN;\n"
         "    return " +
         M +
         "_SKIPPED;\n  }\n  best = 0;\n  for (j = 0; j < NM; ++j) {\n"
         "    s->log_mu[j] = v[j] - lc;\n    if (s->log_mu[j] > s->log_mu[best]) best = j;\n  }\n"
         "  if (nis) *nis = n[best];\n  combine(s);\n" +
         wrap_state_lines(g, "  ") + "  return " + M + "_APPLIED;\n}\n\n";
  }
  return s;
}

}  // namespace

// x0 from a channel's first sample, pre-processed with each grid axis at its centre (seed 001
// converts the first measurement with the grid's centre slope; imm_run.cpp start_at_centre).
Expected<std::string> centre_preprocess(Gen& g, const model::ModesSpec& ms,
                                        const std::vector<model::Mode>& modes) {
  const auto c = static_cast<std::size_t>(g.spec.start_channel);
  if (!g.spec.channels[c].preprocessed()) return std::string();
  ParamValues centre = g.values;
  for (std::size_t a = 0; a < ms.grid.size(); ++a) {
    double lo = modes.front().grid[a], hi = lo;
    for (const model::Mode& m : modes) {
      lo = std::min(lo, m.grid[a]);
      hi = std::max(hi, m.grid[a]);
    }
    centre[ms.grid[a].param] = 0.5 * (lo + hi);
  }
  g.mv = &centre;
  g.mode = 0;
  g.const_sfx = "_centre";
  auto s = preprocess_part(g, c, "_centre");
  g.mv = &g.values;
  g.mode = -1;
  g.const_sfx.clear();
  return s;
}

Expected<std::string> imm_functions(Gen& g) {
  const model::ModesSpec& ms = *g.spec.modes;
  auto modes = ms.modes(g.spec, g.values);
  if (!modes) return modes.err();
  const int r = static_cast<int>(modes->size());
  const std::string M = c_macro(g.P);
  g.ft = g.P + "_filter";
  auto init = filter_init(g, "static void filter_init");
  if (!init) return init.err();
  if (g.ukf()) ukf_defs(g);
  std::string s = "#define STATE " + g.P + "_state\n#define NEG_INF " +
                  std::string(g.opt.single ? "(-HUGE_VALF)" : "(-HUGE_VAL)") + "\n" +
                  chain_constants(g, ms, r) + "\n" + *init;
  std::vector<std::unique_ptr<model::ModelEval>> evs;
  for (int j = 0; j < r; ++j) {
    const model::Mode& m = (*modes)[static_cast<std::size_t>(j)];
    const model::ModelSpec* spec = m.model ? m.model : &g.spec;
    auto ev = model::ModelEval::create(*spec, m.values);
    if (!ev) return Error{ev.error() + " (in mode '" + m.name + "')"};
    evs.push_back(std::move(*ev));
    g.ms = spec;
    g.mv = &m.values;
    g.me = evs.back().get();
    g.mode = j;
    g.sfx = "_m" + std::to_string(j);
    s += "/* Mode " + std::to_string(j) + ": " + comment_text(m.name) + ". */\n";
    auto f = one_filter(g);
    if (!f) return Error{f.error() + " (in mode '" + m.name + "')"};
    s += *f;
  }
  g.ms = &g.spec;
  g.mv = &g.values;
  g.me = &g.ev;
  g.mode = -1;
  g.sfx.clear();
  if (!g.block_of.empty()) {
    s += "/* The blocks of the states (model.modes.structure): entries between them are 0. */\n"
         "static const int block_of[NX] = {";
    for (std::size_t i = 0; i < g.block_of.size(); ++i)
      s += (i ? ", " : "") + std::to_string(g.block_of[i]);
    s += "};\nstatic void drop_cross(real P[NX][NX]) {\n  int i, k;\n  for (i = 0; i < NX; ++i) {\n"
         "    for (k = 0; k < NX; ++k) {\n      if (block_of[i] != block_of[k]) P[i][k] = "
         "LIT(0.0);\n"
         "    }\n  }\n}\n\n";
  }
  if (g.spec.start_channel >= 0) {
    auto pre = centre_preprocess(g, ms, *modes);
    if (!pre) return pre.err();
    s += *pre;
  }
  s += kLogSumExp;
  s += ms.matrix.empty() ? kMixUniform : kMixDense;
  return s + imm_api(g, ms, r);
}

}  // namespace kfw::codegen::detail
