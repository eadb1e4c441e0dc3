// A direct transcription of seed 001's Table 2 (the IMM cycle; Bar-Shalom, Li and Kirubarajan
// 2001, sec. 11.6.6) for linear modes, in the linear domain with plain Eigen: the oracle that the
// model engine's IMM (engine/model/imm/) is held to. It shares no code with the engine.
//
// First row (presets/models/README.md, "Modes"): no mixing and no transition; every mode starts
// from x0, P0 with μ0, and the first measurement updates them. Later rows: mixing from μ_{k−1},
// prediction, update, mode probabilities, combination.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <vector>

namespace kfw::oracles {

struct Table2Mode {
  Eigen::MatrixXd F, Q, H, R;
};

struct Table2Row {
  Eigen::VectorXd x;   // combined estimate
  Eigen::MatrixXd P;   // combined covariance
  Eigen::VectorXd mu;  // mode probabilities
};

class ImmTable2 {
 public:
  ImmTable2(std::vector<Table2Mode> modes, Eigen::MatrixXd p, Eigen::VectorXd mu0,
            const Eigen::VectorXd& x0, const Eigen::MatrixXd& P0)
      : modes_(std::move(modes)), p_(std::move(p)), mu_(std::move(mu0)) {
    x_.assign(modes_.size(), x0);
    P_.assign(modes_.size(), P0);
  }

  // Mixing block by block (presets/models/README.md, "Structure"): the mixed covariances'
  // entries between states of different blocks are dropped. Empty: one block.
  void set_blocks(std::vector<int> block_of) { blocks_ = std::move(block_of); }

  // One row: `first` skips mixing and prediction; `z` empty: no measurement at this row.
  Table2Row step(bool first, const Eigen::VectorXd& z) {
    const std::size_t r = modes_.size();
    Eigen::VectorXd c_bar = mu_;
    if (!first) {
      // Calculation of the mixing probabilities: c̄_j = Σ_i p_ij μ_i, μ_{i|j} = p_ij μ_i / c̄_j.
      c_bar = p_.transpose() * mu_;
      std::vector<Eigen::VectorXd> x0(r);
      std::vector<Eigen::MatrixXd> P0(r);
      for (std::size_t j = 0; j < r; ++j) {
        x0[j] = Eigen::VectorXd::Zero(x_[0].size());
        for (std::size_t i = 0; i < r; ++i)
          x0[j] += p_(i, j) * mu_(i) / c_bar(j) * x_[i];
        P0[j] = Eigen::MatrixXd::Zero(x_[0].size(), x_[0].size());
        for (std::size_t i = 0; i < r; ++i) {
          const Eigen::VectorXd d = x_[i] - x0[j];
          P0[j] += p_(i, j) * mu_(i) / c_bar(j) * (P_[i] + d * d.transpose());
        }
        for (std::size_t a = 0; a < blocks_.size(); ++a) {
          for (std::size_t b = 0; b < blocks_.size(); ++b) {
            if (blocks_[a] != blocks_[b]) P0[j](a, b) = 0.0;
          }
        }
      }
      // Mode-matched prediction.
      for (std::size_t j = 0; j < r; ++j) {
        const Table2Mode& m = modes_[j];
        x_[j] = m.F * x0[j];
        P_[j] = m.F * P0[j] * m.F.transpose() + m.Q;
      }
    }
    mu_ = c_bar;
    if (z.size() > 0) {
      // Mode-matched update and likelihoods Λ_j = N(y_j; 0, S_j); μ_j = Λ_j c̄_j / c.
      Eigen::VectorXd lambda(r);
      for (std::size_t j = 0; j < r; ++j) {
        const Table2Mode& m = modes_[j];
        const Eigen::VectorXd y = z - m.H * x_[j];
        const Eigen::MatrixXd S = m.H * P_[j] * m.H.transpose() + m.R;
        const Eigen::MatrixXd K = P_[j] * m.H.transpose() * S.inverse();
        x_[j] += K * y;
        const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(x_[j].size(), x_[j].size()) - K * m.H;
        P_[j] = IKH * P_[j] * IKH.transpose() + K * m.R * K.transpose();
        const double quad = y.dot(S.inverse() * y);
        lambda(j) = std::exp(-0.5 * quad) /
                    std::sqrt(std::pow(2.0 * std::numbers::pi, static_cast<double>(y.size())) *
                              S.determinant());
      }
      const double c = lambda.dot(c_bar);
      mu_ = lambda.cwiseProduct(c_bar) / c;
    }
    // Combination.
    Table2Row out;
    out.mu = mu_;
    out.x = Eigen::VectorXd::Zero(x_[0].size());
    for (std::size_t j = 0; j < r; ++j)
      out.x += mu_(j) * x_[j];
    out.P = Eigen::MatrixXd::Zero(x_[0].size(), x_[0].size());
    for (std::size_t j = 0; j < r; ++j) {
      const Eigen::VectorXd d = x_[j] - out.x;
      out.P += mu_(j) * (P_[j] + d * d.transpose());
    }
    return out;
  }

 private:
  std::vector<Table2Mode> modes_;
  Eigen::MatrixXd p_;
  Eigen::VectorXd mu_;
  std::vector<Eigen::VectorXd> x_;
  std::vector<Eigen::MatrixXd> P_;
  std::vector<int> blocks_;
};

}  // namespace kfw::oracles
