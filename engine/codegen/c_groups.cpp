// Channel groups (c_export_detail.h; model/model_groups.cpp, model_filter_detail.h): a group of
// scalar channels whose samples wait for their instant. The waiting is the caller's clock (the
// example shows it); a stacked group's update is NAME_update_GROUP — the members' samples at the
// prior, one update with the members' R on the diagonal and the group's cross term elsewhere,
// each member gated on its own S_ii (KalmanFilter::update_group). A sequential group's samples go
// through the members' own updates one after the other.
#include "codegen/c_export_detail.h"

namespace kfw::codegen::detail {

bool group_reads_step(const Gen& g, std::size_t k) {
  for (int c : g.spec.groups[k].members) {
    if (channel_reads_step(g.spec.channels[static_cast<std::size_t>(c)])) return true;
  }
  return false;
}

std::string group_signature(const Gen& g, std::size_t k) {
  const std::string R = g.P + "_real";
  std::string s = "int " + g.P + "_update_" + c_name(g.spec.groups[k].name) + "(" + g.P +
                  "_state *s, int count, const int member[], const " + R + " z[], ";
  if (group_reads_step(g, k)) s += "const " + R + " *u, " + R + " t, ";
  return s + R + " nis[])";
}

std::string stacked_update(Gen& g, std::size_t k) {
  const model::GroupSpec& gs = g.spec.groups[k];
  const std::string M = c_macro(g.P), gm = std::to_string(gs.members.size());
  g.runtime.insert("update_vec");
  g.runtime.insert("diverged");
  std::string s = group_signature(g, k) + " {\n" + g.pp_decl();
  if (!group_reads_step(g, k)) s += "  const real *u = 0;\n  const real t = LIT(0.0);\n";
  s += "  real hx[MX], H1[MX][NX], R1[MX][MX], H[MX][NX], y[MX], r[MX], gate[MX], R[MX][MX];\n"
       "  real S[MX][MX], C[NX][MX], Hk[MX][NX], yk[MX], Rk[MX][MX], Sk[MX][MX], Ck[NX][MX];\n"
       "  int idx[MX], keep[MX], m = 0, nk = 0, a, b, i, res;\n";
  s += "  for (a = 0; a < count; ++a) { /* each member at the prior: zhat, H, R */\n"
       "    nis[a] = NAN;\n    switch (member[a]) {\n";
  for (std::size_t j = 0; j < gs.members.size(); ++j) {
    const auto c = static_cast<std::size_t>(gs.members[j]);
    const auto& ch = g.spec.channels[c];
    s += "      case " + std::to_string(j) + ":\n        channel_" + c_name(ch.name) +
         "(s->x, z + a, u, t, hx, H1, R1" + g.pp_arg() + ");\n";
    if (ch.linear) {
      s += "        hx[0] = LIT(0.0);\n        for (i = 0; i < NX; ++i) hx[0] += H1[0][i] * "
           "s->x[i];\n";
    }
    s += "        gate[m] = " + g.lit(g.ev.channel(c).gate_nis) +
         ";\n        y[m] = z[a] - hx[0];\n";
    if (const int ak = angle_kind(ch.comps[0].angle); ak) {
      g.runtime.insert("wrap_angle");
      s += "        y[m] = wrap_angle(y[m], " + std::to_string(ak) + ");\n";
    }
    s += "        break;\n";
  }
  s += "      default:\n        continue;\n    }\n    if (!isfinite(hx[0])) continue;\n"
       "    for (i = 0; i < NX; ++i) H[m][i] = H1[0][i];\n    r[m] = R1[0][0];\n    idx[m++] = a;\n"
       "  }\n";
  s += "  for (a = 0; a < m; ++a) { /* R: the members' on the diagonal, the cross term elsewhere "
       "*/\n"
       "    for (b = 0; b < m; ++b) R[a][b] = a == b ? r[a] : " +
       g.lit(g.ev.group(k).cross) + ";\n  }\n";
  const auto cs = [](const std::string& h, const std::string& rr, const std::string& c,
                     const std::string& sm, const std::string& n) {
    return "  for (i = 0; i < NX; ++i) {\n    for (a = 0; a < " + n +
           "; ++a) {\n"
           "      real v = LIT(0.0);\n      for (b = 0; b < NX; ++b) v += s->P[i][b] * " +
           h + "[a][b];\n      " + c + "[i][a] = v;\n    }\n  }\n  for (a = 0; a < " + n +
           "; ++a) {\n"
           "    for (b = 0; b < " +
           n +
           "; ++b) {\n      real v = LIT(0.0);\n"
           "      for (i = 0; i < NX; ++i) v += " +
           h + "[a][i] * " + c + "[i][b];\n      " + sm + "[a][b] = v + " + rr +
           "[a][b];\n    }\n  }\n";
  };
  s += cs("H", "R", "C", "S", "m");
  s += "  for (a = 0; a < m; ++a) { /* each member gated on its own S_ii */\n"
       "    nis[idx[a]] = y[a] * y[a] / S[a][a];\n"
       "    if (!(S[a][a] > LIT(0.0)) || !isfinite(S[a][a])) continue;\n"
       "    if (gate[a] > LIT(0.0) && y[a] * y[a] > gate[a] * S[a][a]) continue;\n"
       "    keep[nk++] = a;\n  }\n  if (nk == 0) return " +
       M + "_GATED;\n";
  s += "  for (a = 0; a < nk; ++a) {\n    yk[a] = y[keep[a]];\n"
       "    for (i = 0; i < NX; ++i) Hk[a][i] = H[keep[a]][i];\n"
       "    for (b = 0; b < nk; ++b) Rk[a][b] = R[keep[a]][keep[b]];\n  }\n";
  s += cs("Hk", "Rk", "Ck", "Sk", "nk");
  s += "  res = update_vec(s->x, s->P, nk, yk, Sk, Ck, Hk, Rk, LIT(0.0), 0, 0);\n"
       "  if (res != " +
       M + "_APPLIED) return res;\n" + wrap_state_lines(g, "  ");
  return s + "  return diverged(s->x, s->P) ? " + M + "_DIVERGED : " + M + "_APPLIED;\n}\n\n";
}

std::string group_functions(Gen& g) {
  std::string s;
  for (std::size_t k = 0; k < g.spec.groups.size(); ++k) {
    if (g.ev.group(k).scheme == model::GroupScheme::kStacked) s += stacked_update(g, k);
  }
  return s;
}

}  // namespace kfw::codegen::detail
