// What the window's menu actions share: a std::string as a QString, and a failed action's
// message in a box titled after the action.
#pragma once

#include <QMessageBox>
#include <QString>
#include <string>

#include "core/expected.h"

namespace kfw::window {

inline QString q(const std::string& s) {
  return QString::fromStdString(s);
}

inline void report(QWidget* parent, const char* title, const Status& st) {
  if (!st) QMessageBox::warning(parent, title, q(st.error()));
}

}  // namespace kfw::window
