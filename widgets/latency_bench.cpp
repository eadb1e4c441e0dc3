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
  // Q (a variance) is what users drag most; every scenario has it.
  const auto& values = w.paramPanel()->values();
  const std::string key = values.count("Q") ? "Q" : values.begin()->first;
  const double base = values.at(key);
  for (int i = 0; i < changes; ++i) {
    // Walk a decade up and down around the preset value: a drag.
    const double f = std::pow(10.0, std::sin(6.283185307 * i / 40.0));
    QElapsedTimer t;
    t.start();
    w.setParam(key, base * f * (1.0 + 1e-6 * i));
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
