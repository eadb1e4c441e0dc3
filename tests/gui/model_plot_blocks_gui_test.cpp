// Issue 27, a model file's plot blocks in the window: the generic model view shows one panel per
// block ("plots"), named by its id and titled as declared; the gain_curve block draws k1 and
// p11⁻/N_θ against β with the operating point on the curve, the series block the run's derived
// column up to the replay cursor, the trajectory block the tracks and labelled points, the
// covariance block its cells; export writes them.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QFile>
#include <QTemporaryDir>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"
#include "transport_bar.h"

namespace kfw {
namespace model_plot_blocks_gui_test {
namespace {

using nlohmann::json;
using testing::graphNamed;
using testing::plotNamed;

// presets/helicopter.json with a gain curve and a series block and a derived series to draw.
QString writePreset(const QTemporaryDir& dir) {
  std::ifstream in(KFW_SOURCE_DIR "/presets/helicopter.json");
  json p = json::parse(in);
  p["model"]["derived"]["err_theta"] = {
      {"expression", "theta - truth"}, {"unit", "deg"}, {"label", "angle error"}};
  p["model"]["plots"] = json::parse(R"J([
    {"kind": "gain_curve", "id": "beta_curve", "title": "k1 and p11 against beta",
     "sweep": "Q", "range": [0.5, 5e5], "x": "beta", "y": ["derived.k1"],
     "y2": ["derived.p11_over_R"], "log": ["x", "y", "y2"]},
    {"kind": "series", "id": "angle_error", "y": ["derived.err_theta"]}
  ])J");
  p["parameters"]["sim.duration"]["value"] = 20;
  const QString path = dir.filePath("heli_blocks.json");
  QFile f(path);
  EXPECT_TRUE(f.open(QIODevice::WriteOnly));
  f.write(QByteArray::fromStdString(p.dump(2)));
  return path;
}

QString titleOf(QCustomPlot* p) {
  auto* t = p->findChild<QCPTextElement*>("title");
  return t ? t->text().replace(QChar('\n'), QChar(' ')) : QString();  // wrapped to fit
}

TEST(ModelPlotBlocksWindow, EachBlockIsAPanelWithItsTitleAndData) {
  QTemporaryDir dir;
  const QString path = writePreset(dir);
  MainWindow w;
  auto st = w.loadPreset(path);
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun(60000));
  ASSERT_TRUE(w.result()) << w.lastError().toStdString();

  QCustomPlot* curve = plotNamed(w, "beta_curve");
  ASSERT_NE(curve, nullptr);
  EXPECT_EQ(titleOf(curve), "k1 and p11 against beta");
  EXPECT_EQ(curve->xAxis->scaleType(), QCPAxis::stLogarithmic);
  EXPECT_EQ(curve->yAxis2->scaleType(), QCPAxis::stLogarithmic);
  EXPECT_TRUE(curve->xAxis->label().startsWith("β = m Ts² Nω / Nθ"))
      << curve->xAxis->label().toStdString();
  QCPGraph* k1 = graphNamed(curve, "k1(β), closed-form angle gain");
  ASSERT_NE(k1, nullptr);
  EXPECT_EQ(k1->data()->size(), 100);
  QCPGraph* op = graphNamed(curve, "operating point");
  ASSERT_NE(op, nullptr);
  ASSERT_EQ(op->data()->size(), 1);
  // The operating point sits on the curve: k1 between its neighbours in β (monotone).
  const double b = op->data()->at(0)->key, k = op->data()->at(0)->value;
  const auto above = k1->data()->findBegin(b, false);
  ASSERT_NE(above, k1->data()->constEnd());
  ASSERT_NE(above, k1->data()->constBegin());
  const auto below = above - 1;
  EXPECT_LE(below->key, b);
  EXPECT_GE(above->key, b);
  EXPECT_GE(k, below->value);
  EXPECT_LE(k, above->value);
  const double u =
      (std::log(b) - std::log(below->key)) / (std::log(above->key) - std::log(below->key));
  EXPECT_NEAR(k, below->value + u * (above->value - below->value), 0.01 * k);
  EXPECT_NEAR(b, 0.02 * 0.02 * w.values().at("Q") / w.values().at("R"), 1e-12 * b);
  // Along the curve (only Q moves): the same points, the operating point the run's own closed form
  // at the new β; R moves the curve itself.
  const double k1_at_10 = k1->data()->at(10)->value, beta_at_10 = k1->data()->at(10)->key;
  w.setParam("Q", w.values().at("Q") * 10);
  ASSERT_TRUE(w.waitForRun(60000));
  k1 = graphNamed(curve, "k1(β), closed-form angle gain");
  op = graphNamed(curve, "operating point");
  ASSERT_TRUE(k1 && op && op->data()->size() == 1);
  EXPECT_EQ(k1->data()->at(10)->value, k1_at_10);
  EXPECT_NEAR(op->data()->at(0)->key, w.result()->metrics.at("derived.beta"), 1e-12 * b * 10);
  EXPECT_NEAR(op->data()->at(0)->value, w.result()->metrics.at("derived.k1"), 1e-12);
  w.setParam("R", w.values().at("R") * 10);
  ASSERT_TRUE(w.waitForRun(60000));
  k1 = graphNamed(curve, "k1(β), closed-form angle gain");
  ASSERT_NE(k1, nullptr);
  EXPECT_NEAR(k1->data()->at(10)->key, beta_at_10 / 10, 1e-12 * beta_at_10);  // β ∝ 1/R
  op = graphNamed(curve, "operating point");
  ASSERT_TRUE(op && op->data()->size() == 1);
  EXPECT_NEAR(op->data()->at(0)->key, w.result()->metrics.at("derived.beta"), 1e-12 * b * 10);

  QCustomPlot* series = plotNamed(w, "angle_error");
  ASSERT_NE(series, nullptr);
  EXPECT_EQ(titleOf(series), "angle error over time");
  EXPECT_EQ(series->yAxis->label(), "angle error (deg)");
  QCPGraph* err = graphNamed(series, "angle error");
  ASSERT_NE(err, nullptr);
  const auto& r = dynamic_cast<const model::ModelResult&>(*w.result());
  const std::size_t steps = r.steps();
  EXPECT_GT(err->data()->size(), static_cast<int>(steps / 2));
  // Replay: the series shows the steps up to the cursor.
  w.transport()->seek(steps / 4);
  QCoreApplication::processEvents();
  EXPECT_LE(err->data()->at(err->data()->size() - 1)->key, r.t[steps / 4] + 1e-9);
  w.transport()->seek(steps);
  QCoreApplication::processEvents();

  QTemporaryDir out;
  auto files = w.exportAll(out.path(), {"png"}, {}, {"beta_curve", "angle_error"});
  ASSERT_TRUE(files.ok()) << files.error();
  ASSERT_EQ(files->size(), 2);
  for (const QString& f : *files) {
    EXPECT_TRUE(f.endsWith("heli_blocks_beta_curve.png") ||
                f.endsWith("heli_blocks_angle_error.png"))
        << f.toStdString();
    EXPECT_GT(testing::colouredPixels(f), 10) << f.toStdString();
  }
}

// cv2d.json with a top view (two fixed points) and an error covariance block.
QString writeTopView(const QTemporaryDir& dir) {
  std::ifstream in(KFW_SOURCE_DIR "/presets/models/cv2d.json");
  json p = json::parse(in);
  p["model"]["version"] = 2;
  p["model"]["derived"] = json::parse(R"J({
    "err_x": {"expression": "px - px_true", "unit": "m", "label": "x error"},
    "err_y": {"expression": "py - py_true", "unit": "m", "label": "y error"}})J");
  p["model"]["plots"] = json::parse(R"J([
    {"kind": "trajectory", "id": "top_view", "x": "px", "y": "py",
     "points": {"start": ["0", "0"], "B1": ["100*vx0", "50"]}},
    {"kind": "covariance", "id": "error_cov", "series": ["err_x", "err_y"],
     "design": ["sigma_r^2", "sigma_r^2"]}
  ])J");
  const QString path = dir.filePath("cv2d_blocks.json");
  QFile f(path);
  EXPECT_TRUE(f.open(QIODevice::WriteOnly));
  f.write(QByteArray::fromStdString(p.dump(2)));
  return path;
}

TEST(ModelPlotBlocksWindow, ATopViewAndACovariancePanel) {
  QTemporaryDir dir;
  MainWindow w;
  auto st = w.loadPreset(writeTopView(dir));
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun(60000));
  ASSERT_TRUE(w.result()) << w.lastError().toStdString();
  const auto& r = dynamic_cast<const model::ModelResult&>(*w.result());

  QCustomPlot* top = plotNamed(w, "top_view");
  ASSERT_NE(top, nullptr);
  EXPECT_EQ(titleOf(top), "y against x: true and estimated track");
  EXPECT_EQ(top->xAxis->label(), "x (m)");
  QCPGraph* points = graphNamed(top, "fixed points");
  ASSERT_NE(points, nullptr);
  ASSERT_EQ(points->data()->size(), 2);
  int labels = 0;
  for (int i = 0; i < top->itemCount(); ++i) {
    if (auto* t = qobject_cast<QCPItemText*>(top->item(i))) labels += t->text() == "B1";
  }
  EXPECT_EQ(labels, 1);
  int tracks = 0;
  for (int i = 0; i < top->plottableCount(); ++i) {
    if (auto* c = qobject_cast<QCPCurve*>(top->plottable(i)))
      tracks += c->data()->size() > 10;  // reduced to what the screen shows
  }
  EXPECT_EQ(tracks, 2) << "truth and estimate";
  // The B1 point inside the view.
  EXPECT_TRUE(top->xAxis->range().contains(points->data()->at(1)->key) ||
              top->xAxis->range().contains(points->data()->at(0)->key));

  QCustomPlot* cov = plotNamed(w, "error_cov");
  ASSERT_NE(cov, nullptr);
  int cells = 0;
  for (int i = 0; i < cov->itemCount(); ++i) {
    if (auto* t = qobject_cast<QCPItemText*>(cov->item(i))) cells += !t->text().isEmpty();
  }
  EXPECT_GE(cells, 8) << "2 × 2 sample and design";
  EXPECT_TRUE(cov->xAxis->label().startsWith(QString::number(r.steps())))
      << cov->xAxis->label().toStdString();

  QTemporaryDir out;
  auto files = w.exportAll(out.path(), {"png"}, {}, {"top_view", "error_cov"});
  ASSERT_TRUE(files.ok()) << files.error();
  ASSERT_EQ(files->size(), 2);
  for (const QString& f : *files)
    EXPECT_GT(testing::colouredPixels(f), 10) << f.toStdString();
}

// "equal_scale": one metre is as many pixels east as north in the window, after a resize and in
// exports of either shape (seed 004's top view, as the built-in view draws it).
TEST(ModelPlotBlocksWindow, AnEqualScaleTopViewKeepsOneUnitPerPixelAtAnySize) {
  QTemporaryDir dir;
  std::ifstream in(KFW_SOURCE_DIR "/presets/underwater.json");
  json p = json::parse(in);
  p["parameters"]["sim.duration"]["value"] = 30;
  const QString path = dir.filePath("uw.json");
  QFile f(path);
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write(QByteArray::fromStdString(p.dump(2)));
  f.close();
  MainWindow w;
  auto st = w.loadPreset(path);
  ASSERT_TRUE(st.ok()) << st.error();
  ASSERT_TRUE(w.waitForRun(60000));
  QCustomPlot* top = plotNamed(w, "trajectory");
  ASSERT_NE(top, nullptr);
  QCPGraph* beacons = graphNamed(top, "fixed points");
  ASSERT_NE(beacons, nullptr);
  auto check = [&](const char* where) {
    const QCPAxisRect* ar = top->axisRect();
    ASSERT_GT(ar->width(), 0);
    const double per_px_x = top->xAxis->range().size() / ar->width();
    const double per_px_y = top->yAxis->range().size() / ar->height();
    EXPECT_NEAR(per_px_x / per_px_y, 1.0, 0.01) << where;
    for (auto it = beacons->data()->constBegin(); it != beacons->data()->constEnd(); ++it) {
      EXPECT_TRUE(top->xAxis->range().contains(it->key)) << where;
      EXPECT_TRUE(top->yAxis->range().contains(it->value)) << where;
    }
  };
  w.show();
  QCoreApplication::processEvents();
  top->replot();
  check("window");
  top->resize(500, 300);
  top->replot();
  check("small");
  for (const QSize size : {QSize(1200, 700), QSize(700, 900)}) {
    const QPixmap pm = top->toPixmap(size.width(), size.height());
    ASSERT_EQ(pm.width(), size.width());
    check(size.height() > size.width() ? "tall export" : "wide export");
  }
}

}  // namespace
}  // namespace model_plot_blocks_gui_test
}  // namespace kfw
