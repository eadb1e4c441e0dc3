#include "latency_bench.h"

#include <qcustomplot.h>
#include <QApplication>
#include <QCoreApplication>
#include <QElapsedTimer>
#include <QMouseEvent>
#include <algorithm>
#include <cmath>
#include <ctime>

#include "main_window.h"
#include "param_panel.h"
#include "plot_kit.h"

namespace kfw {

namespace {
// CPU time of every thread of the process: the GUI thread, the run's worker and the drawing
// helper (draw_batch.h).
double processCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::floor(p * static_cast<double>(v.size() - 1)))];
}
}  // namespace

LatencyStats measureLatency(MainWindow& w, int changes) {
  LatencyStats s;
  w.waitForRun();
  if (!w.paramPanel()) return s;
  const std::string key = w.primaryParameter();
  const ParamSpec* spec = w.scenario()->params().find(key);
  const double base = w.paramPanel()->values().at(key);
  std::vector<double> cpu;
  for (int i = 0; i < changes; ++i) {
    // Walk a decade up and down around the preset value: a drag.
    // Log parameters a decade up and down, linear ones ±20 % of their range, kept in range.
    const double phase = std::sin(6.283185307 * i / 40.0) + 1e-6 * i;
    double v = spec->scale == Scale::kLog ? base * std::pow(10.0, phase)
                                          : base + 0.2 * phase * (spec->max - spec->min);
    v = std::clamp(v, spec->min, spec->max);
    QElapsedTimer t;
    t.start();
    const double cpu0 = processCpuMs();
    w.setParam(key, v);
    w.waitForRun();
    QCoreApplication::processEvents();  // the repaint of every plot
    s.samples_ms.push_back(static_cast<double>(t.nsecsElapsed()) / 1e6);
    cpu.push_back(processCpuMs() - cpu0);
  }
  s.p50_ms = percentile(s.samples_ms, 0.50);
  s.p95_ms = percentile(s.samples_ms, 0.95);
  s.max_ms = percentile(s.samples_ms, 1.0);
  s.cpu_p50_ms = percentile(cpu, 0.50);
  s.cpu_p95_ms = percentile(cpu, 0.95);
  // The readout: 100 mouse moves across the first time plot's data.
  QCustomPlot* p = nullptr;
  for (const auto& panel : w.plots()) {
    if (plot::isTimePlot(panel.plot) && panel.plot->isVisible()) {
      p = panel.plot;
      break;
    }
  }
  if (p) {
    std::vector<double> moves;
    const QRect r = p->axisRect()->rect();
    for (int i = 0; i < 100; ++i) {
      const QPointF at(r.left() + 2 + (r.width() - 4) * (i % 50) / 49.0, r.center().y());
      QElapsedTimer t;
      t.start();
      QMouseEvent ev(QEvent::MouseMove, at, p->mapToGlobal(at), Qt::NoButton, Qt::NoButton,
                     Qt::NoModifier);
      QApplication::sendEvent(p, &ev);
      QCoreApplication::processEvents();  // the repaint
      moves.push_back(static_cast<double>(t.nsecsElapsed()) / 1e6);
    }
    s.readout_p50_ms = percentile(moves, 0.50);
    s.readout_p95_ms = percentile(moves, 0.95);
  }
  return s;
}

}  // namespace kfw
