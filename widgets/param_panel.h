// The parameter panel, generated from a scenario's ParamTable: a slider + spin box + unit per
// parameter (log sliders for variances), a combo box for choices, a check box for toggles.
#pragma once

#include <QMap>
#include <QString>
#include <QWidget>
#include <map>
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

 signals:
  void valueChanged(const QString& key, double value);

 private:
  struct Row {
    ParamSpec spec;
    double lo = 0, hi = 1;
    QSlider* slider = nullptr;
    ValueSpinBox* spin = nullptr;
    QComboBox* combo = nullptr;
    QCheckBox* check = nullptr;
    QGroupBox* group = nullptr;
  };
  void commit(Row& row, double v);
  void show(Row& row, double v);

  std::map<std::string, Row, std::less<>> rows_;
  QMap<QString, QGroupBox*> groups_;
  ParamValues values_;
};

}  // namespace kfw
