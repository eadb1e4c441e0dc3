#include "oracles/underwater/underwater_stats.h"

#include <cmath>
#include <vector>

#include "oracles/underwater/underwater_sim.h"

namespace kfw::underwater {

Covariance<kErrorDims> design_covariance(double sigma_range_m, double sigma_corr_m,
                                         double sigma_depth_m) {
  Covariance<kErrorDims> C = Covariance<kErrorDims>::Zero();
  C.topLeftCorner<kBeacons, kBeacons>().setConstant(sigma_corr_m * sigma_corr_m);
  C.topLeftCorner<kBeacons, kBeacons>().diagonal().array() += sigma_range_m * sigma_range_m;
  C(kBeacons, kBeacons) = sigma_depth_m * sigma_depth_m;
  return C;
}

Expected<ErrorStats> error_stats(const Dataset& d) {
  for (const char* c :
       {"t", "range1", "range2", "range3", "range4", "depth", "x_true", "y_true", "z_true"}) {
    if (!d.has(c)) return Error{d.source + ": statistics need column '" + std::string(c) + "'"};
  }
  const std::vector<double>* z[kErrorDims] = {&d.col("range1"), &d.col("range2"), &d.col("range3"),
                                              &d.col("range4"), &d.col("depth")};
  const std::vector<double>* off[kBeacons] = {nullptr, nullptr, nullptr, nullptr};
  for (int b = 0; b < kBeacons; ++b) {
    const std::string name = "outlier" + std::to_string(b + 1);
    if (d.has(name)) off[b] = &d.col(name);
  }
  const auto& xt = d.col("x_true");
  const auto& yt = d.col("y_true");
  const auto& zt = d.col("z_true");

  ErrorStats st;
  std::vector<Vec<kErrorDims>> rows;
  rows.reserve(d.rows());
  Vec<kErrorDims> latest = Vec<kErrorDims>::Zero();
  std::array<bool, kErrorDims> fresh{};
  std::array<bool, kErrorDims> is_outlier{};
  for (std::size_t k = 0; k < d.rows(); ++k) {
    const Vec<3> p(xt[k], yt[k], zt[k]);
    for (int b = 0; b < kBeacons; ++b) {
      if (off[b] && std::isfinite((*off[b])[k]) && (*off[b])[k] != 0.0) ++st.outliers_injected;
    }
    if (!p.allFinite()) continue;
    for (int i = 0; i < kErrorDims; ++i) {
      const double zi = (*z[i])[k];
      if (!std::isfinite(zi)) continue;
      const auto ui = static_cast<std::size_t>(i);
      latest(i) = i < kBeacons ? zi - (beacons()[ui] - p).norm() : zi - p(2);
      fresh[ui] = true;
      is_outlier[ui] = i < kBeacons && off[i] && std::isfinite((*off[i])[k]) && (*off[i])[k] != 0.0;
    }
    bool all = true;
    for (bool f : fresh)
      all = all && f;
    if (!all) continue;
    bool any_outlier = false;
    for (bool o : is_outlier)
      any_outlier = any_outlier || o;
    if (any_outlier) {
      ++st.outlier_instants;
    } else {
      rows.push_back(latest);
    }
    fresh.fill(false);
  }
  st.instants = rows.size();
  if (rows.size() < 2) {
    return Error{d.source + ": " + std::to_string(rows.size()) +
                 " synchronous instants (every range and depth sampled): need at least 2"};
  }
  for (const auto& r : rows)
    st.mean += r;
  st.mean /= static_cast<double>(rows.size());
  for (const auto& r : rows) {
    const Vec<kErrorDims> e = r - st.mean;
    st.covariance.noalias() += e * e.transpose();
  }
  st.covariance /= static_cast<double>(rows.size() - 1);
  return st;
}

}  // namespace kfw::underwater
