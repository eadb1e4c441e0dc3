// The one list of plot block drawers, by kind (the engine's list: model::plot_kinds()).
#include <functional>
#include <map>
#include <string>

#include "plots/block_drawer.h"

namespace kfw::plot {

namespace {

using Factory = std::function<std::unique_ptr<BlockDrawer>(QWidget*, const model::PlotBlockSpec&,
                                                           const Scenario&)>;

const std::map<std::string, Factory>& drawers() {
  static const std::map<std::string, Factory> m = {
      {"gain_curve", &makeGainCurveBlock},
      {"series", &makeSeriesBlock},
      {"trajectory", &makeTrajectoryBlock},
      {"covariance", &makeCovarianceBlock},
  };
  return m;
}

}  // namespace

std::unique_ptr<BlockDrawer> makeBlockDrawer(QWidget* parent, const model::PlotBlockSpec& block,
                                             const Scenario& s) {
  const auto it = drawers().find(block.kind);
  return it == drawers().end() ? nullptr : it->second(parent, block, s);
}

}  // namespace kfw::plot
