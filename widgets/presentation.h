// Presentation mode for the lecture hall: the window full screen, every font × a scale the
// lecturer sets (Ctrl+= / Ctrl+−, remembered), pens wider, bands and ghosts strong, and only the
// plots the lecturer chose, larger (one column for up to two, two columns for more), titles
// wrapped to fit instead of cut.
#pragma once

#include <QFont>
#include <QHash>
#include <QList>
#include <QObject>
#include <QPointer>
#include <QRect>
#include <QStringList>

#include "plot_look.h"
#include "scenario_view.h"

class QMainWindow;
class QCustomPlot;

namespace kfw {

class Presentation : public QObject {
  Q_OBJECT
 public:
  // Scale limits and step (× per Ctrl+= / Ctrl+−).
  static constexpr double kMinScale = 1.0, kMaxScale = 3.0, kStep = 1.15, kDefaultScale = 1.5;

  explicit Presentation(QMainWindow* window);
  bool on() const { return on_; }
  // Enters or leaves: full screen (optional, tests size the window themselves), fonts, look and
  // layout of `plots` (the scenario's) and `others` (consistency, data: look only).
  void setOn(bool on, const QList<PlotPanel>& plots, const QList<QCustomPlot*>& others, Theme theme,
             bool full_screen = true);
  double scale() const { return scale_; }
  // Remembered (QSettings "present/scale"); applied at once when on.
  void setScale(double scale);
  // The plots shown when on, by name; none chosen: those the view flags (PlotPanel::presented),
  // else the first two. Remembered per preset (setScenario takes its stem).
  QStringList chosen(const QList<PlotPanel>& plots) const;
  void setChosen(const QString& scenario, const QStringList& names);
  void setScenario(const QString& scenario);
  // Applies the look (and, when on, the layout) to plots made since (a new preset) or changed
  // (new curves): cheap when nothing changed.
  // Titles wrap to their plot's width now and on every resize (in and out of presentation).
  void wrapTitles(const QList<PlotPanel>& plots, const QList<QCustomPlot*>& others);
  void refresh(const QList<PlotPanel>& plots, const QList<QCustomPlot*>& others, Theme theme);

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void style(QCustomPlot* p, Theme theme, bool force);
  void arrange(const QList<PlotPanel>& plots);
  void restoreLayout(const QList<PlotPanel>& plots);

  QMainWindow* window_;
  bool on_ = false;
  double scale_ = kDefaultScale;
  QString scenario_;
  QStringList chosen_;
  QFont app_font_;
  bool was_maximized_ = false;
  QRect normal_geometry_;
};

}  // namespace kfw
