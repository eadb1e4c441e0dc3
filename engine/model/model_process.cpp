// The process block of a model file: linear (F, B, Q), continuous (A, B, G, Qc), nonlinear (f, Q)
// and continuous nonlinear (xdot, G, Qc, substep; version 2). Jacobians by GiNaC.
#include "model/model_reader.h"

namespace kfw::model::detail {

namespace {

// G (n × q, default I) and Qc (q × q): the continuous forms' noise, parameters only.
Status parse_continuous_noise(const Reader& p, const json& j, ModelSpec& m) {
  const std::string key = "model.process";
  const int n = m.n();
  ProcessSpec& pr = m.process;
  if (j.contains("Q")) return p.error(key + ".Q", "the continuous forms take Qc, not Q");
  int q = n;
  if (j.contains("G")) {
    const json& g = j["G"];
    q = g.is_array() && !g.empty() && g[0].is_array() ? static_cast<int>(g[0].size()) : 1;
    auto G = p.matrix(g, key + ".G", n, q, kParamsOnly, kParamsOnlyWhat);
    if (!G) return G.err();
    pr.G = *G;
  }
  if (!j.contains("Qc")) return p.error(key, "missing key 'Qc'");
  auto Qc = p.matrix(j["Qc"], key + ".Qc", q, q, kParamsOnly, kParamsOnlyWhat, true);
  if (!Qc) return Qc.err();
  pr.Qc = *Qc;
  return p.symmetric(pr.Qc);
}

// ẋ = f(x, u, t) + G w (version 2): f, its Jacobian A(x) by GiNaC, G, Qc and the RK4 sub-step.
Status parse_xdot(const Reader& p, const json& j, ModelSpec& m) {
  const std::string key = "model.process";
  const int n = m.n();
  ProcessSpec& pr = m.process;
  pr.form = ProcessForm::kContinuousNonlinear;
  const json& f = j["xdot"];
  if (!f.is_array() || f.size() != static_cast<std::size_t>(n)) {
    return p.error(key + ".xdot", "wrong dimensions: expected a list of " + std::to_string(n) +
                                      " expressions, one per state");
  }
  pr.A.key = key + ".xdot (Jacobian)";
  pr.A.rows = pr.A.cols = n;
  for (std::size_t i = 0; i < f.size(); ++i) {
    auto e = p.expr(f[i], idx(key + ".xdot", i), kAllSymbols & ~KindMask{kDtSymbol},
                    "parameters, t, states and inputs: a derivative does not depend on dt");
    if (!e) return e.err();
    pr.f.push_back(*e);
    auto d = derivatives(*e, idx(key + ".xdot", i), m.symbols, m.state_slots);
    if (!d) return d.err();
    pr.A.e.insert(pr.A.e.end(), d->begin(), d->end());
  }
  // Affine in states and inputs, coefficients of parameters only, no t (issue 30: a linear plant
  // with limits, seed 003's beam): ẋ = A x + Bu u + c.
  pr.affine = pr.A.dep() <= Dep::kParam;
  pr.Bu.key = key + ".xdot (input Jacobian)";
  pr.Bu.rows = n;
  pr.Bu.cols = static_cast<int>(m.inputs.size());
  for (std::size_t i = 0; i < pr.f.size() && pr.affine; ++i) {
    pr.affine = (pr.f[i].uses & kTimeSymbol) == 0;
    auto d = derivatives(pr.f[i], idx(key + ".xdot", i), m.symbols, m.input_slots);
    if (!d) return d.err();
    pr.Bu.e.insert(pr.Bu.e.end(), d->begin(), d->end());
  }
  pr.affine = pr.affine && pr.Bu.dep() <= Dep::kParam;
  pr.substep = Expr{"0", Dep::kConst, 0.0};
  if (j.contains("substep")) {
    auto h = p.expr(j["substep"], key + ".substep", kParamsOnly, kParamsOnlyWhat);
    if (!h) return h.err();
    pr.substep = *h;
  }
  return parse_continuous_noise(p, j, m);
}

}  // namespace

Status parse_process(const Reader& p, const json& j, ModelSpec& m) {
  const std::string key = "model.process";
  if (!j.is_object()) return p.error(key, "expected an object");
  if (auto st = p.only_keys(j, key, {"F", "B", "Q", "f", "A", "G", "Qc", "xdot", "substep"}); !st) {
    return st;
  }
  const int n = m.n(), nu = static_cast<int>(m.inputs.size());
  const bool has_f = j.contains("f"), has_F = j.contains("F"), has_A = j.contains("A");
  const bool has_xdot = j.contains("xdot");
  if (has_f + has_F + has_A + has_xdot != 1) {
    return p.error(key,
                   "declare exactly one of F (linear), A (continuous), f (nonlinear) or xdot "
                   "(continuous nonlinear)");
  }
  if (j.contains("substep") && !has_xdot) {
    return p.error(key + ".substep", "belongs to the continuous nonlinear form (with xdot)");
  }
  ProcessSpec& pr = m.process;
  auto need = [&](const char* name) -> Expected<const json*> {
    if (!j.contains(name)) return p.error(key, std::string("missing key '") + name + "'");
    return &j.at(name);
  };
  if (j.contains("B")) {
    if (nu == 0) return p.error(key + ".B", "the model declares no inputs");
    if (has_f) return p.error(key + ".B", "a nonlinear model uses the inputs in f");
    if (has_xdot)
      return p.error(key + ".B", "a continuous nonlinear model uses the inputs in xdot");
  }
  if (has_xdot) return parse_xdot(p, j, m);
  if (has_A) {
    pr.form = ProcessForm::kContinuous;
    if (j.contains("Q")) return p.error(key + ".Q", "the continuous forms take Qc, not Q");
    auto A = p.matrix(j["A"], key + ".A", n, n, kParamsOnly, kParamsOnlyWhat);
    if (!A) return A.err();
    pr.A = *A;
    if (j.contains("B")) {
      auto B = p.matrix(j["B"], key + ".B", n, nu, kParamsOnly, kParamsOnlyWhat);
      if (!B) return B.err();
      pr.Bc = *B;
    }
    return parse_continuous_noise(p, j, m);
  }
  if (j.contains("G") || j.contains("Qc")) {
    return p.error(key, "G and Qc belong to the continuous forms (with A or xdot)");
  }
  auto q = need("Q");
  if (!q) return q.err();
  auto Q = p.matrix(**q, key + ".Q", n, n, kAllSymbols, "", true);
  if (!Q) return Q.err();
  pr.Q = *Q;
  if (auto st = p.symmetric(pr.Q); !st) return st;
  if (has_F) {
    pr.form = ProcessForm::kLinear;
    auto F = p.matrix(j["F"], key + ".F", n, n, kLinear, kLinearWhat);
    if (!F) return F.err();
    pr.F = *F;
    if (j.contains("B")) {
      auto B = p.matrix(j["B"], key + ".B", n, nu, kLinear, kLinearWhat);
      if (!B) return B.err();
      pr.B = *B;
    }
    return Ok{};
  }
  pr.form = ProcessForm::kNonlinear;
  const json& f = j["f"];
  if (!f.is_array() || f.size() != static_cast<std::size_t>(n)) {
    return p.error(key + ".f", "wrong dimensions: expected a list of " + std::to_string(n) +
                                   " expressions, one per state");
  }
  pr.F.key = key + ".f (Jacobian)";
  pr.F.rows = pr.F.cols = n;
  for (std::size_t i = 0; i < f.size(); ++i) {
    auto e = p.expr(f[i], idx(key + ".f", i), kAllSymbols, "");
    if (!e) return e.err();
    pr.f.push_back(*e);
    auto d = derivatives(*e, idx(key + ".f", i), m.symbols, m.state_slots);
    if (!d) return d.err();
    pr.F.e.insert(pr.F.e.end(), d->begin(), d->end());
  }
  return Ok{};
}

}  // namespace kfw::model::detail
