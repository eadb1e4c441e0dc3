#include "model/model_sim.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/random.h"
#include "filter/angle.h"
#include "model/model_eval.h"

namespace kfw::model {

bool psd_sqrt(const MatX& M, MatX& L) {
  if (M.size() == 0) {
    L.resize(0, 0);
    return true;
  }
  if (!M.allFinite()) return false;
  Eigen::LLT<MatX> llt(M);
  if (llt.info() == Eigen::Success) {
    L = llt.matrixL();
    return true;
  }
  if (!is_psd(M)) return false;
  Eigen::SelfAdjointEigenSolver<MatX> es(M);
  L = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  return true;
}

Expected<Dataset> simulate_model(const ModelSpec& spec, const ParamValues& values,
                                 const std::string& name) {
  const double seed = param(values, "sim.seed");
  const double duration = param(values, "sim.duration");
  const double dt = param(values, "sim.dt");
  if (!(dt > 0.0) || !(duration >= 0.0)) {
    return Error{"sim.dt must be positive and sim.duration not negative"};
  }
  // Samples at 0, dt, ... up to the duration, and at least two: a filter needs one step (a
  // duration shorter than dt, both inside their ranges, still gives a run).
  const auto rows =
      std::max<std::size_t>(static_cast<std::size_t>(std::floor(duration / dt + 1e-9)) + 1, 2);
  if (rows > 50'000'000) return Error{"sim.duration / sim.dt: more than 50 million rows"};
  auto evr = ModelEval::create(spec, values);
  if (!evr) return evr.err();
  ModelEval& ev = **evr;
  if (auto st = ev.check_dt(dt, "sim.dt"); !st) return st.err();

  // The inputs' simulation expressions, bound to a copy of the symbols (parameters set).
  std::vector<double> vars = ev.vars();
  const auto t_slot = static_cast<std::size_t>(spec.t_slot);
  const std::size_t nu = spec.inputs.size();
  std::vector<double> u(nu, 0.0), u_prev(nu, 0.0);
  ExprGroup input_sim;
  for (std::size_t i = 0; i < nu; ++i)
    input_sim.add(spec.inputs[i].sim.text, &u[i]);
  if (auto st = input_sim.bind(spec.symbols, vars.data()); !st) return st.err();

  Dataset d;
  d.source = "simulated " + name + ", seed " + std::to_string(static_cast<long long>(seed));
  d.add("t", rows);
  for (const auto& in : spec.inputs)
    d.add(in.name, rows);
  for (const auto& c : spec.channels) {
    for (const auto& r : c.roles)
      d.add(r.name, rows);
  }
  const int n = spec.n();
  for (int i = 0; i < n; ++i) {
    if (!spec.truth[static_cast<std::size_t>(i)].empty()) {
      d.add(spec.truth[static_cast<std::size_t>(i)], rows);
    }
  }

  // One stream per noise source (core/random.h): x0, the process, each channel.
  const auto seed_bits = static_cast<std::uint64_t>(seed);
  RandomStream x0_stream(seed_bits, "x0"), process_stream(seed_bits, "process");
  std::vector<RandomStream> channel_streams;
  for (const auto& c : spec.channels)
    channel_streams.emplace_back(seed_bits, "channel." + c.name);
  auto draw = [](RandomStream& r, Eigen::Index m) {
    VecX v(m);
    for (Eigen::Index i = 0; i < m; ++i)
      v(i) = r.normal();
    return v;
  };
  auto fail = [&](std::size_t k, const std::string& what) -> Error {
    std::ostringstream os;
    os << "simulation, step " << k << " (t = " << static_cast<double>(k) * dt << " s): " << what;
    return failure(os.str());
  };

  if (auto st = ev.set_dt(dt); !st) return fail(0, st.error());
  MatX L;
  if (!psd_sqrt(ev.P0, L)) return Error{spec.path + ": model.P0: not positive semidefinite"};
  VecX x = ev.x0 + L * draw(x0_stream, n);
  MatX Lq;
  bool lq_valid = false;
  const bool nonlinear = spec.nonlinear_process();
  std::vector<MatX> Lr(spec.channels.size());
  std::vector<bool> lr_valid(spec.channels.size(), false);

  for (std::size_t k = 0; k < rows; ++k) {
    const double tk = static_cast<double>(k) * dt;
    vars[t_slot] = tk;
    input_sim.eval();
    d.columns[0][k] = tk;
    for (std::size_t i = 0; i < nu; ++i)
      d.columns[1 + i][k] = u[i];
    if (k > 0) {
      // x_k = F x_{k−1} + B u_{k−1} (or f) + w, w ~ N(0, Q).
      if (auto st = ev.set_dt(dt); !st) return fail(k, st.error());
      ev.set_time(tk - dt);
      ev.set_inputs(u_prev.data());
      ev.process_step();
      ev.set_state(x.data());
      VecX next;
      if (nonlinear) {
        ev.process_f();
        next = ev.fx;
      } else {
        next = ev.F * x;
        for (std::size_t i = 0; i < nu; ++i)
          next += ev.B.col(static_cast<Eigen::Index>(i)) * u_prev[i];
      }
      ev.process_noise();
      if (!lq_valid || ev.process_noise_varies()) {
        if (!psd_sqrt(ev.Q, Lq)) return fail(k, "model.process.Q is not positive semidefinite");
        lq_valid = true;
      }
      x = next + Lq * draw(process_stream, n);
      for (int i = 0; i < n; ++i)
        x(i) = wrap(x(i), spec.states[static_cast<std::size_t>(i)].angle);
      if (!x.allFinite()) return fail(k, "the simulated state is not finite");
    }
    u_prev = u;
    ev.set_time(tk);
    ev.set_inputs(u.data());
    ev.set_state(x.data());
    std::size_t col = 1 + nu;
    for (std::size_t c = 0; c < spec.channels.size(); ++c) {
      const ChannelSpec& cs = spec.channels[c];
      const auto m = static_cast<std::size_t>(cs.size());
      auto& ch = ev.channel(c);
      if (k % static_cast<std::size_t>(ch.every) == 0) {
        // z = h(x) + v (or H x + v), v ~ N(0, R).
        ev.channel_step(c);
        ev.channel_noise(c);
        VecX z;
        if (cs.linear) {
          z = ch.H * x;
        } else {
          ev.channel_h(c);
          z = ch.hx;
        }
        if (!lr_valid[c] || ch.R_varies) {
          if (!psd_sqrt(ch.R, Lr[c])) {
            return fail(k, cs.R.key + " is not positive semidefinite");
          }
          lr_valid[c] = true;
        }
        z += Lr[c] * draw(channel_streams[c], cs.size());
        for (std::size_t j = 0; j < m; ++j) {
          d.columns[col + j][k] = wrap(z(static_cast<Eigen::Index>(j)), cs.roles[j].angle);
        }
      }
      col += m;
    }
    for (int i = 0; i < n; ++i) {
      if (!spec.truth[static_cast<std::size_t>(i)].empty()) d.columns[col++][k] = x(i);
    }
  }
  return d;
}

}  // namespace kfw::model
