// Reading what a window's plots hold, for GUI tests.
#pragma once

#include <qcustomplot.h>

#include <QImage>
#include <cstdlib>
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

// Pixels of an exported image (every third row and column) whose colour is clearly not grey: a
// plot with drawn data has many, an empty or flat one almost none. -1 when the file is no image.
inline int colouredPixels(const QString& file) {
  const QImage img(file);
  if (img.isNull()) return -1;
  int coloured = 0;
  for (int y = 0; y < img.height(); y += 3) {
    for (int x = 0; x < img.width(); x += 3) {
      const QColor c = img.pixelColor(x, y);
      coloured += std::abs(c.red() - c.blue()) > 40 || std::abs(c.green() - c.blue()) > 40;
    }
  }
  return coloured;
}

}  // namespace kfw::testing
