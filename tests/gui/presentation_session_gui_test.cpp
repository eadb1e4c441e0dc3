// Presentation mode is part of the session's view state: on/off, the text scale and the chosen
// plots come back when the session is opened in another window.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QJsonDocument>
#include <QJsonObject>
#include <QSettings>
#include <QTemporaryDir>
#include <algorithm>

#include "main_window.h"

namespace kfw {
namespace {

TEST(PresentationSession, OnScaleAndPlotsRoundTrip) {
  QSettings("kfw", "kfw").remove("present");
  QTemporaryDir dir;
  const QString path = dir.filePath("s.json");
  QStringList chosen;
  {
    MainWindow w;
    ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=10"}).ok());
    w.resize(1366, 768);
    w.show();
    ASSERT_TRUE(w.waitForRun());
    ASSERT_GE(w.plots().size(), 4);
    chosen = {w.plots()[3].name, w.plots()[1].name};
    w.setPresentedPlots(chosen);
    w.setPresentationScale(2.0);
    w.setPresentation(true);
    const QJsonObject part =
        QJsonDocument::fromJson(w.viewState().toUtf8()).object()["presentation"].toObject();
    EXPECT_TRUE(part["on"].toBool());
    EXPECT_DOUBLE_EQ(part["scale"].toDouble(), 2.0);
    ASSERT_TRUE(w.saveSession(path).ok());
    w.setPresentation(false);
  }
  // Another window, other remembered settings: the session's state wins.
  QSettings("kfw", "kfw").remove("present");
  MainWindow back;
  back.resize(1366, 768);
  back.show();
  EXPECT_FALSE(back.presentation());
  ASSERT_TRUE(back.loadSession(path).ok());
  ASSERT_TRUE(back.waitForRun());
  EXPECT_TRUE(back.presentation());
  EXPECT_DOUBLE_EQ(back.presentationScale(), 2.0);
  QStringList shown = back.presentedPlots();
  std::sort(shown.begin(), shown.end());
  std::sort(chosen.begin(), chosen.end());
  EXPECT_EQ(shown, chosen);
  // Only the chosen plots are shown.
  for (const PlotPanel& p : back.plots())
    EXPECT_EQ(p.plot->isVisibleTo(&back), chosen.contains(p.name)) << p.name.toStdString();
  // A session saved outside presentation mode leaves it.
  back.setPresentation(false);
  ASSERT_TRUE(back.saveSession(path).ok());
  back.setPresentation(true);
  ASSERT_TRUE(back.loadSession(path).ok());
  ASSERT_TRUE(back.waitForRun());
  EXPECT_FALSE(back.presentation());
  back.setPresentation(false);
  QSettings("kfw", "kfw").remove("present");
}

}  // namespace
}  // namespace kfw
