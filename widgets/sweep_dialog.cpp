#include "sweep_dialog.h"
#include "data/csv.h"

#include <qcustomplot.h>

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QGridLayout>
#include <QLabel>
#include <QMouseEvent>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>
#include <QtConcurrent>
#include <cmath>
#include <sstream>

#include "data/output.h"
#include "plot_export.h"
#include "plot_kit.h"

namespace kfw {

SweepDialog::SweepDialog(std::shared_ptr<const Scenario> scenario,
                         std::shared_ptr<const Dataset> dataset, const ParamValues& base,
                         const Metrics& metrics, QWidget* parent)
    : QDialog(parent), scenario_(std::move(scenario)), data_(std::move(dataset)), base_(base) {
  setWindowTitle("Sweep a metric");
  resize(900, 700);
  auto* lay = new QVBoxLayout(this);
  auto* grid = new QGridLayout;
  grid->addWidget(new QLabel("parameter"), 0, 1);
  grid->addWidget(new QLabel("from"), 0, 2);
  grid->addWidget(new QLabel("to"), 0, 3);
  grid->addWidget(new QLabel("points"), 0, 4);
  for (int a = 0; a < 2; ++a) {
    AxisUi& ui = axes_[a];
    grid->addWidget(new QLabel(a == 0 ? "x" : "y (optional)"), a + 1, 0);
    ui.key = new QComboBox(this);
    ui.key->setObjectName(QString("sweep.key%1").arg(a));
    if (a == 1) ui.key->addItem("—", QString());
    for (const auto& s : scenario_->params().specs()) {
      if (s.scale == Scale::kChoice || s.scale == Scale::kToggle) continue;
      ui.key->addItem(QString::fromStdString(s.key), QString::fromStdString(s.key));
    }
    ui.lo = new QDoubleSpinBox(this);
    ui.hi = new QDoubleSpinBox(this);
    for (auto* sb : {ui.lo, ui.hi}) {
      sb->setDecimals(6);
      sb->setRange(-1e9, 1e9);
    }
    ui.n = new QSpinBox(this);
    ui.n->setRange(1, 200);
    ui.n->setValue(a == 0 ? 30 : 20);
    grid->addWidget(ui.key, a + 1, 1);
    grid->addWidget(ui.lo, a + 1, 2);
    grid->addWidget(ui.hi, a + 1, 3);
    grid->addWidget(ui.n, a + 1, 4);
    connect(ui.key, &QComboBox::currentIndexChanged, this, [this, a] {
      const ParamSpec* s =
          scenario_->params().find(axes_[a].key->currentData().toString().toStdString());
      if (!s) return;
      const double v = base_.count(s->key) ? base_.at(s->key) : s->def;
      const bool log = s->scale == Scale::kLog;
      axes_[a].lo->setValue(log ? std::max(s->min, v / 100) : s->min);
      axes_[a].hi->setValue(log ? std::min(s->max, v * 100) : s->max);
    });
  }
  lay->addLayout(grid);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("metric"));
  metric_ = new QComboBox(this);
  metric_->setObjectName("sweep.metric");
  for (const auto& [k, v] : metrics) {
    // Informational metrics (a gain, a count) have no better value to mark.
    if (describe_metric(*scenario_, k).direction != Direction::kNone)
      metric_->addItem(QString::fromStdString(k));
  }
  metric_->setCurrentText("rmse");
  row->addWidget(metric_, 1);
  run_ = new QPushButton("Run", this);
  cancel_ = new QPushButton("Cancel", this);
  cancel_->setEnabled(false);
  auto* save = new QPushButton("Save PNG…", this);
  auto* csv = new QPushButton("Export CSV…", this);
  row->addWidget(run_);
  row->addWidget(cancel_);
  row->addWidget(save);
  row->addWidget(csv);
  lay->addLayout(row);
  progress_ = new QProgressBar(this);
  progress_->setObjectName("sweep.progress");
  lay->addWidget(progress_);
  status_ = new QLabel(this);
  status_->setObjectName("sweep.status");
  status_->setWordWrap(true);
  lay->addWidget(status_);
  plot_ = plot::makePlot(this, "Sweep", "", "");
  lay->addWidget(plot_, 1);
  axes_[0].key->setCurrentIndex(std::max(0, axes_[0].key->findData("gamma")));
  emit axes_[0].key->currentIndexChanged(axes_[0].key->currentIndex());
  connect(run_, &QPushButton::clicked, this, &SweepDialog::start);
  connect(cancel_, &QPushButton::clicked, this, &SweepDialog::cancel);
  connect(csv, &QPushButton::clicked, this, [this] {
    if (!last_) return;
    const QString f =
        QFileDialog::getSaveFileName(this, "Export sweep", "sweep.csv", "CSV (*.csv)");
    if (f.isEmpty()) return;
    if (auto st = exportCsv(f); !st) status_->setText("⚠ " + QString::fromStdString(st.error()));
  });
  // A click picks the nearest grid point (1-D: by x; 2-D: the cell under the cursor).
  connect(plot_, &QCustomPlot::mousePress, this, [this](QMouseEvent* ev) {
    if (!last_ || last_->points.empty()) return;
    const SweepResult& r = *last_;
    auto coord = [](const SweepAxis& a, double v) { return a.log ? std::log10(v) : v; };
    std::size_t pick = 0;
    double best_d = INFINITY;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      double d = 0;
      if (r.axes.size() == 1) {
        d = std::abs(plot_->xAxis->coordToPixel(r.points[i][0]) - ev->pos().x());
      } else {
        d = std::hypot(
            plot_->xAxis->coordToPixel(coord(r.axes[0], r.points[i][0])) - ev->pos().x(),
            plot_->yAxis->coordToPixel(coord(r.axes[1], r.points[i][1])) - ev->pos().y());
      }
      if (d < best_d) {
        best_d = d;
        pick = i;
      }
    }
    choosePoint(pick);
  });
  connect(save, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, "Save sweep", "sweep.png",
                                                   "PNG (*.png);;PDF (*.pdf);;SVG (*.svg)");
    if (!f.isEmpty()) exportPlot(plot_, f);
  });
  connect(&watcher_, &QFutureWatcher<Expected<SweepResult>>::finished, this, [this] {
    run_->setEnabled(true);
    cancel_->setEnabled(false);
    const auto r = watcher_.result();
    if (!r) {
      status_->setText("⚠ " + QString::fromStdString(r.error()));
    } else if (stop_->load()) {
      // The finished points are kept and shown (issue 32, item 9); the others are gaps.
      std::size_t ran = 0;
      for (const auto& m : r->metrics)
        ran += m.empty() ? 0 : 1;
      last_ = *r;
      if (ran > 0) showResult(*r, running_metric_);
      status_->setText(QString("cancelled after %1 of %2 points%3")
                           .arg(ran)
                           .arg(r->points.size())
                           .arg(ran > 0 ? ": those shown. " + status_->text() : QString()));
    } else {
      progress_->setValue(progress_->maximum());
      last_ = *r;
      showResult(*r, running_metric_);
    }
    emit runFinished();
  });
}

SweepDialog::~SweepDialog() {
  if (stop_) stop_->store(true);
  watcher_.waitForFinished();
}

void SweepDialog::setAxis(int which, const QString& key, double lo, double hi, int n) {
  AxisUi& ui = axes_[which];
  ui.key->setCurrentIndex(std::max(0, ui.key->findData(key)));
  ui.lo->setValue(lo);
  ui.hi->setValue(hi);
  ui.n->setValue(n);
}

void SweepDialog::setMetric(const QString& name) {
  metric_->setCurrentText(name);
}

void SweepDialog::cancel() {
  if (stop_) stop_->store(true);
}

int SweepDialog::progressValue() const {
  return progress_->value();
}

void SweepDialog::choosePoint(std::size_t index) {
  if (!last_ || index >= last_->points.size()) return;
  ParamValues v = base_;
  QStringList parts;
  for (std::size_t a = 0; a < last_->axes.size(); ++a) {
    v[last_->axes[a].key] = last_->points[index][a];
    parts << QString("%1 = %2")
                 .arg(QString::fromStdString(last_->axes[a].key))
                 .arg(last_->points[index][a], 0, 'g', 4);
  }
  status_->setText("applied " + parts.join(", "));
  emit pointChosen(v);
}

Status SweepDialog::exportCsv(const QString& path) const {
  if (!last_) return Error{"no sweep to export"};
  const SweepResult& r = *last_;
  const std::string m = running_metric_.toStdString();
  Dataset table;
  table.source = path.toStdString();
  for (const auto& ax : r.axes)
    table.add(ax.key, r.points.size());
  table.add(m, r.points.size());
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    for (std::size_t k = 0; k < r.axes.size(); ++k)
      table.columns[k][i] = r.points[i][k];
    auto it = r.metrics[i].find(m);
    table.columns[r.axes.size()][i] = it == r.metrics[i].end() ? std::nan("") : it->second;
  }
  std::ostringstream csv;
  write_csv(csv, table);
  return write_file_atomic(path.toStdString(), csv.str());
}

QString SweepDialog::message() const {
  return status_->text();
}

void SweepDialog::start() {
  if (running()) return;
  std::vector<SweepAxis> axes;
  for (const AxisUi& ui : axes_) {
    const QString key = ui.key->currentData().toString();
    if (key.isEmpty()) continue;
    const std::string text = key.toStdString() + "=" +
                             QString::number(ui.lo->value(), 'g', 12).toStdString() + ":" +
                             QString::number(ui.hi->value(), 'g', 12).toStdString() + ":" +
                             std::to_string(ui.n->value());
    auto a = parse_sweep_axis(scenario_->params(), text);
    if (!a) {
      status_->setText("⚠ " + QString::fromStdString(a.error()));
      return;
    }
    axes.push_back(*a);
  }
  running_metric_ = metric_->currentText();
  stop_ = std::make_shared<std::atomic<bool>>(false);
  done_ = std::make_shared<std::atomic<std::size_t>>(0);
  run_->setEnabled(false);
  cancel_->setEnabled(true);
  status_->setText("running…");
  std::size_t total = 1;
  for (const auto& a : axes)
    total *= static_cast<std::size_t>(a.n);
  progress_->setRange(0, static_cast<int>(total));
  progress_->setValue(0);
  auto timer = new QTimer(this);
  auto clock = std::make_shared<QElapsedTimer>();
  clock->start();
  connect(timer, &QTimer::timeout, this, [this, timer, clock, total, done = done_] {
    if (!running()) {
      timer->deleteLater();
      return;
    }
    const std::size_t n = done->load();
    progress_->setValue(static_cast<int>(n));
    // The time left from the rate so far (every point costs about one run).
    if (n > 0 && clock->elapsed() > 300) {
      const double left = clock->elapsed() / 1000.0 * static_cast<double>(total - n) / n;
      status_->setText(QString("running… %1 of %2 points, about %3 left")
                           .arg(n)
                           .arg(total)
                           .arg(left < 90 ? QString("%1 s").arg(std::ceil(left))
                                          : QString("%1 min").arg(std::ceil(left / 60))));
    }
  });
  timer->start(50);
  watcher_.setFuture(
      QtConcurrent::run([s = scenario_, d = data_, b = base_, axes, stop = stop_, done = done_] {
        return sweep(*s, *d, b, axes, 0, stop.get(), Shard{},
                     [done](std::size_t n) { done->store(std::max(done->load(), n)); });
      }));
}

void SweepDialog::showResult(const SweepResult& r, const QString& metric) {
  const std::string m = metric.toStdString();
  auto value = [&](std::size_t i) {
    auto it = r.metrics[i].find(m);
    return it == r.metrics[i].end() ? std::nan("") : it->second;
  };
  plot_->clearGraphs();
  plot_->clearPlottables();
  if (auto* scale = plot_->findChild<QCPColorScale*>()) plot_->plotLayout()->remove(scale);
  plot_->xAxis->setScaleType(QCPAxis::stLinear);
  plot_->xAxis->setTicker(QSharedPointer<QCPAxisTicker>(new QCPAxisTicker));
  if (r.axes[0].log) plot::setLog(plot_->xAxis);
  if (auto* t = plot_->findChild<QCPTextElement*>("title")) {
    t->setText(QString("%1 over %2")
                   .arg(metric, QString::fromStdString(r.axes.size() > 1
                                                           ? r.axes[0].key + " × " + r.axes[1].key
                                                           : r.axes[0].key)));
  }
  plot_->xAxis->setLabel(QString::fromStdString(r.axes[0].key));
  spec_ = describe_metric(*scenario_, m);
  std::size_t best = 0;  // the first finite point, then any better (a cancelled sweep has gaps)
  while (best + 1 < r.points.size() && !std::isfinite(value(best)))
    ++best;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    if (better(spec_, value(i), value(best))) best = i;
  }
  best_ = best;
  const QString sense = spec_.direction == Direction::kTarget
                            ? QString("closest to %1").arg(spec_.target, 0, 'g', 4)
                            : QString(spec_.direction == Direction::kHigher ? "highest" : "lowest");
  if (r.axes.size() == 1) {
    plot_->yAxis->setLabel(metric);
    std::vector<double> x, y;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      x.push_back(r.points[i][0]);
      y.push_back(value(i));
    }
    auto* g = plot::addGraph(plot_, metric, plot::color::kEstimate, plot::Style::kLine, 1.8);
    g->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, 5));
    plot::setSeries(g, x, y, plot::kAll);
    auto* b = plot::addGraph(plot_, "best (" + sense + ")", plot::color::kSecond);
    b->setLineStyle(QCPGraph::lsNone);
    b->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssDisc, 10));
    b->addData(r.points[best][0], value(best));
    plot::rescale(plot_);
  } else {
    plot_->yAxis->setLabel(QString::fromStdString(r.axes[1].key));
    plot_->yAxis->setScaleType(QCPAxis::stLinear);
    plot_->yAxis->setTicker(QSharedPointer<QCPAxisTicker>(new QCPAxisTicker));
    if (r.axes[1].log) plot::setLog(plot_->yAxis);
    const int nx = r.axes[0].n, ny = r.axes[1].n;
    auto* map = new QCPColorMap(plot_->xAxis, plot_->yAxis);
    map->setName(metric);
    // Cells are placed in the axes' own coordinates (log10 of log-scale keys).
    auto coord = [](const SweepAxis& a, double v) { return a.log ? std::log10(v) : v; };
    const auto xs = r.axes[0].values(), ys = r.axes[1].values();
    map->data()->setSize(nx, ny);
    map->data()->setRange(QCPRange(coord(r.axes[0], xs.front()), coord(r.axes[0], xs.back())),
                          QCPRange(coord(r.axes[1], ys.front()), coord(r.axes[1], ys.back())));
    for (int ix = 0; ix < nx; ++ix) {
      for (int iy = 0; iy < ny; ++iy)
        map->data()->setCell(ix, iy, value(static_cast<std::size_t>(ix * ny + iy)));
    }
    // The heat map draws in linear axis coordinates: show log axes as log10 values.
    if (r.axes[0].log) {
      plot_->xAxis->setScaleType(QCPAxis::stLinear);
      plot_->xAxis->setTicker(QSharedPointer<QCPAxisTicker>(new QCPAxisTicker));
      plot_->xAxis->setLabel("log10 " + QString::fromStdString(r.axes[0].key));
    }
    if (r.axes[1].log) {
      plot_->yAxis->setScaleType(QCPAxis::stLinear);
      plot_->yAxis->setTicker(QSharedPointer<QCPAxisTicker>(new QCPAxisTicker));
      plot_->yAxis->setLabel("log10 " + QString::fromStdString(r.axes[1].key));
    }
    auto* scale = new QCPColorScale(plot_);
    plot_->plotLayout()->addElement(plot::axisRectRow(plot_), 1, scale);
    scale->setLabel(metric);
    map->setColorScale(scale);
    map->setGradient(QCPColorGradient::gpThermal);
    map->rescaleDataRange(true);
    // The best cell, marked.
    auto* b = plot::addGraph(plot_, "best (" + sense + ")", plot::color::kSecond);
    b->setLineStyle(QCPGraph::lsNone);
    b->setScatterStyle(
        QCPScatterStyle(QCPScatterStyle::ssCrossCircle, QPen(Qt::white, 2), Qt::NoBrush, 14));
    b->addData(coord(r.axes[0], r.points[best][0]), coord(r.axes[1], r.points[best][1]));
    plot_->legend->setVisible(false);
    plot_->rescaleAxes();
  }
  const QString warnings = sweepWarnings(r, value, best);
  status_->setStyleSheet(warnings.isEmpty() ? QString() : QString("color: #8a1c13;"));
  status_->setText(QString("%1 points; best %2 (%3) = %4 at %5; click a point to apply it%6")
                       .arg(r.points.size())
                       .arg(metric, sense)
                       .arg(value(best), 0, 'g', 5)
                       .arg([&] {
                         QStringList parts;
                         for (std::size_t a = 0; a < r.axes.size(); ++a) {
                           parts << QString("%1 = %2")
                                        .arg(QString::fromStdString(r.axes[a].key))
                                        .arg(r.points[best][a], 0, 'g', 4);
                         }
                         return parts.join(", ");
                       }())
                       .arg(warnings));
  plot_->replot();
}

QString SweepDialog::sweepWarnings(const SweepResult& r,
                                   const std::function<double(std::size_t)>& value,
                                   std::size_t best) const {
  QString out;
  const double vb = value(best);
  if (!std::isfinite(vb)) return out;
  // On the grid's edge: the best may lie beyond it.
  QStringList edge;
  for (std::size_t a = 0; a < r.axes.size(); ++a) {
    const auto v = r.axes[a].values();
    if (v.size() > 2 && (r.points[best][a] == v.front() || r.points[best][a] == v.back()))
      edge << QString::fromStdString(r.axes[a].key);
  }
  if (!edge.isEmpty())
    out += "\n⚠ The best point is on the grid's edge for " + edge.join(", ") + ": widen the range.";
  // A flat valley: many points as good as the best (Q and R scaled together change little).
  std::size_t finite = 0, near = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const double v = value(i);
    if (!std::isfinite(v)) continue;
    ++finite;
    if (std::abs(v - vb) <= kFlatFraction * std::max(std::abs(vb), 1e-300)) ++near;
  }
  if (finite >= 6 && near >= std::max<std::size_t>(3, finite / 10)) {
    out += QString(
               "\n⚠ Flat: %1 of %2 points are within %3 % of the best, so this metric hardly "
               "tells them apart (a ratio such as Q/R may be all it sets). Fix one parameter, "
               "or sweep a consistency metric (NIS).")
               .arg(near)
               .arg(finite)
               .arg(kFlatFraction * 100);
  }
  return out;
}

}  // namespace kfw
