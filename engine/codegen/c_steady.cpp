// --steady (c_export_detail.h): the fixed-gain filter of a linear time-invariant model — the
// engine's `filter = steady` (model/model_kf.cpp) without its covariance: the DARE gain of the
// m-step model (model/model_steady.h) at a fixed interval, baked in with F, B and H.
#include "codegen/c_export_detail.h"
#include "model/model_steady.h"

namespace kfw::codegen::detail {

// --steady: x = F x + B u and x += K (z - H x) with F, B, H and the DARE gain K at the fixed dt.
Expected<std::string> steady_functions(Gen& g) {
  auto& ev = g.ev;
  if (auto st = ev.check_dt(g.opt.steady_dt, "--dt"); !st) return st.err();
  auto ss = model::model_steady_state(g.spec, ev);
  if (!ss) return ss.err();
  const MatX& K = ss->dare.K;
  const auto& ch = g.spec.channels[0];
  const MatX& H = ev.channel(0).H;
  const int m = ch.size();
  const auto mat = [&](const std::string& name, const MatX& A) {
    std::string s = "static const real " + name + "[" + std::to_string(A.rows()) + "][" +
                    std::to_string(A.cols()) + "] = {";
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      s += std::string(i ? ", " : "") + "{";
      for (Eigen::Index j = 0; j < A.cols(); ++j)
        s += (j ? ", " : "") + g.lit(A(i, j));
      s += "}";
    }
    return s + "};\n";
  };
  std::string s =
      "/* The process, the channel and the DARE gain at dt = " + g.lit(g.opt.steady_dt) +
      " s (every " + std::to_string(ss->every) + " rows). */\n";
  s += mat("F", ev.F) + mat("H", H) + mat("K", K);
  if (g.nu > 0) s += mat("B", ev.B);
  s += "\n";
  const std::string M = c_macro(g.P);
  s += "int " + g.P + "_predict(" + g.P + "_state *s, const " + g.P + "_real *u, " + g.P +
       "_real t, " + g.P +
       "_real dt) {\n  real fx[NX];\n  int i;\n  (void)u;\n  (void)t;\n  (void)dt;\n" +
       linear_mean(g, "", "s->x", "fx", "  ") + "  for (i = 0; i < NX; ++i) s->x[i] = fx[i];\n" +
       wrap_state_lines(g, "  ");
  s += "  for (i = 0; i < NX; ++i) {\n    if (!isfinite(s->x[i])) return " + M +
       "_DIVERGED;\n  }\n  return 0;\n}\n\n";
  s += update_signature(g, 0) + " {\n  real y[" + std::to_string(m) + "];\n  int i, j;\n";
  if (channel_reads_step(ch)) s += "  (void)u;\n  (void)t;\n";
  s += "  for (j = 0; j < " + std::to_string(m) +
       "; ++j) {\n    real v = LIT(0.0);\n"
       "    for (i = 0; i < NX; ++i) v += H[j][i] * s->x[i];\n    y[j] = z[j] - v;\n  }\n";
  s += wrap_innovation(g, ch);
  s += "  for (i = 0; i < NX; ++i) {\n    real v = LIT(0.0);\n    for (j = 0; j < " +
       std::to_string(m) + "; ++j) v += K[i][j] * y[j];\n    s->x[i] += v;\n  }\n";
  s += wrap_state_lines(g, "  ") + "  if (nis) *nis = NAN; /* no S on the target */\n";
  s += "  for (i = 0; i < NX; ++i) {\n    if (!isfinite(s->x[i])) return " + M +
       "_DIVERGED;\n  }\n  return " + M + "_APPLIED;\n}\n\n";
  return s;
}

}  // namespace kfw::codegen::detail
