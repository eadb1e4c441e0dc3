#include "model/model_steady.h"

namespace kfw::model {

// By squaring (log₂ m products: `every` may be up to limits::kMaxEvery). Steps a then b compose
// as F_b F_a, F_b Q_a F_bᵀ + Q_b.
void m_step(const MatX& F, const MatX& Q, int m, MatX& Fm, MatX& Qm) {
  const Eigen::Index n = F.rows();
  Fm = MatX::Identity(n, n);
  Qm = MatX::Zero(n, n);
  MatX Fp = F, Qp = Q;  // the 2^k-step model
  for (unsigned bits = static_cast<unsigned>(m); bits; bits >>= 1) {
    if (bits & 1u) {
      Qm = (Fp * Qm * Fp.transpose()).eval() + Qp;
      Fm = (Fp * Fm).eval();
    }
    if (bits > 1) {
      Qp = (Fp * Qp * Fp.transpose()).eval() + Qp;
      Fp = (Fp * Fp).eval();
    }
  }
}

Expected<ModelSteadyState> model_steady_state(const ModelSpec& s, const ModelEval& ev) {
  if (!s.time_invariant()) {
    return Error{s.path + ": no steady-state gain: the model is not linear time-invariant (F, B, " +
                 "Q, H and R must depend on parameters and dt only)"};
  }
  ModelSteadyState out;
  // All channels at one rate m: the m-step model F^m, Σ_{i<m} F^i Q F^iᵀ between updates.
  out.every = ev.channel(0).every;
  int rows = 0;
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    if (ev.channel(c).every != out.every) {
      return Error{s.path + ": no single steady state: the channels update at different rates"};
    }
    rows += s.channels[c].size();
  }
  const Eigen::Index n = s.n();
  MatX H(rows, n), R = MatX::Zero(rows, rows);
  Eigen::Index r0 = 0;
  for (std::size_t c = 0; c < s.channels.size(); ++c) {
    const auto& ch = ev.channel(c);
    H.middleRows(r0, ch.H.rows()) = ch.H;
    R.block(r0, r0, ch.R.rows(), ch.R.cols()) = ch.R;
    r0 += ch.H.rows();
    for (const auto& comp : s.channels[c].comps)
      out.roles.push_back(comp.name);
  }
  MatX Fm, Qm;
  m_step(ev.F, ev.Q, out.every, Fm, Qm);
  auto ss = solve_dare(Fm, H, Qm, R);
  if (!ss) return Error{s.path + ": " + ss.error()};
  out.dare = std::move(*ss);
  return out;
}

}  // namespace kfw::model
