// One main for the GUI tests: defaults QT_QPA_PLATFORM to offscreen (test discovery runs this
// binary at build time, with no display), gives the process settings of its own, and creates the
// single QApplication.
#include <gtest/gtest.h>

#include <QApplication>
#include <QFont>
#include <QTemporaryDir>

int main(int argc, char** argv) {
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  ::testing::InitGoogleTest(&argc, argv);
  // ctest runs the tests in parallel processes: with one shared ~/.config/kfw/kfw.conf, one test's
  // clean-up (the remembered column mappings, the window size) raced another's use of it. Each
  // process gets an empty configuration directory (QSettings reads XDG_CONFIG_HOME).
  QTemporaryDir config;
  if (config.isValid()) qputenv("XDG_CONFIG_HOME", config.path().toLocal8Bit());
  QApplication app(argc, argv);
  QApplication::setFont(QFont("DejaVu Sans", 9));
  return RUN_ALL_TESTS();
}
