// The run controller without a window: a request runs off the GUI thread and settles, a burst
// of requests coalesces to the latest values, file data replace the simulation, a failed run
// keeps the last result, and the experiment dialogs open on the last run's dataset.
#include <gtest/gtest.h>

#include <QSignalSpy>
#include <QWidget>

#include "document/document.h"
#include "monte_carlo_dialog.h"
#include "run_controller.h"
#include "sweep_dialog.h"
#include "tune_dialog.h"

namespace kfw::run_controller_test {
namespace {

Document cv1d() {
  auto d = Document::open("models/cv1d", std::nullopt, {"sim.duration=10"});
  EXPECT_TRUE(d.ok());
  return std::move(*d);
}

TEST(RunController, ARequestRunsAndSettlesWithItsLatency) {
  const Document doc = cv1d();
  RunController runs;
  runs.setScenario(doc.scenario_ptr());
  QSignalSpy applied(&runs, &RunController::applied);
  EXPECT_TRUE(runs.settled());
  runs.request(doc.values());
  EXPECT_TRUE(runs.busy());
  EXPECT_FALSE(runs.settled());
  ASSERT_TRUE(runs.waitSettled());
  ASSERT_EQ(applied.count(), 1);
  EXPECT_TRUE(applied.front().at(0).toBool());
  ASSERT_TRUE(runs.result());
  ASSERT_TRUE(runs.dataset());  // simulated from the sim.* values
  EXPECT_GT(runs.result()->steps(), 0u);
  EXPECT_GT(runs.lastLatencyMs(), 0.0);
  EXPECT_GE(runs.lastWallMs(), 0.0);
  runs.setScenario(doc.scenario_ptr());
  EXPECT_FALSE(runs.result());  // a new scenario has no result yet
}

TEST(RunController, ABurstOfRequestsRunsTheLatestValues) {
  const Document doc = cv1d();
  RunController runs;
  runs.setScenario(doc.scenario_ptr());
  std::vector<double> ran;
  QObject::connect(&runs, &RunController::finished,
                   [&](std::shared_ptr<const RunResult>, const ParamValues& v, double) {
                     ran.push_back(v.at("sigma_r"));
                   });
  ParamValues v = doc.values();
  for (double r : {1.0, 2.0, 3.0, 4.0, 5.0}) {
    v["sigma_r"] = r;
    runs.request(v);
  }
  ASSERT_TRUE(runs.waitSettled());
  ASSERT_FALSE(ran.empty());
  EXPECT_LE(ran.size(), 2u);  // the first, then only the latest
  EXPECT_EQ(ran.back(), 5.0);
}

TEST(RunController, FileDataReplaceTheSimulationAndAFailedRunKeepsTheResult) {
  const Document doc = cv1d();
  RunController runs;
  runs.setScenario(doc.scenario_ptr());
  runs.request(doc.values());
  ASSERT_TRUE(runs.waitSettled());
  auto file = std::make_shared<Dataset>(*runs.dataset());
  file->source = "file.csv";
  runs.setFileDataset(file);
  EXPECT_TRUE(runs.usesFile());
  runs.request(doc.values());
  ASSERT_TRUE(runs.waitSettled());
  EXPECT_EQ(runs.dataset(), file);
  const auto good = runs.result();

  QSignalSpy failed(&runs, &RunController::failed);
  QSignalSpy applied(&runs, &RunController::applied);
  runs.setFileDataset(std::make_shared<Dataset>());  // no columns: the run fails
  runs.request(doc.values());
  ASSERT_TRUE(runs.waitSettled());
  ASSERT_EQ(failed.count(), 1);
  EXPECT_FALSE(failed.front().at(0).toString().isEmpty());
  ASSERT_EQ(applied.count(), 1);
  EXPECT_FALSE(applied.front().at(0).toBool());
  EXPECT_EQ(runs.result(), good);
}

TEST(RunController, TheExperimentDialogsOpenOnTheLastRunsDataset) {
  const Document doc = cv1d();
  RunController runs;
  QWidget parent;
  EXPECT_EQ(runs.openSweep(doc.values(), &parent), nullptr);  // no scenario, no run yet
  runs.setScenario(doc.scenario_ptr());
  EXPECT_EQ(runs.openTune(doc.preset(), doc.values(), "simulated", {}, &parent), nullptr);
  runs.request(doc.values());
  ASSERT_TRUE(runs.waitSettled());
  QStringList chosen;
  QObject::connect(&runs, &RunController::valuesChosen,
                   [&](const ParamValues&, const QString& label) { chosen << label; });
  TuneDialog* tune = runs.openTune(doc.preset(), doc.values(), "simulated", {}, &parent);
  ASSERT_NE(tune, nullptr);
  EXPECT_EQ(tune->parentWidget(), &parent);
  SweepDialog* sweep = runs.openSweep(doc.values(), &parent);
  ASSERT_NE(sweep, nullptr);
  MonteCarloDialog* mc = runs.openMonteCarlo(doc.values(), &parent);
  ASSERT_NE(mc, nullptr);
  emit sweep->pointChosen(doc.values());
  EXPECT_EQ(chosen, QStringList{"sweep point"});
  QSignalSpy problem(&runs, &RunController::problem);
  TuneDialog* again = runs.openTune(doc.preset(), doc.values(), "simulated",
                                    {DataRef{"/no/such/log.csv", {}}}, &parent);
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(problem.count(), 1);  // the tuning set's file that no longer reads
  for (QWidget* d : {static_cast<QWidget*>(tune), static_cast<QWidget*>(sweep),
                     static_cast<QWidget*>(mc), static_cast<QWidget*>(again)})
    d->close();
}

}  // namespace
}  // namespace kfw::run_controller_test
