#include "plot_text.h"

#include <cmath>

namespace kfw::plot {

QString withUnit(const QString& name, const std::string& unit) {
  const QString u = unit.empty() ? QString("–") : QString::fromStdString(unit);
  if (name.endsWith(')') && name.contains('(')) return name.chopped(1) + ", " + u + ")";
  return QString("%1 (%2)").arg(name, u);
}

namespace {

const QString kSubFrom = "0123456789+-−=()aehijklmnoprstuvxβγρφχ";
const QString kSubTo = "₀₁₂₃₄₅₆₇₈₉₊₋₋₌₍₎ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓᵦᵧᵨᵩᵪ";
const QString kSupFrom = "0123456789+-−=()abcdefghijklmnoprstuvwxyzTβγδθφχ";
const QString kSupTo = "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻⁻⁼⁽⁾ᵃᵇᶜᵈᵉᶠᵍʰⁱʲᵏˡᵐⁿᵒᵖʳˢᵗᵘᵛʷˣʸᶻᵀᵝᵞᵟᶿᵠᵡ";

// `run` in the script's forms; empty when a character has none.
QString script(const QString& run, bool sub) {
  const QString& from = sub ? kSubFrom : kSupFrom;
  const QString& to = sub ? kSubTo : kSupTo;
  QString out;
  for (const QChar c : run) {
    const auto i = from.indexOf(c);
    if (i < 0) return {};
    out += to[i];
  }
  return out;
}

}  // namespace

QString typeset(const QString& text) {
  QString out;
  for (qsizetype i = 0; i < text.size(); ++i) {
    const QChar c = text[i];
    const bool sub = c == '_';
    if ((!sub && c != '^') || i == 0 || i + 1 >= text.size() || text[i - 1].isSpace()) {
      out += c;
      continue;
    }
    qsizetype end = i + 1;
    QString run;
    if (text[end] == '{') {
      const auto close = text.indexOf('}', end);
      if (close < 0) {
        out += c;
        continue;
      }
      run = text.mid(end + 1, close - end - 1);
      end = close + 1;
    } else {
      while (end < text.size() &&
             (text[end].isLetterOrNumber() || text[end] == '-' || text[end] == QChar(0x2212)) &&
             end - i <= 2)
        ++end;
      run = text.mid(i + 1, end - i - 1);
      // An identifier's word ("bias_truth"): not a subscript.
      if (end < text.size() && text[end].isLetterOrNumber()) run.clear();
    }
    const QString s = run.isEmpty() ? QString() : script(run, sub);
    if (!s.isEmpty()) {
      out += s;
      i = end - 1;
    } else if (run.size() == 1 || text[i + 1] == '{') {
      out += run;  // no Unicode form: joined to its base ("Rψ")
      i = end - 1;
    } else {
      out += c;
    }
  }
  return out;
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
