#include "oracles/underwater/underwater_ekf.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "filter/kalman_filter.h"

namespace kfw::underwater {

namespace {

struct PendingRange {
  int beacon = 0;
  double z = 0.0;
  std::size_t row = 0;
};

const std::vector<double>* optional_col(const Dataset& d, const char* name) {
  return d.has(name) ? &d.col(name) : nullptr;
}

double at(const std::vector<double>* c, std::size_t k) {
  return c ? (*c)[k] : kNoSample;
}

// Gaps over 1.5 median periods of a sensor's sample times, as the expected times that were skipped.
std::vector<double> missing_times(const std::vector<double>& times) {
  std::vector<double> out;
  if (times.size() < 3) return out;
  std::vector<double> dt(times.size() - 1);
  for (std::size_t i = 1; i < times.size(); ++i)
    dt[i - 1] = times[i] - times[i - 1];
  auto mid = dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2);
  std::nth_element(dt.begin(), mid, dt.end());
  const double period = *mid;
  if (!(period > 0.0)) return out;
  for (std::size_t i = 1; i < times.size() && out.size() < 100000; ++i) {
    if (times[i] - times[i - 1] <= 1.5 * period) continue;
    for (double tm = times[i - 1] + period; tm < times[i] - 0.5 * period; tm += period) {
      out.push_back(tm);
    }
  }
  return out;
}

// (X̂ − X)ᵀ P⁻¹ (X̂ − X) over the covered coordinates; NaN when one of them has no truth or P is
// not positive definite there.
double position_nees(const Gaussian<3>& g, const Vec<3>& truth, const std::vector<int>& covered) {
  const auto m = static_cast<Eigen::Index>(covered.size());
  if (m == 0) return kNoSample;
  if (m == 3) {  // the usual case: eᵀ adj(P) e / det(P), P positive definite by its leading minors
    if (!truth.allFinite()) return kNoSample;
    const auto& P3 = g.P;
    const double c00 = P3(1, 1) * P3(2, 2) - P3(1, 2) * P3(2, 1);
    const double c01 = P3(1, 2) * P3(2, 0) - P3(1, 0) * P3(2, 2);
    const double c02 = P3(1, 0) * P3(2, 1) - P3(1, 1) * P3(2, 0);
    const double det = P3(0, 0) * c00 + P3(0, 1) * c01 + P3(0, 2) * c02;
    const double minor2 = P3(0, 0) * P3(1, 1) - P3(0, 1) * P3(1, 0);
    if (!(P3(0, 0) > 0.0 && minor2 > 0.0 && det > 0.0)) return kNoSample;
    const double c11 = P3(0, 0) * P3(2, 2) - P3(0, 2) * P3(2, 0);
    const double c12 = P3(0, 1) * P3(2, 0) - P3(0, 0) * P3(2, 1);
    const Vec<3> e3 = g.x - truth;
    // adj(P) is symmetric for symmetric P: the quadratic form needs c00, c11, minor2 and the
    // off-diagonal cofactors once each.
    const double q = c00 * e3(0) * e3(0) + c11 * e3(1) * e3(1) + minor2 * e3(2) * e3(2) +
                     2.0 * (c01 * e3(0) * e3(1) + c02 * e3(0) * e3(2) + c12 * e3(1) * e3(2));
    return q / det;
  }
  // At most 3 × 3: fixed-capacity storage, no heap allocation per step.
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> e(m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> P(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const int i = covered[static_cast<std::size_t>(a)];
    if (!std::isfinite(truth(i))) return kNoSample;
    e(a) = g.x(i) - truth(i);
    for (Eigen::Index b = 0; b < m; ++b)
      P(a, b) = g.P(i, covered[static_cast<std::size_t>(b)]);
  }
  const Eigen::LLT<decltype(P)> llt(P);
  if (llt.info() != Eigen::Success) return kNoSample;
  return e.dot(llt.solve(e));
}

}  // namespace

double predicted_range(const Vec<3>& X, const Vec<3>& B) {
  return (X - B).norm();
}

Jacobian<1, 3> range_jacobian(const Vec<3>& X, const Vec<3>& B) {
  const Vec<3> d = X - B;
  const double r = d.norm();
  return r > 0.0 ? Jacobian<1, 3>(d.transpose() / r) : Jacobian<1, 3>::Zero();
}

std::vector<InnovationChannel> UnderwaterResult::channels() const {
  std::vector<InnovationChannel> out;
  auto channel = [&](std::string name, const std::vector<double>& innov,
                     const std::vector<double>& var, const std::vector<double>& used) {
    InnovationChannel c;
    c.name = metric_identifier(name);
    c.label = std::move(name);
    c.nis.assign(t.size(), kNoSample);
    c.normalized.assign(t.size(), kNoSample);
    c.log_det_s.assign(t.size(), kNoSample);
    for (std::size_t k = 0; k < t.size() && k < innov.size() && k < var.size(); ++k) {
      if (k < used.size() && used[k] != kUsed) continue;  // gated or invalid: not an update
      if (std::isfinite(innov[k]) && var[k] > 0) {
        c.nis[k] = innov[k] * innov[k] / var[k];
        c.normalized[k] = innov[k] / std::sqrt(var[k]);
        c.log_det_s[k] = std::log(var[k]);
      }
    }
    out.push_back(std::move(c));
  };
  for (int b = 0; b < kBeacons; ++b) {
    channel("range " + std::to_string(b + 1), innovation[static_cast<std::size_t>(b)],
            S[static_cast<std::size_t>(b)], status[static_cast<std::size_t>(kRange1 + b)]);
  }
  channel("depth", depth_innovation, depth_S, status[kDepth]);
  return out;
}

std::vector<StateSeries> UnderwaterResult::states() const {
  auto truth = [&](const std::vector<double>& v) { return v.size() == t.size() ? &v : nullptr; };
  return {{"x", "x (north)", "m", &x, &Pxx, truth(x_true)},
          {"y", "y (east)", "m", &y, &Pyy, truth(y_true)},
          {"z", "z (down)", "m", &z, &Pzz, truth(z_true)}};
}

NeesSeries UnderwaterResult::nees_series() const {
  if (!(nees_dof > 0.0)) return {};
  return {nees_dof, nees};
}

Dataset UnderwaterResult::table() const {
  Dataset d;
  d.source = "underwater run";
  auto add = [&](const std::string& name, const std::vector<double>& v) {
    d.names.push_back(name);
    d.columns.push_back(v);
  };
  add("t", t);
  add("x", x);
  add("y", y);
  add("z", z);
  add("Pxx", Pxx);
  add("Pyy", Pyy);
  add("Pzz", Pzz);
  add("Pxy", Pxy);
  add("Pxz", Pxz);
  add("Pyz", Pyz);
  add("x_true", x_true);
  add("y_true", y_true);
  add("z_true", z_true);
  add("pos_err", pos_err);
  add("nees", nees);
  static const char* const kInnovation[kBeacons] = {"innovation1", "innovation2", "innovation3",
                                                    "innovation4"};
  static const char* const kS[kBeacons] = {"S1", "S2", "S3", "S4"};
  for (std::size_t i = 0; i < kBeacons; ++i) {
    add(kInnovation[i], innovation[i]);
    add(kS[i], S[i]);
  }
  add("depth_innovation", depth_innovation);
  add("depth_S", depth_S);
  static const char* const kStatus[kSensorCount] = {
      "status_dvl",    "status_ahrs",   "status_range1", "status_range2",
      "status_range3", "status_range4", "status_depth"};
  for (std::size_t s = 0; s < kSensorCount; ++s)
    add(kStatus[s], status[s]);
  return d;
}

Expected<UnderwaterResult> run_ekf(const Dataset& d, const FilterParams& p,
                                   const RunControl& control) {
  for (const char* c : {"t", "dvl_u", "dvl_v", "dvl_w", "ahrs_psi", "range1", "range2", "range3",
                        "range4", "depth"}) {
    if (!d.has(c)) return Error{d.source + ": missing column '" + std::string(c) + "'"};
  }
  const std::size_t n = d.rows();
  if (n < 2) return Error{d.source + ": need at least two rows"};
  const auto& t = d.col("t");
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(t[k]) || (k > 0 && !(t[k] > t[k - 1]))) {
      return Error{d.source + ": time column 't' is not finite and increasing at row " +
                   std::to_string(k + 1)};
    }
  }
  const std::vector<double>* dvl[3] = {&d.col("dvl_u"), &d.col("dvl_v"), &d.col("dvl_w")};
  const std::vector<double>* att[3] = {optional_col(d, "ahrs_phi"), optional_col(d, "ahrs_theta"),
                                       &d.col("ahrs_psi")};
  const std::vector<double>* yaw_rate = optional_col(d, "ahrs_r");
  const std::vector<double>* range[kBeacons] = {&d.col("range1"), &d.col("range2"),
                                                &d.col("range3"), &d.col("range4")};
  const std::vector<double>& depth = d.col("depth");
  const std::vector<double>* truth[3] = {optional_col(d, "x_true"), optional_col(d, "y_true"),
                                         optional_col(d, "z_true")};
  const std::vector<double>* outlier[kBeacons] = {
      optional_col(d, "outlier1"), optional_col(d, "outlier2"), optional_col(d, "outlier3"),
      optional_col(d, "outlier4")};

  UnderwaterResult r;
  r.t = t;
  for (auto* v : {&r.x, &r.y, &r.z, &r.Pxx, &r.Pyy, &r.Pzz, &r.Pxy, &r.Pxz, &r.Pyz, &r.pos_err,
                  &r.nees, &r.depth_innovation, &r.depth_S}) {
    v->assign(n, kNoSample);
  }
  r.x_true = truth[0] ? *truth[0] : std::vector<double>(n, kNoSample);
  r.y_true = truth[1] ? *truth[1] : std::vector<double>(n, kNoSample);
  r.z_true = truth[2] ? *truth[2] : std::vector<double>(n, kNoSample);
  r.x_cmd = d.has("x_cmd") ? d.col("x_cmd") : std::vector<double>(n, kNoSample);
  r.y_cmd = d.has("y_cmd") ? d.col("y_cmd") : std::vector<double>(n, kNoSample);
  for (int b = 0; b < kBeacons; ++b) {
    const auto i = static_cast<std::size_t>(b);
    r.innovation[i].assign(n, kNoSample);
    r.S[i].assign(n, kNoSample);
    r.injected[i] = outlier[b] ? *outlier[b] : std::vector<double>(n, kNoSample);
  }
  for (auto& s : r.status)
    s.assign(n, kNoSample);
  r.outliers_known = outlier[0] && outlier[1] && outlier[2] && outlier[3];
  // NEES covers the coordinates that have truth somewhere in the dataset.
  std::vector<int> covered;
  for (int i = 0; i < 3; ++i) {
    const std::vector<double>& c = i == kX ? r.x_true : i == kY ? r.y_true : r.z_true;
    if (std::any_of(c.begin(), c.end(), [](double v) { return std::isfinite(v); })) {
      covered.push_back(i);
    }
  }
  r.nees_dof = static_cast<double>(covered.size());

  // Initial state: the start point (0, 0) at the first depth reading.
  double z0 = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (std::isfinite(depth[k])) {
      z0 = depth[k];
      break;
    }
  }
  Gaussian<3> g;
  g.x << 0.0, 0.0, z0;
  g.P = Covariance<3>::Identity() * p.sigma0_pos_m * p.sigma0_pos_m;

  const double corr_var = p.corr_in_R ? p.sigma_corr_m * p.sigma_corr_m : 0.0;
  const double R_range_scalar = p.sigma_range_m * p.sigma_range_m + corr_var;
  const double R_depth = p.sigma_depth_m * p.sigma_depth_m;
  const double gate2 = p.gate * p.gate;
  const Mat<3> I3 = Mat<3>::Identity();
  const Jacobian<1, 3> H_depth(0.0, 0.0, 1.0);

  Vec<3> nu = Vec<3>::Zero();  // latest DVL body velocity
  Vec<3> attitude = Vec<3>::Zero();
  double t_attitude = t[0], r_yaw = 0.0;
  std::size_t bad_S = 0, bad_range = 0;
  std::vector<PendingRange> pending;
  pending.reserve(kBeacons);

  auto mark = [&](std::size_t row, int b, double status) {
    r.status[static_cast<std::size_t>(kRange1 + b)][row] = status;
    const double inj = r.injected[static_cast<std::size_t>(b)][row];
    const bool injected = std::isfinite(inj) && inj != 0.0;
    if (status == kUsed) ++r.ranges_used;
    if (status == kInvalid) ++r.ranges_invalid;
    if (status == kRejected) {
      ++r.ranges_rejected;
      if (r.outliers_known) ++(injected ? r.outliers_detected : r.outliers_false_alarm);
    }
  };

  // One gated scalar range update (AS, SI).
  auto scalar_range = [&](const PendingRange& m) {
    const Vec<3>& B = beacons()[static_cast<std::size_t>(m.beacon)];
    const Jacobian<1, 3> H = range_jacobian(g.x, B);
    // Linearised about the prediction: z − h(x⁻) + H x⁻ plays the measurement of a linear update.
    const double y = m.z - predicted_range(g.x, B);
    const double S = H.dot(g.P * H.transpose()) + R_range_scalar;
    r.innovation[static_cast<std::size_t>(m.beacon)][m.row] = y;
    r.S[static_cast<std::size_t>(m.beacon)][m.row] = S;
    if (!(S > 0.0) || !std::isfinite(S)) {
      ++bad_S;
      mark(m.row, m.beacon, kInvalid);
      return;
    }
    if (y * y > gate2 * S) {
      mark(m.row, m.beacon, kRejected);
      return;
    }
    const auto u = update_scalar(g, y + H.dot(g.x), H, R_range_scalar);
    if (!u.ok) {
      ++bad_S;
      mark(m.row, m.beacon, kInvalid);
      return;
    }
    g = u.post;
    mark(m.row, m.beacon, kUsed);
  };

  // SC: every range of the instant gated on its own S_ii, the accepted ones in one stacked update
  // with R = σ_r² I + σ_c² 1 1ᵀ.
  auto stacked_ranges = [&](const std::vector<PendingRange>& batch) {
    const auto m = static_cast<Eigen::Index>(batch.size());
    Eigen::Matrix<double, Eigen::Dynamic, 3> H(m, 3);
    VecX y(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      const auto& b = batch[static_cast<std::size_t>(i)];
      const Vec<3>& B = beacons()[static_cast<std::size_t>(b.beacon)];
      H.row(i) = range_jacobian(g.x, B);
      y(i) = b.z - predicted_range(g.x, B);
    }
    MatX R = MatX::Constant(m, m, corr_var);
    R.diagonal().array() += p.sigma_range_m * p.sigma_range_m;
    const MatX S = H * g.P * H.transpose() + R;
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = 0; i < m; ++i) {
      const auto& b = batch[static_cast<std::size_t>(i)];
      r.innovation[static_cast<std::size_t>(b.beacon)][b.row] = y(i);
      r.S[static_cast<std::size_t>(b.beacon)][b.row] = S(i, i);
      if (!(S(i, i) > 0.0) || !std::isfinite(S(i, i))) {
        ++bad_S;
        mark(b.row, b.beacon, kInvalid);
      } else if (y(i) * y(i) > gate2 * S(i, i)) {
        mark(b.row, b.beacon, kRejected);
      } else {
        keep.push_back(i);
      }
    }
    if (keep.empty()) return;
    const auto mk = static_cast<Eigen::Index>(keep.size());
    Eigen::Matrix<double, Eigen::Dynamic, 3> Hk(mk, 3);
    VecX zk(mk);
    MatX Rk(mk, mk);
    for (Eigen::Index a = 0; a < mk; ++a) {
      Hk.row(a) = H.row(keep[static_cast<std::size_t>(a)]);
      zk(a) = y(keep[static_cast<std::size_t>(a)]) + Hk.row(a).dot(g.x);
      for (Eigen::Index b = 0; b < mk; ++b) {
        Rk(a, b) = R(keep[static_cast<std::size_t>(a)], keep[static_cast<std::size_t>(b)]);
      }
    }
    const auto u = update<3, Eigen::Dynamic>(g, zk, Hk, Rk);
    for (Eigen::Index a = 0; a < mk; ++a) {
      const auto& b = batch[static_cast<std::size_t>(keep[static_cast<std::size_t>(a)])];
      if (!u.ok) ++bad_S;
      mark(b.row, b.beacon, u.ok ? kUsed : kInvalid);
    }
    if (u.ok) g = u.post;
  };

  auto flush = [&]() {
    if (pending.empty()) return;
    if (p.scheme == Scheme::kSC) {
      stacked_ranges(pending);
    } else {
      for (const auto& m : pending)
        scalar_range(m);
    }
    pending.clear();
  };

  std::array<std::vector<double>, kSensorCount> sample_t;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) {
      // Dead reckoning (seed 004, Table 12, line 1): X⁻ = X + R(φ, θ, ψ_mid) ν Δt, P⁻ = P + q² Δt
      // I, ψ_mid extrapolated from the last AHRS heading with its yaw rate.
      const double dt = t[k] - t[k - 1];
      const double t_mid = 0.5 * (t[k] + t[k - 1]);
      const double psi_mid = attitude(2) + r_yaw * (t_mid - t_attitude);
      g.x.noalias() += dt * (rotation(attitude(0), attitude(1), psi_mid) * nu);
      g.P.noalias() += (p.q_pos * p.q_pos * dt) * I3;
    }
    // New inputs take effect from this row on (zero-order hold).
    if (std::isfinite((*dvl[0])[k])) {
      for (int i = 0; i < 3; ++i) {
        const double v = (*dvl[i])[k];
        nu(i) = std::isfinite(v) ? v : 0.0;
      }
      r.status[kDvl][k] = kUsed;
      sample_t[kDvl].push_back(t[k]);
    }
    if (std::isfinite((*att[2])[k])) {
      for (int i = 0; i < 3; ++i) {
        const double a = at(att[i], k);
        attitude(i) = std::isfinite(a) ? a : 0.0;
      }
      const double ry = at(yaw_rate, k);
      r_yaw = std::isfinite(ry) ? ry : 0.0;
      t_attitude = t[k];
      r.status[kAhrs][k] = kUsed;
      sample_t[kAhrs].push_back(t[k]);
    }
    // Depth: a linear scalar update, H = [0 0 1].
    if (std::isfinite(depth[k])) {
      sample_t[kDepth].push_back(t[k]);
      const auto u = update_scalar(g, depth[k], H_depth, R_depth);
      r.depth_innovation[k] = u.innovation(0);
      r.depth_S[k] = u.S(0, 0);
      if (u.ok) {
        g = u.post;
        ++r.depth_used;
        r.status[kDepth][k] = kUsed;
      } else {
        ++bad_S;
        r.status[kDepth][k] = kInvalid;
      }
    }
    // Ranges.
    for (int b = 0; b < kBeacons; ++b) {
      const double z = (*range[b])[k];
      if (std::isnan(z)) continue;
      sample_t[static_cast<std::size_t>(kRange1 + b)].push_back(t[k]);
      if (!(z > 0.0) || !std::isfinite(z)) {
        ++bad_range;
        mark(k, b, kInvalid);
        continue;
      }
      const PendingRange m{b, z, k};
      if (p.scheme == Scheme::kAS) {
        scalar_range(m);
        continue;
      }
      // SC/SI: a beacon seen twice closes the instant (another beacon dropped out).
      const bool repeat = std::any_of(pending.begin(), pending.end(),
                                      [&](const PendingRange& q) { return q.beacon == b; });
      if (repeat) flush();
      pending.push_back(m);
      if (static_cast<int>(pending.size()) == kBeacons) flush();
    }
    r.x[k] = g.x(kX);
    r.y[k] = g.x(kY);
    r.z[k] = g.x(kZ);
    r.Pxx[k] = g.P(kX, kX);
    r.Pyy[k] = g.P(kY, kY);
    r.Pzz[k] = g.P(kZ, kZ);
    r.Pxy[k] = g.P(kX, kY);
    r.Pxz[k] = g.P(kX, kZ);
    r.Pyz[k] = g.P(kY, kZ);
    const Vec<3> xt(r.x_true[k], r.y_true[k], r.z_true[k]);
    if (xt.allFinite()) r.pos_err[k] = (g.x - xt).norm();
    r.nees[k] = position_nees(g, xt, covered);
    if ((k & 0x3FFF) == 0x3FFF && control.cancelled()) break;
  }
  flush();

  for (int s = 0; s < kSensorCount; ++s) {
    r.missing_t[static_cast<std::size_t>(s)] = missing_times(sample_t[static_cast<std::size_t>(s)]);
  }
  for (int b = 0; b < kBeacons; ++b) {
    for (double v : r.injected[static_cast<std::size_t>(b)]) {
      if (std::isfinite(v) && v != 0.0) ++r.outliers_injected;
    }
  }
  if (bad_S) {
    r.warnings.push_back(std::to_string(bad_S) +
                         " updates skipped: S not positive definite or not finite");
  }
  if (bad_range) {
    r.warnings.push_back(std::to_string(bad_range) +
                         " range samples ≤ 0 or infinite were rejected");
  }
  return r;
}

}  // namespace kfw::underwater
