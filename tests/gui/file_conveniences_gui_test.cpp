// The conveniences PlotJuggler and MATLAB users expect (issue 32, item 11): recent files, a file
// dropped on the window, Ctrl+S for the session, shortcuts, a legend click hiding a curve, and the
// command line that reproduces the window's state.
#include <qcustomplot.h>

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <QAction>
#include <QApplication>
#include <QFile>
#include <QMenuBar>
#include <QMimeData>
#include <QTemporaryDir>
#include <QTest>
#include <QUrl>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"
#include "common/plot_probe.h"
#include "main_window.h"
#include "plot_kit.h"

namespace kfw {
namespace {

using testing::graphNamed;
using testing::plotNamed;

QString source(const char* rel) {
  return QString(KFW_SOURCE_DIR) + "/" + rel;
}

void drop(MainWindow& w, const QString& path) {
  QMimeData mime;
  mime.setUrls({QUrl::fromLocalFile(path)});
  QDragEnterEvent enter(QPoint(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&w, &enter);
  ASSERT_TRUE(enter.isAccepted());
  QDropEvent ev(QPointF(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&w, &ev);
}

TEST(FileConveniences, DropOpensByKindAndRecentFilesRemember) {
  QTemporaryDir dir;
  MainWindow w;
  w.show();
  drop(w, source("presets/helicopter.json"));
  ASSERT_TRUE(w.waitForRun());
  EXPECT_TRUE(QString::fromStdString(w.preset().path).endsWith("helicopter.json"));
  drop(w, source("data/helicopter.csv"));
  ASSERT_TRUE(w.waitForRun());
  ASSERT_TRUE(w.document()->data());
  EXPECT_TRUE(QString::fromStdString(w.document()->data()->path).endsWith("helicopter.csv"));
  w.setParam("R", 3.0);
  ASSERT_TRUE(w.waitForRun());
  const QString session = dir.filePath("s.json");
  ASSERT_TRUE(w.saveSessionAs(session).ok());
  EXPECT_EQ(MainWindow::openAsFor(session), MainWindow::OpenAs::kSession);
  ASSERT_TRUE(w.openAnyFile(source("presets/models/cv1d.json")).ok());
  ASSERT_TRUE(w.waitForRun());
  drop(w, session);  // a session: the helicopter back, R = 3
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(w.values().at("R"), 3.0);
  const QStringList recent = MainWindow::recentFiles();
  ASSERT_GE(recent.size(), 4);
  EXPECT_EQ(recent[0], QFileInfo(session).absoluteFilePath());
  EXPECT_EQ(recent[1], QFileInfo(source("presets/models/cv1d.json")).absoluteFilePath());
  // Ctrl+S writes to the session opened last.
  w.setParam("R", 5.0);
  ASSERT_TRUE(w.waitForRun());
  ASSERT_TRUE(w.saveSessionHere().ok());
  QFile f(session);
  ASSERT_TRUE(f.open(QIODevice::ReadOnly));
  EXPECT_EQ(nlohmann::json::parse(f.readAll().toStdString())["values"]["R"], 5.0);
}

// A FIFO named .json (dropped, or left in the recent list) is refused at once, naming it; the
// open preset stays.
TEST(FileConveniences, AFifoIsRefusedWithoutWaiting) {
  QTemporaryDir dir;
  const QString fifo = dir.filePath("pipe.json");
  ASSERT_EQ(::mkfifo(fifo.toLocal8Bit().constData(), 0600), 0);
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("models/cv1d").ok());
  ASSERT_TRUE(w.waitForRun());
  EXPECT_EQ(MainWindow::openAsFor(fifo), MainWindow::OpenAs::kPreset);
  const Status st = w.openAnyFile(fifo);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("pipe.json"), std::string::npos) << st.error();
  EXPECT_TRUE(QString::fromStdString(w.preset().path).endsWith("cv1d.json"));
}

TEST(FileConveniences, ShortcutsAreThereAndDistinct) {
  MainWindow w;
  QMap<QString, QString> by_key;
  for (QAction* a : w.menuBar()->findChildren<QAction*>()) {
    const QString k = a->shortcut().toString();
    if (k.isEmpty()) continue;
    EXPECT_FALSE(by_key.contains(k))
        << k.toStdString() << ": " << a->text().toStdString() << " and " << by_key[k].toStdString();
    by_key[k] = a->text();
  }
  for (const char* k :
       {"Ctrl+S", "Ctrl+T", "Ctrl+Shift+T", "Ctrl+M", "Ctrl+P", "Ctrl+R", "Ctrl+E", "Ctrl+Shift+C"})
    EXPECT_TRUE(by_key.contains(k)) << k;
}

TEST(FileConveniences, ALegendClickHidesACurveThroughRuns) {
  MainWindow w;
  w.resize(1366, 768);
  w.show();
  ASSERT_TRUE(w.loadPreset("helicopter").ok());
  ASSERT_TRUE(w.waitForRun());
  QApplication::processEvents();
  QCustomPlot* p = plotNamed(w, "state.theta");
  ASSERT_TRUE(p);
  QCPGraph* truth = graphNamed(p, "truth");
  ASSERT_TRUE(truth && truth->visible());
  p->replot();
  QCPPlottableLegendItem* entry = p->legend->itemWithPlottable(truth);
  ASSERT_TRUE(entry);
  QTest::mouseClick(p, Qt::LeftButton, {}, entry->rect().center());
  EXPECT_FALSE(truth->visible());
  w.setParam("R", 3.0);  // a new run sets the truth visible again: the user's choice stays
  ASSERT_TRUE(w.waitForRun());
  QApplication::processEvents();
  p->replot();
  EXPECT_FALSE(truth->visible());
  QTest::mouseClick(p, Qt::LeftButton, {}, p->legend->itemWithPlottable(truth)->rect().center());
  EXPECT_TRUE(truth->visible());
}

// The copied kfw-cli line reproduces the window's run: the same metrics.
TEST(FileConveniences, TheCommandLineReproducesTheRun) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("helicopter", source("data/helicopter.csv")).ok());
  ASSERT_TRUE(w.waitForRun());
  w.setParam("R", 3.0);
  w.setParam("Q", 51.25);
  ASSERT_TRUE(w.waitForRun());
  const QString lines = w.commandLine();
  const QString run = lines.section('\n', 0, 0);
  ASSERT_TRUE(run.startsWith("kfw-cli run ")) << lines.toStdString();
  EXPECT_TRUE(lines.section('\n', 1, 1).startsWith("kfw --export plots ")) << lines.toStdString();
  EXPECT_TRUE(run.contains("--set R=3")) << run.toStdString();
  EXPECT_TRUE(run.contains("--set Q=51.25")) << run.toStdString();
  const auto out = testing::run_command(std::string(KFW_CLI_FOR_GUI_TESTS) +
                                        run.mid(7).toStdString() + " 2>/dev/null");
  ASSERT_EQ(out.code, 0) << out.text;
  const auto j = nlohmann::json::parse(out.text);
  EXPECT_DOUBLE_EQ(j.at("rmse").get<double>(), w.result()->metrics.at("rmse"));
  EXPECT_DOUBLE_EQ(j.at("nis_mean").get<double>(), w.result()->metrics.at("nis_mean"));
}

}  // namespace
}  // namespace kfw
