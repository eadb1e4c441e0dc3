// Small helpers shared by GUI tests: a file's bytes, and waiting for a dialog's background run.
#pragma once

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QFile>

namespace kfw::testing {

// The whole file, or empty when it cannot be read.
inline QByteArray readAll(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return f.readAll();
}

// Processes events until the dialog's run (sweep, tune, Monte Carlo) ends; false after `ms`.
template <typename D>
bool waitDone(D* d, int ms = 60000) {
  QDeadlineTimer t(ms);
  while (d->running()) {
    if (t.hasExpired()) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents, 10);
  }
  QCoreApplication::processEvents();
  return true;
}

}  // namespace kfw::testing
