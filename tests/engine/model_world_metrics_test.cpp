// Issue 27 (model files, part 2): whiteness of a channel of two or more components, tested
// component by component (whiteness_p.CHANNEL.ROLE, declared by the model); the channel is as
// white as its worst component.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/model_files.h"

namespace kfw {
namespace model_world_metrics_test {
namespace {

TEST(ModelWorldMetrics, AVectorChannelIsTestedForWhitenessPerComponent) {
  auto s = testing::load_model("range_bearing.json");
  ASSERT_TRUE(s);
  const ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const Metrics& m = (*r)->metrics;
  ASSERT_TRUE(m.count("whiteness_p.radar.range")) << metrics_to_json(m, (*r)->undefined);
  ASSERT_TRUE(m.count("whiteness_p.radar.bearing"));
  ASSERT_TRUE(m.count("whiteness_p.radar"));
  ASSERT_TRUE(m.count("whiteness_p"));
  EXPECT_EQ(m.at("whiteness_p.radar"),
            std::min(m.at("whiteness_p.radar.range"), m.at("whiteness_p.radar.bearing")));
  EXPECT_EQ(m.at("whiteness_p"), m.at("whiteness_p.radar"));
  // A matched filter's innovations are white.
  EXPECT_GT(m.at("whiteness_p.radar.range"), 0.01);
  EXPECT_GT(m.at("whiteness_p.radar.bearing"), 0.01);
  // Declared once, by the model: label, direction and good range.
  EXPECT_TRUE(is_declared_metric(*s, "whiteness_p.radar.bearing"));
  const MetricSpec spec = describe_metric(*s, "whiteness_p.radar.bearing", r->get());
  EXPECT_EQ(spec.direction, Direction::kHigher);
  EXPECT_NE(spec.label.find("bearing"), std::string::npos) << spec.label;
  EXPECT_EQ(judge(spec, 0.001), "bad");
  // Its components reach the consistency view too.
  const auto channels = (*r)->channels();
  ASSERT_EQ(channels.size(), 1u);
  ASSERT_EQ(channels[0].components.size(), 2u);
  EXPECT_EQ(channels[0].components[1].name, "bearing");
}

TEST(ModelWorldMetrics, AColouredComponentIsCaughtAndNamed) {
  auto s = testing::load_model("range_bearing.json");
  ASSERT_TRUE(s);
  const ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  // A slow bias on the bearing (a sensor error the filter does not model): coloured innovations.
  const auto col = std::find(d->names.begin(), d->names.end(), "bearing") - d->names.begin();
  const auto tcol = std::find(d->names.begin(), d->names.end(), "t") - d->names.begin();
  ASSERT_LT(static_cast<std::size_t>(col), d->names.size());
  auto& bearing = d->columns[static_cast<std::size_t>(col)];
  const auto& t = d->columns[static_cast<std::size_t>(tcol)];
  const double sigma = v.at("sigma_bearing");
  for (std::size_t k = 0; k < bearing.size(); ++k)
    bearing[k] =
        std::remainder(bearing[k] + 3.0 * sigma * std::sin(0.2 * t[k]), 2.0 * std::numbers::pi);
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const Metrics& m = (*r)->metrics;
  ASSERT_TRUE(m.count("whiteness_p.radar.bearing"));
  EXPECT_LT(m.at("whiteness_p.radar.bearing"), 0.01);
  EXPECT_LT(m.at("whiteness_p.radar"), 0.01);
  EXPECT_LT(m.at("whiteness_p"), 0.01);
}

TEST(ModelWorldMetrics, TwoComponentPositionFixesAreTestedToo) {
  auto s = testing::load_model("cv2d.json");
  ASSERT_TRUE(s);
  const ParamValues v = s->params().defaults();
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  int components = 0;
  for (const auto& [k, x] : (*r)->metrics) {
    if (k.rfind("whiteness_p.", 0) == 0 && std::count(k.begin(), k.end(), '.') == 2) ++components;
  }
  EXPECT_EQ(components, 2) << metrics_to_json((*r)->metrics, (*r)->undefined);
  EXPECT_FALSE((*r)->undefined.count("whiteness_p"));
}

}  // namespace
}  // namespace model_world_metrics_test
}  // namespace kfw
