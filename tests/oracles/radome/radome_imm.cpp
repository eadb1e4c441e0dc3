#include "oracles/radome/radome_imm.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <string>

#include "filter/covariance_check.h"
#include "oracles/radome/radome_renewal.h"

#include "filter/kalman_filter.h"

namespace kfw::radome {

namespace {
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
const double kLog2Pi = std::log(2.0 * std::numbers::pi);
std::string format_number(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}
}  // namespace

Status check(const FilterParams& p) {
  if (p.grid_min > p.grid_max) {
    return Error{"grid.min (" + std::to_string(p.grid_min) + ") must not exceed grid.max (" +
                 std::to_string(p.grid_max) + ")"};
  }
  if (p.grid_min <= -1.0 || p.grid_max <= -1.0) {
    return Error{"grid.min / grid.max must be > -1 (a slope of -1 cannot be undone)"};
  }
  if (p.n_psi < 1) return Error{"grid.n_psi must be at least 1"};
  if (p.n_theta < 1) return Error{"grid.n_theta must be at least 1"};
  if (!(p.stay > 0.0 && p.stay <= 1.0)) return Error{"markov.stay must be in (0, 1]"};
  if (!(p.Q > 0.0)) return Error{"Q must be positive"};
  if (!(p.var_angle > 0.0)) return Error{"R must be positive"};
  if (!(p.var_range > 0.0)) return Error{"R_range must be positive"};
  if (!(p.tau_s > 0.0)) return Error{"tau must be positive"};
  if (!(p.P0_pos_m2 > 0.0)) return Error{"P0_pos must be positive"};
  if (!(p.P0_vel_m2ps2 > 0.0)) return Error{"P0_vel must be positive"};
  if (!(p.P0_acc_m2ps4 > 0.0)) return Error{"P0_acc must be positive"};
  if (!(p.Kp >= 0.0 && p.Kp <= 1.0)) return Error{"Kp must be in [0, 1]"};
  return Ok{};
}

bool Sample::has_measurement() const {
  return std::isfinite(range_m) && std::isfinite(psi_rad) && std::isfinite(theta_rad) &&
         std::isfinite(psi_a_rad) && std::isfinite(theta_a_rad);
}

Expected<RadomeImm> RadomeImm::create(const FilterParams& p, double T_s) {
  if (auto st = check(p); !st) return st.err();
  RadomeImm f;
  f.p_ = p;
  f.T_s_ = T_s;
  f.n_psi_ = p.n_psi;
  f.n_theta_ = p.n_theta;
  const double c = 0.5 * (p.grid_min + p.grid_max);
  f.center_psi_ = f.center_theta_ = f.est_psi_ = f.est_theta_ = c;
  for (double g : grid_axis(p.grid_min, p.grid_max, p.n_psi))
    f.off_psi_.push_back(g - c);
  for (double g : grid_axis(p.grid_min, p.grid_max, p.n_theta))
    f.off_theta_.push_back(g - c);
  auto chain = MarkovChain::uniform(f.modes(), p.stay);
  if (!chain) return chain.err();
  f.chain_ = *chain;
  f.chain_matrix_ = chain->matrix();
  auto m = axis_model(p.tau_s, p.Q, T_s);
  if (!m) return m.err();
  f.axis_ = *m;
  f.model_dt_s_ = T_s;
  f.F9_ = full_F(f.axis_);
  f.Gamma9_ = full_Gamma(f.axis_);
  f.Q9_ = full_Q(f.axis_);
  const int r = f.modes();
  f.log_mu_ = VecX::Constant(r, -std::log(static_cast<double>(r)));
  f.log_lik_ = VecX::Zero(r);
  f.cpsi_.resize(static_cast<std::size_t>(p.n_psi));
  f.spsi_ = f.inv1p_psi_ = f.cpsi_;
  f.ctheta_.resize(static_cast<std::size_t>(p.n_theta));
  f.stheta_ = f.inv1p_theta_ = f.ctheta_;
  return f;
}

void RadomeImm::set_model(double dt_s) {
  if (std::abs(dt_s - model_dt_s_) <= 1e-9 * model_dt_s_) return;
  auto m = axis_model(p_.tau_s, p_.Q, dt_s);
  if (!m) return;  // dt > 0 by the dataset's increasing time column; keep the last model
  axis_ = *m;
  model_dt_s_ = dt_s;
  F9_ = full_F(axis_);
  Gamma9_ = full_Gamma(axis_);
  Q9_ = full_Q(axis_);
}

void RadomeImm::initialize(const Sample& s) {
  elapsed_s_ = 0.0;
  const Vec<3> Y = pseudo_measurement(s.range_m, undo_slope(s.psi_rad, center_psi_, s.psi_a_rad),
                                      undo_slope(s.theta_rad, center_theta_, s.theta_a_rad));
  const auto r = static_cast<std::size_t>(modes());
  for (int ax = 0; ax < 3; ++ax) {
    Gaussian<3> g;
    g.x = Vec<3>(Y(ax), 0.0, 0.0);
    g.P = Vec<3>(p_.P0_pos_m2, p_.P0_vel_m2ps2, p_.P0_acc_m2ps4).asDiagonal();
    axis_modes_[static_cast<std::size_t>(ax)].assign(r, g);
  }
  Gaussian<9> g9;
  g9.x.setZero();
  g9.x.head<3>() = Y;
  g9.P.setZero();
  g9.P.diagonal() << Vec<3>::Constant(p_.P0_pos_m2), Vec<3>::Constant(p_.P0_vel_m2ps2),
      Vec<3>::Constant(p_.P0_acc_m2ps4);
  full_modes_.assign(r, g9);
  combined_pos_ = Y;
  combined_P_pos_ = Covariance<3>::Identity() * p_.P0_pos_m2;
}

StepOutput RadomeImm::step(const Sample& s, double dt_s) {
  StepOutput o;
  // Mode-parameter renewal (seed 001, eq. 4): the whole grid moves by Kp (R̂_{k−1} − mean R̄_{k−1}).
  elapsed_s_ += dt_s;
  const double kp = elapsed_s_ < p_.renewal_start_s ? 0.0 : p_.Kp;
  const double gain = p_.renewal == Renewal::kRate ? std::min(1.0, kp * dt_s) : kp;
  const double d_psi = gain * (est_psi_ - center_psi_);
  const double d_theta = gain * (est_theta_ - center_theta_);
  if (p_.renewal == Renewal::kSlope && (d_psi != 0.0 || d_theta != 0.0)) {
    const VecX moved =
        remap_probabilities(imm_probabilities(log_mu_), off_psi_, off_theta_, d_psi, d_theta);
    log_mu_ = moved.array().max(1e-300).log().matrix();
  }
  moved_chain_.reset();
  if (p_.renewal == Renewal::kMix && (d_psi != 0.0 || d_theta != 0.0)) {
    // Old mode i → moved-grid mode i' (shares T), then the Markov chain among the moved modes.
    auto moved =
        MarkovChain::dense(shift_transition(off_psi_, off_theta_, d_psi, d_theta) * chain_matrix_);
    if (moved) moved_chain_ = std::move(*moved);
  }
  center_psi_ += d_psi;
  center_theta_ += d_theta;
  set_model(dt_s);
  if (p_.structure == Structure::kFull) {
    step_full(s, o);
  } else {
    step_axis(s, o);
  }
  finish(o);
  return o;
}

void RadomeImm::step_axis(const Sample& s, StepOutput& o) {
  const ImmMixing w = imm_mixing(moved_chain_ ? *moved_chain_ : chain_, log_mu_);
  const auto r = static_cast<std::size_t>(modes());
  for (std::size_t ax = 0; ax < 3; ++ax) {
    imm_mix(w, axis_modes_[ax], axis_mixed_[ax]);
    const Vec<3> Bu = axis_.Gamma * s.U(static_cast<Eigen::Index>(ax));
    // Modes without own weight share one mixed prior (w.own = 0): predict it once.
    std::size_t shared = r;
    for (std::size_t j = 0; j < r; ++j) {
      if (w.uniform && w.own(static_cast<Eigen::Index>(j)) == 0.0 && shared < r) {
        axis_modes_[ax][j] = axis_modes_[ax][shared];
        continue;
      }
      axis_modes_[ax][j] = predict(axis_mixed_[ax][j], axis_.F, Bu, axis_.Q);
      if (w.uniform && w.own(static_cast<Eigen::Index>(j)) == 0.0) shared = j;
    }
  }
  if (!s.has_measurement()) {
    log_mu_ = w.log_c_bar;
    return;
  }
  // Corrected angles per grid line: ψ^a depends on a only, θ^b on b only.
  for (int a = 0; a < n_psi_; ++a) {
    const double slope = center_psi_ + off_psi_[static_cast<std::size_t>(a)];
    const double psi = undo_slope(s.psi_rad, slope, s.psi_a_rad);
    cpsi_[static_cast<std::size_t>(a)] = std::cos(psi);
    spsi_[static_cast<std::size_t>(a)] = std::sin(psi);
    inv1p_psi_[static_cast<std::size_t>(a)] = 1.0 / ((1.0 + slope) * (1.0 + slope));
  }
  for (int b = 0; b < n_theta_; ++b) {
    const double slope = center_theta_ + off_theta_[static_cast<std::size_t>(b)];
    const double theta = undo_slope(s.theta_rad, slope, s.theta_a_rad);
    ctheta_[static_cast<std::size_t>(b)] = std::cos(theta);
    stheta_[static_cast<std::size_t>(b)] = std::sin(theta);
    inv1p_theta_[static_cast<std::size_t>(b)] = 1.0 / ((1.0 + slope) * (1.0 + slope));
  }
  const double rng = s.range_m, vR = p_.var_range, r2 = rng * rng;
  double best_y[3] = {0, 0, 0}, best_S[3] = {0, 0, 0};
  double best_log = kNegInf;
  for (int b = 0; b < n_theta_; ++b) {
    const auto ub = static_cast<std::size_t>(b);
    const double ct = ctheta_[ub], st = stheta_[ub];
    const double vT = p_.var_angle * inv1p_theta_[ub];
    for (int a = 0; a < n_psi_; ++a) {
      const auto ua = static_cast<std::size_t>(a);
      const std::size_t j = ua + static_cast<std::size_t>(n_psi_) * ub;
      const double cp = cpsi_[ua], sp = spsi_[ua];
      const double vP = p_.var_angle * inv1p_psi_[ua];
      // Seed 001, eq. 3, and the diagonal of J diag(σ_R², σ_ψ², σ_θ²) J^T.
      const double Y[3] = {rng * ct * cp, rng * ct * sp, rng * st};
      const double R[3] = {
          vR * ct * ct * cp * cp + vP * r2 * ct * ct * sp * sp + vT * r2 * st * st * cp * cp,
          vR * ct * ct * sp * sp + vP * r2 * ct * ct * cp * cp + vT * r2 * st * st * sp * sp,
          vR * st * st + vT * r2 * ct * ct};
      double quad = 0.0, det = 1.0;  // Σ y²/S and Π S: one log per mode, not three
      double ys[3], Ss[3];
      bool ok = true;
      for (std::size_t ax = 0; ax < 3; ++ax) {
        Gaussian<3>& g = axis_modes_[ax][j];
        // Scalar update with H = [1 0 0]: S = P00 + R, K = P e1 / S, P ← P − K S K^T.
        const double S = g.P(0, 0) + R[ax];
        const double y = Y[ax] - g.x(0);
        if (!(S > 0.0) || !std::isfinite(S) || !std::isfinite(y)) {
          ok = false;
          break;
        }
        const Vec<3> PHt = g.P.col(0);
        g.x.noalias() += PHt * (y / S);
        g.P.noalias() -= PHt * (PHt.transpose() / S);
        debug_check_covariance(g.P, "a radome axis update");
        quad += y * y / S;
        det *= S;
        ys[ax] = y;
        Ss[ax] = S;
      }
      if (!ok) {
        ++o.failed_modes;
        log_lik_(static_cast<Eigen::Index>(j)) = kNegInf;
        continue;
      }
      const double ll = -0.5 * (3.0 * kLog2Pi + std::log(det) + quad);
      log_lik_(static_cast<Eigen::Index>(j)) = ll;
      const double post = w.log_c_bar(static_cast<Eigen::Index>(j)) + ll;
      if (post > best_log) {
        best_log = post;
        o.map_mode = static_cast<int>(j);
        for (int ax = 0; ax < 3; ++ax) {
          best_y[ax] = ys[ax];
          best_S[ax] = Ss[ax];
        }
      }
    }
  }
  const ImmProbabilities pr = imm_update_probabilities(w.log_c_bar, log_lik_);
  log_mu_ = pr.log_mu;
  o.updated = pr.ok;
  o.innovation = Vec<3>(best_y[0], best_y[1], best_y[2]);
  o.S_diag = Vec<3>(best_S[0], best_S[1], best_S[2]);
  o.nis = best_y[0] * best_y[0] / best_S[0] + best_y[1] * best_y[1] / best_S[1] +
          best_y[2] * best_y[2] / best_S[2];
}

void RadomeImm::step_full(const Sample& s, StepOutput& o) {
  const ImmMixing w = imm_mixing(moved_chain_ ? *moved_chain_ : chain_, log_mu_);
  const auto r = static_cast<std::size_t>(modes());
  imm_mix(w, full_modes_, full_mixed_);
  const Vec<9> Bu = Gamma9_ * s.U;
  std::size_t shared = r;  // as in step_axis: one prediction for all modes without own weight
  for (std::size_t j = 0; j < r; ++j) {
    if (w.uniform && w.own(static_cast<Eigen::Index>(j)) == 0.0 && shared < r) {
      full_modes_[j] = full_modes_[shared];
      continue;
    }
    full_modes_[j] = predict(full_mixed_[j], F9_, Bu, Q9_);
    if (w.uniform && w.own(static_cast<Eigen::Index>(j)) == 0.0) shared = j;
  }
  if (!s.has_measurement()) {
    log_mu_ = w.log_c_bar;
    return;
  }
  double best_log = kNegInf;
  for (std::size_t j = 0; j < r; ++j) {
    const int ji = static_cast<int>(j);
    const double sp = slope_psi_of(ji), st = slope_theta_of(ji);
    const double psi = undo_slope(s.psi_rad, sp, s.psi_a_rad);
    const double theta = undo_slope(s.theta_rad, st, s.theta_a_rad);
    const Vec<3> Y = pseudo_measurement(s.range_m, psi, theta);
    const Covariance<3> R =
        pseudo_covariance(s.range_m, psi, theta, p_.var_range, p_.var_angle / ((1 + sp) * (1 + sp)),
                          p_.var_angle / ((1 + st) * (1 + st)));
    // H = [I 0 0]: P H^T = P's first three columns, S = P_pp + R; symmetric-form update
    // P ← P − K S K^T (forced symmetric), a quarter of the Joseph form's work.
    Gaussian<9>& g = full_modes_[j];
    const Mat<9, 3> PHt = g.P.leftCols<3>();
    const Covariance<3> S = PHt.topRows<3>() + R;
    const Vec<3> y = Y - g.x.head<3>();
    const Eigen::LLT<Covariance<3>> llt(S);
    if (llt.info() != Eigen::Success || !S.allFinite() || !y.allFinite()) {
      ++o.failed_modes;
      log_lik_(ji) = kNegInf;
      continue;
    }
    const Mat<3, 9> KT = llt.solve(PHt.transpose());  // K^T = S^{-1} H P
    g.x.noalias() += KT.transpose() * y;
    g.P.noalias() -= PHt * KT;
    g.P = 0.5 * (g.P + g.P.transpose()).eval();
    debug_check_covariance(g.P, "a radome update");
    const Vec<3> u = llt.matrixL().solve(y);
    double log_det = 0.0;
    for (int i = 0; i < 3; ++i)
      log_det += 2.0 * std::log(llt.matrixLLT()(i, i));
    const double nis = u.squaredNorm();
    log_lik_(ji) = -0.5 * (nis + log_det + 3.0 * kLog2Pi);
    const double post = w.log_c_bar(ji) + log_lik_(ji);
    if (post > best_log) {
      best_log = post;
      o.map_mode = ji;
      o.innovation = y;
      o.S_diag = S.diagonal();
      o.nis = nis;
    }
  }
  const ImmProbabilities pr = imm_update_probabilities(w.log_c_bar, log_lik_);
  log_mu_ = pr.log_mu;
  o.updated = pr.ok;
}

void RadomeImm::finish(StepOutput& o) {
  const VecX mu = imm_probabilities(log_mu_);
  double sp = 0.0, st = 0.0;
  for (int j = 0; j < modes(); ++j) {
    sp += mu(j) * off_psi_[static_cast<std::size_t>(j % n_psi_)];
    st += mu(j) * off_theta_[static_cast<std::size_t>(j / n_psi_)];
  }
  // R̂ = Σ μ^j R̄^j (seed 001, sec. 2.2.2); Σ μ = 1, so the centre factors out.
  est_psi_ = center_psi_ + sp;
  est_theta_ = center_theta_ + st;
  if (p_.structure == Structure::kFull) {
    const Gaussian<9> c = imm_combine(full_modes_, mu);
    combined_pos_ = c.x.head<3>();
    combined_P_pos_ = c.P.topLeftCorner<3, 3>();
  } else {
    combine_axis_positions(mu);
  }
  o.slope_psi = est_psi_;
  o.slope_theta = est_theta_;
  o.center_psi = center_psi_;
  o.center_theta = center_theta_;
  o.pos = combined_pos_;
  o.P_pos = combined_P_pos_;
}

void RadomeImm::combine_axis_positions(const VecX& mu) {
  // Combination (seed 001, Table 2) of the position, the only part the outputs use. Within a mode
  // the axis blocks are independent, so across axes the mixture's covariance is the spread term
  // Σ μ^j d^j d^jᵀ alone (d^j = x^j − x̂); along the diagonal Σ μ^j P^j_pp is added as well.
  const auto r = static_cast<std::size_t>(modes());
  Vec<3> x = Vec<3>::Zero();
  for (std::size_t j = 0; j < r; ++j) {
    for (std::size_t ax = 0; ax < 3; ++ax)
      x(static_cast<Eigen::Index>(ax)) +=
          mu(static_cast<Eigen::Index>(j)) * axis_modes_[ax][j].x(kPos);
  }
  Covariance<3> P = Covariance<3>::Zero();
  for (std::size_t j = 0; j < r; ++j) {
    const double m = mu(static_cast<Eigen::Index>(j));
    if (m == 0.0) continue;
    Vec<3> d;
    for (std::size_t ax = 0; ax < 3; ++ax) {
      const auto i = static_cast<Eigen::Index>(ax);
      const Gaussian<3>& g = axis_modes_[ax][j];
      d(i) = g.x(kPos) - x(i);
      P(i, i) += m * g.P(kPos, kPos);
    }
    P.noalias() += (m * d) * d.transpose();
  }
  combined_pos_ = x;
  combined_P_pos_ = P;
}

Expected<RadomeResult> run_radome_imm(const Inputs& in, const FilterParams& p,
                                      const RunControl& control) {
  if (!in.t || !in.range || !in.psi || !in.theta || !in.psi_a || !in.theta_a) {
    return Error{"radome: missing input column"};
  }
  const std::size_t n = in.t->size();
  if (n < 2) return Error{"radome: need at least two rows"};
  const auto& t = *in.t;
  auto sample = [&](std::size_t k) {
    Sample s;
    s.t_s = t[k];
    s.range_m = (*in.range)[k];
    s.psi_rad = (*in.psi)[k];
    s.theta_rad = (*in.theta)[k];
    s.psi_a_rad = (*in.psi_a)[k];
    s.theta_a_rad = (*in.theta_a)[k];
    for (int ax = 0; ax < 3; ++ax) {
      const auto* col = in.U[static_cast<std::size_t>(ax)];
      const double u = col ? (*col)[k] : 0.0;
      s.U(ax) = std::isfinite(u) ? u : 0.0;
    }
    return s;
  };
  std::size_t first = 0;
  while (first < n && !sample(first).has_measurement())
    ++first;
  if (first >= n) return Error{"radome: no row has range, angles and attitude all present"};
  const double T = t[1] - t[0];
  auto f = RadomeImm::create(p, T > 0 ? T : 1.0);
  if (!f) return f.err();
  RadomeImm& imm = *f;

  RadomeResult r;
  r.n_psi = imm.n_psi();
  r.n_theta = imm.n_theta();
  r.offsets_psi = imm.offsets_psi();
  r.offsets_theta = imm.offsets_theta();
  r.t = t;
  auto nan_col = [&] { return std::vector<double>(n, kNaN); };
  r.slope_psi = r.slope_theta = r.center_psi = r.center_theta = nan_col();
  r.alpha_est_deg = r.psi_los_est_deg = r.theta_los_est_deg = nan_col();
  r.psi_meas_deg = r.theta_meas_deg = nan_col();
  r.x_est = r.y_est = r.z_est = r.nis = r.map_mode = nan_col();
  r.P_pos.assign(n, Covariance<3>::Constant(kNaN));
  for (int ax = 0; ax < 3; ++ax) {
    r.innovation[static_cast<std::size_t>(ax)] = nan_col();
    r.S[static_cast<std::size_t>(ax)] = nan_col();
  }
  const auto modes = static_cast<std::size_t>(imm.modes());
  r.mu.assign(n * modes, std::numeric_limits<float>::quiet_NaN());

  std::size_t failed_steps = 0, failed_mode_updates = 0;
  auto record = [&](std::size_t k, const Sample& s, const StepOutput& o) {
    r.slope_psi[k] = o.slope_psi;
    r.slope_theta[k] = o.slope_theta;
    r.center_psi[k] = o.center_psi;
    r.center_theta[k] = o.center_theta;
    r.x_est[k] = o.pos(0);
    r.y_est[k] = o.pos(1);
    r.z_est[k] = o.pos(2);
    r.P_pos[k] = o.P_pos;
    const double pe = los_psi(o.pos), te = los_theta(o.pos);
    r.psi_los_est_deg[k] = pe * kRadToDeg;
    r.theta_los_est_deg[k] = te * kRadToDeg;
    r.psi_meas_deg[k] = s.psi_rad * kRadToDeg;
    r.theta_meas_deg[k] = s.theta_rad * kRadToDeg;
    if (std::isfinite(s.psi_a_rad) && std::isfinite(s.theta_a_rad)) {
      r.alpha_est_deg[k] =
          refraction_error(o.slope_psi, o.slope_theta, pe, te, s.psi_a_rad, s.theta_a_rad) *
          kRadToDeg;
    }
    if (o.updated) {
      for (int ax = 0; ax < 3; ++ax) {
        r.innovation[static_cast<std::size_t>(ax)][k] = o.innovation(ax);
        r.S[static_cast<std::size_t>(ax)][k] = o.S_diag(ax);
      }
      r.nis[k] = o.nis;
      ++r.updates;
    }
    r.map_mode[k] = o.map_mode;
    const VecX& lm = imm.log_mu();
    for (std::size_t j = 0; j < modes; ++j) {
      r.mu[k * modes + j] = static_cast<float>(std::exp(lm(static_cast<Eigen::Index>(j))));
    }
  };

  const Sample s0 = sample(first);
  imm.initialize(s0);
  StepOutput o0;
  o0.slope_psi = o0.center_psi = 0.5 * (p.grid_min + p.grid_max);
  o0.slope_theta = o0.center_theta = o0.slope_psi;
  o0.pos = pseudo_measurement(s0.range_m, s0.psi_rad, s0.theta_rad);
  o0.P_pos = Covariance<3>::Identity() * p.P0_pos_m2;
  o0.map_mode = imm.modes() / 2;
  record(first, s0, o0);
  for (std::size_t k = first + 1; k < n; ++k) {
    const Sample s = sample(k);
    const StepOutput o = imm.step(s, t[k] - t[k - 1]);
    if (s.has_measurement() && !o.updated) ++failed_steps;
    failed_mode_updates += static_cast<std::size_t>(o.failed_modes);
    record(k, s, o);
    if ((k & 63) == 0) {
      if (control.cancelled()) {
        r.warnings.push_back("cancelled at step " + std::to_string(k));
        break;
      }
      if (control.progress) control.progress(static_cast<double>(k) / static_cast<double>(n));
    }
  }
  // Equal ends with several values per axis (a slider passing through equality, say) make
  // identical modes: the run is valid but the grid cannot tell slopes apart.
  if (p.grid_min == p.grid_max && (p.n_psi > 1 || p.n_theta > 1)) {
    r.warnings.push_back("grid.min = grid.max = " + format_number(p.grid_min) +
                         " with grid.n_psi = " + std::to_string(p.n_psi) + ", grid.n_theta = " +
                         std::to_string(p.n_theta) + ": all " + std::to_string(imm.modes()) +
                         " modes have the same slopes, so the slope estimate cannot move");
  }
  if (first > 0) {
    r.warnings.push_back(std::to_string(first) + " leading rows without a measurement skipped");
  }
  if (failed_steps) {
    r.warnings.push_back(std::to_string(failed_steps) +
                         " measurements no mode could use (S not positive definite)");
  }
  if (failed_mode_updates) {
    r.warnings.push_back(std::to_string(failed_mode_updates) +
                         " mode updates skipped (S not positive definite)");
  }
  return r;
}

}  // namespace kfw::radome
