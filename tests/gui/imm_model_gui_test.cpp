// Issue 28: the IMM panels of a model with modes in the generic view — mode probabilities, the
// grid's heat map, each axis's estimate — and the grid sliders: changing an axis's n or bounds
// re-runs the IMM with the new grid (the heat map's size and the lines follow); the heat map's
// ticks on the grid values, and under renewal lines named by their values at the cursor.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QRegularExpression>
#include <QSet>
#include <QTemporaryDir>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using nlohmann::json;
using testing::plotNamed;

json imm_gui_param(double v, double lo, double hi, const char* scale = "linear") {
  return {{"value", v}, {"min", lo}, {"max", hi}, {"scale", scale}};
}

json imm_gui_list(std::initializer_list<nlohmann::detail::json_ref<json>> e) {
  return json::array(e);
}

// A 1-D constant-velocity model with a 4 × 3 grid over its process and measurement noise.
json grid_preset() {
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}, {"title", "grid IMM"}};
  p["parameters"] = {{"q", imm_gui_param(0.5, 1e-3, 10, "log")},
                     {"r", imm_gui_param(1.0, 1e-3, 10, "log")},
                     {"sim.dt", imm_gui_param(0.1, 0.01, 1)},
                     {"sim.duration", imm_gui_param(20, 1, 100)}};
  const auto L = imm_gui_list;
  p["model"] = {{"version", 2},
                {"states", L({"x", "v"})},
                {"x0", L({"0", "0"})},
                {"P0", L({"10", "1"})},
                {"process",
                 {{"F", L({L({"1", "dt"}), L({"0", "1"})})},
                  {"Q", L({L({"dt^4/4*q^2", "dt^3/2*q^2"}), L({"dt^3/2*q^2", "dt^2*q^2"})})}}},
                {"measurements",
                 {{"pos", {{"roles", L({"z"})}, {"H", L({L({"1", "0"})})}, {"R", L({"r^2"})}}}}},
                {"truth", {{"x", "x_true"}}},
                {"modes",
                 {{"grid", L({{{"param", "q"}, {"min", 0.1}, {"max", 2.0}, {"n", 4}},
                              {{"param", "r"}, {"min", 0.5}, {"max", 2.0}, {"n", 3}}})}}}};
  return p;
}

QCPColorMap* colorMapOf(QCustomPlot* p) {
  for (int i = 0; p && i < p->plottableCount(); ++i) {
    if (auto* m = qobject_cast<QCPColorMap*>(p->plottable(i))) return m;
  }
  return nullptr;
}

class ImmModelWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(dir.isValid());
    path = dir.filePath("grid_imm.json");
    std::ofstream(path.toStdString()) << grid_preset().dump(2);
    ASSERT_TRUE(w.loadPreset(path).ok());
    ASSERT_TRUE(w.waitForRun());
  }
  QTemporaryDir dir;
  QString path;
  MainWindow w;
};

TEST_F(ImmModelWindow, DrawsTheModesTheGridAndEachAxis) {
  QCustomPlot* lines = plotNamed(w, "mode_probabilities");
  ASSERT_NE(lines, nullptr);
  EXPECT_EQ(lines->graphCount(), 8);  // 12 modes: the 8 most probable
  for (const char* name : {"mode_heatmap", "grid.q", "grid.r"})
    EXPECT_NE(plotNamed(w, name), nullptr) << name;
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r && r->imm);
  QCPGraph* est = testing::graphNamed(plotNamed(w, "grid.q"), "IMM estimate Σ μʲ qʲ");
  ASSERT_NE(est, nullptr);
  const auto drawn = testing::graphValues(est);
  ASSERT_FALSE(drawn.empty());
  EXPECT_DOUBLE_EQ(drawn.back(), r->imm->axes[0].estimate.back());
}

TEST_F(ImmModelWindow, GridSlidersReRunWithTheNewGrid) {
  QCPColorMap* heat = colorMapOf(plotNamed(w, "mode_heatmap"));
  ASSERT_NE(heat, nullptr);
  EXPECT_EQ(heat->data()->keySize(), 4);
  EXPECT_EQ(heat->data()->valueSize(), 3);
  w.setParam("grid.q.n", 6);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(heat->data()->keySize(), 6);
  EXPECT_EQ(heat->data()->valueSize(), 3);
  w.setParam("grid.r.n", 2);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(heat->data()->keySize(), 6);
  EXPECT_EQ(heat->data()->valueSize(), 2);
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r && r->imm);
  EXPECT_EQ(r->imm->modes(), 12u);
  // New bounds: the heat map's cells span them.
  w.setParam("grid.q.max", 4.0);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_DOUBLE_EQ(heat->data()->keyRange().upper, 4.0);
  EXPECT_DOUBLE_EQ(heat->data()->keyRange().lower, 0.1);
}

// The heat map's ticks sit on the grid's values, each with as few decimals as tell them apart
// (q: 0.1 … 2 in 4, r: 0.5 … 2 in 3); the 8 lines have 8 different colours.
TEST_F(ImmModelWindow, HeatMapTicksSitOnTheGridValuesAndLinesDiffer) {
  QCustomPlot* heat = plotNamed(w, "mode_heatmap");
  ASSERT_NE(heat, nullptr);
  const auto ticks = [](QCPAxis* a) {
    auto t = a->ticker().dynamicCast<QCPAxisTickerText>();
    return t ? t->ticks() : QMap<double, QString>();
  };
  const auto x = ticks(heat->xAxis), y = ticks(heat->yAxis);
  ASSERT_EQ(x.size(), 4);
  ASSERT_EQ(y.size(), 3);
  EXPECT_EQ(x.values(), QList<QString>({"0.10", "0.73", "1.37", "2.00"}));
  EXPECT_EQ(y.values(), QList<QString>({"0.50", "1.25", "2.00"}));
  EXPECT_NEAR(x.keys()[1], 0.1 + 1.9 / 3, 1e-12);
  QCustomPlot* lines = plotNamed(w, "mode_probabilities");
  ASSERT_NE(lines, nullptr);
  QSet<QRgb> colours;
  for (int i = 0; i < lines->graphCount(); ++i)
    colours.insert(lines->graph(i)->pen().color().rgb());
  EXPECT_EQ(colours.size(), lines->graphCount());
  // A fixed grid names its modes by their values, with no time.
  EXPECT_EQ(lines->graph(0)->name(), "q = 0.10, r = 0.50");
  // The note at the cursor (the last step): the time, the most probable mode, the estimate; no
  // truth (these axes map none).
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r && r->imm);
  const std::size_t k = r->steps() - 1;
  std::size_t best = 0;
  for (std::size_t j = 0; j < r->imm->modes(); ++j) {
    if (r->imm->mu_at(k, j) > r->imm->mu_at(k, best)) best = j;
  }
  QCPItemText* note = nullptr;  // the first text item (the plot kit adds a readout after it)
  for (int i = 0; i < heat->itemCount() && !note; ++i)
    note = qobject_cast<QCPItemText*>(heat->item(i));
  ASSERT_NE(note, nullptr);
  const QString want = QString("t = %1 s   max μ = %2 at (%3, %4)\nestimate (")
                           .arg(r->t[k], 0, 'f', 2)
                           .arg(r->imm->mu_at(k, best), 0, 'f', 3)
                           .arg(x.values()[static_cast<int>(best % 4)])
                           .arg(y.values()[static_cast<int>(best / 4)]);
  EXPECT_TRUE(note->text().startsWith(want)) << note->text().toStdString();
  EXPECT_FALSE(note->text().contains("truth")) << note->text().toStdString();
}

// Under renewal a line stands for its grid values moved to the cursor, and says when.
TEST(ImmModelWindowRenewal, LinesAreNamedByTheirValuesAtTheCursor) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  json p = grid_preset();
  p["model"]["modes"]["renewal"] = {{"gain", 0.0}, {"start", 0.0}, {"mode", "index"}};
  const QString path = dir.filePath("renew.json");
  std::ofstream(path.toStdString()) << p.dump(2);
  MainWindow w;
  ASSERT_TRUE(w.loadPreset(path, {}, {"Kp=0.05"}).ok());
  ASSERT_TRUE(w.waitForRun());
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r && r->imm);
  const auto& q = r->imm->axes[0];
  ASSERT_GT(std::fabs(q.centre.back() - q.centre.front()), 0.01);  // the grid moved
  QCustomPlot* lines = plotNamed(w, "mode_probabilities");
  ASSERT_NE(lines, nullptr);
  for (std::size_t k : {r->steps() - 1, r->steps() / 2}) {
    w.transport()->seek(k);
    const std::size_t at = w.transport()->index();
    static const QRegularExpression re(R"(^q = (-?[0-9.]+), r = (-?[0-9.]+) at t = ([0-9.]+) s$)");
    int named = 0;
    for (int i = 0; i < lines->graphCount(); ++i) {
      const auto m = re.match(lines->graph(i)->name());
      ASSERT_TRUE(m.hasMatch()) << lines->graph(i)->name().toStdString();
      EXPECT_NEAR(m.captured(3).toDouble(), r->t[at], 0.051);
      const double shift = q.centre[at] - q.centre.front();
      bool some_mode = false;  // the value is one of the grid's, moved by the shift
      for (double v : q.values)
        some_mode = some_mode || std::fabs(m.captured(1).toDouble() - (v + shift)) < 0.006;
      EXPECT_TRUE(some_mode) << lines->graph(i)->name().toStdString();
      ++named;
    }
    EXPECT_EQ(named, 8);
  }
}

// model.first_panels: those panels first, in the file's order (radome: the slopes, refraction and
// LOS errors, the heat map, as the built-in view had them); the view's names are the engine's
// panel_names, which the file's names are checked against.
TEST(ImmModelWindowPanels, FirstPanelsComeFirstAndNamesAreTheEngines) {
  for (const char* preset : {"radome", "helicopter", "models/cv_ct_imm"}) {
    SCOPED_TRACE(preset);
    MainWindow w;
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/" + preset + ".json").ok());
    ASSERT_TRUE(w.waitForRun(60000));
    const auto layout = model_layout_of(*w.scenario());
    ASSERT_TRUE(layout);
    std::vector<std::string> engine = layout->panels;
    std::vector<std::string> window;
    for (const PlotPanel& p : w.plots())
      window.push_back(p.name.toStdString());
    const auto& first = layout->first_panels;
    ASSERT_GE(window.size(), first.size());
    EXPECT_EQ(std::vector<std::string>(window.begin(), window.begin() + first.size()), first);
    std::sort(engine.begin(), engine.end());
    std::sort(window.begin(), window.end());
    EXPECT_EQ(window, engine);
  }
}

}  // namespace
}  // namespace kfw
