// Issue 28: the IMM panels of a model with modes in the generic view — mode probabilities, the
// grid's heat map, each axis's estimate — and the grid sliders: changing an axis's n or bounds
// re-runs the IMM with the new grid (the heat map's size and the lines follow).
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QTemporaryDir>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"

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

}  // namespace
}  // namespace kfw
