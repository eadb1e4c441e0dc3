// The one way plot text is written: titles, axis labels with units, legend names and the numbers
// of notes. The generic model view and the model file's plot blocks (widgets/plots/) go through
// it, so a quantity reads the same in every panel.
#pragma once

#include <QString>
#include <string>
#include <vector>

namespace kfw::plot {

// A quantity with its unit for an axis: "position (m)"; "(–)" only when it has no unit.
QString withUnit(const QString& name, const std::string& unit);
// A panel's title: the one the file declares, else `fallback`.
QString panelTitle(const std::string& declared, const QString& fallback);
// A legend entry for one of several quantities on an axis: "label" when the axis label carries
// the unit (`shared` true), else "label (unit)".
QString legendName(const std::string& label, const std::string& unit, bool shared);
// The axis that holds quantities with these labels and units: the one quantity with its unit;
// several of one unit, "value (unit)" unless `what` names them; mixed units, "WHAT (units in
// the legend)".
QString axisLabel(const std::vector<std::string>& labels, const std::vector<std::string>& units,
                  const QString& what = "value");
// True when every unit is the same (the axis label carries it).
bool sameUnit(const std::vector<std::string>& units);
// A quantity's symbol for a note, from its label: up to the first comma or space ("k1(β),
// closed-form angle gain" → "k1(β)"); a key "derived.NAME" → "NAME".
QString symbolOf(const std::string& label);
// A number in a note: four significant digits.
QString noteNumber(double v);

}  // namespace kfw::plot
