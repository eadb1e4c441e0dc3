// The one way plot text is written: titles, axis labels with units, legend names and the numbers
// of notes. The generic model view and the model file's plot blocks (widgets/plots/) go through
// it, so a quantity reads the same in every panel.
#pragma once

#include <QString>
#include <string>
#include <vector>

namespace kfw::plot {

// A quantity with its unit for an axis: "position (m)"; "(–)" only when it has no unit; a name
// that ends in parentheses takes the unit inside them: "θ (angle, deg)".
QString withUnit(const QString& name, const std::string& unit);
// Source notation as a reader of the paper would typeset it, in Unicode: "x_1" → "x₁",
// "μ^j" → "μʲ", "P^{-1}" → "P⁻¹", "K_{p}" → "Kₚ"; a one-letter subscript with no Unicode form
// joins its base ("R_ψ" → "Rψ"); longer words after "_" (an identifier: "bias_truth") stay.
// Every title, axis label and legend name goes through it (plot_kit.h).
QString typeset(const QString& text);
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
