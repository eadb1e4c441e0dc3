// The window a user meets (issue 17): it fits 1366×768 and 1280×720, the metrics panel puts the
// primary metric first and cuts no value, log sliders are fine enough for a hand, the replay
// keys work with any focus but text entry, Reset keeps the snapshots, and Help finds the README.
#include <gtest/gtest.h>
#include <qcustomplot.h>

#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QLineEdit>
#include <QScrollArea>
#include <QSignalSpy>
#include <QSlider>
#include <QStyle>
#include <QStyleOptionSlider>
#include <QTemporaryDir>
#include <QTest>
#include <cmath>

#include "common/plot_probe.h"
#include "common/widget_geometry.h"
#include "core/metrics.h"
#include "main_window.h"
#include "metrics_panel.h"
#include "param_panel.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using testing::inWindow;
using testing::plotNamed;
using testing::shownPart;

void maybeScreenshot(QWidget& w, const char* name) {
  const QByteArray dir = qgetenv("KFW_TEST_SCREENSHOTS");
  if (!dir.isEmpty()) w.grab().save(QString::fromUtf8(dir) + "/" + name);
}

class WindowGui : public ::testing::Test {
 protected:
  void open(const char* preset, const QStringList& sets, QSize size) {
    ASSERT_TRUE(w.loadPreset(preset, {}, sets).ok());
    w.resize(size);
    w.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
    ASSERT_TRUE(w.waitForRun());
    QApplication::processEvents();
  }
  MainWindow w;
};

TEST_F(WindowGui, FirstSizeComesFromTheScreen) {
  const QRect avail = w.screen()->availableGeometry();
  EXPECT_LE(w.width(), avail.width());
  EXPECT_LE(w.height(), avail.height());
}

TEST_F(WindowGui, TransportAndFirstPlotRowVisibleAtSmallScreens) {
  for (const QSize size : {QSize(1366, 768), QSize(1280, 720)}) {
    for (const char* preset : {"helicopter", "radome", "underwater", "ballbeam"}) {
      SCOPED_TRACE(std::string(preset) + " at " + std::to_string(size.width()));
      MainWindow win;
      ASSERT_TRUE(win.loadPreset(preset).ok());
      win.resize(size);
      win.show();
      ASSERT_TRUE(QTest::qWaitForWindowExposed(&win));
      ASSERT_TRUE(win.waitForRun(60000));
      QApplication::processEvents();
      EXPECT_EQ(win.size(), size) << "the layout forces a larger window";
      const QWidget* bar = win.transport();
      ASSERT_TRUE(bar->isVisible());
      EXPECT_EQ(shownPart(bar, &win), inWindow(bar, &win));
      EXPECT_GE(bar->height(), bar->minimumSizeHint().height());
      ASSERT_GE(win.plots().size(), 2);
      for (int i = 0; i < 2; ++i) {
        const QWidget* p = win.plots()[i].plot;
        EXPECT_EQ(shownPart(p, &win), inWindow(p, &win)) << win.plots()[i].name.toStdString();
        EXPECT_GE(p->height(), 200);
      }
      if (size.width() == 1366 && std::string(preset) == "helicopter")
        maybeScreenshot(win, "window_1366x768_helicopter.png");
      if (size.width() == 1366 && std::string(preset) == "radome")
        maybeScreenshot(win, "window_1366x768_radome.png");
    }
  }
}

TEST_F(WindowGui, MetricsPrimaryFirstGroupedAndNothingCut) {
  open("helicopter", {"sim.duration=20"}, QSize(1366, 768));
  MetricsPanel* m = w.metricsPanel();
  ASSERT_GT(m->rowCount(), 3);
  // The primary metric: the first declared shared metric the run reports (rmse, with truth).
  EXPECT_EQ(m->primaryKey(), "rmse");
  EXPECT_EQ(m->item(0, 0)->data(MetricsPanel::kKeyRole).toString(), "rmse");
  EXPECT_TRUE(m->item(0, 0)->data(MetricsPanel::kPrimaryRole).toBool());
  EXPECT_TRUE(m->item(0, 0)->font().bold());
  EXPECT_NE(m->item(0, 1)->background(), m->item(2, 1) ? m->item(2, 1)->background() : QBrush());
  // Groups in their declared order; each metric under the header of its declared group.
  int last_group = -1;
  int current = -1;
  int headers = 0;
  for (int r = 1; r < m->rowCount(); ++r) {
    const QVariant g = m->item(r, 0)->data(MetricsPanel::kGroupRole);
    if (g.isValid()) {
      int idx = -1;
      for (int k = 0; k <= static_cast<int>(MetricGroup::kScenario); ++k)
        if (g.toString() == group_name(static_cast<MetricGroup>(k))) idx = k;
      ASSERT_GE(idx, 0) << g.toString().toStdString();
      EXPECT_GT(idx, last_group) << "groups out of order";
      last_group = current = idx;
      ++headers;
      continue;
    }
    const std::string key = m->item(r, 0)->data(MetricsPanel::kKeyRole).toString().toStdString();
    EXPECT_EQ(static_cast<int>(describe_metric(*w.scenario(), key, w.result().get()).group),
              current)
        << key;
  }
  EXPECT_GE(headers, 2);
  // No value text cut: every value fits its column (text + the good/bad mark + margins).
  for (int r = 0; r < m->rowCount(); ++r) {
    for (int c = 1; c < m->columnCount(); ++c) {
      const QTableWidgetItem* it = m->item(r, c);
      if (!it || m->columnSpan(r, 0) > 1) continue;
      const QFontMetrics fm(it->font());
      int need = fm.horizontalAdvance(it->text());
      if (!it->icon().isNull()) need += m->iconSize().width() > 0 ? 10 : 0;
      EXPECT_LE(need, m->columnWidth(c)) << it->text().toStdString();
    }
    // Names wrap instead of being cut: the row is as tall as the wrapped text needs.
    const QTableWidgetItem* name = m->item(r, 0);
    if (!name || m->columnSpan(r, 0) > 1) continue;
    const QFontMetrics fm(name->font());
    const QRect need =
        fm.boundingRect(QRect(0, 0, m->columnWidth(0) - 8, 10000), Qt::TextWordWrap, name->text());
    EXPECT_LE(need.height(), m->rowHeight(r) + 2) << name->text().toStdString();
  }
  // A declared bound gives a good/bad mark: NIS inside its 95 % bounds.
  bool marked = false;
  for (int r = 0; r < m->rowCount(); ++r) {
    auto* it = m->item(r, 0);
    if (it && it->data(MetricsPanel::kKeyRole).toString() == "nis_in_bounds")
      marked = !m->item(r, 1)->icon().isNull() && m->item(r, 1)->toolTip().contains("inside");
  }
  EXPECT_TRUE(marked);
  // The primary row and the first group are in view without scrolling.
  EXPECT_EQ(m->rowAt(0), 0);
  EXPECT_GE(m->viewport()->height(), m->rowViewportPosition(4) + m->rowHeight(4));
  // A tuned objective goes first.
  w.setPrimaryMetric("nis_mean");
  EXPECT_EQ(m->item(0, 0)->data(MetricsPanel::kKeyRole).toString(), "nis_mean");
  EXPECT_FALSE(w.statusText().contains(" ms")) << w.statusText().toStdString();
  EXPECT_TRUE(w.statusText().contains("NIS")) << w.statusText().toStdString();
  maybeScreenshot(w, "window_1366x768_metrics.png");
}

TEST(Format, FourSignificantDigits) {
  EXPECT_EQ(MetricsPanel::format(1.234567), "1.235");
  EXPECT_EQ(MetricsPanel::format(0.0123456), "0.01235");
  EXPECT_EQ(MetricsPanel::format(12345.6), "12346");
  EXPECT_EQ(MetricsPanel::format(2.5), "2.5");
  EXPECT_EQ(MetricsPanel::format(0.95), "0.95");
  EXPECT_EQ(MetricsPanel::format(1.5e-6), "1.5e-06");
  EXPECT_EQ(MetricsPanel::format(0.0), "0");
}

TEST_F(WindowGui, LogSliderDragOfNinetyPixelsStaysWithinTwoDecades) {
  open("helicopter", {"sim.duration=10"}, QSize(1366, 768));
  auto* slider = w.findChild<QSlider*>("slider.R");
  ASSERT_NE(slider, nullptr);
  const auto [lo, hi] = w.paramPanel()->sliderRange("R");
  EXPECT_LE(std::log10(hi / lo), ParamPanel::kLogWindowDecades + 1e-9);
  const double before = w.values().at("R");
  EXPECT_GT(before, lo);
  EXPECT_LT(before, hi);
  // A real drag: press on the handle, move 90 px, release.
  QStyleOptionSlider opt;
  opt.initFrom(slider);
  opt.orientation = slider->orientation();
  opt.minimum = slider->minimum();
  opt.maximum = slider->maximum();
  opt.sliderPosition = slider->sliderPosition();
  opt.sliderValue = slider->value();
  const QRect handle =
      slider->style()->subControlRect(QStyle::CC_Slider, &opt, QStyle::SC_SliderHandle, slider);
  ASSERT_TRUE(handle.isValid());
  // The drag stays on the slider (a drag past its end would only show the clamp).
  ASSERT_GT(slider->width(), 150);
  const QPoint start = handle.center();
  QTest::mousePress(slider, Qt::LeftButton, Qt::NoModifier, start);
  for (int dx = 10; dx <= 90; dx += 10)
    QTest::mouseMove(slider, start + QPoint(dx, 0));
  QTest::mouseRelease(slider, Qt::LeftButton, Qt::NoModifier, start + QPoint(90, 0));
  ASSERT_TRUE(w.waitForRun());
  const double after = w.values().at("R");
  const double decades = std::log10(after / before);
  EXPECT_GT(decades, 0.3) << "the drag did not move the value";
  EXPECT_LE(decades, 2.0) << before << " -> " << after;
  EXPECT_LE(ParamPanel::kLogWindowDecades, 4.0);
  std::printf("90-px drag: %.3g decades (slider %d px)\n", decades, slider->width());
  // Re-centred on release: the window is around the new value.
  const auto [lo2, hi2] = w.paramPanel()->sliderRange("R");
  EXPECT_NEAR(std::log10(after / lo2), ParamPanel::kLogWindowDecades / 2, 0.01);
  EXPECT_NEAR(std::log10(hi2 / after), ParamPanel::kLogWindowDecades / 2, 0.01);
  // Shift + drag: ten times finer.
  {
    const double v0 = w.values().at("R");
    const QPoint c(slider->width() / 2, slider->height() / 2);
    QTest::mousePress(slider, Qt::LeftButton, Qt::ShiftModifier, c);
    for (int dx = 10; dx <= 90; dx += 10) {
      QTest::mouseMove(slider, c + QPoint(dx, 0));
    }
    QTest::mouseRelease(slider, Qt::LeftButton, Qt::ShiftModifier, c + QPoint(90, 0));
    ASSERT_TRUE(w.waitForRun());
    const double fine = std::log10(w.values().at("R") / v0);
    EXPECT_GT(fine, 0.0);
    EXPECT_LT(fine, 0.2 * decades + 0.05) << "normal " << decades << " decades, fine " << fine;
  }
  // The spin box still takes the declared extremes.
  const ParamSpec* spec = nullptr;
  for (const auto& s : w.scenario()->params().specs())
    if (s.key == "R") spec = &s;
  ASSERT_NE(spec, nullptr);
  auto* spin = w.findChild<QDoubleSpinBox*>("spin.R");
  for (double v : {spec->max, spec->min}) {
    spin->setValue(v);
    ASSERT_TRUE(w.waitForRun());
    EXPECT_DOUBLE_EQ(w.values().at("R"), v);
    const auto [a, b] = w.paramPanel()->sliderRange("R");
    EXPECT_TRUE(a <= v && v <= b);
  }
}

TEST_F(WindowGui, ReplayKeysWithAnyFocusButText) {
  open("helicopter", {"sim.duration=20"}, QSize(1366, 768));
  TransportBar* t = w.transport();
  EXPECT_FALSE(t->showAll()) << "show all is an explicit choice";
  EXPECT_EQ(t->index() + 1, w.result()->steps()) << "the first run shows the whole run";
  auto* spin = w.findChild<QDoubleSpinBox*>("spin.R");
  w.activateWindow();
  spin->setFocus();
  QApplication::processEvents();
  const double r = w.values().at("R");
  t->seek(100);
  QTest::keyClick(spin, Qt::Key_Space);
  EXPECT_TRUE(t->playing());
  // While playing, every time plot follows a window of the last seconds.
  QTest::qWait(150);
  QCustomPlot* angle = plotNamed(w, "state.theta");
  ASSERT_NE(angle, nullptr);
  EXPECT_NEAR(angle->xAxis->range().size(), t->windowSeconds(), 1e-9);
  EXPECT_LE(angle->xAxis->range().lower, w.result()->t[t->index()]);
  EXPECT_GE(angle->xAxis->range().upper, w.result()->t[t->index()]);
  QTest::keyClick(spin, Qt::Key_Space);
  EXPECT_FALSE(t->playing());
  const std::size_t at = t->index();
  QTest::keyClick(spin, Qt::Key_Right);
  EXPECT_EQ(t->index(), at + 1);
  QTest::keyClick(spin, Qt::Key_Left);
  QTest::keyClick(spin, Qt::Key_Left);
  EXPECT_EQ(t->index(), at - 1);
  QTest::keyClick(spin, Qt::Key_End);
  EXPECT_EQ(t->index() + 1, w.result()->steps());
  QTest::keyClick(spin, Qt::Key_Home);
  EXPECT_EQ(t->index(), 0u);
  EXPECT_EQ(w.values().at("R"), r) << "the keys went to the spin box too";
  // A typed time: the text field is text entry (Space types), Enter seeks.
  auto* time = w.findChild<QLineEdit*>("transport.time");
  ASSERT_NE(time, nullptr);
  time->setFocus();
  time->clear();
  QTest::keyClicks(time, "12.5");
  QTest::keyClick(time, Qt::Key_Space);
  EXPECT_FALSE(t->playing());
  QTest::keyClick(time, Qt::Key_Return);
  const auto& tt = w.result()->t;
  ASSERT_LT(t->index() + 1, tt.size());
  EXPECT_LE(tt[t->index()], 12.5);
  EXPECT_GT(tt[t->index() + 1], 12.5);
  EXPECT_TRUE(time->text().contains("12.5")) << time->text().toStdString();
  // The time label tells the truth with show all, too.
  t->setShowAll(true);
  EXPECT_TRUE(t->timeText().startsWith("all")) << t->timeText().toStdString();
  t->setShowAll(false);
}

TEST_F(WindowGui, ReplayStateRoundTripsThroughTheSession) {
  open("helicopter", {"sim.duration=20"}, QSize(1366, 768));
  w.transport()->seek(321);
  QTemporaryDir dir;
  const QString path = dir.filePath("s.json");
  ASSERT_TRUE(w.saveSession(path).ok());
  MainWindow back;
  ASSERT_TRUE(back.loadSession(path).ok());
  ASSERT_TRUE(back.waitForRun());
  EXPECT_EQ(back.transport()->index(), 321u);
  EXPECT_FALSE(back.transport()->showAll());
  EXPECT_EQ(back.transport()->cursor(), 321u);
}

// Issue 32, item 7: radome opened drawn to 5.4 s of 60 s, the helicopter's replay time.
TEST_F(WindowGui, AnotherPresetOpensWithTheWholeRunNotTheLastCursor) {
  open("helicopter", {"sim.duration=20"}, QSize(1366, 768));
  TransportBar* t = w.transport();
  t->seek(321);
  t->play();
  ASSERT_TRUE(t->playing());
  ASSERT_TRUE(w.loadPreset("models/cv1d", {}, {}).ok());
  ASSERT_TRUE(w.waitForRun());
  QApplication::processEvents();
  EXPECT_FALSE(t->playing());
  EXPECT_EQ(t->index() + 1, w.result()->steps());
}

TEST_F(WindowGui, ResetKeepsSnapshotsAndIsOneUndoStep) {
  open("helicopter", {"sim.duration=10"}, QSize(1366, 768));
  const ParamValues preset = w.document()->preset().values;  // the file's values
  w.setParam("R", 50.0);
  ASSERT_TRUE(w.waitForRun());
  w.pinSnapshot("loose");
  w.resetToPreset();
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values(), preset);
  EXPECT_EQ(w.snapshotCount(), 1);
  ASSERT_TRUE(w.undo());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_DOUBLE_EQ(w.values().at("R"), 50.0);
  EXPECT_EQ(w.snapshotCount(), 1);
  // Re-picking the open preset resets the same way, without asking, and keeps the snapshot.
  int asked = 0;
  w.setConfirmHandler([&](const QString&) {
    ++asked;
    return true;
  });
  auto* combo = w.findChild<QComboBox*>("presets");
  emit combo->activated(combo->currentIndex());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(asked, 0);
  EXPECT_EQ(w.values(), preset);
  EXPECT_EQ(w.snapshotCount(), 1);
}

TEST_F(WindowGui, ErrorBannerClearsAfterALaterSuccess) {
  open("helicopter", {"sim.duration=10"}, QSize(1366, 768));
  QTemporaryDir dir;
  const QString bad = dir.filePath("bad.csv");
  {
    QFile f(bad);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write("t,gyro,angle\n0,1,2\n0.02,abc,3\n");
  }
  EXPECT_FALSE(w.openDataset(bad).ok());
  auto* banner = w.findChild<QLabel*>("errorBanner");
  EXPECT_FALSE(banner->isHidden());
  w.setParam("R", 3.0);
  ASSERT_TRUE(w.waitForRun());
  EXPECT_TRUE(banner->isHidden());
}

TEST_F(WindowGui, OrientationDescriptionHelpAndAbout) {
  open("helicopter", {}, QSize(1366, 768));
  EXPECT_FALSE(w.presetDescription().isEmpty());
  auto* label = w.findChild<QLabel*>("presetDescription");
  ASSERT_NE(label, nullptr);
  EXPECT_TRUE(label->isVisible());
  EXPECT_FALSE(MainWindow::readmePath().isEmpty());
  const QString usage = MainWindow::usageText();
  EXPECT_TRUE(usage.startsWith("## Using it")) << usage.left(80).toStdString();
  EXPECT_TRUE(usage.contains("kfw-cli"));
  EXPECT_FALSE(usage.contains("## Layout"));
  const QString about = MainWindow::aboutText();
  EXPECT_TRUE(about.contains("GPL-3.0-or-later"));
  EXPECT_TRUE(about.contains("QCustomPlot"));
  EXPECT_TRUE(about.contains("CC BY 4.0"));
  const QString version = QCoreApplication::applicationVersion().isEmpty()
                              ? QString("0.1.0")
                              : QCoreApplication::applicationVersion();
  EXPECT_TRUE(about.contains(version));
}

}  // namespace
}  // namespace kfw
