// Where a widget is and how much of it a user sees, for GUI tests.
#pragma once

#include <QRect>
#include <QWidget>

namespace kfw::testing {

// The rectangle of `w` in `top`'s coordinates.
inline QRect inWindow(const QWidget* w, const QWidget* top) {
  return QRect(w->mapTo(top, QPoint(0, 0)), w->size());
}

// What of `w` is shown: its rectangle clipped by every ancestor up to `top`.
inline QRect shownPart(const QWidget* w, const QWidget* top) {
  QRect r = inWindow(w, top);
  for (const QWidget* p = w->parentWidget(); p && p != top; p = p->parentWidget())
    r &= inWindow(p, top);
  return r & top->rect();
}

// Visible and not clipped by any ancestor.
inline bool wholeShown(const QWidget* w, const QWidget* top) {
  return w->isVisible() && shownPart(w, top) == inWindow(w, top);
}

}  // namespace kfw::testing
