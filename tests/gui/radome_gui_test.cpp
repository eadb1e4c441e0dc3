// The radome window driven as a user would, offscreen: the IMM grid editor changes the run, the
// heat map follows the replay cursor, export writes every plot, a bad grid shows an error.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QDoubleSpinBox>
#include <QFile>
#include <QImage>
#include <QLabel>
#include <QSpinBox>
#include <QTemporaryDir>
#include <algorithm>
#include <cmath>

#include "common/plot_probe.h"
#include "common/time_scale.h"
#include "main_window.h"
#include "scenarios/radome/radome_imm.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::plotNamed;

QCPColorMap* colorMap(QCustomPlot* p) {
  for (int i = 0; i < p->plottableCount(); ++i) {
    if (auto* m = qobject_cast<QCPColorMap*>(p->plottable(i))) return m;
  }
  return nullptr;
}

std::shared_ptr<const radome::RadomeResult> radomeResult(const MainWindow& w) {
  return std::dynamic_pointer_cast<const radome::RadomeResult>(w.result());
}

class RadomeWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/radome.json").ok());
    ASSERT_TRUE(w.waitForRun());
    ASSERT_TRUE(radomeResult(w));
  }
  MainWindow w;
};

TEST_F(RadomeWindow, HasEveryPlotOfTheIssue) {
  for (const char* name : {"slope_psi", "slope_theta", "refraction_error", "los", "mode_heatmap",
                           "mode_top", "innovation", "nis"}) {
    EXPECT_NE(plotNamed(w, name), nullptr) << name;
  }
  auto* values = w.findChild<QLabel*>("radome.gridValues");
  ASSERT_NE(values, nullptr);
  EXPECT_TRUE(values->text().contains("-0.0500")) << values->text().toStdString();
  EXPECT_TRUE(values->text().contains("0.0167")) << values->text().toStdString();
}

TEST_F(RadomeWindow, GridEditorChangesTheModeCount) {
  auto* n_psi = w.findChild<QSpinBox*>("radome.grid.n_psi");
  ASSERT_NE(n_psi, nullptr);
  EXPECT_EQ(n_psi->value(), 7);
  n_psi->setValue(5);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("grid.n_psi"), 5.0);
  auto r = radomeResult(w);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->modes(), 35);
  QCPColorMap* map = colorMap(plotNamed(w, "mode_heatmap"));
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->data()->keySize(), 5);
  EXPECT_EQ(map->data()->valueSize(), 7);
}

TEST_F(RadomeWindow, RenewalMovesTheGridCentre) {
  QCPGraph* centre = graphNamed(plotNamed(w, "slope_psi"), "grid centre");
  ASSERT_NE(centre, nullptr);
  auto spread = [&] {
    double lo = 1e9, hi = -1e9;
    for (auto it = centre->data()->constBegin(); it != centre->data()->constEnd(); ++it) {
      lo = std::min(lo, it->value);
      hi = std::max(hi, it->value);
    }
    return hi - lo;
  };
  EXPECT_EQ(spread(), 0.0);  // Kp = 0 in the preset
  auto* kp = w.findChild<QDoubleSpinBox*>("radome.Kp");
  ASSERT_NE(kp, nullptr);
  kp->setValue(0.45);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("Kp"), 0.45);
  EXPECT_GT(spread(), 0.05);
}

TEST_F(RadomeWindow, HeatMapFollowsTheReplayCursor) {
  auto r = radomeResult(w);
  QCPColorMap* map = colorMap(plotNamed(w, "mode_heatmap"));
  ASSERT_TRUE(r && map);
  for (std::size_t k : {std::size_t{100}, std::size_t{700}}) {
    w.transport()->seek(k);
    const auto mu = r->mode_probabilities(k);
    ASSERT_EQ(mu.size(), 49u);
    for (int j : {0, 24, 48}) {
      const double expect = std::log10(std::max(mu[static_cast<std::size_t>(j)], 1e-8));
      EXPECT_NEAR(map->data()->cell(j % 7, j / 7), expect, 1e-9) << "step " << k << " mode " << j;
    }
  }
}

TEST_F(RadomeWindow, HeatMapTicksSitOnTheGridSlopes) {
  QCustomPlot* heat = plotNamed(w, "mode_heatmap");
  ASSERT_NE(heat, nullptr);
  auto ticks_of = [](QCPAxis* a) {
    auto t = a->ticker().dynamicCast<QCPAxisTickerText>();
    return t ? t->ticks() : QMap<double, QString>{};
  };
  auto expect_on_grid = [&](std::size_t k) {
    auto r = radomeResult(w);
    ASSERT_TRUE(r);
    const auto gp = r->grid_psi(k), gt = r->grid_theta(k);
    const auto tp = ticks_of(heat->xAxis), tt = ticks_of(heat->yAxis);
    ASSERT_EQ(tp.size(), static_cast<int>(gp.size())) << "step " << k;
    ASSERT_EQ(tt.size(), static_cast<int>(gt.size())) << "step " << k;
    int i = 0;
    for (auto it = tp.constBegin(); it != tp.constEnd(); ++it, ++i) {
      EXPECT_NEAR(it.key(), gp[static_cast<std::size_t>(i)], 1e-12);
      EXPECT_EQ(
          it.value(),
          QString::number(gp[static_cast<std::size_t>(i)], 'f', 3).replace("-0.000", "0.000"));
    }
    i = 0;
    for (auto it = tt.constBegin(); it != tt.constEnd(); ++it, ++i)
      EXPECT_NEAR(it.key(), gt[static_cast<std::size_t>(i)], 1e-12);
  };
  expect_on_grid(radomeResult(w)->steps() - 1);
  EXPECT_TRUE(ticks_of(heat->xAxis).values().contains("-0.017"));
  EXPECT_TRUE(ticks_of(heat->xAxis).values().contains("0.000"));
  // The grid moves with renewal: the ticks follow it at the replay cursor.
  w.setParam("Kp", 0.45);
  ASSERT_TRUE(w.waitForRun());
  for (std::size_t k : {std::size_t{300}, std::size_t{900}}) {
    w.transport()->seek(k);
    expect_on_grid(k);
  }
  // More than 9 values on an axis: the normal ticker there.
  w.setParam("grid.n_psi", 11);
  ASSERT_TRUE(w.waitForRun(20000 * testing::kTimeScale));  // 77 modes: > 20 s under ASan
  EXPECT_TRUE(ticks_of(heat->xAxis).isEmpty());
  EXPECT_EQ(ticks_of(heat->yAxis).size(), 7);
}

TEST_F(RadomeWindow, SnapshotDrawsGhostSlopesAndRefractionError) {
  w.pinSnapshot("plain");
  w.setParam("Kp", 0.45);
  ASSERT_TRUE(w.waitForRun());
  const std::pair<const char*, const char*> ghosts[] = {
      {"slope_psi", "estimate [pinned: plain]"},
      {"slope_theta", "estimate [pinned: plain]"},
      {"refraction_error", "estimated [pinned: plain]"}};
  for (const auto& [plot, name] : ghosts) {
    QCPGraph* g = graphNamed(plotNamed(w, plot), QString::fromUtf8(name));
    ASSERT_NE(g, nullptr) << name;
    EXPECT_GT(g->data()->size(), 100) << name;
    EXPECT_TRUE(std::isfinite(g->data()->constBegin()->value)) << name;
  }
  // The ghost holds the pinned (Kp = 0) estimate, not the live (Kp = 0.45) one.
  auto r = radomeResult(w);
  QCPGraph* ghost = graphNamed(plotNamed(w, "slope_psi"), "estimate [pinned: plain]");
  double diff = 0.0;
  for (auto it = ghost->data()->constBegin(); it != ghost->data()->constEnd(); ++it) {
    const auto k = static_cast<std::size_t>(
        std::lower_bound(r->t.begin(), r->t.end(), it->key - 1e-9) - r->t.begin());
    ASSERT_LT(k, r->steps());
    diff = std::max(diff, std::abs(it->value - r->slope_psi[k]));
  }
  EXPECT_GT(diff, 1e-3);
  // Cut at the replay cursor like the live curves.
  w.transport()->seek(200);
  EXPECT_LE((ghost->data()->constEnd() - 1)->key, r->t[200] + 1e-9);
  EXPECT_GE((ghost->data()->constEnd() - 1)->key, r->t[190]);
  // A new snapshot list replaces the ghosts; an empty one removes them.
  w.pinSnapshot("renewal");
  EXPECT_NE(graphNamed(plotNamed(w, "slope_psi"), "estimate [pinned: renewal]"), nullptr);
  EXPECT_NE(graphNamed(plotNamed(w, "slope_psi"), "estimate [pinned: plain]"), nullptr);
  w.clearSnapshots();
  for (const auto& [plot, name] : ghosts)
    EXPECT_EQ(graphNamed(plotNamed(w, plot), QString::fromUtf8(name)), nullptr) << name;
  EXPECT_EQ(graphNamed(plotNamed(w, "slope_psi"), "estimate [pinned: renewal]"), nullptr);
}

TEST_F(RadomeWindow, GridEnvelopeLegendShowsAFilledSwatch) {
  QCustomPlot* p = plotNamed(w, "slope_psi");
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
  // The first steps' innovations reach hundreds of metres; the axis shows the settled ones.
  auto r = radomeResult(w);
  double settled = 0.0;
  const double t_settle = r->t.front() + 0.05 * (r->t.back() - r->t.front());
  for (std::size_t k = 0; k < r->steps(); ++k) {
    if (r->t[k] < t_settle) continue;
    for (int ax = 0; ax < 3; ++ax) {
      const double y = r->innovation[static_cast<std::size_t>(ax)][k];
      const double S = r->S[static_cast<std::size_t>(ax)][k];
      if (std::isfinite(y)) settled = std::max({settled, std::abs(y), 2.0 * std::sqrt(S)});
    }
  }
  const QCPRange y = plotNamed(w, "innovation")->yAxis->range();
  EXPECT_LT(y.upper, 2.0 * settled);
  EXPECT_GT(y.upper, settled);
}

TEST_F(RadomeWindow, ExportWritesEveryPlot) {
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), w.exportedPlots().size());
  for (const QString& f : *files) {
    QImage img(f);
    ASSERT_FALSE(img.isNull()) << f.toStdString();
    const int colored = testing::colouredPixels(f);
    EXPECT_GT(colored, 200) << "no coloured content in " << f.toStdString();
  }
}

TEST_F(RadomeWindow, GridEndsCannotCross) {
  // The declared ranges bracket zero (grid.min <= 0 <= grid.max): the editors stop there, so no
  // value an editor accepts reverses the grid.
  auto* mn = w.findChild<QDoubleSpinBox*>("radome.grid.min");
  auto* mx = w.findChild<QDoubleSpinBox*>("radome.grid.max");
  ASSERT_NE(mn, nullptr);
  ASSERT_NE(mx, nullptr);
  EXPECT_EQ(mn->maximum(), 0.0);
  EXPECT_EQ(mx->minimum(), 0.0);
  mn->setValue(0.2);  // held at 0
  EXPECT_EQ(mn->value(), 0.0);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_TRUE(w.lastError().isEmpty()) << w.lastError().toStdString();
}

}  // namespace
}  // namespace kfw
