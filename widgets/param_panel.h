// The parameter panel, generated from a scenario's ParamTable: a slider + spin box + unit per
// parameter (log sliders for variances), a combo box for choices, a check box for toggles.
#pragma once

#include <QList>
#include <QMap>
#include <QString>
#include <QWidget>
#include <map>
#include <optional>
#include <utility>

#include "core/param_spec.h"

class QSlider;
class QComboBox;
class QCheckBox;
class QGroupBox;

namespace kfw {

class ValueSpinBox;

class ParamPanel : public QWidget {
  Q_OBJECT
 public:
  using Ranges = std::map<std::string, std::pair<double, double>, std::less<>>;
  ParamPanel(const ParamTable& table, const Ranges& ranges, QWidget* parent = nullptr);

  const ParamValues& values() const { return values_; }
  // Shows new values without emitting valueChanged.
  void setValues(const ParamValues& values);
  // Sets one value as if the user had moved its control (emits valueChanged when it changes).
  void setValue(const std::string& key, double value);
  // Enables or disables every control of a group ("Simulator" when the data come from a file).
  void setGroupEnabled(const QString& group, bool enabled, const QString& why = {});

  // Slider position <-> value, exposed for tests.
  static int toSlider(const ParamSpec& s, double lo, double hi, double v);
  static double fromSlider(const ParamSpec& s, double lo, double hi, int pos);
  static constexpr int kSliderSteps = 1000;
  // A log slider spans at most this many decades around the current value (re-centred when the
  // drag ends or the value changes otherwise); the spin box takes the whole range.
  static constexpr double kLogWindowDecades = 3.0;
  // The range a slider spans now: the window of a log slider, else [lo, hi].
  std::pair<double, double> sliderRange(const std::string& key) const;

 signals:
  void valueChanged(const QString& key, double value);

 protected:
  // Shift + drag on a slider: ten times finer than the slider's own scale.
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  struct Row {
    ParamSpec spec;
    double lo = 0, hi = 1;
    double wlo = 0, whi = 1;  // what the slider spans (a log slider: a window around the value)
    QSlider* slider = nullptr;
    ValueSpinBox* spin = nullptr;
    QComboBox* combo = nullptr;
    QCheckBox* check = nullptr;
    QGroupBox* group = nullptr;
    QList<QWidget*> widgets;  // every widget of the row (label, unit, controls): shown together
  };
  // Shows each row whose ParamSpec::shown_with choice holds one of its labels, hides the others.
  void updateShown();
  void commit(Row& row, double v);
  void show(Row& row, double v);
  // Centres a log slider's window on v (within [lo, hi]); other sliders span [lo, hi].
  static void centre(Row& row, double v);

  std::map<std::string, Row, std::less<>> rows_;
  struct FineDrag {
    std::string key;
    int x0 = 0;
    int pos0 = 0;  // the slider position (in its window) where the drag started
  };
  std::optional<FineDrag> fine_;
  QMap<QString, QGroupBox*> groups_;
  ParamValues values_;
};

}  // namespace kfw
