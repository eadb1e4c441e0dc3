// One main for the GUI tests: defaults QT_QPA_PLATFORM to offscreen (test discovery runs this
// binary at build time, with no display) and creates the single QApplication.
#include <gtest/gtest.h>

#include <QApplication>
#include <QFont>

int main(int argc, char** argv) {
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  ::testing::InitGoogleTest(&argc, argv);
  QApplication app(argc, argv);
  QApplication::setFont(QFont("DejaVu Sans", 9));
  return RUN_ALL_TESTS();
}
