#include "latency_bench.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <algorithm>
#include <cmath>

#include "main_window.h"
#include "param_panel.h"

namespace kfw {

LatencyStats measureLatency(MainWindow& w, int changes) {
  LatencyStats s;
  w.waitForRun();
  if (!w.paramPanel()) return s;
  const std::string key = w.primaryParameter();
  const ParamSpec* spec = w.scenario()->params().find(key);
  const double base = w.paramPanel()->values().at(key);
  for (int i = 0; i < changes; ++i) {
    // Walk a decade up and down around the preset value: a drag.
    // Log parameters a decade up and down, linear ones ±20 % of their range, kept in range.
    const double phase = std::sin(6.283185307 * i / 40.0) + 1e-6 * i;
    double v = spec->scale == Scale::kLog ? base * std::pow(10.0, phase)
                                          : base + 0.2 * phase * (spec->max - spec->min);
    v = std::clamp(v, spec->min, spec->max);
    QElapsedTimer t;
    t.start();
    w.setParam(key, v);
    w.waitForRun();
    QCoreApplication::processEvents();  // the repaint of every plot
    s.samples_ms.push_back(static_cast<double>(t.nsecsElapsed()) / 1e6);
  }
  auto v = s.samples_ms;
  std::sort(v.begin(), v.end());
  auto pct = [&](double p) { return v[static_cast<std::size_t>(std::floor(p * (v.size() - 1)))]; };
  s.p50_ms = pct(0.50);
  s.p95_ms = pct(0.95);
  s.max_ms = v.back();
  return s;
}

}  // namespace kfw
