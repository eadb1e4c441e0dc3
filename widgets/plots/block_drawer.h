// The drawers of a model file's plot blocks (engine/model/plots/model_plots.h): one file per kind,
// widgets/plots/<kind>_block.cpp, each registered in block_registry.cpp, the one place that
// lists them. A drawer makes one panel and fills it from what the engine computed; it computes
// no filter maths itself.
#pragma once

#include <QString>
#include <memory>
#include <utility>
#include <vector>

#include "core/dataset.h"
#include "core/param_spec.h"
#include "core/scenario.h"
#include "model/model_result.h"
#include "model/plots/model_plots.h"
#include "plot_blocks.h"

class QCustomPlot;
class QWidget;

namespace kfw::plot {

// What a block is drawn from: the scenario (its steady state, its metric declarations), the
// finished run, the values it ran with and its dataset (null: simulated).
struct BlockInput {
  const Scenario& scenario;
  const model::ModelResult& result;
  const ParamValues& values;
  const Dataset* data = nullptr;
};

class BlockDrawer {
 public:
  virtual ~BlockDrawer() = default;
  virtual QCustomPlot* plot() const = 0;
  // The panel's title as shown and exported.
  virtual QString title() const = 0;
  // A new run: rebuild the panel's data and replot.
  virtual void setResult(const BlockInput& in) = 0;
  // Replay: a time plot shows the frame's steps; other plots stay.
  virtual void draw(const Frame& f) { (void)f; }
  // Pinned snapshots (name, run of the same model; the view keeps them alive): a block that
  // draws a run's estimates adds each as a faded ghost, cut at the cursor's time in draw().
  using Ghost = std::pair<QString, const model::ModelResult*>;
  virtual void setGhosts(const std::vector<Ghost>& ghosts) { (void)ghosts; }
};

// A drawer for the block's kind (nullptr for a kind with no drawer in this build); `s` is the
// scenario the block belongs to (its declarations name units and labels).
std::unique_ptr<BlockDrawer> makeBlockDrawer(QWidget* parent, const model::PlotBlockSpec& block,
                                             const Scenario& s);

// The kinds' factories (one file each).
std::unique_ptr<BlockDrawer> makeGainCurveBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                                const Scenario& s);
std::unique_ptr<BlockDrawer> makeSeriesBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                             const Scenario& s);
std::unique_ptr<BlockDrawer> makeTrajectoryBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                                 const Scenario& s);
std::unique_ptr<BlockDrawer> makeCovarianceBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                                 const Scenario& s);

}  // namespace kfw::plot
