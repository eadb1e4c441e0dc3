// Issue 32, item 14: the UKF's α, β, κ are shown only under filter = ukf (they were shown, and did
// nothing, under kf and ekf). The keys stay in the table: the CLI, tune and sweep take them.
#include <gtest/gtest.h>

#include <QApplication>
#include <QComboBox>
#include <QLabel>
#include <QSlider>
#include <QTest>

#include "main_window.h"
#include "param_panel.h"

namespace kfw {
namespace {

TEST(ParamShownGui, UkfSlidersFollowTheFilterChoice) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("models/range_bearing", {}, {"sim.duration=20"}).ok());
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  ASSERT_TRUE(w.waitForRun());
  ParamPanel* panel = w.paramPanel();
  auto* filter = panel->findChild<QComboBox*>("combo.filter");
  ASSERT_NE(filter, nullptr);
  const int ukf = filter->findText("ukf");
  const int ekf = filter->findText("ekf");
  ASSERT_GE(ukf, 0);
  ASSERT_GE(ekf, 0);
  const auto shown = [&](const char* key) {
    auto* s = panel->findChild<QSlider*>(QString("slider.") + key);
    auto* l = panel->findChild<QLabel*>(QString("label.") + key);
    EXPECT_NE(s, nullptr) << key;
    EXPECT_NE(l, nullptr) << key;
    return s && l && s->isVisibleTo(panel) && l->isVisibleTo(panel);
  };
  for (int choice : {ekf, ukf, ekf}) {
    w.setParam("filter", choice);
    ASSERT_TRUE(w.waitForRun());
    QApplication::processEvents();
    for (const char* key : {"ukf.alpha", "ukf.beta", "ukf.kappa"})
      EXPECT_EQ(shown(key), choice == ukf)
          << key << " under " << filter->itemText(choice).toStdString();
    EXPECT_TRUE(shown("sigma_a"));  // every other row stays
  }
  EXPECT_TRUE(w.values().count("ukf.alpha"));  // the key is still a value of the run
}

}  // namespace
}  // namespace kfw
