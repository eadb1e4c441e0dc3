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
#include <cmath>

#include "main_window.h"
#include "scenarios/radome/radome_imm.h"
#include "transport_bar.h"

namespace kfw {
namespace {

QCustomPlot* plotNamed(const MainWindow& w, const QString& name) {
  for (const auto& p : w.plots()) {
    if (p.name == name) return p.plot;
  }
  return nullptr;
}

QCPGraph* graphNamed(QCustomPlot* p, const QString& name) {
  for (int i = 0; i < p->graphCount(); ++i) {
    if (p->graph(i)->name() == name) return p->graph(i);
  }
  return nullptr;
}

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

TEST_F(RadomeWindow, ExportWritesEveryPlot) {
  QTemporaryDir dir;
  auto files = w.exportAll(dir.path(), {"png"});
  ASSERT_TRUE(files.ok()) << files.error();
  EXPECT_EQ(files->size(), w.exportedPlots().size());
  for (const QString& f : *files) {
    QImage img(f);
    ASSERT_FALSE(img.isNull()) << f.toStdString();
    int colored = 0;
    for (int y = 0; y < img.height(); y += 3) {
      for (int x = 0; x < img.width(); x += 3) {
        const QColor c = img.pixelColor(x, y);
        colored += std::abs(c.red() - c.blue()) > 40 || std::abs(c.green() - c.blue()) > 40;
      }
    }
    EXPECT_GT(colored, 200) << "no coloured content in " << f.toStdString();
  }
}

TEST_F(RadomeWindow, InvertedGridShowsAnErrorAndKeepsTheResult) {
  const auto before = w.result();
  auto* mn = w.findChild<QDoubleSpinBox*>("radome.grid.min");
  ASSERT_NE(mn, nullptr);
  mn->setValue(0.2);  // above grid.max = 0.05
  w.waitForRun();
  EXPECT_NE(w.lastError().indexOf("grid.min"), -1) << w.lastError().toStdString();
  EXPECT_EQ(w.result(), before);
}

}  // namespace
}  // namespace kfw
