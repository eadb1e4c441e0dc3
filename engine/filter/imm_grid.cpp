#include "filter/imm_grid.h"

#include <algorithm>
#include <cstddef>

namespace kfw {

MatX grid_share_matrix(const std::vector<double>& off, double d) {
  const auto n = static_cast<Eigen::Index>(off.size());
  MatX W = MatX::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = off[static_cast<std::size_t>(i)] - d;  // the old value in moved offsets
    if (n == 1 || x <= off.front()) {
      W(i, 0) = 1.0;
    } else if (x >= off.back()) {
      W(i, n - 1) = 1.0;
    } else {
      const auto hi =
          static_cast<Eigen::Index>(std::upper_bound(off.begin(), off.end(), x) - off.begin());
      const double lo_v = off[static_cast<std::size_t>(hi - 1)];
      const double span = off[static_cast<std::size_t>(hi)] - lo_v;
      const double f = span > 0.0 ? (x - lo_v) / span : 0.0;
      W(i, hi - 1) += 1.0 - f;
      W(i, hi) += f;
    }
  }
  return W;
}

VecX grid_remap(const VecX& mu, const std::vector<std::vector<double>>& off,
                const std::vector<double>& d) {
  VecX out = mu;
  Eigen::Index stride = 1;
  for (std::size_t a = 0; a < off.size(); ++a) {
    const auto n = static_cast<Eigen::Index>(off[a].size());
    if (d[a] != 0.0) {
      const MatX W = grid_share_matrix(off[a], d[a]);
      VecX next = VecX::Zero(out.size());
      // Each line along axis a: the modes base + i·stride, i = 0 … n − 1.
      for (Eigen::Index j = 0; j < out.size(); ++j) {
        const Eigen::Index i = (j / stride) % n;
        const Eigen::Index base = j - i * stride;
        for (Eigen::Index i2 = 0; i2 < n; ++i2)
          next(base + i2 * stride) += W(i, i2) * out(j);
      }
      out = next;
    }
    stride *= n;
  }
  return out;
}

MatX grid_shift_transition(const std::vector<std::vector<double>>& off,
                           const std::vector<double>& d) {
  std::vector<MatX> W;
  Eigen::Index r = 1;
  for (std::size_t a = 0; a < off.size(); ++a) {
    W.push_back(grid_share_matrix(off[a], d[a]));
    r *= static_cast<Eigen::Index>(off[a].size());
  }
  MatX T = MatX::Ones(r, r);
  for (Eigen::Index i = 0; i < r; ++i) {
    for (Eigen::Index i2 = 0; i2 < r; ++i2) {
      Eigen::Index a_i = i, a_i2 = i2;
      for (const MatX& w : W) {
        const Eigen::Index n = w.rows();
        T(i, i2) *= w(a_i % n, a_i2 % n);
        a_i /= n;
        a_i2 /= n;
      }
    }
  }
  return T;
}

}  // namespace kfw
