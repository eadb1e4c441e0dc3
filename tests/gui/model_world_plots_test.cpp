// Issue 27 (model files, part 2) in the window: a channel of two components gets its whiteness
// per component in the Consistency tab; an angle's lines break at its wrap instead of crossing
// the plot; each gain entry carries its unit.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QFile>
#include <QTemporaryDir>
#include <cmath>
#include <numbers>

#include "common/plot_probe.h"
#include "consistency_panel.h"
#include "main_window.h"
#include "transport_bar.h"

namespace kfw {
namespace model_world_plots_gui_test {
namespace {

using testing::graphNamed;
using testing::plotNamed;

QString modelPreset(const char* name) {
  return QString(KFW_SOURCE_DIR) + "/presets/models/" + name + ".json";
}

// A heading that turns at 1 rad/s for 20 s: wrapped to (−π, π], it crosses ±π three times.
const char* const kSpin = R"({
  "format": "kfw-preset", "version": 2, "scenario": "model", "title": "Spin",
  "parameters": {
    "q": {"value": 1e-4, "min": 1e-8, "max": 1, "unit": "rad²/s³", "scale": "log"},
    "sigma": {"value": 0.05, "min": 1e-4, "max": 1, "unit": "rad", "scale": "log"},
    "omega0": {"value": 1.0, "min": -5, "max": 5, "unit": "rad/s"},
    "sim.dt": {"value": 0.1, "min": 0.001, "max": 1, "unit": "s", "scale": "log"},
    "sim.duration": {"value": 20, "min": 1, "max": 100, "unit": "s"}
  },
  "model": {
    "version": 1,
    "states": [{"name": "theta", "unit": "rad", "angle": "rad"}, {"name": "omega", "unit": "rad/s"}],
    "x0": ["0", "omega0"],
    "P0": ["1e-4", "1e-4"],
    "process": {"F": [["1", "dt"], ["0", "1"]],
                "Q": [["q*dt^3/3", "q*dt^2/2"], ["q*dt^2/2", "q*dt"]]},
    "measurements": {"heading": {"roles": [{"name": "psi", "unit": "rad", "angle": "rad"}],
                                 "H": [["1", "0"]], "R": ["sigma^2"]}},
    "truth": {"theta": "theta_true", "omega": "omega_true"}
  }
})";

struct Jumps {
  int gaps = 0;          // NaN points
  double largest = 0.0;  // largest step between consecutive drawn points
};
Jumps jumpsOf(QCPGraph* g) {
  Jumps j;
  double prev = std::nan("");
  for (auto it = g->data()->constBegin(); it != g->data()->constEnd(); ++it) {
    if (std::isnan(it->value)) {
      ++j.gaps;
    } else if (!std::isnan(prev)) {
      j.largest = std::max(j.largest, std::abs(it->value - prev));
    }
    prev = it->value;
  }
  return j;
}

TEST(ModelWorldWindow, AnAngleStateAndPredictionBreakAtTheWrap) {
  QTemporaryDir dir;
  const QString path = dir.filePath("spin.json");
  {
    QFile f(path);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write(kSpin);
  }
  MainWindow w;
  auto st = w.loadPreset(path);
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun(60000));
  ASSERT_TRUE(w.result()) << w.lastError().toStdString();
  constexpr double kHalfTurn = std::numbers::pi;

  QCustomPlot* state = plotNamed(w, "state.theta");
  ASSERT_NE(state, nullptr);
  QCPGraph* est = graphNamed(state, "estimate of theta");
  ASSERT_NE(est, nullptr);
  const Jumps e = jumpsOf(est);
  EXPECT_GE(e.gaps, 3) << "the estimate wraps three times";
  EXPECT_LT(e.largest, kHalfTurn) << "no line across the plot";
  // The ±2σ band breaks with it: no graph of the plot draws a line across ±π.
  int broken = 0;
  for (int i = 0; i < state->graphCount(); ++i) {
    const Jumps g = jumpsOf(state->graph(i));
    if (state->graph(i)->data()->size() < 10) continue;  // the cursor's and level lines
    EXPECT_LT(g.largest, kHalfTurn) << state->graph(i)->name().toStdString();
    broken += g.gaps > 0;
  }
  EXPECT_GE(broken, 3) << "estimate and both band edges";

  // The predicted measurement of an angle role: a line, broken at the wrap.
  QCustomPlot* measured = plotNamed(w, "measured.heading.psi");
  ASSERT_NE(measured, nullptr);
  QCPGraph* zhat = graphNamed(measured, "predicted ẑ (before the update)");
  ASSERT_NE(zhat, nullptr);
  EXPECT_NE(zhat->lineStyle(), QCPGraph::lsNone);
  const Jumps z = jumpsOf(zhat);
  EXPECT_GE(z.gaps, 3);
  EXPECT_LT(z.largest, kHalfTurn);

  // Replay shows the steps up to the cursor, gaps included: half the run, one or two wraps.
  w.transport()->seek(100);
  QCoreApplication::processEvents();
  const Jumps half = jumpsOf(est);
  EXPECT_GE(half.gaps, 1);
  EXPECT_LT(half.gaps, e.gaps);
  EXPECT_LE(est->data()->at(est->data()->size() - 1)->key, 10.0 + 1e-9);
}

TEST(ModelWorldWindow, EachGainEntryCarriesItsUnit) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("cv1d"), {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(w.waitForRun(60000));
  QCustomPlot* gain = plotNamed(w, "gain");
  ASSERT_NE(gain, nullptr);
  EXPECT_NE(graphNamed(gain, "K[x, z] (–)"), nullptr);
  EXPECT_NE(graphNamed(gain, "K[v, z] (1/s)"), nullptr);
  EXPECT_EQ(gain->yAxis->label(), "gain (units in the legend)");
  QCustomPlot* curve = plotNamed(w, "gain_curve");
  ASSERT_NE(curve, nullptr);
  EXPECT_NE(graphNamed(curve, "K[v, z] (1/s)"), nullptr);
  EXPECT_EQ(curve->yAxis->label(), "gain (units in the legend)");

  MainWindow rb;
  ASSERT_TRUE(rb.loadPreset(modelPreset("range_bearing"), {}, {"sim.duration=20"}).ok());
  ASSERT_TRUE(rb.waitForRun(60000));
  QCustomPlot* g = plotNamed(rb, "gain");
  ASSERT_NE(g, nullptr);
  EXPECT_NE(graphNamed(g, "K[px, bearing] (m/rad)"), nullptr);
  EXPECT_NE(graphNamed(g, "K[vx, bearing] ((m/s)/rad)"), nullptr);
  EXPECT_NE(graphNamed(g, "K[vy, range] (1/s)"), nullptr);
}

TEST(ModelWorldWindow, AVectorChannelShowsItsComponentsWhiteness) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(modelPreset("range_bearing")).ok());
  ASSERT_TRUE(w.waitForRun(60000));
  w.consistency()->refresh();
  const QString text = w.consistency()->summary();
  EXPECT_TRUE(text.contains("Ljung–Box p per component: range")) << text.toStdString();
  EXPECT_TRUE(text.contains("bearing")) << text.toStdString();
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->filter("_consistency_whiteness.radar").size(), 1);
}

}  // namespace
}  // namespace model_world_plots_gui_test
}  // namespace kfw
