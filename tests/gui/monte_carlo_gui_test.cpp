// The Monte Carlo dialog driven offscreen: a matched model (cv1d, x0 from the prior) over 20
// seeds plots the error band against the filter's ±2σ and ANEES/ANIS with their bounds; Cancel
// stops a long run with a message.
#include <qcustomplot.h>

#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <cstdlib>

#include "common/gui_util.h"
#include "document/preset.h"
#include "monte_carlo_dialog.h"

namespace kfw {
namespace {

using testing::waitDone;

TEST(MonteCarloDialog, PlotsTheErrorBandAndTheAveragesWithBounds) {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/models/cv1d.json");
  ASSERT_TRUE(p.ok()) << p.error();
  ParamValues v = p->values;
  v["sim.duration"] = 5.0;  // 51 steps
  MonteCarloDialog d(p->instance->with_x0_from_prior(), v);
  d.setSeeds(1, 20);
  d.start();
  ASSERT_TRUE(waitDone(&d));
  EXPECT_TRUE(d.message().contains("20 seeds, 20 completed")) << d.message().toStdString();
  EXPECT_TRUE(d.message().contains("ANEES (20 runs)")) << d.message().toStdString();
  // Band (2 graphs), mean error, ±2σ (2 graphs).
  ASSERT_EQ(d.errorPlot()->graphCount(), 5);
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(d.errorPlot()->graph(i)->data()->size(), 51) << i;
  // ANEES and ANIS of the one channel, each with its two bounds.
  ASSERT_EQ(d.consistencyPlot()->graphCount(), 6);
  EXPECT_EQ(d.consistencyPlot()->graph(0)->data()->size(), 51);
  EXPECT_NEAR(d.consistencyPlot()->graph(1)->data()->at(10)->value, 24.433 / 20,
              1e-4);  // χ²₀.₀₂₅(40)/20
  // KFW_TEST_SHOT_DIR=DIR keeps a picture of the dialog for a human to look at.
  if (const char* dir = std::getenv("KFW_TEST_SHOT_DIR")) {
    d.show();
    QCoreApplication::processEvents();
    d.grab().save(QString(dir) + "/monte_carlo_dialog.png");
  }
}

TEST(MonteCarloDialog, CancelStopsTheRun) {
  auto p = load_preset(KFW_SOURCE_DIR "/presets/models/cv1d.json");
  ASSERT_TRUE(p.ok()) << p.error();
  ParamValues v = p->values;
  v["sim.duration"] = 600.0;
  MonteCarloDialog d(p->instance, v);
  d.setSeeds(1, 5000);
  d.start();
  d.cancel();
  ASSERT_TRUE(waitDone(&d));
  EXPECT_TRUE(d.message().contains("cancelled")) << d.message().toStdString();
}

}  // namespace
}  // namespace kfw
