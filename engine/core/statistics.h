// Small statistics used by runners and metrics: NaN-aware summaries and χ² quantiles.
#pragma once

#include <cstddef>
#include <vector>

namespace kfw {

// Mean of the finite entries; NaN when there are none.
double mean_finite(const std::vector<double>& v, std::size_t from = 0);
// sqrt(mean((a - b)^2)) over indices >= from where both are finite; NaN when none.
double rmse_finite(const std::vector<double>& a, const std::vector<double>& b,
                   std::size_t from = 0);
// Last finite entry; NaN when there is none.
double last_finite(const std::vector<double>& v);
// Number of finite entries.
std::size_t count_finite(const std::vector<double>& v);

// Regularised lower incomplete gamma P(a, x).
double gamma_p(double a, double x);
// χ² cumulative distribution with k degrees of freedom.
double chi2_cdf(double x, double k);
// Inverse of chi2_cdf: the p-quantile of χ²(k).
double chi2_quantile(double p, double k);

// Fraction of finite NIS values inside the two-sided (1 - alpha) χ²(dof) bounds.
double fraction_inside(const std::vector<double>& nis, double dof, double alpha = 0.05);

}  // namespace kfw
