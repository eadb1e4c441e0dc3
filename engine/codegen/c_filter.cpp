// The exported filter's own functions (c_export_detail.h): the model's matrices as C, and the
// bodies of NAME_init, NAME_predict and NAME_update_<channel> — the engine's KalmanFilter and
// UnscentedFilter (model/model_filters.h) step for step, and its steady-state filter.
#include <cmath>
#include <stdexcept>

#include "codegen/c_export_detail.h"
#include "filter/ukf.h"
#include "model/world/model_world_noise.h"

namespace kfw::codegen::detail {

namespace {

struct Assign {
  std::string target;
  const model::Expr* e;
  std::string key;
};

// "target = expression;" lines, the expressions' common sub-expressions computed once before.
Expected<std::string> assignments(Gen& g, const std::vector<Assign>& list,
                                  const std::string& indent = "  ") {
  CExprSet set = g.exprs();
  for (const Assign& a : list) {
    if (auto r = set.add(a.e->text, a.key); !r) return r.err();
  }
  std::vector<std::string> texts;
  std::string out;
  try {
    out = set.emit(indent, texts);
  } catch (const std::exception& e) {
    return Error{e.what()};
  }
  for (std::size_t i = 0; i < list.size(); ++i)
    out += indent + list[i].target + " = " + texts[i] + ";\n";
  g.runtime.insert(set.helpers().begin(), set.helpers().end());
  return out;
}

std::string ij(int i, int j) {
  return "[" + std::to_string(i) + "][" + std::to_string(j) + "]";
}

// An IMM's approximate structure (model.modes.structure): R's entries between components whose H
// rows read different blocks are 0 (model/imm/imm_run.cpp, drop_cross).
std::string drop_R(const Gen& g, std::size_t c) {
  if (!g.approximate || c >= g.component_block.size()) return {};
  std::string s;
  const auto& b = g.component_block[c];
  for (std::size_t i = 0; i < b.size(); ++i) {
    for (std::size_t j = 0; j < b.size(); ++j) {
      if (b[i] != b[j])
        s += "  R" + ij(static_cast<int>(i), static_cast<int>(j)) + " = LIT(0.0);\n";
    }
  }
  return s;
}

// The same for Q, before the prediction.
std::string drop_Q(const Gen& g) {
  if (!g.approximate) return {};
  std::string s;
  for (std::size_t i = 0; i < g.block_of.size(); ++i) {
    for (std::size_t j = 0; j < g.block_of.size(); ++j) {
      if (g.block_of[i] != g.block_of[j])
        s += "  s->Q" + ij(static_cast<int>(i), static_cast<int>(j)) + " = LIT(0.0);\n";
    }
  }
  return s;
}

// The entries of `m` into `target` (prefix such as "s->F") whose class `pick` accepts.
void matrix(std::vector<Assign>& out, const model::MatrixSpec& m, const std::string& target,
            bool step) {
  for (int i = 0; i < m.rows; ++i) {
    for (int j = 0; j < m.cols; ++j) {
      const model::Expr& e = m.at(i, j);
      if ((e.dep >= model::Dep::kStep) != step) continue;
      out.push_back({target + ij(i, j), &e, m.key + ij(i, j)});
    }
  }
}

// process_at(s, dt): the process at a new interval: process_dt, or (continuous) Van Loan's
// result for that interval from the cache.
std::string process_at(const Gen& g) {
  std::string s = "/* F, B and Q at the interval dt. */\nstatic void process_at" + g.sfx + "(" +
                  g.ft + " *s, real dt) {\n";
  if (g.ms->process.form != model::ProcessForm::kContinuous)
    return s + "  process_dt" + g.sfx + "(s, dt);\n  s->dt = dt;\n}\n\n";
  const std::string C = c_macro(g.P) + "_DT_CACHE";
  const bool b = g.nu > 0 && !g.ms->process.Bc.empty();
  s += "  int c, i, j;\n  for (c = 0; c < " + C +
       "; ++c) {\n    if (s->cache_dt[c] == dt) break;\n"
       "  }\n  if (c == " +
       C + ") {\n    process_dt" + g.sfx +
       "(s, dt);\n    c = s->next;\n"
       "    s->next = (s->next + 1) % " +
       C +
       ";\n    s->cache_dt[c] = dt;\n"
       "    for (i = 0; i < NX; ++i) {\n      for (j = 0; j < NX; ++j) {\n"
       "        s->cache_F[c][i][j] = s->F[i][j];\n        s->cache_Q[c][i][j] = s->Q[i][j];\n"
       "      }\n";
  if (b) s += "      for (j = 0; j < NU; ++j) s->cache_B[c][i][j] = s->B[i][j];\n";
  s += "    }\n  } else {\n    for (i = 0; i < NX; ++i) {\n      for (j = 0; j < NX; ++j) {\n"
       "        s->F[i][j] = s->cache_F[c][i][j];\n        s->Q[i][j] = s->cache_Q[c][i][j];\n"
       "      }\n";
  if (b) s += "      for (j = 0; j < NU; ++j) s->B[i][j] = s->cache_B[c][i][j];\n";
  return s + "    }\n  }\n  s->dt = dt;\n}\n\n";
}

const char* kVoidAll = "  (void)x;\n  (void)u;\n  (void)t;\n  (void)dt;\n";

// process_dt(s, dt): the entries of F, B and Q of parameters and dt (Van Loan for the continuous
// form), recomputed only when dt changes. process_step(s, x, u, t, dt, fx): those of t, the
// inputs and the state, and (nonlinear) f, at x.
// The continuous nonlinear process: xdot(x, u, t, k) = ẋ, xdot_A(x, u, t, A) = ∂ẋ/∂x (GiNaC's),
// and process_noise(x, u, t, dt, Q): Van Loan of (A(x), G Qc Gᵀ) over dt.
Expected<std::string> xdot_parts(Gen& g) {
  const auto& pr = g.ms->process;
  std::vector<Assign> k, a;
  for (int i = 0; i < g.n; ++i)
    k.push_back({"k[" + std::to_string(i) + "]", &pr.f[static_cast<std::size_t>(i)],
                 "model.process.xdot[" + std::to_string(i) + "]"});
  matrix(a, pr.A, "A", false);
  matrix(a, pr.A, "A", true);
  auto kt = assignments(g, k);
  if (!kt) return kt.err();
  auto at = assignments(g, a);
  if (!at) return at.err();
  const std::string ctx =
      g.rt() ? "  const " + g.P + "_params *pp = (const " + g.P + "_params *)ctx;\n  (void)pp;\n"
             : "  (void)ctx;\n";
  std::string s = "/* xdot = f(x, u, t). */\nstatic void xdot" + g.sfx +
                  "(const void *ctx, const real *x, const real *u, real t, real *k) {\n" + ctx +
                  "  (void)x;\n  (void)u;\n  (void)t;\n" + *kt + "}\n\n";
  s += "/* A = df/dx at x, u, t. */\nstatic void xdot_A" + g.sfx +
       "(const void *ctx, const real *x, const real *u, real t, real (*A)[NX]) {\n" + ctx +
       "  (void)x;\n  (void)u;\n  (void)t;\n" + *at + "}\n\n";
  std::vector<Assign> noise;
  if (!pr.G.empty()) matrix(noise, pr.G, "G", false);
  matrix(noise, pr.Qc, "Qc", false);
  auto nt = assignments(g, noise);
  if (!nt) return nt.err();
  const int q = pr.G.empty() ? g.n : pr.G.cols;
  const std::string qs = std::to_string(q);
  g.runtime.insert("van_loan");
  g.runtime.insert("rk4");
  s += "/* Q by Van Loan's method on the linearisation (A(x), G Qc G') over dt. */\n";
  s += "static void process_noise" + g.sfx +
       "(const real x[NX], const real *u, real t, real dt, real Q[NX][NX]" + g.pp_param() +
       ") {\n" + g.pp_void() + "  real A[NX][NX], W[NX][NX], Fd[NX][NX], G[NX][" + qs + "], Qc[" +
       qs + "][" + qs + "];\n  int i, j, a, b;\n" + *nt;
  if (pr.G.empty()) {
    s += "  for (i = 0; i < NX; ++i) {\n    for (j = 0; j < NX; ++j) G[i][j] = i == j ? LIT(1.0) : "
         "LIT(0.0);\n  }\n";
  }
  s += "  for (i = 0; i < NX; ++i) { /* W = G Qc G' */\n    for (j = 0; j < NX; ++j) {\n"
       "      real v = LIT(0.0);\n      for (a = 0; a < " +
       qs +
       "; ++a) {\n"
       "        real gq = LIT(0.0);\n        for (b = 0; b < " +
       qs +
       "; ++b) gq += G[i][b] * "
       "Qc[b][a];\n        v += gq * G[j][a];\n      }\n      W[i][j] = v;\n    }\n  }\n";
  s += "  xdot_A" + g.sfx + "(" + g.ctx_arg() +
       ", x, u, t, A);\n  van_loan(A, W, dt, Fd, Q);\n}\n\n";
  return s;
}

// The number of RK4 sub-steps over dt (at most `substep` seconds each; 1 without).
std::string rk4_steps(Gen& g) {
  double substep = 0.0;
  if (!g.ms->process.substep.text.empty()) {
    std::vector<double> vars = g.me->vars();
    auto v =
        model::detail::param_value(g.ms->process.substep, *g.ms, vars, "model.process.substep");
    if (v) substep = *v;
  }
  if (!(substep > 0.0)) return "  const int steps = 1;\n";
  return "  int steps = (int)CEIL(dt / " + g.lit(substep) +
         " - LIT(1e-9));\n  if (steps < 1) steps = 1;\n";
}

Expected<std::string> process_parts(Gen& g) {
  const auto& pr = g.ms->process;
  const bool nonlinear = g.ms->nonlinear_process();
  if (pr.form == model::ProcessForm::kContinuousNonlinear) return xdot_parts(g);
  std::string s = "/* F, B and Q of parameters and dt: when dt changes. */\n";
  s += "static void process_dt" + g.sfx + "(" + g.ft + " *s, real dt) {\n" + g.pp_decl();
  std::vector<Assign> at_dt;
  if (pr.form == model::ProcessForm::kContinuous) {
    g.runtime.insert("van_loan");
    const int gcols = pr.G.empty() ? g.n : pr.G.cols;
    s += "  real A[NX][NX], W[NX][NX], G[NX][" + std::to_string(gcols) + "], Qc[" +
         std::to_string(pr.Qc.rows) + "][" + std::to_string(pr.Qc.cols) + "];\n  int i, j, a, b;\n";
    matrix(at_dt, pr.A, "A", false);
    if (!pr.G.empty()) {
      matrix(at_dt, pr.G, "G", false);
    }
    matrix(at_dt, pr.Qc, "Qc", false);
    if (!pr.Bc.empty()) matrix(at_dt, pr.Bc, "Bc", false);
    if (!pr.Bc.empty()) s += "  real Bc[NX][NU];\n";
    auto a = assignments(g, at_dt);
    if (!a) return a.err();
    s += *a;
    if (pr.G.empty()) {
      s += "  for (i = 0; i < NX; ++i) {\n    for (j = 0; j < NX; ++j) G[i][j] = i == j ? LIT(1.0) "
           ": LIT(0.0);\n  }\n";
    }
    const std::string q = std::to_string(pr.G.empty() ? g.n : pr.G.cols);
    s += "  for (i = 0; i < NX; ++i) { /* W = G Qc G' */\n    for (j = 0; j < NX; ++j) {\n"
         "      real v = LIT(0.0);\n      for (a = 0; a < " +
         q +
         "; ++a) {\n"
         "        real gq = LIT(0.0);\n        for (b = 0; b < " +
         q +
         "; ++b) gq += G[i][b] * "
         "Qc[b][a];\n        v += gq * G[j][a];\n      }\n      W[i][j] = v;\n    }\n  }\n";
    s += "  van_loan(A, W, dt, s->F, s->Q);\n";
    if (!pr.Bc.empty()) {
      g.runtime.insert("van_loan_input");
      s += "  van_loan_input(A, Bc, dt, s->B);\n";
    }
    s += "}\n\n";
  } else {
    if (!(nonlinear && g.ukf())) matrix(at_dt, pr.F, "s->F", false);
    if (!pr.B.empty()) matrix(at_dt, pr.B, "s->B", false);
    matrix(at_dt, pr.Q, "s->Q", false);
    auto a = assignments(g, at_dt);
    if (!a) return a.err();
    s += "  (void)s;\n  (void)dt;\n" + *a + "}\n\n";
  }
  s += process_at(g);
  std::vector<Assign> step;
  if (pr.form != model::ProcessForm::kContinuous) {
    if (nonlinear && !g.ukf()) {
      for (int i = 0; i < g.n; ++i)
        step.push_back({"fx[" + std::to_string(i) + "]", &pr.f[static_cast<std::size_t>(i)],
                        "model.process.f[" + std::to_string(i) + "]"});
    }
    if (!(nonlinear && g.ukf())) matrix(step, pr.F, "s->F", true);
    if (!pr.B.empty()) matrix(step, pr.B, "s->B", true);
    matrix(step, pr.Q, "s->Q", true);
  }
  auto a = assignments(g, step);
  if (!a) return a.err();
  s += "/* The entries of t, the inputs and the state, at x" +
       std::string(nonlinear && !g.ukf() ? "; fx = f(x)" : "") + ". */\n";
  s += "static void process_step" + g.sfx + "(" + g.ft +
       " *s, const real x[NX], const real *u, real t, "
       "real dt, real fx[NX]) {\n" +
       g.pp_decl() + "  (void)s;\n  (void)fx;\n" + kVoidAll + *a + "}\n\n";
  if (nonlinear && g.ukf()) {
    std::vector<Assign> f;
    for (int i = 0; i < g.n; ++i)
      f.push_back({"fx[" + std::to_string(i) + "]", &pr.f[static_cast<std::size_t>(i)],
                   "model.process.f[" + std::to_string(i) + "]"});
    auto fa = assignments(g, f);
    if (!fa) return fa.err();
    s += "/* fx = f(x): one sigma point through the process. */\n";
    s += "static void process_f" + g.sfx +
         "(const real x[NX], const real *u, real t, real dt, real fx[NX]" + g.pp_param() +
         ") "
         "{\n" +
         g.pp_void() + std::string(kVoidAll) + *fa + "}\n\n";
  }
  return s;
}

// channel_C(x, u, t, hx, H, R): ẑ = h(x) (EKF), H (KF, EKF, linear UKF) and R at x; and for the
// UKF of a nonlinear channel channel_C_h(x, u, t, hx) for the sigma points.
// preprocess_C(zr, u, t, z): a pre-processed channel's components from its roles' raw sample
// zr (model.measurements.C.z); 0 when one is not finite (the engine skips the update).
Expected<std::string> preprocess_text(Gen& g, std::size_t c, const std::string& sfx) {
  const auto& ch = g.ms->channels[c];
  std::vector<Assign> list;
  for (int j = 0; j < ch.size(); ++j)
    list.push_back({"z[" + std::to_string(j) + "]", &ch.z[static_cast<std::size_t>(j)],
                    "model.measurements." + ch.name + ".z[" + std::to_string(j) + "]"});
  g.chan = static_cast<int>(c);
  auto a = assignments(g, list);
  g.chan = -1;
  if (!a) return a.err();
  return "/* Channel " + comment_text(ch.name) + "'s components from its raw sample. */\n" +
         "static int preprocess_" + c_name(ch.name) + sfx +
         "(const real *zr, const real *u, real t, real z[MX]" + g.pp_param() + ") {\n" +
         g.pp_void() +
         "  int j;\n  (void)u;\n"
         "  (void)t;\n" +
         *a + "  for (j = 0; j < " + std::to_string(ch.size()) +
         "; ++j) {\n    if (!isfinite(z[j])) return 0;\n  }\n  return 1;\n}\n\n";
}

// channel_C(x, zr, u, t, hx, H, R): ẑ = h(x) (EKF), H (KF, EKF, linear UKF) and R at x (zr: the
// raw sample, which a pre-processed channel's R may read); and for the UKF of a nonlinear channel
// channel_C_h(x, zr, u, t, hx) for the sigma points.
Expected<std::string> channel_parts(Gen& g, std::size_t c) {
  const auto& ch = g.ms->channels[c];
  const std::string name = c_name(ch.name);
  std::vector<Assign> list;
  const std::string key = "model.measurements." + ch.name;
  if (!ch.linear && !g.ukf()) {
    for (int j = 0; j < ch.size(); ++j)
      list.push_back({"hx[" + std::to_string(j) + "]", &ch.h[static_cast<std::size_t>(j)],
                      key + ".h[" + std::to_string(j) + "]"});
  }
  for (bool step : {false, true}) {
    if (ch.linear || !g.ukf()) matrix(list, ch.H, "H", step);
    matrix(list, ch.R, "R", step);
  }
  g.chan = static_cast<int>(c);
  auto a = assignments(g, list);
  g.chan = -1;
  if (!a) return a.err();
  std::string s;
  if (ch.preprocessed()) {
    auto pp = preprocess_text(g, c, g.sfx);
    if (!pp) return pp.err();
    s += *pp;
  }
  s += "/* Channel " + comment_text(ch.name) + " at x. */\n";
  s += "static void channel_" + name + g.sfx +
       "(const real x[NX], const real *zr, const real *u, real t, real hx[MX], "
       "real H[MX][NX], real R[MX][MX]" +
       g.pp_param() + ") {\n" + g.pp_void() +
       "  (void)x;\n  (void)zr;\n  (void)u;\n  (void)t;\n"
       "  (void)hx;\n  (void)H;\n" +
       *a + "}\n\n";
  if (!ch.linear && g.ukf()) {
    std::vector<Assign> h;
    for (int j = 0; j < ch.size(); ++j)
      h.push_back({"hx[" + std::to_string(j) + "]", &ch.h[static_cast<std::size_t>(j)],
                   key + ".h[" + std::to_string(j) + "]"});
    g.chan = static_cast<int>(c);
    auto ha = assignments(g, h);
    g.chan = -1;
    if (!ha) return ha.err();
    s += "static void channel_" + name + "_h" + g.sfx +
         "(const real x[NX], const real *zr, const real *u, real t, "
         "real hx[MX]" +
         g.pp_param() + ") {\n" + g.pp_void() +
         "  (void)x;\n  (void)zr;\n  (void)u;\n  (void)t;\n" + *ha + "}\n\n";
  }
  return s;
}

// s->x[i] wrapped where state i is an angle.
std::string wrap_states(Gen& g, const std::string& indent) {
  std::string s;
  for (int i = 0; i < g.n; ++i) {
    const int k = angle_kind(g.spec.states[static_cast<std::size_t>(i)].angle);
    if (!k) continue;
    g.runtime.insert("wrap_angle");
    const std::string x = "s->x[" + std::to_string(i) + "]";
    s += indent + x + " = wrap_angle(" + x + ", " + std::to_string(k) + ");\n";
  }
  return s;
}

// `name`(FT *s): x0 and P0, the process unset. The model's NAME_init, or an IMM's filter_init.
std::string init_function(Gen& g, std::string& error, const std::string& name) {
  std::vector<Assign> list;
  for (int i = 0; i < g.n; ++i)
    list.push_back({"s->x[" + std::to_string(i) + "]",
                    &g.spec.x0[static_cast<std::size_t>(i)].value,
                    "model.x0[" + std::to_string(i) + "]"});
  if (!g.steady()) matrix(list, g.spec.P0, "s->P", false);
  auto a = assignments(g, list);
  if (!a) {
    error = a.error();
    return {};
  }
  // The model's own NAME_init takes the parameters (runtime mode); an IMM's sets them first.
  const bool own = g.rt() && g.modes == 0;
  std::string s = name + "(" + g.ft + " *s" + (own ? ", const " + g.P + "_params *p" : "") +
                  ") {\n" + (own ? "  s->par = *p;\n" : "") + g.pp_decl() + *a;
  if (!g.steady()) {
    s += "  s->dt = NAN;\n  {\n    int i, j;\n    for (i = 0; i < NX; ++i) {\n"
         "      for (j = 0; j < NX; ++j) s->F[i][j] = s->Q[i][j] = LIT(0.0);\n";
    if (g.nu > 0) s += "      for (j = 0; j < NU; ++j) s->B[i][j] = LIT(0.0);\n";
    s += "    }\n";
    if (g.spec.process.form == model::ProcessForm::kContinuous) {
      s += "    for (i = 0; i < " + c_macro(g.P) +
           "_DT_CACHE; ++i) s->cache_dt[i] = NAN;\n"
           "    s->next = 0;\n";
    }
    s += "  }\n";
  }
  s += "}\n\n";
  if (g.modes > 0) return s;  // the IMM sets every mode's
  std::set<std::string> cols;
  for (const auto& x0 : g.spec.x0) {
    if (x0.first_column.empty() || !cols.insert(x0.first_column).second) continue;
    s += "void " + g.P + "_init_from_" + c_name(x0.first_column) + "(" + g.P + "_state *s, " + g.P +
         "_real value) {\n";
    for (int i = 0; i < g.n; ++i) {
      if (g.spec.x0[static_cast<std::size_t>(i)].first_column == x0.first_column)
        s += "  s->x[" + std::to_string(i) + "] = value;\n";
    }
    s += "}\n\n";
  }
  return s;
}

std::string predict_kf(Gen& g) {
  const bool nonlinear = g.ms->nonlinear_process();
  g.runtime.insert("predict_cov");
  g.runtime.insert("diverged");
  std::string s = "static int filter_predict" + g.sfx + "(" + g.ft +
                  " *s, const real *u, real t, real dt) {\n  real fx[NX];\n  int i;\n" +
                  g.pp_decl();
  if (g.ms->process.form == model::ProcessForm::kContinuousNonlinear) {
    s += rk4_steps(g) + "  rk4(xdot" + g.sfx + ", xdot_A" + g.sfx + ", " + g.ctx_arg() +
         ", s->x, u, t, dt, steps, fx, s->F);\n  process_noise" + g.sfx + "(s->x, u, t, dt, s->Q" +
         g.pp_arg() + ");\n";
    s += "  predict_cov(s->P, s->F, s->Q);\n  for (i = 0; i < NX; ++i) s->x[i] = fx[i];\n";
    s += wrap_states(g, "  ");
    return s + "  return diverged(s->x, s->P) ? " + c_macro(g.P) + "_DIVERGED : 0;\n}\n\n";
  }
  s += "  if (!(dt == s->dt)) process_at" + g.sfx + "(s, dt);\n";
  s += "  process_step" + g.sfx + "(s, s->x, u, t, dt, fx);\n" + drop_Q(g);
  if (!nonlinear) {
    s += "  for (i = 0; i < NX; ++i) { /* fx = F x + B u */\n    int j;\n    real v = LIT(0.0);\n"
         "    for (j = 0; j < NX; ++j) v += s->F[i][j] * s->x[j];\n    fx[i] = v;\n  }\n";
    if (g.nu > 0) {
      s += "  {\n    int j;\n    for (j = 0; j < NU; ++j) {\n      for (i = 0; i < NX; ++i) "
           "fx[i] += s->B[i][j] * u[j];\n    }\n  }\n";
    }
  }
  s += "  predict_cov(s->P, s->F, s->Q);\n  for (i = 0; i < NX; ++i) s->x[i] = fx[i];\n";
  s += wrap_states(g, "  ");
  return s + "  return diverged(s->x, s->P) ? " + c_macro(g.P) + "_DIVERGED : 0;\n}\n\n";
}

std::string angles_array(const std::string& name, const std::vector<int>& kinds) {
  std::string s = "static const int " + name + "[" + std::to_string(kinds.size()) + "] = {";
  for (std::size_t i = 0; i < kinds.size(); ++i)
    s += (i ? ", " : "") + std::to_string(kinds[i]);
  return s + "};\n";
}

std::string predict_ukf(Gen& g) {
  const bool nonlinear = g.ms->nonlinear_process();
  g.runtime.insert("sigma_points");
  g.runtime.insert("diverged");
  std::string s = "static int filter_predict" + g.sfx + "(" + g.ft +
                  " *s, const real *u, real t, real dt) {\n" + g.pp_decl();
  s += "  real X[NX][NS], Y[NX][NS], xs[NX], ys[NX], d[NX];\n  int i, j, r;\n";
  const bool xdot = g.ms->process.form == model::ProcessForm::kContinuousNonlinear;
  if (xdot) {
    s += rk4_steps(g) + "  process_noise" + g.sfx + "(s->x, u, t, dt, s->Q" + g.pp_arg() + ");\n";
  } else {
    s += "  if (!(dt == s->dt)) process_at" + g.sfx + "(s, dt);\n";
    s += "  process_step" + g.sfx + "(s, s->x, u, t, dt, ys);\n" + drop_Q(g);
  }
  s += "  if (!sigma_points(s->x, s->P, X)) return " + c_macro(g.P) + "_DIVERGED;\n";
  s += "  for (j = 0; j < NS; ++j) {\n    for (i = 0; i < NX; ++i) xs[i] = X[i][j];\n";
  if (xdot) {
    s += "    rk4(xdot" + g.sfx + ", xdot_A" + g.sfx + ", " + g.ctx_arg() +
         ", xs, u, t, dt, steps, ys, 0);\n";
  } else if (nonlinear) {
    s += "    process_f" + g.sfx + "(xs, u, t, dt, ys" + g.pp_arg() + ");\n";
  } else {
    s += "    for (i = 0; i < NX; ++i) {\n      int k;\n      real v = LIT(0.0);\n"
         "      for (k = 0; k < NX; ++k) v += s->F[i][k] * xs[k];\n      ys[i] = v;\n    }\n";
    if (g.nu > 0) {
      s += "    for (r = 0; r < NU; ++r) {\n      for (i = 0; i < NX; ++i) ys[i] += s->B[i][r] * "
           "u[r];\n    }\n";
    }
  }
  s += "    for (i = 0; i < NX; ++i) Y[i][j] = ys[i];\n  }\n";
  s += "  for (r = 0; r < NX; ++r) s->x[r] = sigma_mean(Y[r], state_angle[r]);\n";
  s += "  for (i = 0; i < NX; ++i) {\n    for (r = 0; r < NX; ++r) s->P[i][r] = s->Q[i][r];\n  }\n";
  s += "  for (j = 0; j < NS; ++j) {\n    for (r = 0; r < NX; ++r) d[r] = wrap_angle(Y[r][j] - "
       "s->x[r], state_angle[r]);\n    for (i = 0; i < NX; ++i) {\n      for (r = 0; r < NX; ++r) "
       "s->P[i][r] += ukf_wc(j) * d[i] * d[r];\n    }\n  }\n";
  s += "  for (i = 0; i < NX; ++i) {\n    for (r = 0; r < i; ++r) {\n      const real v = LIT(0.5) "
       "* (s->P[i][r] + s->P[r][i]);\n      s->P[i][r] = s->P[r][i] = v;\n    }\n  }\n";
  return s + "  return diverged(s->x, s->P) ? " + c_macro(g.P) + "_DIVERGED : 0;\n}\n\n";
}

// The head of an update function: its locals, u and t where the channel does not read them.
std::string update_head(Gen& g, std::size_t c) {
  std::string s = "static int filter_update_" + c_name(g.spec.channels[c].name) + g.sfx + "(" +
                  g.ft +
                  " *s, const real *z, const real *zr, const real *u, real t, real *nis, "
                  "real *logdet) {\n" +
                  g.pp_decl();
  return s;
}

std::string update_kf(Gen& g, std::size_t c) {
  const auto& ch = g.ms->channels[c];
  const std::string M = c_macro(g.P), name = c_name(ch.name);
  const int m = ch.size();
  const double gate = g.me->channel(c).gate_nis;
  g.runtime.insert("diverged");
  std::string s = update_head(g, c);
  s += "  real hx[MX], H[MX][NX], R[MX][MX], y[MX];\n  int j, r;\n";
  s += "  channel_" + name + g.sfx + "(s->x, zr, u, t, hx, H, R" + g.pp_arg() + ");\n" +
       drop_R(g, c);
  if (ch.linear) {
    s += "  for (j = 0; j < " + std::to_string(m) +
         "; ++j) { /* zhat = H x */\n    int i;\n"
         "    real v = LIT(0.0);\n    for (i = 0; i < NX; ++i) v += H[j][i] * s->x[i];\n"
         "    hx[j] = v;\n  }\n";
  }
  s += "  for (j = 0; j < " + std::to_string(m) +
       "; ++j) {\n    if (!isfinite(hx[j])) {\n"
       "      if (nis) *nis = NAN;\n      return " +
       M +
       "_SKIPPED;\n    }\n"
       "    y[j] = z[j] - hx[j];\n  }\n";
  s += wrap_innovation(g, ch);
  if (m == 1) {
    g.runtime.insert("update_scalar");
    s +=
        "  r = update_scalar(s->x, s->P, H[0], R[0][0], y[0], " + g.lit(gate) + ", nis, logdet);\n";
  } else {
    g.runtime.insert("update_vec");
    const std::string ms = std::to_string(m);
    s += "  {\n    real C[NX][MX], S[MX][MX];\n    int i, a, b;\n";
    s += "    for (i = 0; i < NX; ++i) { /* C = P H' */\n      for (a = 0; a < " + ms +
         "; ++a) {\n        real v = LIT(0.0);\n        for (b = 0; b < NX; ++b) v += s->P[i][b] "
         "* H[a][b];\n        C[i][a] = v;\n      }\n    }\n";
    s += "    for (a = 0; a < " + ms + "; ++a) { /* S = H C + R */\n      for (b = 0; b < " + ms +
         "; ++b) {\n        real v = LIT(0.0);\n        for (i = 0; i < NX; ++i) v += H[a][i] * "
         "C[i][b];\n        S[a][b] = v + R[a][b];\n      }\n    }\n";
    s += "    r = update_vec(s->x, s->P, " + ms + ", y, S, C, H, R, " + g.lit(gate) +
         ", nis, logdet);\n";
    s += "  }\n";
  }
  s += "  if (r != " + M + "_APPLIED) return r;\n" + wrap_states(g, "  ");
  return s + "  return diverged(s->x, s->P) ? " + M + "_DIVERGED : " + M + "_APPLIED;\n}\n\n";
}

std::string update_ukf(Gen& g, std::size_t c) {
  const auto& ch = g.ms->channels[c];
  const std::string M = c_macro(g.P), name = c_name(ch.name), ms = std::to_string(ch.size());
  const double gate = g.me->channel(c).gate_nis;
  g.runtime.insert("update_vec");
  g.runtime.insert("sigma_points");
  g.runtime.insert("diverged");
  std::string s = update_head(g, c);
  s += "  real hx[MX], H[MX][NX], R[MX][MX], y[MX], X[NX][NS], Z[MX][NS], S[MX][MX], C[NX][MX];\n"
       "  real xs[NX], zhat[MX], dz[MX], d[NX];\n  int i, j, a, r;\n";
  s += "  channel_" + name + g.sfx + "(s->x, zr, u, t, hx, H, R" + g.pp_arg() + ");\n" +
       drop_R(g, c);
  s += "  if (!sigma_points(s->x, s->P, X)) return " + M + "_DIVERGED;\n";
  s += "  for (j = 0; j < NS; ++j) {\n    for (i = 0; i < NX; ++i) xs[i] = X[i][j];\n";
  if (ch.linear) {
    s += "    for (a = 0; a < " + ms +
         "; ++a) {\n      real v = LIT(0.0);\n      for (i = 0; i < "
         "NX; ++i) v += H[a][i] * xs[i];\n      hx[a] = v;\n    }\n";
  } else {
    s += "    channel_" + name + "_h" + g.sfx + "(xs, zr, u, t, hx" + g.pp_arg() + ");\n";
  }
  s += "    for (a = 0; a < " + ms + "; ++a) Z[a][j] = hx[a];\n  }\n";
  s += "  for (a = 0; a < " + ms + "; ++a) zhat[a] = sigma_mean(Z[a], role_angle_" + name +
       "[a]);\n";
  s += "  for (a = 0; a < " + ms + "; ++a) {\n    for (r = 0; r < " + ms +
       "; ++r) S[a][r] = R[a][r];\n    for (i = 0; i < NX; ++i) C[i][a] = LIT(0.0);\n  }\n";
  s += "  for (j = 0; j < NS; ++j) {\n    for (a = 0; a < " + ms +
       "; ++a) dz[a] = wrap_angle(Z[a][j] "
       "- zhat[a], role_angle_" +
       name +
       "[a]);\n    for (i = 0; i < NX; ++i) d[i] = "
       "wrap_angle(X[i][j] - s->x[i], state_angle[i]);\n    for (a = 0; a < " +
       ms +
       "; ++a) {\n"
       "      for (r = 0; r < " +
       ms +
       "; ++r) S[a][r] += ukf_wc(j) * dz[a] * dz[r];\n"
       "      for (i = 0; i < NX; ++i) C[i][a] += ukf_wc(j) * d[i] * dz[a];\n    }\n  }\n";
  s += "  for (a = 0; a < " + ms +
       "; ++a) {\n    if (!isfinite(zhat[a])) {\n      if (nis) *nis = "
       "NAN;\n      return " +
       M +
       "_SKIPPED;\n    }\n    y[a] = wrap_angle(z[a] - zhat[a], "
       "role_angle_" +
       name + "[a]);\n  }\n";
  s += "  r = update_vec(s->x, s->P, " + ms + ", y, S, C, 0, 0, " + g.lit(gate) +
       ", nis, logdet);\n";
  s += "  if (r != " + M + "_APPLIED) return r;\n" + wrap_states(g, "  ");
  return s + "  return diverged(s->x, s->P) ? " + M + "_DIVERGED : " + M + "_APPLIED;\n}\n\n";
}

// The model's own filter: NAME_predict and NAME_update_CHANNEL over filter_predict and
// filter_update_CHANNEL.
std::string api_wrappers(Gen& g) {
  std::string s = "int " + g.P + "_predict(" + g.P + "_state *s, const " + g.P + "_real *u, " +
                  g.P + "_real t, " + g.P +
                  "_real dt) {\n  return filter_predict(s, u, t, dt);\n}\n\n";
  for (std::size_t c = 0; c < g.spec.channels.size(); ++c) {
    s += update_signature(g, c) + " {\n";
    if (!channel_reads_step(g.spec.channels[c]))
      s += "  const real *u = 0;\n  const real t = LIT(0.0);\n";
    const std::string name = c_name(g.spec.channels[c].name);
    if (g.spec.channels[c].preprocessed()) {
      s += g.pp_decl() + "  real zp[MX];\n  if (!preprocess_" + name + "(z, u, t, zp" + g.pp_arg() +
           ")) {\n    if (nis) *nis = NAN;\n"
           "    return " +
           c_macro(g.P) + "_SKIPPED;\n  }\n  return filter_update_" + name +
           "(s, zp, z, u, t, nis, 0);\n}\n\n";
    } else {
      s += "  return filter_update_" + name + "(s, z, z, u, t, nis, 0);\n}\n\n";
    }
  }
  if (g.spec.start_channel >= 0)
    s += start_head(g, "") + start_lines(g, "s->x") + "  return 1;\n}\n\n";
  return s;
}

}  // namespace

Expected<std::string> preprocess_part(Gen& g, std::size_t c, const std::string& sfx) {
  return preprocess_text(g, c, sfx);
}

std::string start_head(const Gen& g, const std::string& sfx) {
  const auto c = static_cast<std::size_t>(g.spec.start_channel);
  const auto& ch = g.spec.channels[c];
  std::string s = init_channel_signature(g) + " {\n  real zp[MX];\n" + g.pp_decl();
  if (!channel_reads_step(ch)) s += "  const real *u = 0;\n  const real t = LIT(0.0);\n";
  if (ch.preprocessed())
    return s + "  if (!preprocess_" + c_name(ch.name) + sfx + "(z, u, t, zp" + g.pp_arg() +
           ")) return 0;\n";
  return s + "  int j;\n  (void)u;\n  (void)t;\n  for (j = 0; j < " + std::to_string(ch.size()) +
         "; ++j) {\n    if (!isfinite(z[j])) return 0;\n    zp[j] = z[j];\n  }\n";
}

std::string start_lines(const Gen& g, const std::string& x) {
  std::string s;
  for (std::size_t i = 0; i < g.spec.x0.size(); ++i) {
    const auto& x0 = g.spec.x0[i];
    if (x0.first_channel != g.spec.start_channel) continue;
    s += "  " + x + "[" + std::to_string(i) + "] = zp[" + std::to_string(x0.first_component) +
         "];\n";
  }
  return s;
}

std::string wrap_innovation(Gen& g, const model::ChannelSpec& ch) {
  std::string s;
  for (int j = 0; j < ch.size(); ++j) {
    const int k = angle_kind(ch.comps[static_cast<std::size_t>(j)].angle);
    if (!k) continue;
    g.runtime.insert("wrap_angle");
    s += "  y[" + std::to_string(j) + "] = wrap_angle(y[" + std::to_string(j) + "], " +
         std::to_string(k) + ");\n";
  }
  return s;
}

std::string wrap_state_lines(Gen& g, const std::string& indent) {
  return wrap_states(g, indent);
}

void ukf_defs(Gen& g) {
  std::string& d = g.defs;
  const auto w = UkfWeights::scaled(g.n, g.filter.alpha, g.filter.beta, g.filter.kappa);
  d += "/* The scaled unscented transform: alpha = " + g.lit(g.filter.alpha) +
       ", beta = " + g.lit(g.filter.beta) + ", kappa = " + g.lit(g.filter.kappa) + ". */\n";
  d += "static const real UKF_C = " + g.lit(w.c) + ", UKF_WM0 = " + g.lit(w.m0) +
       ", UKF_WC0 = " + g.lit(w.c0) + ", UKF_WI = " + g.lit(w.i) + ";\n";
  std::vector<int> kinds;
  for (const auto& st : g.spec.states)
    kinds.push_back(angle_kind(st.angle));
  d += angles_array("state_angle", kinds);
  for (const auto& ch : g.spec.channels) {
    kinds.clear();
    for (const auto& r : ch.comps)
      kinds.push_back(angle_kind(r.angle));
    d += angles_array("role_angle_" + c_name(ch.name), kinds);
  }
  d += "\n";
  g.runtime.insert("wrap_angle");
}

Expected<std::string> one_filter(Gen& g) {
  auto p = process_parts(g);
  if (!p) return p.err();
  std::string s = *p;
  for (std::size_t c = 0; c < g.ms->channels.size(); ++c) {
    auto ch = channel_parts(g, c);
    if (!ch) return ch.err();
    s += *ch;
  }
  s += g.ukf() ? predict_ukf(g) : predict_kf(g);
  for (std::size_t c = 0; c < g.ms->channels.size(); ++c)
    s += g.ukf() ? update_ukf(g, c) : update_kf(g, c);
  return s;
}

Expected<std::string> filter_init(Gen& g, const std::string& name) {
  std::string error;
  std::string s = init_function(g, error, name);
  if (!error.empty()) return Error{error};
  return s;
}

Expected<std::string> filter_functions(Gen& g) {
  g.ms = &g.spec;
  g.mv = &g.values;
  g.me = &g.ev;
  g.sfx.clear();
  g.ft = g.P + "_state";
  if (g.modes > 0) return imm_functions(g);
  auto init = filter_init(g, "void " + g.P + "_init");
  if (!init) return init.err();
  if (g.steady()) {
    auto s = steady_functions(g);
    if (!s) return s.err();
    return *init + *s;
  }
  if (g.ukf()) ukf_defs(g);
  auto f = one_filter(g);
  if (!f) return f.err();
  return *init + *f + api_wrappers(g) + group_functions(g);
}

}  // namespace kfw::codegen::detail
