// The radome window driven as a user would, offscreen: the grid's sliders change the run, the heat
// map follows the replay cursor, export writes every plot, a bad grid shows an error. Since issue
// 28 presets/radome.json is seed 001's model file in the generic model view; each test below is
// the built-in view's, held against that view's panels (the built-in's panel → the model view's:
// slope_psi/slope_theta → grid.R_psi/grid.R_theta, refraction_error → refraction, los →
// los_errors, mode_top → mode_probabilities, innovation → innovation.seeker.Yx/Yy/Yz, the grid
// editor's spin boxes → the parameter panel's).
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QDoubleSpinBox>
#include <QImage>
#include <QTemporaryDir>
#include <algorithm>
#include <cmath>

#include "common/plot_probe.h"
#include "common/time_scale.h"
#include "main_window.h"
#include "model/imm/imm_spec.h"
#include "model/model_result.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::plotNamed;

QCPColorMap* colorMap(QCustomPlot* p) {
  for (int i = 0; p && i < p->plottableCount(); ++i) {
    if (auto* m = qobject_cast<QCPColorMap*>(p->plottable(i))) return m;
  }
  return nullptr;
}

std::shared_ptr<const model::ModelResult> radomeResult(const MainWindow& w) {
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  return r && r->imm && r->imm->axes.size() == 2 ? r : nullptr;
}

QMap<double, QString> ticksOf(QCPAxis* a) {
  auto t = a->ticker().dynamicCast<QCPAxisTickerText>();
  return t ? t->ticks() : QMap<double, QString>{};
}

class RadomeWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/radome.json").ok());
    ASSERT_TRUE(w.waitForRun(60000));
    ASSERT_TRUE(radomeResult(w));
  }
  MainWindow w;
};

TEST_F(RadomeWindow, HasEveryPlotOfTheIssue) {
  for (const char* name :
       {"grid.R_psi", "grid.R_theta", "refraction", "los_errors", "slope_errors", "mode_heatmap",
        "mode_probabilities", "innovation.seeker.Yx", "nis.seeker"}) {
    EXPECT_NE(plotNamed(w, name), nullptr) << name;
  }
  // The grid's slope values, readable (the built-in's grid-values label; here the heat map's
  // ticks on the 7 values).
  const auto x = ticksOf(plotNamed(w, "mode_heatmap")->xAxis).values();
  EXPECT_TRUE(x.contains("-0.050")) << x.join(' ').toStdString();
  EXPECT_TRUE(x.contains("0.017")) << x.join(' ').toStdString();
}

TEST_F(RadomeWindow, GridEditorChangesTheModeCount) {
  auto* n_psi = w.findChild<QDoubleSpinBox*>("spin.grid.n_psi");
  ASSERT_NE(n_psi, nullptr);
  EXPECT_EQ(n_psi->value(), 7);
  n_psi->setValue(5);
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_EQ(w.values().at("grid.n_psi"), 5.0);
  auto r = radomeResult(w);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->imm->modes(), 35u);
  QCPColorMap* map = colorMap(plotNamed(w, "mode_heatmap"));
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->data()->keySize(), 5);
  EXPECT_EQ(map->data()->valueSize(), 7);
}

TEST_F(RadomeWindow, RenewalMovesTheGridCentre) {
  QCPGraph* lower = nullptr;  // the grid envelope's lower edge
  QCustomPlot* p = plotNamed(w, "grid.R_psi");
  ASSERT_NE(p, nullptr);
  for (int i = 0; i < p->graphCount(); ++i) {
    if (p->graph(i)->channelFillGraph()) lower = p->graph(i);
  }
  ASSERT_NE(lower, nullptr);
  auto spread = [&] {
    double lo = 1e9, hi = -1e9;
    for (auto it = lower->data()->constBegin(); it != lower->data()->constEnd(); ++it) {
      lo = std::min(lo, it->value);
      hi = std::max(hi, it->value);
    }
    return hi - lo;
  };
  EXPECT_EQ(spread(), 0.0);  // Kp = 0 in the preset
  w.setParam("Kp", 0.45);
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_EQ(w.values().at("Kp"), 0.45);
  EXPECT_GT(spread(), 0.05);
}

TEST_F(RadomeWindow, HeatMapFollowsTheReplayCursor) {
  auto r = radomeResult(w);
  QCPColorMap* map = colorMap(plotNamed(w, "mode_heatmap"));
  ASSERT_TRUE(r && map);
  for (std::size_t k : {std::size_t{100}, std::size_t{700}}) {
    w.transport()->seek(k);
    ASSERT_EQ(r->imm->modes(), 49u);
    for (std::size_t j : {0u, 24u, 48u}) {
      const double expect = std::log10(std::max(static_cast<double>(r->imm->mu_at(k, j)), 1e-8));
      EXPECT_NEAR(map->data()->cell(static_cast<int>(j % 7), static_cast<int>(j / 7)), expect, 1e-9)
          << "step " << k << " mode " << j;
    }
  }
}

TEST_F(RadomeWindow, HeatMapTicksSitOnTheGridSlopes) {
  QCustomPlot* heat = plotNamed(w, "mode_heatmap");
  ASSERT_NE(heat, nullptr);
  // The grid's values along an axis at step k (moved by renewal).
  auto grid = [&](std::size_t axis, std::size_t k) {
    auto r = radomeResult(w);
    const auto& a = r->imm->axes[axis];
    std::vector<double> v;
    for (double x : a.values) {
      if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
    }
    std::sort(v.begin(), v.end());
    for (double& x : v)
      x += a.centre[k] - a.centre.front();
    return v;
  };
  auto expect_on_grid = [&](std::size_t k) {
    const auto gp = grid(0, k), gt = grid(1, k);
    const auto tp = ticksOf(heat->xAxis), tt = ticksOf(heat->yAxis);
    ASSERT_EQ(tp.size(), static_cast<int>(gp.size())) << "step " << k;
    ASSERT_EQ(tt.size(), static_cast<int>(gt.size())) << "step " << k;
    int i = 0;
    for (auto it = tp.constBegin(); it != tp.constEnd(); ++it, ++i) {
      EXPECT_NEAR(it.key(), gp[static_cast<std::size_t>(i)], 1e-12);
      EXPECT_EQ(it.value(),
                QString::fromStdString(model::grid_value_text(gp[static_cast<std::size_t>(i)], 3)));
    }
    i = 0;
    for (auto it = tt.constBegin(); it != tt.constEnd(); ++it, ++i)
      EXPECT_NEAR(it.key(), gt[static_cast<std::size_t>(i)], 1e-12);
  };
  expect_on_grid(radomeResult(w)->steps() - 1);
  EXPECT_TRUE(ticksOf(heat->xAxis).values().contains("-0.017"));
  EXPECT_TRUE(ticksOf(heat->xAxis).values().contains("0.000"));
  // The grid moves with renewal: the ticks follow it at the replay cursor.
  w.setParam("Kp", 0.45);
  ASSERT_TRUE(w.waitForRun(60000));
  for (std::size_t k : {std::size_t{300}, std::size_t{900}}) {
    w.transport()->seek(k);
    expect_on_grid(k);
  }
  // More than 9 values on an axis: the normal ticker there.
  w.setParam("grid.n_psi", 11);
  ASSERT_TRUE(w.waitForRun(60000 * testing::kTimeScale));  // 77 modes
  EXPECT_TRUE(ticksOf(heat->xAxis).isEmpty());
  EXPECT_EQ(ticksOf(heat->yAxis).size(), 7);
}

TEST_F(RadomeWindow, SnapshotDrawsGhostSlopesAndRefractionError) {
  w.pinSnapshot("plain");
  w.setParam("Kp", 0.45);
  ASSERT_TRUE(w.waitForRun(60000));
  const std::pair<const char*, const char*> ghosts[] = {
      {"grid.R_psi", "estimate [pinned: plain]"},
      {"grid.R_theta", "estimate [pinned: plain]"},
      {"refraction", "refraction-angle error [pinned: plain]"}};
  for (const auto& [plot, name] : ghosts) {
    QCPGraph* g = graphNamed(plotNamed(w, plot), QString::fromUtf8(name));
    ASSERT_NE(g, nullptr) << name;
    EXPECT_GT(g->data()->size(), 100) << name;
    EXPECT_TRUE(std::isfinite((g->data()->constEnd() - 1)->value)) << name;
  }
  // The ghost holds the pinned (Kp = 0) estimate, not the live (Kp = 0.45) one.
  auto r = radomeResult(w);
  QCPGraph* ghost = graphNamed(plotNamed(w, "grid.R_psi"), "estimate [pinned: plain]");
  double diff = 0.0;
  for (auto it = ghost->data()->constBegin(); it != ghost->data()->constEnd(); ++it) {
    const auto k = static_cast<std::size_t>(
        std::lower_bound(r->t.begin(), r->t.end(), it->key - 1e-9) - r->t.begin());
    ASSERT_LT(k, r->steps());
    if (std::isfinite(it->value) && std::isfinite(r->imm->axes[0].estimate[k]))
      diff = std::max(diff, std::abs(it->value - r->imm->axes[0].estimate[k]));
  }
  EXPECT_GT(diff, 1e-3);
  // Cut at the replay cursor like the live curves.
  w.transport()->seek(200);
  EXPECT_LE((ghost->data()->constEnd() - 1)->key, r->t[200] + 1e-9);
  EXPECT_GE((ghost->data()->constEnd() - 1)->key, r->t[190]);
  // A new snapshot list replaces the ghosts; an empty one removes them.
  w.pinSnapshot("renewal");
  EXPECT_NE(graphNamed(plotNamed(w, "grid.R_psi"), "estimate [pinned: renewal]"), nullptr);
  EXPECT_NE(graphNamed(plotNamed(w, "grid.R_psi"), "estimate [pinned: plain]"), nullptr);
  w.clearSnapshots();
  for (const auto& [plot, name] : ghosts)
    EXPECT_EQ(graphNamed(plotNamed(w, plot), QString::fromUtf8(name)), nullptr) << name;
  EXPECT_EQ(graphNamed(plotNamed(w, "grid.R_psi"), "estimate [pinned: renewal]"), nullptr);
}

TEST_F(RadomeWindow, GridEnvelopeLegendShowsAFilledSwatch) {
  QCustomPlot* p = plotNamed(w, "grid.R_psi");
  int entries = 0;
  for (int i = 0; i < p->legend->itemCount(); ++i) {
    auto* item = qobject_cast<QCPPlottableLegendItem*>(p->legend->item(i));
    if (!item || item->plottable()->name() != "grid envelope") continue;
    ++entries;
    // The icon is a filled swatch, not a line: most of its pixels are painted.
    p->replot();
    const QImage img = p->toPixmap().toImage();
    const QRect icon(item->rect().topLeft(), p->legend->iconSize());
    int painted = 0;
    for (int y = icon.top(); y <= icon.bottom(); ++y) {
      for (int x = icon.left(); x <= icon.right(); ++x) {
        if (qGray(img.pixel(x, y)) < 245) ++painted;
      }
    }
    EXPECT_GT(painted, icon.width() * icon.height() / 2) << painted;
  }
  EXPECT_EQ(entries, 1);
}

TEST_F(RadomeWindow, InnovationScaleIgnoresTheStartUpTransient) {
  // The first steps' innovations reach hundreds of metres; each axis shows the settled ones.
  auto r = radomeResult(w);
  const double t_settle = r->t.front() + 0.05 * (r->t.back() - r->t.front());
  const auto& seeker = r->chans.front();
  for (std::size_t c = 0; c < 3; ++c) {
    double settled = 0.0;
    for (std::size_t k = 0; k < r->steps(); ++k) {
      if (r->t[k] < t_settle) continue;
      const double y = seeker.y[c][k], S = seeker.S[c][k];
      if (std::isfinite(y)) settled = std::max({settled, std::abs(y), 2.0 * std::sqrt(S)});
    }
    const std::string name = "innovation.seeker.Y" + std::string(1, "xyz"[c]);
    const QCPRange y = plotNamed(w, QString::fromStdString(name))->yAxis->range();
    EXPECT_LT(y.upper, 2.0 * settled) << name;
    EXPECT_GT(y.upper, settled) << name;
  }
}

TEST_F(RadomeWindow, ExportWritesEveryPlot) {
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), w.exportedPlots().size());
  for (const QString& f : *files) {
    QImage img(f);
    ASSERT_FALSE(img.isNull()) << f.toStdString();
    // Blank plots have next to none; the measured Cartesian x of the pseudo-measurement (a
    // straight rise, 1 201 grey dots over the blue prediction) has the fewest, about 185.
    const int colored = testing::colouredPixels(f);
    EXPECT_GT(colored, 100) << "no coloured content in " << f.toStdString();
  }
}

TEST_F(RadomeWindow, GridEndsCannotCross) {
  // The declared ranges bracket zero (grid.min <= 0 <= grid.max): the editors stop there, so no
  // value an editor accepts reverses the grid.
  auto* mn = w.findChild<QDoubleSpinBox*>("spin.grid.min");
  auto* mx = w.findChild<QDoubleSpinBox*>("spin.grid.max");
  ASSERT_NE(mn, nullptr);
  ASSERT_NE(mx, nullptr);
  EXPECT_EQ(mn->maximum(), 0.0);
  EXPECT_EQ(mx->minimum(), 0.0);
  mn->setValue(0.2);  // held at 0
  EXPECT_EQ(mn->value(), 0.0);
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_TRUE(w.lastError().isEmpty()) << w.lastError().toStdString();
}

}  // namespace
}  // namespace kfw
