// The continuous nonlinear process ẋ = f(x, u, t) + G w of a model file (version 2): the mean
// by the classical fourth-order Runge–Kutta method in equal sub-steps of at most `substep`, the
// EKF's transition matrix as the exact Jacobian of that step map (the chain rule through the four
// stages of every sub-step), and Q by Van Loan's method (1978) on the linearisation
// (A(x_{k−1|k−1}), G Qc Gᵀ) over dt — the same discretisation as the linear continuous form.
#include <algorithm>
#include <cmath>
#include <limits>

#include "filter/discretize.h"
#include "model/model_eval.h"

namespace kfw::model {

namespace {

// More sub-steps than this per interval is refused (a sub-step far below the data's dt).
constexpr double kMaxSubsteps = 100'000;

}  // namespace

Status ModelEval::set_rk4_steps(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    return Error{spec_.path + ": model.process.xdot: dt = " + number(dt) +
                 " s: the continuous process needs a positive interval"};
  }
  const double steps = substep_ > 0.0 ? std::ceil(dt / substep_ - 1e-9) : 1.0;
  if (!(steps <= kMaxSubsteps)) {
    return Error{spec_.path + ": model.process.substep: needs " + number(steps) +
                 " RK4 sub-steps per interval (at most 100000)"};
  }
  rk4_steps_ = std::max(1, static_cast<int>(steps));
  return Ok{};
}

// ẋ = A x + b over the interval (b = Bu u + c, the inputs held): the four stages as products,
// the same RK4 as rk4() to rounding — a third of seed 003's closed loop was muparser here.
void ModelEval::rk4_affine() {
  const int n = spec_.n();
  VecX x(n);
  for (int i = 0; i < n; ++i)
    x(i) = vars_[static_cast<std::size_t>(spec_.state_slots[static_cast<std::size_t>(i)])];
  VecX u(static_cast<Eigen::Index>(spec_.inputs.size()));
  for (Eigen::Index i = 0; i < u.size(); ++i)
    u(i) = vars_[static_cast<std::size_t>(spec_.input_slots[static_cast<std::size_t>(i)])];
  if (!c_ready_) {
    xdot_state_.eval();  // at this state and these inputs: c = ẋ − A x − Bu u
    c_ = xdot_ - A * x - (u.size() ? VecX(Bu_ * u) : VecX::Zero(n));
    c_ready_ = true;
  }
  const VecX b = (u.size() ? VecX(Bu_ * u) : VecX::Zero(n)) + c_;
  const double h = dt_ / rk4_steps_;
  VecX k1(n), k2(n), k3(n), k4(n);
  for (int s = 0; s < rk4_steps_; ++s) {
    k1.noalias() = A * x;
    k1 += b;
    k2.noalias() = A * (x + 0.5 * h * k1);
    k2 += b;
    k3.noalias() = A * (x + 0.5 * h * k2);
    k3 += b;
    k4.noalias() = A * (x + h * k3);
    k4 += b;
    x += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    if (!limits_.empty()) apply_limits(limits_, x);
  }
  fx = x;
}

void ModelEval::rk4(bool jacobian) {
  if (!jacobian && spec_.process.affine) {
    rk4_affine();
    return;
  }
  const int n = spec_.n();
  const auto t_slot = static_cast<std::size_t>(spec_.t_slot);
  VecX x(n);
  for (int i = 0; i < n; ++i)
    x(i) = vars_[static_cast<std::size_t>(spec_.state_slots[static_cast<std::size_t>(i)])];
  const VecX x_start = x;
  const double t0 = vars_[t_slot];
  const double h = dt_ / rk4_steps_;
  VecX k1(n), k2(n), k3(n), k4(n), xs(n);
  MatX D1, D2, D3, D4, J, I;
  if (jacobian) {
    I = MatX::Identity(n, n);
    J = I;
  }
  // ẋ (and A, then D = A · ∂xs/∂x of the stage) at stage state xs, time ts.
  auto stage = [&](const VecX& s, double ts, VecX& k, MatX* D, const MatX* dxs) {
    set_state(s.data());
    vars_[t_slot] = ts;
    xdot_state_.eval();
    k = xdot_;
    if (D) {
      A_state_.eval();
      *D = dxs ? (A * *dxs).eval() : A;
    }
  };
  for (int s = 0; s < rk4_steps_; ++s) {
    const double ts = t0 + s * h;
    stage(x, ts, k1, jacobian ? &D1 : nullptr, nullptr);
    xs = x + 0.5 * h * k1;
    MatX dx;
    if (jacobian) dx = I + 0.5 * h * D1;
    stage(xs, ts + 0.5 * h, k2, jacobian ? &D2 : nullptr, &dx);
    xs = x + 0.5 * h * k2;
    if (jacobian) dx = I + 0.5 * h * D2;
    stage(xs, ts + 0.5 * h, k3, jacobian ? &D3 : nullptr, &dx);
    xs = x + h * k3;
    if (jacobian) dx = I + h * D3;
    stage(xs, ts + h, k4, jacobian ? &D4 : nullptr, &dx);
    x += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    if (!limits_.empty()) apply_limits(limits_, x);
    if (jacobian) J = ((I + (h / 6.0) * (D1 + 2.0 * D2 + 2.0 * D3 + D4)) * J).eval();
  }
  fx = x;
  if (jacobian) F = J;
  set_state(x_start.data());
  vars_[t_slot] = t0;
}

void ModelEval::continuous_noise() {
  // No noise enters (a world whose plant is deterministic, seed 003's beam): Q = 0 without the
  // matrix exponential of Van Loan's method, which was 40 % of such a closed loop's time.
  if (Qc.isZero(0.0) || G.isZero(0.0)) {
    Q.setZero(spec_.n(), spec_.n());
    return;
  }
  A_state_.eval();
  auto d = van_loan(A, MatX(), G, Qc, dt_);
  if (d) {
    Q = d->Q;
  } else {
    Q.setConstant(std::numeric_limits<double>::quiet_NaN());  // caught by the noise check
  }
}

}  // namespace kfw::model
