// The underwater window driven as a user would, offscreen: filter and simulator parameters change
// what the plots hold, pinned snapshots draw ghost tracks and errors, the top view keeps one metre
// as long east as north at any size, and the covariance numbers are readable. Issue 27:
// presets/underwater.json is a model file, so these are the generic view's panels and the file's
// plot blocks (trajectory, distance_error, covariance) where the built-in view had its own.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QApplication>
#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::graphValues;
using testing::plotNamed;

QCPCurve* curveNamed(QCustomPlot* p, const QString& name) {
  if (!p) return nullptr;
  for (int i = 0; i < p->plottableCount(); ++i) {
    auto* c = qobject_cast<QCPCurve*>(p->plottable(i));
    if (c && c->name() == name) return c;
  }
  return nullptr;
}

std::vector<QPointF> points(QCPCurve* c) {
  std::vector<QPointF> v;
  for (auto it = c->data()->constBegin(); it != c->data()->constEnd(); ++it)
    v.emplace_back(it->key, it->value);
  return v;
}

// Metres per pixel along x and y of a plot's axis rect.
std::pair<double, double> metresPerPixel(QCustomPlot* p) {
  const QCPAxisRect* ar = p->axisRect();
  return {p->xAxis->range().size() / ar->width(), p->yAxis->range().size() / ar->height()};
}

class UnderwaterWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset(QString(KFW_SOURCE_DIR) + "/presets/underwater.json").ok());
    ASSERT_TRUE(w.waitForRun(60000));
    ASSERT_TRUE(w.result());
    track = plotNamed(w, "trajectory");
    err = plotNamed(w, "distance_error");
    ASSERT_TRUE(track && err);
  }
  std::shared_ptr<const model::ModelResult> result() const {
    return std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  }
  // The gate's marks over the four ranges' innovations.
  int rejectedMarks() const {
    int n = 0;
    for (int b = 1; b <= 4; ++b) {
      const QString id = QString("innovation.range%1.range%1").arg(b);
      if (QCPGraph* g = graphNamed(plotNamed(w, id), "rejected by the gate"))
        n += g->data()->size();
    }
    return n;
  }
  MainWindow w;
  QCustomPlot* track = nullptr;
  QCustomPlot* err = nullptr;
};

TEST_F(UnderwaterWindow, FilterParametersChangeWhatThePlotsHold) {
  QCPCurve* est = curveNamed(track, "estimate");
  QCPGraph* dist = graphNamed(err, "distance error");
  ASSERT_TRUE(est && dist);
  const auto track_before = points(est);
  const auto err_before = graphValues(dist);
  ASSERT_GT(track_before.size(), 100u);
  EXPECT_GT(rejectedMarks(), 200);  // 276 injected ±1 m outliers

  w.setParam("gate", 50.0);  // wide open: nothing rejected, the outliers pull the estimate
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_EQ(rejectedMarks(), 0);
  EXPECT_NE(points(est), track_before);
  EXPECT_NE(graphValues(dist), err_before);

  const auto err_open = graphValues(dist);
  w.setParam("scheme", 0.0);  // AS
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_EQ(w.values().at("scheme"), 0.0);
  EXPECT_NE(graphValues(dist), err_open);
}

TEST_F(UnderwaterWindow, SimulatorParameterResimulates) {
  QCPCurve* truth = curveNamed(track, "truth");
  ASSERT_NE(truth, nullptr);
  const auto before = points(truth);
  const auto data_before = w.dataset();
  w.setParam("sim.seed", 7);
  ASSERT_TRUE(w.waitForRun(60000));
  EXPECT_NE(w.dataset(), data_before);
  EXPECT_NE(points(truth), before);
}

TEST_F(UnderwaterWindow, SnapshotsDrawGhostTrackAndErrorCutAtTheCursor) {
  w.pinSnapshot("SC");
  w.setParam("scheme", 0.0);
  ASSERT_TRUE(w.waitForRun(60000));
  QCPCurve* ghost_track = curveNamed(track, "estimate [pinned: SC]");
  QCPGraph* ghost_err = graphNamed(err, "distance error [pinned: SC]");
  ASSERT_TRUE(ghost_track && ghost_err);
  EXPECT_GT(ghost_track->data()->size(), 100);
  EXPECT_GT(ghost_err->data()->size(), 100);
  // The ghost is the pinned SC run, not the live AS one.
  EXPECT_NE(points(ghost_track), points(curveNamed(track, "estimate")));
  EXPECT_NE(graphValues(ghost_err), graphValues(graphNamed(err, "distance error")));
  // Cut at the replay cursor like the live curves.
  auto r = result();
  ASSERT_TRUE(r);
  w.transport()->seek(2000);
  EXPECT_LE((ghost_err->data()->constEnd() - 1)->key, r->t[2000] + 1e-9);
  EXPECT_GE((ghost_err->data()->constEnd() - 1)->key, r->t[1900]);
  const int cut = ghost_track->data()->size();
  w.transport()->setShowAll(true);
  EXPECT_GT(ghost_track->data()->size(), cut);
  // A new list replaces the ghosts; clearing removes them.
  w.pinSnapshot("AS");
  EXPECT_NE(curveNamed(track, "estimate [pinned: AS]"), nullptr);
  EXPECT_NE(curveNamed(track, "estimate [pinned: SC]"), nullptr);
  const int plottables = track->plottableCount();
  w.pinSnapshot("AS again");
  EXPECT_EQ(track->plottableCount(), plottables + 1);
  w.clearSnapshots();
  EXPECT_EQ(curveNamed(track, "estimate [pinned: SC]"), nullptr);
  EXPECT_EQ(curveNamed(track, "estimate [pinned: AS]"), nullptr);
  EXPECT_EQ(graphNamed(err, "distance error [pinned: SC]"), nullptr);
}

TEST_F(UnderwaterWindow, TopViewIsEqualScaleAtAnySizeWithBeaconsAndLabelsInside) {
  w.show();
  QApplication::processEvents();
  auto check = [&](const char* where) {
    const auto [mx, my] = metresPerPixel(track);
    EXPECT_NEAR(mx / my, 1.0, 0.01) << where;
    const QRect rect = track->axisRect()->rect();
    // The legend sits beside the plot, not over it.
    EXPECT_FALSE(track->legend->outerRect().intersects(rect)) << where;
    // The beacons and their labels stay inside.
    QCPGraph* beacons = graphNamed(track, "fixed points");
    ASSERT_NE(beacons, nullptr);
    ASSERT_EQ(beacons->data()->size(), 4);
    for (auto it = beacons->data()->constBegin(); it != beacons->data()->constEnd(); ++it) {
      EXPECT_TRUE(track->xAxis->range().contains(it->key)) << where;
      EXPECT_TRUE(track->yAxis->range().contains(it->value)) << where;
    }
    int labels = 0;
    for (int i = 0; i < track->itemCount(); ++i) {
      auto* t = qobject_cast<QCPItemText*>(track->item(i));
      if (!t || !t->text().startsWith("B")) continue;
      ++labels;
      const QRectF box(t->topLeft->pixelPosition(), t->bottomRight->pixelPosition());
      EXPECT_TRUE(QRectF(rect).contains(box))
          << where << " " << t->text().toStdString() << " box " << box.left() << "," << box.top()
          << " " << box.right() << "," << box.bottom() << " in " << rect.left() << "," << rect.top()
          << " " << rect.right() << "," << rect.bottom();
    }
    EXPECT_EQ(labels, 4);
  };
  track->replot();
  check("window");
  // Exports draw at their own size (no replot): the ranges follow that size.
  for (const QSize size : {QSize(1200, 700), QSize(700, 900)}) {
    const QPixmap pm = track->toPixmap(size.width(), size.height());
    ASSERT_EQ(pm.width(), size.width());
    EXPECT_GT(track->axisRect()->width(), size.width() / 2);
    check(size.height() > size.width() ? "tall export" : "wide export");
  }
  track->resize(500, 300);
  track->replot();
  check("small");
  // The truth's whole track is in view: east (y) across, north (x) up.
  const auto r = result();
  ASSERT_TRUE(r);
  for (std::size_t k = 0; k < r->steps(); k += 50) {
    if (!std::isfinite(r->truth[0][k])) continue;
    EXPECT_TRUE(track->xAxis->range().contains(r->truth[1][k]));
    EXPECT_TRUE(track->yAxis->range().contains(r->truth[0][k]));
  }
}

TEST_F(UnderwaterWindow, CovarianceNumbersAreReadableWithoutGridLines) {
  QCustomPlot* cov = plotNamed(w, "covariance");
  ASSERT_NE(cov, nullptr);
  EXPECT_FALSE(cov->xAxis->grid()->visible());
  EXPECT_FALSE(cov->yAxis->grid()->visible());
  int numbers = 0;
  for (int i = 0; i < cov->itemCount(); ++i) {
    auto* t = qobject_cast<QCPItemText*>(cov->item(i));
    bool number = false;
    if (t) t->text().toDouble(&number);
    if (!number) continue;
    ++numbers;
    EXPECT_GE(t->font().pointSizeF(), 8.0);
  }
  EXPECT_EQ(numbers, 50);  // 5 × 5 simulated and 5 × 5 design
}

}  // namespace
}  // namespace kfw
