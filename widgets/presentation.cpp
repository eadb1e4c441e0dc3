#include "presentation.h"

#include <qcustomplot.h>

#include <QApplication>
#include <QEvent>
#include <QGridLayout>
#include <QMainWindow>
#include <QSettings>
#include <algorithm>

#include "draw_batch.h"

namespace kfw {

namespace {

const char* const kStamp = "kfwLookStamp";
const char* const kGridPos = "kfwGridPos";  // QRect(column, row, column span, row span)
const char* const kMinHeight = "kfwMinHeight";
const char* const kColumnStretch = "kfwColumnStretch";  // the grid's own, while presenting

QSettings settings() {
  return QSettings("kfw", "kfw");
}

}  // namespace

Presentation::Presentation(QMainWindow* window) : QObject(window), window_(window) {
  bool ok = false;
  const double s = settings().value("present/scale").toDouble(&ok);
  if (ok) scale_ = std::clamp(s, kMinScale, kMaxScale);
}

void Presentation::setScenario(const QString& scenario) {
  if (scenario == scenario_) return;
  scenario_ = scenario;
  chosen_ = settings().value("present/plots/" + scenario).toStringList();
}

QStringList Presentation::chosen(const QList<PlotPanel>& plots) const {
  QStringList out;
  for (const PlotPanel& p : plots) {
    if (chosen_.contains(p.name)) out << p.name;
  }
  if (out.isEmpty()) {
    for (const PlotPanel& p : plots) {
      if (p.presented) out << p.name;
    }
  }
  if (out.isEmpty()) {
    for (int i = 0; i < std::min<int>(2, static_cast<int>(plots.size())); ++i)
      out << plots[i].name;
  }
  return out;
}

void Presentation::setChosen(const QString& scenario, const QStringList& names) {
  scenario_ = scenario;
  chosen_ = names;
  settings().setValue("present/plots/" + scenario, names);
}

void Presentation::setScale(double scale) {
  scale_ = std::clamp(scale, kMinScale, kMaxScale);
  settings().setValue("present/scale", scale_);
  if (on_) {
    QFont f = app_font_;
    f.setPointSizeF(app_font_.pointSizeF() * scale_);
    QApplication::setFont(f);
  }
}

void Presentation::style(QCustomPlot* p, Theme theme, bool force) {
  const PlotLook look{theme, on_ ? scale_ : 1.0, on_};
  const QString stamp = QString("%1/%2/%3/%4/%5")
                            .arg(static_cast<int>(theme))
                            .arg(look.font_scale)
                            .arg(look.strong)
                            .arg(p->plottableCount())
                            .arg(p->itemCount());
  if (!force && p->property(kStamp).toString() == stamp) return;
  p->setProperty(kStamp, stamp);
  setPlotLook(p, look);
  wrapTitlesToWidth(p);
  p->removeEventFilter(this);
  p->installEventFilter(this);
  plot::replotQueued(p);
}

void Presentation::wrapTitles(const QList<PlotPanel>& plots, const QList<QCustomPlot*>& others) {
  QList<QCustomPlot*> all = others;
  for (const PlotPanel& p : plots)
    all << p.plot;
  for (QCustomPlot* p : all) {
    if (wrapTitlesToWidth(p)) plot::replotQueued(p);
    // Before every replot too: a view may set a new title with its data.
    if (!p->property("kfwWrapOnReplot").toBool()) {
      p->setProperty("kfwWrapOnReplot", true);
      connect(p, &QCustomPlot::beforeReplot, p, [p] { wrapTitlesToWidth(p); });
    }
    p->removeEventFilter(this);
    p->installEventFilter(this);
  }
}

void Presentation::refresh(const QList<PlotPanel>& plots, const QList<QCustomPlot*>& others,
                           Theme theme) {
  for (const PlotPanel& p : plots)
    style(p.plot, theme, false);
  for (QCustomPlot* p : others)
    style(p, theme, false);
  if (on_ && !plots.isEmpty() && !plots.front().plot->property(kGridPos).isValid()) arrange(plots);
}

void Presentation::setOn(bool on, const QList<PlotPanel>& plots, const QList<QCustomPlot*>& others,
                         Theme theme, bool full_screen) {
  if (on && !on_) {
    app_font_ = QApplication::font();
    was_maximized_ = window_->isMaximized();
    normal_geometry_ = window_->geometry();
  }
  if (on == on_) {
    // Only the scale or the choice of plots changed.
    if (on) {
      arrange(plots);
    }
  } else if (!on) {
    restoreLayout(plots);
  }
  const bool entering = on && !on_;
  on_ = on;
  if (on) {
    QFont f = app_font_;
    f.setPointSizeF(app_font_.pointSizeF() * scale_);
    QApplication::setFont(f);
  } else {
    QApplication::setFont(app_font_);
  }
  for (const PlotPanel& p : plots)
    style(p.plot, theme, true);
  for (QCustomPlot* p : others)
    style(p, theme, true);
  if (entering) {
    arrange(plots);
    if (full_screen) window_->showFullScreen();
  } else if (!on) {
    if (window_->isFullScreen()) {
      if (was_maximized_) {
        window_->showMaximized();
      } else {
        window_->showNormal();
        window_->setGeometry(normal_geometry_);
      }
    }
  }
}

// The chosen plots, alone and larger, in the plots' grid; the places they had are kept on them
// (a property) so leaving gives back the window's own layout.
void Presentation::arrange(const QList<PlotPanel>& plots) {
  if (plots.isEmpty()) return;
  const QStringList shown = chosen(plots);
  auto* grid = qobject_cast<QGridLayout*>(plots.front().plot->parentWidget()->layout());
  for (const PlotPanel& p : plots) {
    if (!p.plot->property(kMinHeight).isValid())
      p.plot->setProperty(kMinHeight, p.plot->minimumHeight());
    if (grid && !p.plot->property(kGridPos).isValid()) {
      const int index = grid->indexOf(p.plot);
      if (index >= 0) {
        int row = 0, col = 0, rs = 1, cs = 1;
        grid->getItemPosition(index, &row, &col, &rs, &cs);
        p.plot->setProperty(kGridPos, QRect(col, row, cs, rs));
      }
    }
  }
  if (grid) {
    for (const PlotPanel& p : plots)
      grid->removeWidget(p.plot);
  }
  const int columns = shown.size() <= 2 ? 1 : 2;
  if (grid) {
    // One column takes the whole width (the window's grid gives its two columns equal stretch).
    QWidget* host = grid->parentWidget();
    if (!host->property(kColumnStretch).isValid())
      host->setProperty(kColumnStretch, QPoint(grid->columnStretch(0), grid->columnStretch(1)));
    grid->setColumnStretch(1, columns == 2 ? std::max(1, grid->columnStretch(0)) : 0);
  }
  int k = 0;
  for (const PlotPanel& p : plots) {
    const bool show = shown.contains(p.name);
    p.plot->setVisible(show);
    if (!show) continue;
    p.plot->setMinimumHeight(200);
    if (grid) grid->addWidget(p.plot, k / columns, k % columns);
    ++k;
  }
}

void Presentation::restoreLayout(const QList<PlotPanel>& plots) {
  if (plots.isEmpty()) return;
  auto* grid = qobject_cast<QGridLayout*>(plots.front().plot->parentWidget()->layout());
  if (grid) {
    for (const PlotPanel& p : plots)
      grid->removeWidget(p.plot);
    QWidget* host = grid->parentWidget();
    if (const QVariant s = host->property(kColumnStretch); s.isValid()) {
      grid->setColumnStretch(0, s.toPoint().x());
      grid->setColumnStretch(1, s.toPoint().y());
      host->setProperty(kColumnStretch, QVariant());
    }
  }
  for (const PlotPanel& p : plots) {
    const QVariant pos = p.plot->property(kGridPos);
    if (grid && pos.isValid()) {
      const QRect r = pos.toRect();
      grid->addWidget(p.plot, r.y(), r.x(), r.height(), r.width());
    }
    p.plot->setProperty(kGridPos, QVariant());
    const QVariant mh = p.plot->property(kMinHeight);
    if (mh.isValid()) p.plot->setMinimumHeight(mh.toInt());
    p.plot->setVisible(true);
  }
}

bool Presentation::eventFilter(QObject* watched, QEvent* event) {
  if (event->type() == QEvent::Resize) {
    auto* p = qobject_cast<QCustomPlot*>(watched);
    if (p && wrapTitlesToWidth(p)) plot::replotQueued(p);
  }
  return QObject::eventFilter(watched, event);
}

}  // namespace kfw
