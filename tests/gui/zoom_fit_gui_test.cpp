// A plot zoomed in time fits its value axis to what is in view, through re-runs: inspecting a
// transient does not leave it a sliver of an axis sized for the whole run.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"
#include "plot_kit.h"

namespace kfw {
namespace {

using testing::plotNamed;

TEST(ZoomFit, TimeZoomedPlotFitsItsValuesInView) {
  MainWindow w;
  w.resize(1400, 900);
  w.show();
  ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/helicopter.json").ok());
  ASSERT_TRUE(w.waitForRun());
  QCustomPlot* angle = plotNamed(w, "state.theta");
  ASSERT_TRUE(angle);
  const QCPRange whole = angle->yAxis->range();
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r);
  // Zoom the time axis only, to 4 % of the run in its middle, then re-run with another R.
  const double t0 = r->t.front(), t1 = r->t.back();
  const double lo = t0 + 0.48 * (t1 - t0), hi = t0 + 0.52 * (t1 - t0);
  angle->xAxis->setRange(lo, hi);
  plot::setUserZoom(angle, true, false);
  w.setParam("R", w.values().at("R") * 4.0);
  ASSERT_TRUE(w.waitForRun());
  r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  EXPECT_DOUBLE_EQ(angle->xAxis->range().lower, lo);
  EXPECT_DOUBLE_EQ(angle->xAxis->range().upper, hi);
  // The estimate and the truth in view, from the run's arrays.
  double vmin = INFINITY, vmax = -INFINITY;
  for (std::size_t k = 0; k < r->t.size(); ++k) {
    if (r->t[k] < lo || r->t[k] > hi) continue;
    for (double v : {r->x[0][k], r->truth[0][k]}) {
      if (!std::isfinite(v)) continue;
      vmin = std::min(vmin, v);
      vmax = std::max(vmax, v);
    }
  }
  ASSERT_LT(vmin, vmax);
  const QCPRange y = angle->yAxis->range();
  EXPECT_LE(y.lower, vmin);
  EXPECT_GE(y.upper, vmax);
  // Fitted to the view (with the band, the sensor's dots and margins), not to the whole run.
  EXPECT_LT(y.size(), 0.6 * whole.size()) << y.size() << " vs " << whole.size();
}

}  // namespace
}  // namespace kfw
