#include "model/world/model_world_noise.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "model/model_eval.h"

namespace kfw::model::detail {

Expected<double> param_value(const Expr& e, const ModelSpec& spec, std::vector<double>& vars,
                             const std::string& key) {
  double v = e.value;
  if (e.dep != Dep::kConst) {
    ExprGroup g;
    g.add(e.text, &v);
    if (auto st = g.bind(spec.symbols, vars.data()); !st) return st.err();
    g.eval();
  }
  if (!std::isfinite(v)) {
    return Error{spec.path + ": " + key + ": " + number(v) + " at the parameters' values"};
  }
  return v;
}

Expected<NoiseSources> NoiseSources::create(const ModelSpec& world, std::vector<double>& vars,
                                            std::uint64_t seed, double dt, double duration,
                                            std::size_t max_windows) {
  NoiseSources out;
  for (const auto& spec : world.noise) {
    const std::string key = "model.world.noise." + spec.name;
    Source s{&spec, RandomStream(seed, "noise." + spec.name)};
    const auto value = [&](const Expr& e, const char* k, double& to) -> Status {
      auto v = param_value(e, world, vars, key + "." + k);
      if (!v) return v.err();
      to = *v;
      return Ok{};
    };
    double tau = 1.0;
    for (auto [e, k, to] :
         {std::tuple{&spec.sigma, "sigma", &s.sigma}, std::tuple{&spec.lo, "min", &s.lo},
          std::tuple{&spec.hi, "max", &s.hi}, std::tuple{&spec.hold, "hold", &s.hold},
          std::tuple{&spec.tau, "tau", &tau}}) {
      if (auto st = value(*e, k, *to); !st) return st.err();
    }
    const auto bad = [&](const char* k, const std::string& what) {
      return Error{world.path + ": " + key + "." + k + ": " + what};
    };
    if (s.sigma < 0.0) return bad("sigma", number(s.sigma) + ": expected ≥ 0");
    if (s.hold < 0.0) return bad("hold", number(s.hold) + " s: expected ≥ 0 (0: held for the run)");
    if (!(tau > 0.0)) return bad("tau", number(tau) + " s: expected a correlation time > 0");
    if (spec.uniform && !(s.hi >= s.lo)) return bad("max", "below min");
    if (spec.held_once) s.hold = 0.0;
    if (s.hold > 0.0 && duration / s.hold > static_cast<double>(max_windows)) {
      return bad("hold", number(s.hold) + " s: more than " + std::to_string(max_windows) +
                             " windows over sim.duration");
    }
    if (spec.kind == NoiseKind::kRandomWalk) {
      s.a = 1.0;
      s.b = s.sigma * std::sqrt(dt);
    } else if (spec.kind == NoiseKind::kGaussMarkov) {
      s.a = std::exp(-dt / tau);
      s.b = s.sigma * std::sqrt(-std::expm1(-2.0 * dt / tau));
    }
    out.sources_.push_back(std::move(s));
  }
  return out;
}

double NoiseSources::draw(Source& s) {
  if (s.spec->uniform) return s.lo + (s.hi - s.lo) * s.stream.uniform();
  return s.sigma * s.stream.normal();
}

void NoiseSources::step(std::size_t j) {
  for (auto& s : sources_) {
    switch (s.spec->kind) {
      case NoiseKind::kWhite:
        s.value = draw(s);
        break;
      case NoiseKind::kHeld:
        break;
      case NoiseKind::kRandomWalk:
        s.value = j == 0 ? 0.0 : s.value + s.b * s.stream.normal();
        break;
      case NoiseKind::kGaussMarkov:
        s.value = j == 0 ? draw(s) : s.a * s.value + s.b * s.stream.normal();
        break;
    }
  }
}

void NoiseSources::at_time(double t) {
  for (auto& s : sources_) {
    if (s.spec->kind != NoiseKind::kHeld) continue;
    const double w = s.hold > 0.0 ? std::floor(t / s.hold) : 0.0;
    const auto window = static_cast<std::size_t>(std::clamp(w, 0.0, 1e15));
    while (s.held.size() <= window)
      s.held.push_back(draw(s));
    s.value = s.held[window];
  }
}

void NoiseSources::write(double* vars) const {
  for (const auto& s : sources_)
    vars[static_cast<std::size_t>(s.spec->slot)] = s.value;
}

Expected<std::vector<double>> clock_ticks(const ClockSpec& clock, const ModelSpec& world,
                                          std::vector<double>& vars, std::uint64_t seed,
                                          double duration, std::size_t max_ticks) {
  const std::string key = "model.world.clocks." + clock.name;
  double v[4];
  const std::pair<const Expr*, const char*> fields[4] = {{&clock.period, "period"},
                                                         {&clock.offset, "offset"},
                                                         {&clock.jitter, "jitter"},
                                                         {&clock.resolution, "resolution"}};
  for (int i = 0; i < 4; ++i) {
    auto x = param_value(*fields[i].first, world, vars, key + "." + fields[i].second);
    if (!x) return x.err();
    v[i] = *x;
  }
  const double period = v[0], offset = v[1], jitter = v[2], resolution = v[3];
  if (!(period > 0.0)) return Error{world.path + ": " + key + ".period: expected > 0 s"};
  for (int i = 1; i < 4; ++i) {
    if (v[i] < 0.0) {
      return Error{world.path + ": " + key + "." + fields[i].second + ": expected ≥ 0 s"};
    }
  }
  if (duration / period > static_cast<double>(max_ticks)) {
    return Error{world.path + ": " + key + ".period: more than " + std::to_string(max_ticks) +
                 " ticks over sim.duration"};
  }
  RandomStream stream(seed, "clock." + clock.name);
  std::vector<double> ticks;
  double t = offset;
  while (t <= duration + 1e-9) {
    ticks.push_back(resolution > 0.0 ? std::round(t / resolution) * resolution : t);
    const double step = jitter > 0.0 ? period + jitter * stream.normal() : period;
    t += std::max(step, 0.1 * period);
  }
  return ticks;
}

std::vector<Outlier> draw_outliers(std::vector<Sample> samples, bool by_count, double amount,
                                   double size, std::uint64_t seed, const std::string& group) {
  RandomStream stream(seed, "outliers." + group);
  std::vector<Outlier> out;
  const auto sign = [&] { return stream.uniform() < 0.5 ? -size : size; };
  if (by_count) {
    const std::size_t n = samples.size();
    const auto count = std::min(n, static_cast<std::size_t>(std::max(0.0, amount)));
    for (std::size_t i = 0; i < count; ++i) {
      const auto left = static_cast<double>(n - i);
      const auto pick = std::min(static_cast<std::size_t>(stream.uniform() * left), n - i - 1);
      std::swap(samples[i], samples[i + pick]);
      out.push_back({samples[i], sign()});
    }
    return out;
  }
  for (const Sample& s : samples) {
    if (stream.uniform() < amount) out.push_back({s, sign()});
  }
  return out;
}

}  // namespace kfw::model::detail
