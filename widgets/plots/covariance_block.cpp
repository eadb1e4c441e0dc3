// The covariance block: the sample covariance of several derived series (left) beside the
// declared design matrix (right), one colour scale for both and each cell's number written in
// it — seed 004's error covariance panel, from a model file. The numbers are the engine's
// (model::covariance_block_data).
#include <qcustomplot.h>

#include <algorithm>
#include <cmath>

#include "plot_kit.h"
#include "plot_text.h"
#include "plots/block_drawer.h"

namespace kfw::plot {

namespace {

// Dark text on light cells, white on saturated ones.
QColor textOn(double v, double top) {
  return std::isfinite(v) && std::abs(v) > 0.6 * top ? Qt::white : Qt::black;
}

class CovarianceBlock final : public BlockDrawer {
 public:
  CovarianceBlock(QWidget* parent, const model::PlotBlockSpec& b)
      : block_(b), n_(static_cast<int>(b.series.size())) {
    std::vector<std::string> units;
    for (const auto& l : b.series)
      units.push_back(l.unit);
    unit_ = sameUnit(units) && !units.front().empty() ? QString::fromStdString(units.front()) + "²"
                                                      : QString();
    title_ = panelTitle(b.title, "Sample covariance (left) vs design (right)");
    plot_ = makePlot(parent, title_, "", "");
    plot_->legend->setVisible(false);
    plot_->setInteractions(QCP::Interactions());
    sample_ = addMap(0);
    design_ = addMap(n_ + 1);
    scale_ = new QCPColorScale(plot_);
    plot_->plotLayout()->addElement(axisRectRow(plot_), 1, scale_);
    scale_->setLabel(withUnit("covariance", unit_.toStdString()));
    QCPColorGradient g;
    g.setColorStopAt(0.0, QColor(33, 102, 172));
    g.setColorStopAt(0.5, QColor(247, 247, 247));
    g.setColorStopAt(1.0, QColor(178, 24, 43));
    for (QCPColorMap* m : {sample_, design_}) {
      m->setColorScale(scale_);
      m->setGradient(g);
    }
    setTicks();
    for (int k = 0; k < 2 * n_ * n_; ++k) {
      auto* t = new QCPItemText(plot_);
      t->setFont(QFont(plot_->font().family(), 9));
      t->position->setType(QCPItemPosition::ptPlotCoords);
      texts_.push_back(t);
    }
  }

  QCustomPlot* plot() const override { return plot_; }
  QString title() const override { return title_; }

  void setResult(const BlockInput& in) override {
    const model::CovarianceData c = model::covariance_block_data(block_, in.result);
    double top = 1e-300;
    for (const auto* m : {&c.sample, &c.design}) {
      for (double v : *m) {
        if (std::isfinite(v)) top = std::max(top, std::abs(v));
      }
    }
    const auto at = [](const std::vector<double>& m, std::size_t k) {
      return k < m.size() ? m[k] : std::nan("");
    };
    std::size_t t = 0;
    for (int i = 0; i < n_; ++i) {
      for (int j = 0; j < n_; ++j) {
        const std::size_t k = static_cast<std::size_t>(i * n_ + j);
        const double s = at(c.sample, k), d = at(c.design, k);
        sample_->data()->setCell(j, i, s);
        design_->data()->setCell(j, i, d);
        cell(texts_[t++], j, i, s, top);
        cell(texts_[t++], n_ + 1 + j, i, d, top);
      }
    }
    for (QCPColorMap* m : {sample_, design_})
      m->setDataRange(QCPRange(-top, top));
    if (!block_.instants) {
      plot_->xAxis->setLabel(QString("%1 steps where every series is finite").arg(c.count));
    } else if (c.excluded > 0) {
      plot_->xAxis->setLabel(
          QString("%1 synchronous instants (%2 holding a marked outlier left out)")
              .arg(c.count)
              .arg(c.excluded));
    } else {
      plot_->xAxis->setLabel(QString("%1 synchronous instants").arg(c.count));
    }
    replot(plot_);
  }

 private:
  QCPColorMap* addMap(int first_column) {
    auto* m = new QCPColorMap(plot_->xAxis, plot_->yAxis);
    m->data()->setSize(n_, n_);
    m->data()->setRange(QCPRange(first_column, first_column + n_ - 1), QCPRange(0, n_ - 1));
    m->setInterpolate(false);
    return m;
  }

  // Each series' symbol under both matrices and beside the rows; no grid through the gap.
  void setTicks() {
    QSharedPointer<QCPAxisTickerText> cx(new QCPAxisTickerText), cy(new QCPAxisTickerText);
    // The labels' symbols ("range 1 error" → "range"), or the series' names where those repeat.
    QStringList names;
    for (const auto& line : block_.series)
      names << symbolOf(line.label);
    if (names.removeDuplicates() > 0) {
      names.clear();
      for (const auto& line : block_.series)
        names << symbolOf(line.key);
    }
    for (int i = 0; i < n_; ++i) {
      const QString name = names[i];
      cx->addTick(i, name);
      cx->addTick(n_ + 1 + i, name);
      cy->addTick(i, name);
    }
    plot_->xAxis->setTicker(cx);
    plot_->yAxis->setTicker(cy);
    plot_->xAxis->setRange(-0.6, 2 * n_ + 0.6);
    plot_->yAxis->setRange(-0.6, n_ - 0.4);
    plot_->yAxis->setRangeReversed(true);
    for (QCPAxis* a : {plot_->xAxis, plot_->yAxis}) {
      a->grid()->setVisible(false);
      a->grid()->setZeroLinePen(Qt::NoPen);
      a->setSubTicks(false);
    }
  }

  void cell(QCPItemText* t, int x, int y, double v, double top) {
    t->position->setCoords(x, y);
    t->setText(noteNumber(v));
    t->setColor(textOn(v, top));
  }

  model::PlotBlockSpec block_;
  int n_ = 0;
  QString title_, unit_;
  QCustomPlot* plot_ = nullptr;
  QCPColorMap *sample_ = nullptr, *design_ = nullptr;
  QCPColorScale* scale_ = nullptr;
  std::vector<QCPItemText*> texts_;
};

}  // namespace

std::unique_ptr<BlockDrawer> makeCovarianceBlock(QWidget* parent, const model::PlotBlockSpec& b,
                                                 const Scenario&) {
  return std::make_unique<CovarianceBlock>(parent, b);
}

}  // namespace kfw::plot
