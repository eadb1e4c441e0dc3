// Internal to the model filters (model_kf.cpp, model_ukf.cpp): fixed-size types per state count,
// angle wrapping, the data columns of a run, and the per-step recording shared by every filter.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "model/model_eval.h"
#include "model/model_filter.h"
#include "model/model_result.h"

namespace kfw::model::detail {

inline constexpr int kM = kMaxChannelSize;

// Eigen wants row-major storage for a compile-time row vector.
template <int R, int C>
inline constexpr int kOpts = (R == 1 && C != 1) ? Eigen::RowMajor : Eigen::ColMajor;

// State-size N fixed (fast, no heap) or Eigen::Dynamic; measurement sizes up to kM, no heap.
template <int N>
struct Types {
  using VecN = Eigen::Matrix<double, N, 1>;
  using MatN = Eigen::Matrix<double, N, N>;
  using VecM = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kM, 1>;
  using MatM = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kM, kM>;
  using MatNM = Eigen::Matrix<double, N, Eigen::Dynamic, kOpts<N, Eigen::Dynamic>, N, kM>;
  using MatMN = Eigen::Matrix<double, Eigen::Dynamic, N, kOpts<Eigen::Dynamic, N>, kM, N>;
};

// An angle to (−π, π] (rad) or (−180, 180] (deg); other values unchanged.
inline double wrap(double v, Angle a) {
  if (a == Angle::kNone) return v;
  const double period = a == Angle::kRad ? 2.0 * std::numbers::pi : 360.0;
  double r = std::remainder(v, period);
  if (r <= -0.5 * period) r += period;
  return r;
}

// The dataset's columns for a run, by role.
struct Data {
  std::size_t rows = 0;
  const std::vector<double>* t = nullptr;
  std::vector<const std::vector<double>*> u;               // per input
  std::vector<std::vector<const std::vector<double>*>> z;  // per channel, per component
  std::vector<const std::vector<double>*> truth;           // per state; null: no truth
};

// What every filter shares: the evaluator, the data, the result being filled, inputs held.
struct Context {
  const ModelSpec& spec;
  ModelEval& ev;
  const Data& data;
  ModelResult& r;
  const RunControl& control;
  FilterOptions options;
  std::vector<double> u_held;     // the inputs, last finite value held
  std::vector<int> truth_states;  // states with a truth column
  std::vector<double> z_buf;      // one channel's measurement

  std::string where(std::size_t k) const {
    std::ostringstream os;
    os << "step " << k << " (t = " << (*data.t)[k] << " s)";
    return os.str();
  }
  Error fail(std::size_t k, const std::string& what) const {
    return failure(where(k) + ": " + what);
  }

  // Takes row k's inputs, holding the last finite value of a missing sample.
  void hold_inputs(std::size_t k) {
    for (std::size_t i = 0; i < u_held.size(); ++i) {
      const double v = (*data.u[i])[k];
      if (std::isfinite(v)) u_held[i] = v;
    }
  }

  // The channel updates at row k: its clock allows and every value is present. Fills z_buf.
  bool channel_ready(std::size_t c, std::size_t k) {
    const auto& ch = ev.channel(c);
    if (k % static_cast<std::size_t>(ch.every) != 0) return false;
    const auto& cols = data.z[c];
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const double v = (*cols[j])[k];
      if (!std::isfinite(v)) return false;
      z_buf[j] = v;
    }
    return true;
  }

  // Stores x and P (upper triangle) at step k and the NEES over the states with truth.
  template <class V, class M>
  void record_state(std::size_t k, const V& x, const M& P) {
    const auto n = static_cast<std::size_t>(x.size());
    for (std::size_t i = 0; i < n; ++i)
      r.x[i][k] = x(static_cast<Eigen::Index>(i));
    std::size_t e = 0;
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(n); ++i) {
      for (Eigen::Index j = i; j < static_cast<Eigen::Index>(n); ++j)
        r.P[e++][k] = P(i, j);
    }
    if (truth_states.empty()) return;
    const auto d = static_cast<Eigen::Index>(truth_states.size());
    typename Types<Eigen::Dynamic>::VecM err(d);
    for (Eigen::Index a = 0; a < d; ++a) {
      const int s = truth_states[static_cast<std::size_t>(a)];
      const double tv = (*data.truth[static_cast<std::size_t>(s)])[k];
      if (!std::isfinite(tv)) return;
      err(a) = wrap(x(s) - tv, spec.states[static_cast<std::size_t>(s)].angle);
    }
    if (d == 1) {
      const double v = P(truth_states[0], truth_states[0]);
      r.nees[k] = err(0) * err(0) / v;
      return;
    }
    typename Types<Eigen::Dynamic>::MatM Ps(d, d);
    for (Eigen::Index a = 0; a < d; ++a) {
      for (Eigen::Index b = 0; b < d; ++b)
        Ps(a, b) =
            P(truth_states[static_cast<std::size_t>(a)], truth_states[static_cast<std::size_t>(b)]);
    }
    Eigen::LLT<typename Types<Eigen::Dynamic>::MatM> llt(Ps);
    if (llt.info() == Eigen::Success) r.nees[k] = err.dot(llt.solve(err));
  }

  // Stores one channel's innovation, S diagonal, NIS, log det S and gain at step k.
  template <class Y, class S, class K>
  void record_update(std::size_t c, std::size_t k, const Y& y, const S& Sm, double nis,
                     double log_det, const K& Km) {
    ChannelSeries& ch = r.chans[c];
    const auto m = static_cast<std::size_t>(y.size());
    for (std::size_t j = 0; j < m; ++j) {
      const auto jj = static_cast<Eigen::Index>(j);
      ch.y[j][k] = y(jj);
      ch.S[j][k] = Sm(jj, jj);
    }
    ch.nis[k] = nis;
    ch.log_det_s[k] = log_det;
    if (!std::isfinite(nis)) return;
    for (Eigen::Index i = 0; i < Km.rows(); ++i) {
      for (Eigen::Index j = 0; j < Km.cols(); ++j)
        ch.K[static_cast<std::size_t>(i) * m + static_cast<std::size_t>(j)][k] = Km(i, j);
    }
  }

  // A state that stops being finite ends the run.
  template <class V>
  Status check_finite(std::size_t k, const V& x) const {
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      if (!std::isfinite(x(i))) {
        return fail(k, "the state '" + spec.states[static_cast<std::size_t>(i)].name +
                           "' is not finite; the run stops here");
      }
    }
    return Ok{};
  }

  // Q or R evaluated at a state or time must stay positive semidefinite.
  Status check_noise(std::size_t k, const MatX& M, const std::string& key) const {
    if (M.rows() == 1 ? M(0, 0) >= 0.0 : is_psd(M)) return Ok{};
    std::ostringstream os;
    os << key << " lost definiteness (smallest eigenvalue " << min_eigenvalue(M)
       << "); the run stops here";
    return fail(k, os.str());
  }
};

template <int N>
Status run_kf(Context& ctx, typename Types<N>::VecN x, typename Types<N>::MatN P);
template <int N>
Status run_ukf(Context& ctx, typename Types<N>::VecN x, typename Types<N>::MatN P);

}  // namespace kfw::model::detail
