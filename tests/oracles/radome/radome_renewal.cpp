#include "oracles/radome/radome_renewal.h"

#include <algorithm>
#include <cstddef>

namespace kfw::radome {

namespace {

// W(i, i'): the share of old point i (at off[i]) that goes to new point i' (at off[i'] + d).
MatX share_matrix(const std::vector<double>& off, double d) {
  const auto n = static_cast<Eigen::Index>(off.size());
  MatX W = MatX::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = off[static_cast<std::size_t>(i)] - d;  // old slope in new-grid offsets
    if (n == 1 || x <= off.front()) {
      W(i, 0) = 1.0;
      continue;
    }
    if (x >= off.back()) {
      W(i, n - 1) = 1.0;
      continue;
    }
    const auto hi =
        static_cast<Eigen::Index>(std::upper_bound(off.begin(), off.end(), x) - off.begin());
    const Eigen::Index lo = hi - 1;
    const double span = off[static_cast<std::size_t>(hi)] - off[static_cast<std::size_t>(lo)];
    const double f = span > 0.0 ? (x - off[static_cast<std::size_t>(lo)]) / span : 0.0;
    W(i, lo) += 1.0 - f;
    W(i, hi) += f;
  }
  return W;
}

}  // namespace

MatX shift_transition(const std::vector<double>& off_psi, const std::vector<double>& off_theta,
                      double d_psi, double d_theta) {
  const MatX Wp = share_matrix(off_psi, d_psi), Wt = share_matrix(off_theta, d_theta);
  const Eigen::Index np = Wp.rows(), nt = Wt.rows();
  MatX T(np * nt, np * nt);
  for (Eigen::Index b = 0; b < nt; ++b)
    for (Eigen::Index b2 = 0; b2 < nt; ++b2)
      T.block(b * np, b2 * np, np, np) = Wt(b, b2) * Wp;
  return T;
}

VecX remap_probabilities(const VecX& mu, const std::vector<double>& off_psi,
                         const std::vector<double>& off_theta, double d_psi, double d_theta) {
  const auto np = static_cast<Eigen::Index>(off_psi.size());
  const auto nt = static_cast<Eigen::Index>(off_theta.size());
  const MatX Wp = share_matrix(off_psi, d_psi), Wt = share_matrix(off_theta, d_theta);
  // μ as an n_ψ × n_θ matrix M(a, b); the moved M' = Wpᵀ M Wt (separable shares).
  const Eigen::Map<const MatX> M(mu.data(), np, nt);
  const MatX moved = Wp.transpose() * M * Wt;
  return Eigen::Map<const VecX>(moved.data(), np * nt);
}

}  // namespace kfw::radome
