// The series block: states (estimates) and derived series over time, one line each, with the
// replay cursor; the values are the run's own arrays (model::series_block_data).
#include <qcustomplot.h>

#include "plot_kit.h"
#include "plot_text.h"
#include "plots/block_drawer.h"

namespace kfw::plot {

namespace {

class SeriesBlock final : public BlockDrawer {
 public:
  SeriesBlock(QWidget* parent, const model::PlotBlockSpec& b) : block_(b) {
    std::vector<std::string> labels, units;
    for (const auto& l : b.series) {
      labels.push_back(l.label);
      units.push_back(l.unit);
    }
    QString fallback;
    for (const auto& l : b.series)
      fallback += (fallback.isEmpty() ? "" : ", ") + QString::fromStdString(l.label);
    title_ = panelTitle(b.title, fallback + " over time");
    plot_ = makePlot(parent, title_, "time (s)", axisLabel(labels, units));
    const bool shared = sameUnit(units);
    for (std::size_t i = 0; i < b.series.size(); ++i) {
      graphs_.push_back(addGraph(plot_,
                                 legendName(labels[i], units[i], shared || b.series.size() == 1),
                                 color::cycle(static_cast<int>(i))));
    }
    cursor_ = addCursor(plot_);
  }

  QCustomPlot* plot() const override { return plot_; }
  QString title() const override { return title_; }

  void setResult(const BlockInput& in) override {
    result_ = &in.result;
    data_ = model::series_block_data(block_, in.result);
  }

  // Each pinned run's lines, faded and dashed, in the legend as "LABEL [pinned: NAME]".
  void setGhosts(const std::vector<Ghost>& ghosts) override {
    for (auto& g : ghosts_)
      plot_->removeGraph(g.graph);
    ghosts_.clear();
    int colour = 0;
    for (const auto& [name, r] : ghosts) {
      const auto data = model::series_block_data(block_, *r);
      for (const auto& d : data) {
        if (!d.y) continue;
        const QString label = QString::fromStdString(d.line.label) + " [pinned: " + name + "]";
        ghosts_.push_back({addGhost(plot_, label, colour), &r->t, d.y});
      }
      ++colour;
    }
  }

  void draw(const Frame& f) override {
    if (!result_) return;
    for (const auto& g : ghosts_)
      setSeries(g.graph, *g.t, *g.y, f.all ? g.t->size() : stepsUpTo(*g.t, f));
    for (std::size_t i = 0; i < graphs_.size() && i < data_.size(); ++i) {
      if (data_[i].y) {
        setSeries(graphs_[i], result_->t, *data_[i].y, f.n);
      } else {
        graphs_[i]->data()->clear();
      }
    }
    rescale(plot_, f.t0, f.t1, f.settle());
    setCursorAt(cursor_, f.tc, !f.all);
    replot(plot_);
  }

 private:
  struct GhostLine {
    QCPGraph* graph = nullptr;
    const std::vector<double>*t = nullptr, *y = nullptr;
  };

  model::PlotBlockSpec block_;
  QString title_;
  QCustomPlot* plot_ = nullptr;
  std::vector<QCPGraph*> graphs_;
  std::vector<GhostLine> ghosts_;
  QCPItemStraightLine* cursor_ = nullptr;
  const model::ModelResult* result_ = nullptr;  // the view keeps the result alive
  std::vector<model::SeriesData> data_;
};

}  // namespace

std::unique_ptr<BlockDrawer> makeSeriesBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                             const Scenario&) {
  return std::make_unique<SeriesBlock>(parent, b);
}

}  // namespace kfw::plot
