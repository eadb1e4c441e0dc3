// The panels of a model with modes (an IMM, presets/models/README.md "Modes") in the generic model
// view: the mode probabilities over time (a line per mode, the 8 most probable on average for a
// bigger grid), for a two-axis grid the probabilities on the grid at the replay cursor (a heat
// map, log₁₀ μ), and per grid axis the μ-weighted estimate over time with the grid's ends and the
// truth when mapped. Laid out from the model; rebuilt at each result, so a grid's n or bounds
// redraw the lines and the heat map's cells. Grid values read as few decimals as tell them apart
// (model::grid_value_text); under renewal the lines are named by their values at the cursor.
#pragma once

#include <QList>
#include <QSharedPointer>
#include <QString>
#include <memory>
#include <utility>
#include <vector>

#include "model/imm/imm_spec.h"
#include "model/model_result.h"
#include "model/model_scenario.h"
#include "plot_blocks.h"
#include "plot_kit.h"
#include "scenario_view.h"

class QCustomPlot;
class QCPGraph;
class QCPColorMap;
class QCPItemText;
class QCPAxisTicker;
class QCPAxisTickerText;
class QCPItemStraightLine;
class QWidget;

namespace kfw {

class ImmPanels {
 public:
  // The panels for `layout` (none when the model has no modes), appended to `out`.
  void create(QWidget* parent, const ModelLayout& layout, QList<PlotPanel>& out);
  void setResult(const model::ModelResult& r);
  void draw(const plot::Frame& f, std::size_t index);
  // Pinned runs: their estimates of the grid axes as ghosts.
  void setSnapshots(
      const std::vector<std::pair<QString, std::shared_ptr<const model::ModelResult>>>& pins);

 private:
  struct Axis {
    QCustomPlot* plot = nullptr;
    QCPGraph *estimate = nullptr, *truth = nullptr;
    plot::Band envelope;
    std::vector<QCPGraph*> ghosts;  // per pinned run
    QCPItemStraightLine* cursor = nullptr;
    std::vector<double> lo_v, hi_v;
  };
  void drawHeatMap(std::size_t k);
  void nameLinesAt(std::size_t k);
  QString heatInfo(std::size_t k) const;

  const model::ModelResult* result_ = nullptr;
  QCustomPlot* lines_ = nullptr;
  QCPItemStraightLine* lines_cursor_ = nullptr;
  std::vector<QCPGraph*> graphs_;
  std::vector<std::vector<double>> mu_;
  std::vector<std::size_t> line_modes_;  // per line: its mode
  std::vector<int> decimals_;            // per grid axis: grid_decimals of its values
  bool moving_ = false;                  // renewal moves the grid in this result
  QSharedPointer<QCPAxisTickerText> text_ticker_[2];
  QSharedPointer<QCPAxisTicker> normal_ticker_[2];
  QCustomPlot* heat_ = nullptr;
  QCPColorMap* heat_map_ = nullptr;
  QCPItemText* info_ = nullptr;  // the heat map's note: time, top mode, estimate, truth
  std::vector<Axis> axes_;
  std::vector<std::shared_ptr<const model::ModelResult>> ghosts_;  // pinned runs with the axes
};

}  // namespace kfw
