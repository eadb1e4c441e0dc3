// Issue 32, item 3: the mouse wheel over the parameter panel scrolls it and never moves a control
// it passes (R moved, "Undo set R", while a lecturer scrolled); a control clicked or tabbed to
// takes the wheel as before.
#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QSlider>
#include <QTest>
#include <QWheelEvent>

#include "main_window.h"
#include "param_panel.h"

namespace kfw {
namespace {

// Sends `steps` wheel notches down over the middle of `target`; true when the control accepted
// every one. An ignored wheel event goes on to the parents (the panel's scroll area) when Qt
// delivers a real one; a sent event stops at the receiver (Qt propagates only spontaneous ones),
// so the tests read the acceptance.
bool wheelOver(QWidget* target, int steps) {
  const QPointF at = QRectF(target->rect()).center();
  bool accepted = true;
  for (int i = 0; i < steps; ++i) {
    QWheelEvent ev(at, target->mapToGlobal(at), QPoint(), QPoint(0, -120), Qt::NoButton,
                   Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(target, &ev);
    accepted = accepted && ev.isAccepted();
  }
  QApplication::processEvents();
  return accepted;
}

class ParamWheelGui : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=20"}).ok());
    w.resize(1280, 720);  // a panel taller than its column: the wheel has something to scroll
    w.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
    ASSERT_TRUE(w.waitForRun());
    QApplication::processEvents();
  }
  MainWindow w;
};

TEST_F(ParamWheelGui, TheWheelOverAnUnfocusedControlChangesNoValue) {
  const ParamValues before = w.values();
  ParamPanel* panel = w.paramPanel();
  auto* slider = panel->findChild<QSlider*>("slider.R");
  auto* spin = panel->findChild<QDoubleSpinBox*>("spin.Q");
  QComboBox* combo = nullptr;  // the first choice (the filter: kf, steady, ekf, ukf)
  for (auto* c : panel->findChildren<QComboBox*>())
    if (!combo && c->objectName().startsWith("combo.")) combo = c;
  ASSERT_NE(slider, nullptr);
  ASSERT_NE(spin, nullptr);
  ASSERT_NE(combo, nullptr);
  for (QWidget* c :
       {static_cast<QWidget*>(slider), static_cast<QWidget*>(spin), static_cast<QWidget*>(combo)}) {
    EXPECT_EQ(c->focusPolicy(), Qt::StrongFocus) << c->objectName().toStdString();
    EXPECT_FALSE(c->hasFocus());
    EXPECT_FALSE(wheelOver(c, 3)) << c->objectName().toStdString() << " kept the wheel";
  }
  EXPECT_EQ(w.values(), before);
  EXPECT_EQ(panel->values(), before);
}

TEST_F(ParamWheelGui, AFocusedSliderTakesTheWheel) {
  auto* slider = w.paramPanel()->findChild<QSlider*>("slider.R");
  ASSERT_NE(slider, nullptr);
  w.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&w));
  slider->setFocus();
  QApplication::processEvents();
  ASSERT_TRUE(slider->hasFocus());
  const double r = w.values().at("R");
  wheelOver(slider, 1);  // (a log slider re-centres its window on the new value: read the value)
  EXPECT_NE(w.values().at("R"), r);
}

}  // namespace
}  // namespace kfw
