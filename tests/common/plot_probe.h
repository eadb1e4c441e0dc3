// Reading what a window's plots hold, for GUI tests.
#pragma once

#include <qcustomplot.h>

#include <vector>

#include "main_window.h"

namespace kfw::testing {

inline QCustomPlot* plotNamed(const MainWindow& w, const QString& name) {
  for (const auto& p : w.plots()) {
    if (p.name == name) return p.plot;
  }
  return nullptr;
}

inline QCPGraph* graphNamed(QCustomPlot* p, const QString& name) {
  if (!p) return nullptr;
  for (int i = 0; i < p->graphCount(); ++i) {
    if (p->graph(i)->name() == name) return p->graph(i);
  }
  return nullptr;
}

inline std::vector<double> graphValues(QCPGraph* g) {
  std::vector<double> v;
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it)
    v.push_back(it->value);
  return v;
}

}  // namespace kfw::testing
