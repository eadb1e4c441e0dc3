// RadomeResult: what a run of the radome IMM keeps (per-step mode probabilities, grids, the
// combined estimate) and the views of it the workbench reads (channels, states, table, NEES).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "oracles/radome/radome_imm.h"

namespace kfw::radome {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

std::vector<double> RadomeResult::mode_probabilities(std::size_t k) const {
  const auto r = static_cast<std::size_t>(modes());
  if (k >= steps() || mu.size() < (k + 1) * r) return {};
  return std::vector<double>(mu.begin() + static_cast<std::ptrdiff_t>(k * r),
                             mu.begin() + static_cast<std::ptrdiff_t>((k + 1) * r));
}

std::vector<double> RadomeResult::grid_psi(std::size_t k) const {
  std::vector<double> g;
  if (k >= center_psi.size()) return g;
  for (double o : offsets_psi)
    g.push_back(center_psi[k] + o);
  return g;
}

std::vector<double> RadomeResult::grid_theta(std::size_t k) const {
  std::vector<double> g;
  if (k >= center_theta.size()) return g;
  for (double o : offsets_theta)
    g.push_back(center_theta[k] + o);
  return g;
}

std::vector<int> RadomeResult::top_modes(int count) const {
  const auto r = static_cast<std::size_t>(modes());
  std::vector<double> mean(r, 0.0);
  const std::size_t n = r ? mu.size() / r : 0;
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t j = 0; j < r; ++j)
      mean[j] += mu[k * r + j];
  }
  std::vector<int> idx(r);
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) {
    return mean[static_cast<std::size_t>(a)] > mean[static_cast<std::size_t>(b)];
  });
  idx.resize(std::min(r, static_cast<std::size_t>(std::max(count, 0))));
  return idx;
}

std::vector<InnovationChannel> RadomeResult::channels() const {
  std::vector<InnovationChannel> out;
  out.push_back({"position", "position (3-D)", 3.0, nis, {}, {}});
  const char* names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    InnovationChannel c;
    c.name = names[a];
    c.label = std::string(names[a]) + " axis";
    c.nis.assign(t.size(), kNoSample);
    c.normalized.assign(t.size(), kNoSample);
    for (std::size_t k = 0; k < t.size() && k < innovation[a].size(); ++k) {
      const double y = innovation[a][k], S_k = S[a][k];
      if (std::isfinite(y) && S_k > 0) {
        c.nis[k] = y * y / S_k;
        c.normalized[k] = y / std::sqrt(S_k);
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<StateSeries> RadomeResult::states() const {
  const bool truth = x_true.size() == t.size();
  return {{"x", "x (target position)", "m", &x_est, nullptr, truth ? &x_true : nullptr},
          {"y", "y (target position)", "m", &y_est, nullptr, truth ? &y_true : nullptr},
          {"z", "z (target position)", "m", &z_est, nullptr, truth ? &z_true : nullptr}};
}

Dataset RadomeResult::table() const {
  Dataset d;
  d.source = "radome run";
  d.names = {"t",
             "slope_psi",
             "slope_theta",
             "slope_psi_true",
             "slope_theta_true",
             "grid_center_psi",
             "grid_center_theta",
             "alpha_true_deg",
             "alpha_meas_deg",
             "alpha_est_deg",
             "psi_los_true_deg",
             "theta_los_true_deg",
             "psi_meas_deg",
             "theta_meas_deg",
             "psi_los_est_deg",
             "theta_los_est_deg",
             "x_est",
             "y_est",
             "z_est",
             "innovation_x",
             "innovation_y",
             "innovation_z",
             "S_x",
             "S_y",
             "S_z",
             "nis",
             "map_mode"};
  d.columns = {t,
               slope_psi,
               slope_theta,
               slope_psi_true,
               slope_theta_true,
               center_psi,
               center_theta,
               alpha_true_deg,
               alpha_meas_deg,
               alpha_est_deg,
               psi_los_true_deg,
               theta_los_true_deg,
               psi_meas_deg,
               theta_meas_deg,
               psi_los_est_deg,
               theta_los_est_deg,
               x_est,
               y_est,
               z_est,
               innovation[0],
               innovation[1],
               innovation[2],
               S[0],
               S[1],
               S[2],
               nis,
               map_mode};
  // The combined position variances and the NEES (appended: earlier columns keep their place).
  const char* var_names[3] = {"var_x", "var_y", "var_z"};
  for (int ax = 0; ax < 3; ++ax) {
    std::vector<double> v(t.size(), kNaN);
    for (std::size_t k = 0; k < v.size() && k < P_pos.size(); ++k)
      v[k] = P_pos[k](ax, ax);
    d.names.push_back(var_names[ax]);
    d.columns.push_back(std::move(v));
  }
  d.names.push_back("nees");
  d.columns.push_back(nees.size() == t.size() ? nees : std::vector<double>(t.size(), kNaN));
  return d;
}

void RadomeResult::compute_nees() {
  const std::size_t n = t.size();
  nees.assign(n, kNaN);
  nees_dof = 3.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k >= P_pos.size() || k >= x_true.size() || k >= y_true.size() || k >= z_true.size()) break;
    const Vec<3> e(x_est[k] - x_true[k], y_est[k] - y_true[k], z_est[k] - z_true[k]);
    if (!e.allFinite() || !P_pos[k].allFinite()) continue;
    const Eigen::LLT<Covariance<3>> llt(P_pos[k]);
    if (llt.info() != Eigen::Success) continue;  // not positive definite: unknown
    nees[k] = e.dot(llt.solve(e));
  }
}

}  // namespace kfw::radome
