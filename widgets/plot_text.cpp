#include "plot_text.h"

#include <cmath>

namespace kfw::plot {

QString withUnit(const QString& name, const std::string& unit) {
  return unit.empty() ? QString("%1 (–)").arg(name)
                      : QString("%1 (%2)").arg(name, QString::fromStdString(unit));
}

QString panelTitle(const std::string& declared, const QString& fallback) {
  return declared.empty() ? fallback : QString::fromStdString(declared);
}

bool sameUnit(const std::vector<std::string>& units) {
  for (const auto& u : units) {
    if (u != units.front()) return false;
  }
  return true;
}

QString legendName(const std::string& label, const std::string& unit, bool shared) {
  const QString l = QString::fromStdString(label);
  return shared ? l : withUnit(l, unit);
}

QString axisLabel(const std::vector<std::string>& labels, const std::vector<std::string>& units,
                  const QString& what) {
  if (labels.size() == 1 && units.size() == 1) {
    return withUnit(QString::fromStdString(labels.front()), units.front());
  }
  if (units.empty()) return withUnit(what, "");
  if (!sameUnit(units)) return QString("%1 (units in the legend)").arg(what);
  return withUnit(what, units.front());
}

QString symbolOf(const std::string& label) {
  std::string s = label.rfind("derived.", 0) == 0 ? label.substr(8) : label;
  // A gain entry's "K[x, x_meas]" is one symbol: cut after its bracket, not inside.
  const std::size_t open = s.find('[');
  const std::size_t close = open == std::string::npos ? std::string::npos : s.find(']', open);
  const std::size_t from = close == std::string::npos ? 0 : close;
  s = s.substr(0, s.find_first_of(", ", from));
  return QString::fromStdString(s.empty() ? label : s);
}

QString noteNumber(double v) {
  return std::isfinite(v) ? QString::number(v, 'g', 4) : QString("–");
}

}  // namespace kfw::plot
