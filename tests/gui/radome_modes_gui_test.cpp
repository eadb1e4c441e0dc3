// Radome's mode legend names each mode by the slopes it stands for at the shown time: the grid's
// values moved by renewal to the replay step (with renewal, Kp > 0, the grid moves, and the label
// says at which time); without renewal the slopes are the fixed grid's and no time is named.
// Since issue 28 the preset is seed 001's model file: the generic view's `mode_probabilities`
// (the 8 most probable modes) in place of the built-in's `mode_top` (5).
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QRegularExpression>
#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "model/model_result.h"
#include "transport_bar.h"

namespace kfw {
namespace {

// The slopes a legend name states: "Rψ = A, Rθ = B[ at t = T s]" (typeset: plot_text.h).
bool parse(const QString& name, double& a, double& b, double& t) {
  static const QRegularExpression re(
      R"(^Rψ = (-?[0-9.]+), Rθ = (-?[0-9.]+)(?: at t = ([0-9.]+) s)?$)");
  const auto m = re.match(name);
  if (!m.hasMatch()) return false;
  a = m.captured(1).toDouble();
  b = m.captured(2).toDouble();
  t = m.captured(3).isEmpty() ? std::nan("") : m.captured(3).toDouble();
  return true;
}

// Every shown mode's name against the engine's arrays at step k: some mode's grid values, moved
// by each axis's centre since the start.
void expectNamesAt(const MainWindow& w, std::size_t k, bool moving) {
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r && r->imm && r->imm->axes.size() == 2);
  const auto& ap = r->imm->axes[0];
  const auto& at = r->imm->axes[1];
  QCustomPlot* lines = testing::plotNamed(w, "mode_probabilities");
  ASSERT_NE(lines, nullptr);
  int checked = 0;
  for (int i = 0; i < lines->graphCount(); ++i) {
    const QCPGraph* g = lines->graph(i);
    double a = 0, b = 0, t = 0;
    ASSERT_TRUE(parse(g->name(), a, b, t)) << g->name().toStdString();
    bool found = false;
    for (std::size_t j = 0; j < r->imm->modes() && !found; ++j) {
      found = std::fabs(a - (ap.values[j] + ap.centre[k] - ap.centre.front())) < 0.0005 &&
              std::fabs(b - (at.values[j] + at.centre[k] - at.centre.front())) < 0.0005;
    }
    EXPECT_TRUE(found) << g->name().toStdString() << " at step " << k;
    if (moving) {
      EXPECT_NEAR(t, r->t[k], 0.05) << g->name().toStdString();
    } else {
      EXPECT_TRUE(std::isnan(t)) << "a fixed grid names no time: " << g->name().toStdString();
    }
    ++checked;
  }
  EXPECT_GE(checked, 2);
}

TEST(RadomeModes, LabelsAreTheSlopesAtTheShownTime) {
  MainWindow w;
  ASSERT_TRUE(w.loadPreset("radome", {}, {"sim.duration=20", "Kp=0.45"}).ok());
  ASSERT_TRUE(w.waitForRun(60000));
  auto r = std::dynamic_pointer_cast<const model::ModelResult>(w.result());
  ASSERT_TRUE(r && r->imm);
  const std::size_t n = r->steps();
  // The grid does move with renewal (else this test proves nothing).
  const auto& cp = r->imm->axes[0].centre;
  const auto& ct = r->imm->axes[1].centre;
  EXPECT_GT(std::fabs(cp[n - 1] - cp[0]) + std::fabs(ct[n - 1] - ct[0]), 0.002);
  expectNamesAt(w, w.transport()->index(), true);
  for (std::size_t k : {n / 4, n / 2}) {
    w.transport()->seek(k);
    expectNamesAt(w, w.transport()->index(), true);
  }
  // Without renewal: the fixed grid's slopes, no time.
  w.setParam("Kp", 0.0);
  ASSERT_TRUE(w.waitForRun(60000));
  expectNamesAt(w, w.transport()->index(), false);
}

}  // namespace
}  // namespace kfw
