// MainWindow: the View menu — presentation mode (F11), text size (Ctrl+= / Ctrl+−), the plots shown
// when presenting, the theme — and screenshot mode (no live timings in view).
#include <qcustomplot.h>

#include <QAction>
#include <QGuiApplication>
#include <QJsonArray>
#include <QJsonObject>
#include <QLabel>
#include <QMenu>
#include <QMenuBar>
#include <QRegularExpression>

#include "consistency_panel.h"
#include "main_window.h"
#include "presentation.h"

namespace kfw {

namespace {

// The status text without its live timings ("run 1.2 ms", "request→plots 8.0 ms"): every
// " · "-separated part that holds a duration is left out.
QString withoutTimings(const QString& text) {
  static const QRegularExpression duration(R"(\d\s*(ms|s)\b)");
  QStringList kept;
  for (const QString& part : text.split(" · ")) {
    if (!part.contains(duration)) kept << part;
  }
  return kept.join(" · ");
}

}  // namespace

void MainWindow::buildViewMenu() {
  present_ = new Presentation(this);
  QMenu* view = menuBar()->addMenu("&View");
  QAction* present = view->addAction("&Presentation mode");
  present->setObjectName("presentAction");
  present->setCheckable(true);
  present->setShortcut(QKeySequence(Qt::Key_F11));
  connect(present, &QAction::toggled, this, [this](bool on) { setPresentation(on); });
  QAction* leave = new QAction("Leave presentation mode", this);
  leave->setShortcut(QKeySequence(Qt::Key_Escape));
  leave->setShortcutContext(Qt::WindowShortcut);
  connect(leave, &QAction::triggered, this, [this] {
    if (presentation()) setPresentation(false);
  });
  addAction(leave);
  QAction* larger = view->addAction("&Larger text");
  larger->setShortcuts(
      {QKeySequence(Qt::CTRL | Qt::Key_Equal), QKeySequence(Qt::CTRL | Qt::Key_Plus)});
  connect(larger, &QAction::triggered, this,
          [this] { setPresentationScale(presentationScale() * Presentation::kStep); });
  QAction* smaller = view->addAction("&Smaller text");
  smaller->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Minus));
  connect(smaller, &QAction::triggered, this,
          [this] { setPresentationScale(presentationScale() / Presentation::kStep); });
  QMenu* plots = view->addMenu("Plots shown when &presenting");
  plots->setObjectName("presentPlotsMenu");
  connect(plots, &QMenu::aboutToShow, this, [this, plots] {
    plots->clear();
    const QStringList shown = presentedPlots();
    for (const PlotPanel& p : plots_) {
      QAction* a = plots->addAction(p.title.isEmpty() ? p.name : p.title);
      a->setCheckable(true);
      a->setChecked(shown.contains(p.name));
      connect(a, &QAction::toggled, this, [this, name = p.name](bool on) {
        QStringList s = presentedPlots();
        if (on && !s.contains(name)) s << name;
        if (!on) s.removeAll(name);
        setPresentedPlots(s);
      });
    }
  });
  view->addSeparator();
  QAction* dark = view->addAction("&Dark theme");
  dark->setObjectName("darkAction");
  dark->setCheckable(true);
  connect(dark, &QAction::toggled, this,
          [this](bool on) { setTheme(on ? Theme::kDark : Theme::kLight); });
  connect(this, &MainWindow::resultApplied, this, &MainWindow::restyleLook);
  // Presentation in the session's view state: on/off, the text scale and the chosen plots.
  addViewStatePart(
      "presentation",
      [this] {
        QJsonObject o;
        o["on"] = presentation();
        o["scale"] = presentationScale();
        o["plots"] = QJsonArray::fromStringList(presentedPlots());
        return QJsonValue(o);
      },
      [this](const QJsonValue& v) {
        const QJsonObject o = v.toObject();
        if (o["scale"].isDouble()) present_->setScale(o["scale"].toDouble());
        if (o["plots"].isArray()) {
          QStringList names;
          for (const QJsonValue& n : o["plots"].toArray()) {
            if (n.isString()) names << n.toString();
          }
          if (!names.isEmpty()) setPresentedPlots(names);
        }
        if (o["on"].isBool() && o["on"].toBool() != presentation()) {
          setPresentation(o["on"].toBool());
        } else if (presentation()) {
          setPresentation(true);  // the new scale and plots
        }
      });
}

void MainWindow::restyleLook() {
  if (scenario_) present_->setScenario(QString::fromStdString(scenario_->name()));
  if (screenshot_mode_) status_->setText(withoutTimings(status_->text()));
  QList<QCustomPlot*> others;
  for (const PlotPanel& p : consistency_->plots())
    others << p.plot;
  if (data_plot_) others << data_plot_;
  // Long titles wrap at a narrow window's width (they were cut at both ends at 1366 × 768).
  present_->wrapTitles(plots_, others);
  if (theme_ == Theme::kLight && !present_->on()) return;  // plot_kit's look: nothing more
  present_->refresh(plots_, others, theme_);
}

void MainWindow::setTheme(Theme theme) {
  theme_ = theme;
  applyWindowTheme(this, theme);
  QList<QCustomPlot*> others;
  for (const PlotPanel& p : consistency_->plots())
    others << p.plot;
  if (data_plot_) others << data_plot_;
  for (const PlotPanel& p : plots_)
    others << p.plot;
  for (QCustomPlot* p : others) {
    applyTheme(p, theme);
    p->replot(QCustomPlot::rpQueuedReplot);
  }
}

void MainWindow::setPresentation(bool on) {
  if (scenario_) present_->setScenario(QString::fromStdString(scenario_->name()));
  QList<QCustomPlot*> others;
  for (const PlotPanel& p : consistency_->plots())
    others << p.plot;
  if (data_plot_) others << data_plot_;
  // Offscreen (tests, --screenshot --present) the window keeps the size it was given: the
  // offscreen screen is 800 × 600.
  const bool full_screen = QGuiApplication::platformName() != "offscreen";
  present_->setOn(on, plots_, others, theme_, full_screen);
  if (auto* a = findChild<QAction*>("presentAction")) {
    const QSignalBlocker b(a);
    a->setChecked(on);
  }
}

bool MainWindow::presentation() const {
  return present_->on();
}

void MainWindow::setPresentationScale(double scale) {
  present_->setScale(scale);
  if (present_->on()) setPresentation(true);
}

double MainWindow::presentationScale() const {
  return present_->scale();
}

void MainWindow::setPresentedPlots(const QStringList& names) {
  present_->setChosen(scenario_ ? QString::fromStdString(scenario_->name()) : QString(), names);
  if (present_->on()) setPresentation(true);
}

QStringList MainWindow::presentedPlots() const {
  return present_->chosen(plots_);
}

void MainWindow::setScreenshotMode(bool on) {
  screenshot_mode_ = on;
  if (on) status_->setText(withoutTimings(status_->text()));
}

}  // namespace kfw
