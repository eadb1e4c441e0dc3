// The GUI side of a scenario: its plots (and optional extra controls). One per scenario, in
// widgets/scenarios/<name>_plots.cpp, registered by name; the main window knows no scenario.
#pragma once

#include <QList>
#include <QObject>
#include <QPair>
#include <QString>
#include <functional>
#include <map>
#include <memory>

#include "core/param_spec.h"
#include "core/scenario.h"

class QCustomPlot;
class QWidget;

namespace kfw {

struct PlotPanel {
  QString name;   // file stem for export: "angle", "innovation", ...
  QString title;  // shown above the plot
  QCustomPlot* plot = nullptr;
  // Shown by presentation mode until the lecturer chooses (none flagged: the first two).
  bool presented = false;
};

class ScenarioView : public QObject {
  Q_OBJECT
 public:
  using QObject::QObject;
  ~ScenarioView() override = default;

  // The scenario this view draws, before createPlots (a view whose plots depend on the model,
  // or that asks the engine for more than a result holds, keeps it).
  virtual void setScenario(std::shared_ptr<const Scenario> scenario) { Q_UNUSED(scenario); }
  // The dataset of the next setResult (file or simulated).
  virtual void setDataset(std::shared_ptr<const Dataset> data) { Q_UNUSED(data); }
  // Creates the plots once, as children of `parent`; the main window lays them out.
  virtual QList<PlotPanel> createPlots(QWidget* parent) = 0;
  // Optional controls shown under the parameter panel (an IMM grid editor, ...).
  virtual QWidget* createControls(QWidget* parent) {
    Q_UNUSED(parent);
    return nullptr;
  }
  // A new run result (GUI thread). Rebuild every plot's data from it; `values` are the
  // parameters it was run with. Call replot on every plot.
  virtual void setResult(std::shared_ptr<const RunResult> result, const ParamValues& values) = 0;
  // Replay: show steps [0, index]; index >= steps() shows everything. Replot.
  virtual void setCursor(std::size_t index) = 0;
  // True while the view still computes something in the background (a gain curve); the window's
  // waitForRun() waits for it, so tests and exports see the finished plots.
  virtual bool busy() const { return false; }
  // Pinned tunings to draw as faded ghosts beside the live run (optional; empty clears).
  using Snapshots = QList<QPair<QString, std::shared_ptr<const RunResult>>>;
  virtual void setSnapshots(const Snapshots& snapshots) { Q_UNUSED(snapshots); }

 signals:
  // A control of createControls() changed a parameter (key, new value).
  void parameterEdited(const QString& key, double value);
  // The background work busy() reported is done and drawn.
  void idle();
};

class ViewRegistry {
 public:
  using Factory = std::function<std::unique_ptr<ScenarioView>()>;
  void add(const std::string& scenario, Factory f) { factories_[scenario] = std::move(f); }
  std::unique_ptr<ScenarioView> make(const std::string& scenario) const;

 private:
  std::map<std::string, Factory> factories_;
};

// Every view compiled in (widgets/scenarios/*_plots.cpp: the model view).
const ViewRegistry& views();

}  // namespace kfw
