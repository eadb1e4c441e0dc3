// The model's matrices as C (c_export_detail.h): the process — its entries of parameters and dt
// recomputed when dt changes (Van Loan's results cached for the continuous form), those of t, the
// inputs and the state at each step, the continuous nonlinear process's ẋ, A and noise — and each
// channel's ẑ, H and R (and a pre-processed channel's components).
#include <cmath>
#include <stdexcept>

#include "codegen/c_export_detail.h"
#include "model/world/model_world_noise.h"

namespace kfw::codegen::detail {

// "target = expression;" lines, the expressions' common sub-expressions computed once before.
Expected<std::string> assignments(Gen& g, const std::vector<Assign>& list,
                                  const std::string& indent) {
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

}  // namespace kfw::codegen::detail
