// A mode filter that runs block by block (presets/models/README.md, "Structure"): when a linear
// model's states fall in blocks of B states that F, Q, H, R and P0 keep apart (or `approximate`
// drops what couples them), each mode is one small fixed-size Kalman filter per block — seed
// 001's three [p, v, a] axis filters — instead of one over the whole state. The same arithmetic
// as the whole-state filter with block-diagonal P (model_filters.h), at a fraction of the cost;
// the IMM (imm_run.cpp) mixes it block by block and combines the blocks into the whole state.
#pragma once

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "filter/angle.h"
#include "model/imm/imm_spec.h"
#include "model/model_filter_detail.h"

namespace kfw::model::detail {

template <int B>
struct BlockKalman {
  static constexpr int kBlockSize = B;
  using MeasB = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kM, 1>;
  using CovB = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kM, kM>;
  using JacB = Eigen::Matrix<double, Eigen::Dynamic, B, 0, kM, B>;
  using GainB = Eigen::Matrix<double, B, Eigen::Dynamic, 0, B, kM>;

  Context& ctx;
  std::vector<std::array<Eigen::Index, B>> idx;  // per block: its states
  std::vector<Vec<B>> x;                         // per block
  std::vector<Covariance<B>> P;
  // Per channel: per block, the components its H rows read; and those that read no state.
  std::vector<std::vector<std::vector<Eigen::Index>>> comps;
  std::vector<std::vector<Eigen::Index>> free;
  std::string why;

  // Blocks of B states each (StructureSpec::blocks_of_size), x0 and P0's diagonal blocks.
  BlockKalman(Context& c, const StructureSpec& st, const VecX& x0, const MatX& P0) : ctx(c) {
    int blocks = 0;
    for (int b : st.block_of)
      blocks = std::max(blocks, b + 1);
    idx.resize(static_cast<std::size_t>(blocks));
    std::vector<int> fill(idx.size(), 0);
    for (std::size_t i = 0; i < st.block_of.size(); ++i) {
      const auto b = static_cast<std::size_t>(st.block_of[i]);
      idx[b][static_cast<std::size_t>(fill[b]++)] = static_cast<Eigen::Index>(i);
    }
    for (const auto& s : idx) {
      Vec<B> xb;
      Covariance<B> Pb;
      for (int i = 0; i < B; ++i) {
        xb(i) = x0(s[static_cast<std::size_t>(i)]);
        for (int j = 0; j < B; ++j)
          Pb(i, j) = P0(s[static_cast<std::size_t>(i)], s[static_cast<std::size_t>(j)]);
      }
      x.push_back(xb);
      P.push_back(Pb);
    }
    for (const auto& blocks_of_c : st.component_block) {
      comps.emplace_back(idx.size());
      free.emplace_back();
      for (std::size_t j = 0; j < blocks_of_c.size(); ++j) {
        const auto jj = static_cast<Eigen::Index>(j);
        if (blocks_of_c[j] < 0) {
          free.back().push_back(jj);
        } else {
          comps.back()[static_cast<std::size_t>(blocks_of_c[j])].push_back(jj);
        }
      }
    }
  }

  // Per block: x = F_b x + (B u)_b, P = F_b P Fᵀ_b + Q_b.
  Status predict(std::size_t k) {
    ModelEval& ev = ctx.ev;
    if (ev.process_noise_varies()) {
      if (auto st = ctx.check_process_noise(k); !st) return st;
    }
    Covariance<B> F, Q;
    for (std::size_t b = 0; b < idx.size(); ++b) {
      const auto& s = idx[b];
      Vec<B> bu = Vec<B>::Zero();
      for (int i = 0; i < B; ++i) {
        const auto si = s[static_cast<std::size_t>(i)];
        for (int j = 0; j < B; ++j) {
          F(i, j) = ev.F(si, s[static_cast<std::size_t>(j)]);
          Q(i, j) = ev.Q(si, s[static_cast<std::size_t>(j)]);
        }
        for (Eigen::Index u = 0; u < ev.B.cols(); ++u)
          bu(i) += ev.B(si, u) * ctx.u_held[static_cast<std::size_t>(u)];
      }
      x[b] = F * x[b] + bu;
      P[b] = F * P[b] * F.transpose() + Q;
      if (auto st = check(k, b); !st) return st;
    }
    return Ok{};
  }

  // Channel c's components (ctx.z_buf) block by block: y, S = H P Hᵀ + R, the Joseph-form
  // update; the log-likelihood, NIS and gains kept in the context's capture (an IMM's mode).
  Status update(std::size_t c, std::size_t k) {
    const ModelEval::Channel& ch = ctx.ev.channel(c);
    if (ch.R_varies) {
      if (auto st = ctx.check_channel_noise(c, k); !st) return st;
    }
    Context::Capture& cap = *ctx.capture;
    const auto m = static_cast<std::size_t>(ch.H.rows());
    cap.m = m;
    cap.K.assign(idx.size() * B * m, 0.0);
    double nis = 0.0, log_det = 0.0;
    for (Eigen::Index j : free[c]) {  // read no state: y = z, S = R
      const double S = ch.R(j, j), y = ctx.z_buf[static_cast<std::size_t>(j)];
      if (!(S > 0.0)) return ctx.skip(c, k, ctx.s_not_pd(c, ch.R, false));
      keep(j, y, S);
      nis += y * y / S;
      log_det += std::log(S);
    }
    for (std::size_t b = 0; b < idx.size(); ++b) {
      const auto& cb = comps[c][b];
      if (cb.empty()) continue;
      if (cb.size() == 1) {  // one component in the block (seed 001's axes): a scalar update
        if (auto st = update_scalar(c, k, b, cb[0], m, nis, log_det); !st) return st;
        continue;
      }
      const auto mb = static_cast<Eigen::Index>(cb.size());
      JacB H(mb, B);
      CovB R(mb, mb);
      MeasB y(mb);
      for (Eigen::Index a = 0; a < mb; ++a) {
        const Eigen::Index ja = cb[static_cast<std::size_t>(a)];
        for (int i = 0; i < B; ++i)
          H(a, i) = ch.H(ja, idx[b][static_cast<std::size_t>(i)]);
        for (Eigen::Index e = 0; e < mb; ++e)
          R(a, e) = ch.R(ja, cb[static_cast<std::size_t>(e)]);
        y(a) = wrap(ctx.z_buf[static_cast<std::size_t>(ja)] - H.row(a).dot(x[b]),
                    ctx.role_angle[c][static_cast<std::size_t>(ja)]);
      }
      const GainB PHt = P[b] * H.transpose();
      const CovB S = H * PHt + R;
      const Eigen::LLT<CovB> llt(S);
      if (llt.info() != Eigen::Success || !S.allFinite()) {
        return ctx.skip(c, k, ctx.s_not_pd(c, MatX(S), false));
      }
      const GainB K = llt.solve(PHt.transpose()).transpose();
      const Covariance<B> A = Covariance<B>::Identity() - K * H;
      P[b] = A * P[b] * A.transpose() + K * R * K.transpose();
      P[b] = (0.5 * (P[b] + P[b].transpose())).eval();
      x[b] += K * y;
      const MeasB u = llt.matrixL().solve(y);
      nis += u.squaredNorm();
      for (Eigen::Index a = 0; a < mb; ++a) {
        log_det += 2.0 * std::log(llt.matrixLLT()(a, a));
        const Eigen::Index ja = cb[static_cast<std::size_t>(a)];
        keep(ja, y(a), S(a, a));
        for (int i = 0; i < B; ++i) {
          const auto state = static_cast<std::size_t>(idx[b][static_cast<std::size_t>(i)]);
          cap.K[state * m + static_cast<std::size_t>(ja)] = K(i, a);
        }
      }
      if (auto st = check(k, b); !st) return st;
    }
    cap.applied = true;
    cap.nis = nis;
    cap.log_det_s = log_det;
    return Ok{};
  }

  // The whole state: x and the block-diagonal P.
  template <class V, class M>
  void full(V& xf, M& Pf) const {
    for (std::size_t b = 0; b < idx.size(); ++b) {
      for (int i = 0; i < B; ++i) {
        const auto si = idx[b][static_cast<std::size_t>(i)];
        xf(si) = x[b](i);
        for (int j = 0; j < B; ++j)
          Pf(si, idx[b][static_cast<std::size_t>(j)]) = P[b](i, j);
      }
    }
  }

 private:
  // Component j alone in block b: S = h P hᵀ + r, K = P hᵀ / S, the Joseph form.
  Status update_scalar(std::size_t c, std::size_t k, std::size_t b, Eigen::Index j, std::size_t m,
                       double& nis, double& log_det) {
    const ModelEval::Channel& ch = ctx.ev.channel(c);
    Vec<B> h;
    for (int i = 0; i < B; ++i)
      h(i) = ch.H(j, idx[b][static_cast<std::size_t>(i)]);
    const double r = ch.R(j, j);
    const Vec<B> Ph = P[b] * h;
    const double S = h.dot(Ph) + r;
    const double y = wrap(ctx.z_buf[static_cast<std::size_t>(j)] - h.dot(x[b]),
                          ctx.role_angle[c][static_cast<std::size_t>(j)]);
    if (!(S > 0.0) || !std::isfinite(S)) {
      return ctx.skip(c, k, ctx.s_not_pd(c, MatX::Constant(1, 1, S), false));
    }
    const Vec<B> K = Ph / S;
    const Covariance<B> A = Covariance<B>::Identity() - K * h.transpose();
    P[b] = A * P[b] * A.transpose() + (r * K) * K.transpose();
    P[b] = (0.5 * (P[b] + P[b].transpose())).eval();
    x[b] += K * y;
    nis += y * y / S;
    log_det += std::log(S);
    keep(j, y, S);
    Context::Capture& cap = *ctx.capture;
    for (int i = 0; i < B; ++i) {
      const auto state = static_cast<std::size_t>(idx[b][static_cast<std::size_t>(i)]);
      cap.K[state * m + static_cast<std::size_t>(j)] = K(i);
    }
    return check(k, b);
  }

  void keep(Eigen::Index j, double y, double S) {
    Context::Capture& cap = *ctx.capture;
    cap.y[j] = y;
    cap.S[j] = S;
    cap.z[j] = ctx.z_buf[static_cast<std::size_t>(j)];
  }

  // Block b's states finite and their variances too (Context::check_estimate by state name).
  Status check(std::size_t k, std::size_t b) const {
    for (int i = 0; i < B; ++i) {
      const auto name =
          ctx.spec.states[static_cast<std::size_t>(idx[b][static_cast<std::size_t>(i)])].name;
      if (!std::isfinite(x[b](i))) {
        return ctx.fail(k, "the state '" + name + "' is not finite; the run stops here");
      }
      if (!std::isfinite(P[b](i, i))) {
        return ctx.fail(k, "the variance of '" + name +
                               "' is not finite (P overflowed: is the process unstable and the "
                               "state unobserved?); the run stops here");
      }
    }
    return Ok{};
  }
};

// The block size when every block of `st` has the same number of states, else 0.
inline int equal_block_size(const StructureSpec& st) {
  std::vector<int> count;
  for (int b : st.block_of) {
    if (b >= static_cast<int>(count.size())) count.resize(static_cast<std::size_t>(b) + 1, 0);
    ++count[static_cast<std::size_t>(b)];
  }
  for (int c : count) {
    if (c != count.front()) return 0;
  }
  return count.empty() ? 0 : count.front();
}

}  // namespace kfw::model::detail
