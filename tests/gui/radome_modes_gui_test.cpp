// Radome's top-mode legend names each mode by the slopes it stands for at the shown time: the grid
// centre at the replay step plus the mode's offsets (with renewal, Kp > 0, the grid moves, and the
// label says at which time); without renewal the slopes are the fixed grid's and no time is named.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QRegularExpression>
#include <cmath>

#include "common/plot_probe.h"
#include "main_window.h"
#include "scenarios/radome/radome_imm.h"
#include "transport_bar.h"

namespace kfw {
namespace {

using radome::RadomeResult;

// The slopes a legend name states: "μ of R̄_ψ = A, R̄_θ = B[ at t = T s]".
bool parse(const QString& name, double& a, double& b, double& t) {
  static const QRegularExpression re(
      R"(^μ of R̄_ψ = (-?[0-9.]+), R̄_θ = (-?[0-9.]+)(?: at t = ([0-9.]+) s)?$)");
  const auto m = re.match(name);
  if (!m.hasMatch()) return false;
  a = m.captured(1).toDouble();
  b = m.captured(2).toDouble();
  t = m.captured(3).isEmpty() ? std::nan("") : m.captured(3).toDouble();
  return true;
}

// Every shown top-mode entry against the engine's arrays at step k: centre + offset per axis.
void expectNamesAt(const MainWindow& w, std::size_t k, bool moving) {
  auto r = std::dynamic_pointer_cast<const RadomeResult>(w.result());
  ASSERT_TRUE(r);
  QCustomPlot* top = testing::plotNamed(w, "mode_top");
  ASSERT_NE(top, nullptr);
  const std::vector<int> ids = r->top_modes(top->graphCount());
  int checked = 0;
  for (int i = 0, mode = 0; i < top->graphCount(); ++i) {
    const QCPGraph* g = top->graph(i);
    if (!g->visible() || !g->name().startsWith("μ of")) continue;
    ASSERT_LT(mode, static_cast<int>(ids.size()));
    const int j = ids[static_cast<std::size_t>(mode++)];
    double a = 0, b = 0, t = 0;
    ASSERT_TRUE(parse(g->name(), a, b, t)) << g->name().toStdString();
    const double want_a = r->center_psi[k] + r->offsets_psi[static_cast<std::size_t>(j % r->n_psi)];
    const double want_b =
        r->center_theta[k] + r->offsets_theta[static_cast<std::size_t>(j / r->n_psi)];
    EXPECT_NEAR(a, want_a, 0.0005) << g->name().toStdString() << " at step " << k;
    EXPECT_NEAR(b, want_b, 0.0005) << g->name().toStdString() << " at step " << k;
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
  auto r = std::dynamic_pointer_cast<const RadomeResult>(w.result());
  ASSERT_TRUE(r);
  const std::size_t n = r->steps();
  // The grid does move with renewal (else this test proves nothing).
  EXPECT_GT(std::fabs(r->center_psi[n - 1] - r->center_psi[0]) +
                std::fabs(r->center_theta[n - 1] - r->center_theta[0]),
            0.002);
  expectNamesAt(w, n - 1, true);
  for (std::size_t k : {n / 4, n / 2}) {
    w.transport()->seek(k);
    expectNamesAt(w, k, true);
  }
  // Without renewal: the fixed grid's slopes, no time.
  w.setParam("Kp", 0.0);
  ASSERT_TRUE(w.waitForRun(60000));
  r = std::dynamic_pointer_cast<const RadomeResult>(w.result());
  expectNamesAt(w, w.transport()->index(), false);
}

}  // namespace
}  // namespace kfw
