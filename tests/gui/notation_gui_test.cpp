// Titles, axis labels and legends read as a reader of the paper would typeset them (issue 32,
// item 12): subscripts and superscripts in Unicode, no source notation ("R_ψ", "μ^j") in any
// preset's plots, and no doubled parentheses ("θ (angle) (deg)").
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QDir>
#include <QRegularExpression>

#include "main_window.h"
#include "plot_text.h"

namespace kfw {
namespace {

TEST(Notation, TypesetWritesScriptsInUnicode) {
  using plot::typeset;
  EXPECT_EQ(typeset("x_1"), "x₁");
  EXPECT_EQ(typeset("μ^j"), "μʲ");
  EXPECT_EQ(typeset("P^{-1}"), "P⁻¹");
  EXPECT_EQ(typeset("K_p gain"), "Kₚ gain");
  EXPECT_EQ(typeset("Σ μ^j R̄_ψ^j"), "Σ μʲ R̄ψʲ");
  EXPECT_EQ(typeset("z_ψ − ψ_LOS"), "zψ − ψ_LOS");  // no capital subscripts: left as written
  EXPECT_EQ(typeset("R = N_θ, angle noise variance"), "R = Nθ, angle noise variance");
  EXPECT_EQ(typeset("bias_truth"), "bias_truth");  // an identifier stays
  EXPECT_EQ(typeset("x^T S^{-1} y"), "xᵀ S⁻¹ y");
  EXPECT_EQ(plot::withUnit("θ (angle)", "deg"), "θ (angle, deg)");
  EXPECT_EQ(plot::withUnit("position", "m"), "position (m)");
}

// Every preset's plots: no one-letter "_x" subscript or "^" superscript in source notation, no
// ") (" doubled parentheses. (An identifier a file declares, a role "x_meas", is its name.)
TEST(Notation, NoSourceNotationInAnyPresetsPlots) {
  const QRegularExpression source(R"([^\s_]_[^\s_A-Z](?![\p{Ll}\p{Lu}\p{N}])|\^|\) \()");
  QStringList presets;
  for (const QString& dir : {QString("presets"), QString("presets/models")}) {
    const QDir d(QString(KFW_SOURCE_DIR) + "/" + dir);
    for (const QString& f : d.entryList({"*.json"}, QDir::Files, QDir::Name))
      presets << d.filePath(f);
  }
  int texts = 0;
  for (const QString& preset : presets) {
    MainWindow w;
    const Status st = w.loadPreset(preset);
    // A preset whose log is not here (a clone without ../shared) is left out.
    if (!st && QString::fromStdString(st.error()).contains("no such file", Qt::CaseInsensitive))
      continue;
    ASSERT_TRUE(st.ok()) << st.error();
    ASSERT_TRUE(w.waitForRun(60000));
    for (const auto& p : w.plots()) {
      QStringList shown;
      for (int i = 0; i < p.plot->plotLayout()->elementCount(); ++i) {
        if (auto* t = qobject_cast<QCPTextElement*>(p.plot->plotLayout()->elementAt(i)))
          shown << t->text();
      }
      for (const QCPAxis* a : p.plot->axisRect()->axes())
        shown << a->label();
      for (int i = 0; i < p.plot->plottableCount(); ++i)
        shown << p.plot->plottable(i)->name();
      for (const QString& s : shown) {
        if (s.isEmpty()) continue;
        ++texts;
        EXPECT_FALSE(source.match(s).hasMatch())
            << QFileInfo(preset).fileName().toStdString() << " " << p.name.toStdString() << ": "
            << s.toStdString();
      }
    }
  }
  EXPECT_GT(texts, 300);
}

}  // namespace
}  // namespace kfw
