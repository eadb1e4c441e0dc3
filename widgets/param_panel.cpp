#include "param_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QGroupBox>
#include <QLabel>
#include <QMouseEvent>
#include <QSignalBlocker>
#include <QSlider>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <utility>

#include "plot_text.h"

namespace kfw {

// A control of the scrolling panel that takes the mouse wheel only once it has the focus (clicked
// or tabbed to): a wheel that scrolls the panel past a slider leaves it alone — the ignored event
// goes on to the scroll area (issue 32: R moved while the lecturer scrolled).
template <class Base>
class FocusWheel : public Base {
 public:
  template <class... Args>
  explicit FocusWheel(Args&&... args) : Base(std::forward<Args>(args)...) {
    this->setFocusPolicy(Qt::StrongFocus);
  }

 protected:
  void wheelEvent(QWheelEvent* e) override {
    if (this->hasFocus()) {
      Base::wheelEvent(e);
    } else {
      e->ignore();
    }
  }
};

// A spin box that shows any magnitude readably (1e-06 … 1e+06) and steps in ratio on log scales.
class ValueSpinBox : public FocusWheel<QDoubleSpinBox> {
 public:
  ValueSpinBox(bool log, QWidget* parent) : FocusWheel<QDoubleSpinBox>(parent), log_(log) {
    setDecimals(12);
    setKeyboardTracking(false);
    setAlignment(Qt::AlignRight);
    // Sized for what textFromValue shows ("-1.23457e+06"), not for 12 decimals of the maximum.
    setFixedWidth(fontMetrics().horizontalAdvance("-1.23457e+06") + 34);
  }
  QString textFromValue(double v) const override { return QString::number(v, 'g', 6); }
  double valueFromText(const QString& text) const override { return text.trimmed().toDouble(); }
  QValidator::State validate(QString& text, int&) const override {
    bool ok = false;
    const double v = text.trimmed().toDouble(&ok);
    if (text.trimmed().isEmpty() || text.trimmed() == "-" || text.endsWith('e') ||
        text.endsWith("e-") || text.endsWith("e+") || text.endsWith('.')) {
      return QValidator::Intermediate;
    }
    if (!ok) return QValidator::Invalid;
    return (v >= minimum() && v <= maximum()) ? QValidator::Acceptable : QValidator::Intermediate;
  }
  void stepBy(int steps) override {
    if (log_ && value() > 0) {
      setValue(value() * std::pow(10.0, 0.1 * steps));
    } else {
      QDoubleSpinBox::stepBy(steps);
    }
  }

 private:
  bool log_;
};

int ParamPanel::toSlider(const ParamSpec& s, double lo, double hi, double v) {
  double f = 0.0;
  if (s.scale == Scale::kLog && lo > 0) {
    f = (std::log10(std::max(v, lo)) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  } else if (s.scale == Scale::kInteger && hi - lo <= kSliderSteps) {
    return static_cast<int>(std::lround(v - lo));
  } else {
    f = (v - lo) / (hi - lo);
  }
  return static_cast<int>(std::lround(std::clamp(f, 0.0, 1.0) * kSliderSteps));
}

double ParamPanel::fromSlider(const ParamSpec& s, double lo, double hi, int pos) {
  if (s.scale == Scale::kInteger && hi - lo <= kSliderSteps) return lo + pos;
  const double f = static_cast<double>(pos) / kSliderSteps;
  double v = 0.0;
  if (s.scale == Scale::kLog && lo > 0) {
    v = std::pow(10.0, std::log10(lo) + f * (std::log10(hi) - std::log10(lo)));
    // Three significant digits: values a user can read back and type.
    const double mag = std::pow(10.0, std::floor(std::log10(v)) - 2);
    v = std::clamp(std::round(v / mag) * mag, lo, hi);
  } else {
    v = lo + f * (hi - lo);
  }
  if (s.scale == Scale::kInteger) v = std::round(v);
  return v;
}

ParamPanel::ParamPanel(const ParamTable& table, const Ranges& ranges, QWidget* parent)
    : QWidget(parent) {
  auto* outer = new QVBoxLayout(this);
  outer->setContentsMargins(0, 0, 0, 0);
  values_ = table.defaults();
  for (const ParamSpec& s : table.specs()) {
    const QString gname = QString::fromStdString(s.group.empty() ? "Parameters" : s.group);
    QGroupBox* box = groups_.value(gname, nullptr);
    if (!box) {
      box = new QGroupBox(gname, this);
      box->setObjectName("group." + gname);
      auto* grid = new QGridLayout(box);
      grid->setContentsMargins(6, 4, 6, 4);
      grid->setVerticalSpacing(2);
      grid->setColumnStretch(1, 1);
      groups_.insert(gname, box);
      outer->addWidget(box);
    }
    auto* grid = static_cast<QGridLayout*>(box->layout());
    const int r = grid->rowCount();
    Row row;
    row.spec = s;
    row.group = box;
    row.lo = s.min;
    row.hi = s.max;
    if (auto it = ranges.find(s.key); it != ranges.end()) {
      row.lo = it->second.first;
      row.hi = it->second.second;
    }
    const QString key = QString::fromStdString(s.key);
    QString text = plot::typeset(QString::fromStdString(s.label));
    auto* label = new QLabel(text, box);
    label->setToolTip(QString::fromStdString(s.key + ": " + s.description));
    label->setObjectName("label." + key);
    grid->addWidget(label, r, 0, 1, 3);
    const QString unit = QString::fromStdString(s.unit);
    if (s.scale == Scale::kChoice) {
      row.combo = new FocusWheel<QComboBox>(box);
      row.combo->setObjectName("combo." + key);
      for (const auto& c : s.choices)
        row.combo->addItem(QString::fromStdString(c));
      grid->addWidget(row.combo, r + 1, 0, 1, 3);
      connect(row.combo, &QComboBox::currentIndexChanged, this,
              [this, k = s.key](int i) { commit(rows_.at(k), static_cast<double>(i)); });
    } else if (s.scale == Scale::kToggle) {
      row.check = new QCheckBox("on", box);
      row.check->setObjectName("check." + key);
      grid->addWidget(row.check, r + 1, 0, 1, 3);
      connect(row.check, &QCheckBox::toggled, this,
              [this, k = s.key](bool on) { commit(rows_.at(k), on ? 1.0 : 0.0); });
    } else {
      row.slider = new FocusWheel<QSlider>(Qt::Horizontal, box);
      row.slider->setObjectName("slider." + key);
      const bool direct = s.scale == Scale::kInteger && row.hi - row.lo <= kSliderSteps;
      row.slider->setRange(0, direct ? static_cast<int>(row.hi - row.lo) : kSliderSteps);
      row.slider->setToolTip(label->toolTip());
      row.spin = new ValueSpinBox(s.scale == Scale::kLog, box);
      row.spin->setObjectName("spin." + key);
      row.spin->setRange(row.lo, row.hi);
      if (s.scale == Scale::kInteger) {
        row.spin->setSingleStep(1.0);
      } else if (s.scale == Scale::kLinear) {
        row.spin->setSingleStep(std::pow(10.0, -std::min(s.decimals, 6)));
      }
      // The label with its unit on one row, the slider and the value below: the slider gets
      // ~190 px, so a log slider's three decades make a 90-px drag about 1.5 decades.
      grid->removeWidget(label);
      label->setWordWrap(true);
      grid->addWidget(label, r, 0, 1, 2);
      auto* unit_label = new QLabel(unit, box);
      unit_label->setObjectName("unit." + key);
      unit_label->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
      // A palette, not a style sheet: a styled label keeps the font it had when polished, so
      // leaving presentation left the units large (issue 32, item 5).
      QPalette pal = unit_label->palette();
      pal.setColor(QPalette::WindowText, QColor(0x66, 0x66, 0x66));
      unit_label->setPalette(pal);
      grid->addWidget(unit_label, r, 2);
      grid->addWidget(row.slider, r + 1, 0, 1, 2);
      grid->addWidget(row.spin, r + 1, 2);
      if (s.scale == Scale::kLog) {
        row.slider->setToolTip(label->toolTip() +
                               QString("\nThe slider spans %1 decades around the value (re-centred "
                                       "when you let go); type any value in the box.")
                                   .arg(kLogWindowDecades));
      }
      connect(row.slider, &QSlider::valueChanged, this, [this, k = s.key](int pos) {
        Row& rw = rows_.at(k);
        commit(rw, fromSlider(rw.spec, rw.wlo, rw.whi, pos));
      });
      row.slider->installEventFilter(this);
      connect(row.slider, &QSlider::sliderReleased, this, [this, k = s.key] {
        Row& rw = rows_.at(k);
        show(rw, values_.count(k) ? values_.at(k) : rw.spec.def);
      });
      connect(row.spin, &QDoubleSpinBox::valueChanged, this, [this, k = s.key](double v) {
        Row& rw = rows_.at(k);
        if (rw.spec.scale == Scale::kInteger) v = std::round(v);
        commit(rw, v);
      });
    }
    for (int i = 0; i < grid->count(); ++i) {
      int gr = 0, gc = 0, rs = 0, cs = 0;
      grid->getItemPosition(i, &gr, &gc, &rs, &cs);
      if ((gr == r || gr == r + 1) && grid->itemAt(i)->widget())
        row.widgets.append(grid->itemAt(i)->widget());
    }
    rows_.emplace(s.key, row);
  }
  outer->addStretch(1);
  setValues(values_);
}

void ParamPanel::updateShown() {
  for (auto& [key, row] : rows_) {
    if (row.spec.shown_with.empty()) continue;
    bool shown = true;
    if (auto c = rows_.find(row.spec.shown_with); c != rows_.end() && values_.count(c->first)) {
      const auto& choices = c->second.spec.choices;
      const auto i = static_cast<std::size_t>(values_.at(c->first));
      const auto& want = row.spec.shown_for;
      shown = i < choices.size() && std::find(want.begin(), want.end(), choices[i]) != want.end();
    }
    for (QWidget* w : row.widgets)
      w->setVisible(shown);
  }
}

void ParamPanel::centre(Row& row, double v) {
  row.wlo = row.lo;
  row.whi = row.hi;
  if (row.spec.scale != Scale::kLog || row.lo <= 0 || !(v > 0)) return;
  const double span = std::pow(10.0, kLogWindowDecades);
  if (row.hi / row.lo <= span) return;
  const double half = std::pow(10.0, kLogWindowDecades / 2);
  row.wlo = v / half;
  row.whi = v * half;
  if (row.wlo < row.lo) {
    row.wlo = row.lo;
    row.whi = row.lo * span;
  } else if (row.whi > row.hi) {
    row.whi = row.hi;
    row.wlo = row.hi / span;
  }
}

std::pair<double, double> ParamPanel::sliderRange(const std::string& key) const {
  auto it = rows_.find(key);
  if (it == rows_.end()) return {0.0, 0.0};
  return {it->second.wlo, it->second.whi};
}

void ParamPanel::show(Row& row, double v) {
  const QSignalBlocker b1(row.slider), b2(row.spin), b3(row.combo), b4(row.check);
  // While the slider is dragged its window stays put (the thumb follows the hand).
  if (row.slider && !row.slider->isSliderDown()) centre(row, v);
  if (row.slider) row.slider->setValue(toSlider(row.spec, row.wlo, row.whi, v));
  if (row.spin) row.spin->setValue(v);
  if (row.combo) row.combo->setCurrentIndex(static_cast<int>(v));
  if (row.check) row.check->setChecked(v != 0.0);
}

void ParamPanel::commit(Row& row, double v) {
  v = std::clamp(v, row.spec.min, row.spec.max);
  show(row, v);
  auto it = values_.find(row.spec.key);
  if (it != values_.end() && it->second == v) return;
  values_[row.spec.key] = v;
  updateShown();
  emit valueChanged(QString::fromStdString(row.spec.key), v);
}

bool ParamPanel::eventFilter(QObject* watched, QEvent* event) {
  auto* slider = qobject_cast<QSlider*>(watched);
  if (!slider || !slider->objectName().startsWith("slider."))
    return QWidget::eventFilter(watched, event);
  const std::string key = slider->objectName().mid(7).toStdString();
  auto it = rows_.find(key);
  if (it == rows_.end()) return QWidget::eventFilter(watched, event);
  Row& row = it->second;
  // Only mouse events are QMouseEvents (casting any other event is undefined: UBSan, issue 16).
  const QEvent::Type type = event->type();
  if (type != QEvent::MouseButtonPress && type != QEvent::MouseMove &&
      type != QEvent::MouseButtonRelease)
    return QWidget::eventFilter(watched, event);
  auto* me = static_cast<QMouseEvent*>(event);
  switch (type) {
    case QEvent::MouseButtonPress:
      if (me->button() == Qt::LeftButton && (me->modifiers() & Qt::ShiftModifier)) {
        fine_ = FineDrag{key, qRound(me->position().x()), slider->value()};
        return true;
      }
      break;
    case QEvent::MouseMove:
      if (fine_ && fine_->key == key) {
        // One slider step per ten pixels' worth of the normal drag.
        const int span = std::max(1, slider->width() - 20);
        const double steps = (me->position().x() - fine_->x0) * slider->maximum() / span / 10.0;
        const double f = std::clamp((fine_->pos0 + steps) / slider->maximum(), 0.0, 1.0);
        double v = 0.0;
        if (row.spec.scale == Scale::kLog && row.wlo > 0) {
          v = std::pow(10.0, std::log10(row.wlo) + f * (std::log10(row.whi) - std::log10(row.wlo)));
        } else {
          v = row.wlo + f * (row.whi - row.wlo);
          if (row.spec.scale == Scale::kInteger) v = std::round(v);
        }
        const QSignalBlocker b(slider);
        slider->setSliderDown(true);  // the window stays put while the hand moves
        commit(row, v);
        return true;
      }
      break;
    case QEvent::MouseButtonRelease:
      if (fine_ && fine_->key == key) {
        fine_.reset();
        slider->setSliderDown(false);
        show(row, values_.count(key) ? values_.at(key) : row.spec.def);
        return true;
      }
      break;
    default:
      break;
  }
  return QWidget::eventFilter(watched, event);
}

void ParamPanel::setValues(const ParamValues& values) {
  for (const auto& [key, v] : values) {
    auto it = rows_.find(key);
    if (it == rows_.end()) continue;
    values_[key] = v;
    // A preset value outside the slider's narrowed range widens it to the table's limits.
    if (v < it->second.lo || v > it->second.hi) {
      it->second.lo = it->second.spec.min;
      it->second.hi = it->second.spec.max;
      if (it->second.spin) it->second.spin->setRange(it->second.lo, it->second.hi);
    }
    show(it->second, v);
  }
  updateShown();
}

void ParamPanel::setValue(const std::string& key, double value) {
  auto it = rows_.find(key);
  if (it != rows_.end()) commit(it->second, value);
}

void ParamPanel::setGroupEnabled(const QString& group, bool enabled, const QString& why) {
  if (QGroupBox* box = groups_.value(group, nullptr)) {
    box->setEnabled(enabled);
    box->setToolTip(enabled ? QString() : why);
    box->setTitle(enabled || why.isEmpty() ? group : group + " — " + why);
  }
}

}  // namespace kfw
