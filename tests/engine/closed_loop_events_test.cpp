// Issue 30: a world's events beyond the one that ends the loop. An event with "ends": false is
// reported at its first row — seed 003's beam beyond the small-angle range of ẍ = a3 θ, which
// the built-in warned about — and the run goes on; a closed-loop model filtering a log (replay)
// evaluates its events on the log's truth columns (the ball leaving the beam in a recorded run);
// and a channel whose sample lost some of its roles says so after the run (seed 001's angles
// without their range).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/model_files.h"
#include "core/scenario.h"
#include "data/csv.h"

namespace kfw {
namespace {

const std::string kBallbeam = KFW_SOURCE_DIR "/presets/ballbeam.json";

bool has_warning(const RunResult& r, const std::string& start) {
  return std::any_of(r.warnings.begin(), r.warnings.end(),
                     [&](const std::string& w) { return w.rfind(start, 0) == 0; });
}

TEST(ClosedLoopEvents, AnEventThatDoesNotEndTheRunIsReportedAtItsFirstRow) {
  auto s = testing::load_model_file(kBallbeam);
  ASSERT_TRUE(s);
  ParamValues v = s->params().defaults();
  v["detection"] = 0.0;
  v["sim.seed"] = 8;  // the ball stays on the beam, the beam hits its stops
  auto r = s->run(Dataset{}, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& m = (*r)->metrics;
  EXPECT_EQ(m.at("event.small_angle"), 1.0);
  EXPECT_EQ(m.at("event.left_beam"), 0.0);
  EXPECT_GT(m.at("max_abs_theta"), 0.25);
  EXPECT_NEAR((*r)->t.back(), 15.0, 1e-9);  // the run goes on to its end
  const double at = m.at("event.small_angle_at_s");
  EXPECT_TRUE(has_warning(**r, "beam beyond the small-angle range")) << at;
  // With the circuit the beam stays within it.
  v["detection"] = 1.0;
  auto calm = s->run(Dataset{}, v);
  ASSERT_TRUE(calm.ok()) << calm.error();
  EXPECT_EQ(calm->get()->metrics.at("event.small_angle"), 0.0);
  EXPECT_EQ(calm->get()->undefined.count("event.small_angle_at_s"), 1u);
}

TEST(ClosedLoopEvents, AReplayedLogReportsTheEventsOfItsTruth) {
  auto s = testing::load_model_file(kBallbeam);
  ASSERT_TRUE(s);
  auto log = read_csv(KFW_SOURCE_DIR "/data/ballbeam.csv");
  ASSERT_TRUE(log.ok()) << log.error();
  ParamValues v = s->params().defaults();
  v["mode"] = 1.0;  // replay
  auto quiet = s->run(*log, v);
  ASSERT_TRUE(quiet.ok()) << quiet.error();
  EXPECT_EQ(quiet->get()->metrics.at("event.left_beam"), 0.0);
  // The recorded ball rolls off at row 1000: reported there, and the whole log is filtered.
  Dataset d = *log;
  auto& truth = d.columns[static_cast<std::size_t>(d.index("truth"))];
  for (std::size_t k = 1000; k < truth.size(); ++k)
    truth[k] = 0.3;
  auto r = s->run(d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ((*r)->metrics.at("event.left_beam"), 1.0);
  EXPECT_DOUBLE_EQ((*r)->metrics.at("event.left_beam_at_s"), d.col("t")[1000]);
  EXPECT_EQ((*r)->steps(), d.rows());
  EXPECT_TRUE(has_warning(**r, "ball off the beam at t = 10 s, in the log's truth"));
}

TEST(ClosedLoopEvents, ASampleMissingSomeOfItsRolesIsNamedAfterTheRun) {
  auto s = testing::load_model_file(KFW_SOURCE_DIR "/presets/radome.json");
  ASSERT_TRUE(s);
  auto log = read_csv(KFW_SOURCE_DIR "/data/radome.csv");
  ASSERT_TRUE(log.ok()) << log.error();
  Dataset d = *log;
  auto& psi = d.columns[static_cast<std::size_t>(d.index("psi_rad"))];
  for (std::size_t k = 300; k < 310; ++k)
    psi[k] = std::nan("");
  auto r = s->run(d, s->params().defaults());
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(has_warning(**r,
                          "channel 'seeker': 10 samples with some roles missing were not "
                          "applied, the first at step 300"));
  auto clean = s->run(*log, s->params().defaults());
  ASSERT_TRUE(clean.ok());
  EXPECT_FALSE(has_warning(**clean, "channel 'seeker': "));
}

}  // namespace
}  // namespace kfw
