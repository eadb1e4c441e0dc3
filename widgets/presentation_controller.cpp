#include "presentation_controller.h"

#include <qcustomplot.h>

#include <QAction>
#include <QGuiApplication>
#include <QJsonArray>
#include <QJsonObject>
#include <QLabel>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QRegularExpression>

#include "draw_batch.h"
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

PresentationController::PresentationController(QMainWindow* window, QLabel* status)
    : QObject(window), window_(window), status_(status), present_(new Presentation(window)) {}

void PresentationController::setPlotSources(std::function<QList<PlotPanel>()> plots,
                                            std::function<QList<QCustomPlot*>()> others) {
  plots_ = std::move(plots);
  others_ = std::move(others);
}

QList<PlotPanel> PresentationController::plots() const {
  return plots_ ? plots_() : QList<PlotPanel>();
}

QList<QCustomPlot*> PresentationController::others() const {
  QList<QCustomPlot*> out = others_ ? others_() : QList<QCustomPlot*>();
  return out + adopted_;
}

void PresentationController::buildMenu(QMenuBar* bar) {
  QMenu* view = bar->addMenu("&View");
  present_action_ = view->addAction("&Presentation mode");
  present_action_->setObjectName("presentAction");
  present_action_->setCheckable(true);
  present_action_->setShortcut(QKeySequence(Qt::Key_F11));
  connect(present_action_, &QAction::toggled, this, [this](bool on) { setPresentation(on); });
  auto* leave = new QAction("Leave presentation mode", window_);
  leave->setShortcut(QKeySequence(Qt::Key_Escape));
  leave->setShortcutContext(Qt::WindowShortcut);
  connect(leave, &QAction::triggered, this, [this] {
    if (presentation()) setPresentation(false);
  });
  window_->addAction(leave);
  QAction* larger = view->addAction("&Larger text");
  larger->setShortcuts(
      {QKeySequence(Qt::CTRL | Qt::Key_Equal), QKeySequence(Qt::CTRL | Qt::Key_Plus)});
  connect(larger, &QAction::triggered, this, [this] { setScale(scale() * Presentation::kStep); });
  QAction* smaller = view->addAction("&Smaller text");
  smaller->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Minus));
  connect(smaller, &QAction::triggered, this, [this] { setScale(scale() / Presentation::kStep); });
  QMenu* shown = view->addMenu("Plots shown when &presenting");
  shown->setObjectName("presentPlotsMenu");
  connect(shown, &QMenu::aboutToShow, this, [this, shown] {
    shown->clear();
    const QStringList chosen = presentedPlots();
    for (const PlotPanel& p : plots()) {
      QAction* a = shown->addAction(p.title.isEmpty() ? p.name : p.title);
      a->setCheckable(true);
      a->setChecked(chosen.contains(p.name));
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
}

void PresentationController::restyle() {
  if (!scenario_.isEmpty()) present_->setScenario(scenario_);
  if (screenshot_mode_ && status_) status_->setText(withoutTimings(status_->text()));
  // Long titles wrap at a narrow window's width (they were cut at both ends at 1366 × 768).
  const QList<PlotPanel> shown = plots();
  const QList<QCustomPlot*> rest = others();
  present_->wrapTitles(shown, rest);
  if (theme_ == Theme::kLight && !present_->on()) return;  // plot_kit's look: nothing more
  present_->refresh(shown, rest, theme_);
}

void PresentationController::adopt(QWidget* dialog) {
  if (!dialog) return;
  for (QCustomPlot* p : dialog->findChildren<QCustomPlot*>()) {
    if (adopted_.contains(p)) continue;  // a dialog opened again
    adopted_ << p;
    // Cheap when nothing changed (the look's stamp); a new curve gets the look before it shows.
    connect(p, &QCustomPlot::beforeReplot, this, [this, p] { present_->refresh({}, {p}, theme_); });
    connect(p, &QObject::destroyed, this, [this, p] { adopted_.removeAll(p); });
  }
  present_->refresh({}, adopted_, theme_);
}

void PresentationController::setTheme(Theme theme) {
  theme_ = theme;
  applyWindowTheme(window_, theme);
  QList<QCustomPlot*> all = others();
  for (const PlotPanel& p : plots())
    all << p.plot;
  for (QCustomPlot* p : all) {
    applyTheme(p, theme);
    plot::replotQueued(p);
  }
}

void PresentationController::setPresentation(bool on) {
  if (!scenario_.isEmpty()) present_->setScenario(scenario_);
  // Offscreen (tests, --screenshot --present) the window keeps the size it was given: the
  // offscreen screen is 800 × 600.
  const bool full_screen = QGuiApplication::platformName() != "offscreen";
  present_->setOn(on, plots(), others(), theme_, full_screen);
  if (present_action_) {
    const QSignalBlocker b(present_action_);
    present_action_->setChecked(on);
  }
  emit presentationChanged(on);
}

bool PresentationController::presentation() const {
  return present_->on();
}

void PresentationController::setScale(double scale) {
  present_->setScale(scale);
  if (present_->on()) setPresentation(true);
}

double PresentationController::scale() const {
  return present_->scale();
}

void PresentationController::setPresentedPlots(const QStringList& names) {
  present_->setChosen(scenario_, names);
  if (present_->on()) setPresentation(true);
}

QStringList PresentationController::presentedPlots() const {
  return present_->chosen(plots());
}

void PresentationController::setScreenshotMode(bool on) {
  screenshot_mode_ = on;
  if (on && status_) status_->setText(withoutTimings(status_->text()));
}

QJsonValue PresentationController::saveState() const {
  QJsonObject o;
  o["on"] = presentation();
  o["scale"] = scale();
  o["plots"] = QJsonArray::fromStringList(presentedPlots());
  return QJsonValue(o);
}

void PresentationController::restoreState(const QJsonValue& v) {
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
}

}  // namespace kfw
