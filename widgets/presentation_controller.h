// The window's look: the theme of the window and its plots, presentation mode (full screen,
// fonts × scale, strong pens, the chosen plots only; widgets/presentation.h does the work), the
// View menu that drives them, their part of the session's view state, and screenshot mode (no
// live timings in the status bar, so two screenshots are identical).
#pragma once

#include <QJsonValue>
#include <QList>
#include <QObject>
#include <QString>
#include <QStringList>
#include <functional>

#include "plot_look.h"
#include "scenario_view.h"

class QAction;
class QCustomPlot;
class QLabel;
class QMainWindow;
class QMenuBar;

namespace kfw {

class Presentation;

class PresentationController : public QObject {
  Q_OBJECT
 public:
  // `status` (may be null): the label whose timings screenshot mode leaves out.
  explicit PresentationController(QMainWindow* window, QLabel* status = nullptr);

  // Where the plots come from, asked each time: the scenario's (laid out when presenting) and
  // the others (consistency, data: their look only).
  void setPlotSources(std::function<QList<PlotPanel>()> plots,
                      std::function<QList<QCustomPlot*>()> others);
  // What the chosen plots are remembered under (the preset's stem).
  void setScenario(const QString& name) { scenario_ = name; }
  // The View menu: presentation mode (F11, Esc leaves), text size (Ctrl+= / Ctrl+−), the plots
  // shown when presenting, the dark theme.
  void buildMenu(QMenuBar* bar);

  void setTheme(Theme theme);
  Theme theme() const { return theme_; }
  void setPresentation(bool on);
  bool presentation() const;
  void setScale(double scale);
  double scale() const;
  void setPresentedPlots(const QStringList& names);
  QStringList presentedPlots() const;
  void setScreenshotMode(bool on);
  // New plots or curves take the theme and presentation look (after each run).
  void restyle();
  // A dialog's plots (Tune, Sweep, Monte Carlo) take the theme and presentation look now and
  // whenever they are redrawn with new curves; `dialog` may be null.
  void adopt(QWidget* dialog);
  // On/off, the text scale and the chosen plots, for the session.
  QJsonValue saveState() const;
  void restoreState(const QJsonValue& v);

 signals:
  // Presentation entered, left or re-laid out (a new scale or choice of plots).
  void presentationChanged(bool on);

 private:
  QList<PlotPanel> plots() const;
  QList<QCustomPlot*> others() const;

  QMainWindow* window_;
  QLabel* status_;
  Presentation* present_;
  QAction* present_action_ = nullptr;
  std::function<QList<PlotPanel>()> plots_;
  std::function<QList<QCustomPlot*>()> others_;
  QList<QCustomPlot*> adopted_;  // the open dialogs' plots
  QString scenario_;
  Theme theme_ = Theme::kLight;
  bool screenshot_mode_ = false;
};

}  // namespace kfw
