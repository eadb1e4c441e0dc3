// The exported filter's own functions (c_export_detail.h): NAME_init, the filter's predict and
// update over the model's matrices (c_parts.cpp) — the engine's KalmanFilter and UnscentedFilter
// (model/model_filters.h) step for step — and the API over them.
#include <cmath>
#include <stdexcept>

#include "codegen/c_export_detail.h"
#include "filter/ukf.h"

namespace kfw::codegen::detail {

namespace {
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
  if (!nonlinear) s += linear_mean(g, "s->", "s->x", "fx", "  ");
  s += "  predict_cov(s->P, s->F, s->Q);\n  for (i = 0; i < NX; ++i) s->x[i] = fx[i];\n";
  s += wrap_states(g, "  ");
  return s + "  return diverged(s->x, s->P) ? " + c_macro(g.P) + "_DIVERGED : 0;\n}\n\n";
}

}  // namespace

std::string linear_mean(const Gen& g, const std::string& m, const std::string& in,
                        const std::string& out, const std::string& indent) {
  const std::string& d = indent;
  std::string s = d + "{ /* " + out + " = F " + in + " + B u */\n" + d + "  int a, b;\n" + d +
                  "  for (a = 0; a < NX; ++a) {\n" + d + "    real v = LIT(0.0);\n" + d +
                  "    for (b = 0; b < NX; ++b) v += " + m + "F[a][b] * " + in + "[b];\n";
  if (g.nu > 0) s += d + "    for (b = 0; b < NU; ++b) v += " + m + "B[a][b] * u[b];\n";
  return s + d + "    " + out + "[a] = v;\n" + d + "  }\n" + d + "}\n";
}

namespace {

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
    s += linear_mean(g, "s->", "xs", "ys", "    ");
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
