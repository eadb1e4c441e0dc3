#include "sweep_dialog.h"

#include <qcustomplot.h>

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QGridLayout>
#include <QLabel>
#include <QPushButton>
#include <QSpinBox>
#include <QVBoxLayout>
#include <QtConcurrent>
#include <cmath>

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
  for (const auto& [k, v] : metrics)
    metric_->addItem(QString::fromStdString(k));
  metric_->setCurrentText("rmse");
  row->addWidget(metric_, 1);
  run_ = new QPushButton("Run", this);
  auto* save = new QPushButton("Save PNG…", this);
  row->addWidget(run_);
  row->addWidget(save);
  lay->addLayout(row);
  status_ = new QLabel(this);
  status_->setObjectName("sweep.status");
  lay->addWidget(status_);
  plot_ = plot::makePlot(this, "Sweep", "", "");
  lay->addWidget(plot_, 1);
  axes_[0].key->setCurrentIndex(std::max(0, axes_[0].key->findData("gamma")));
  emit axes_[0].key->currentIndexChanged(axes_[0].key->currentIndex());
  connect(run_, &QPushButton::clicked, this, &SweepDialog::start);
  connect(save, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, "Save sweep", "sweep.png",
                                                   "PNG (*.png);;PDF (*.pdf);;SVG (*.svg)");
    if (!f.isEmpty()) exportPlot(plot_, f);
  });
  connect(&watcher_, &QFutureWatcher<Expected<SweepResult>>::finished, this, [this] {
    run_->setEnabled(true);
    const auto r = watcher_.result();
    if (!r) {
      status_->setText("⚠ " + QString::fromStdString(r.error()));
    } else {
      showResult(*r, running_metric_);
    }
    emit done();
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
  run_->setEnabled(false);
  status_->setText("running…");
  watcher_.setFuture(QtConcurrent::run([s = scenario_, d = data_, b = base_, axes, stop = stop_] {
    return sweep(*s, *d, b, axes, 2, stop.get());
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
  std::size_t best = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    if (std::isfinite(value(i)) && (!std::isfinite(value(best)) || value(i) < value(best)))
      best = i;
  }
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
    auto* b = plot::addGraph(plot_, "minimum", plot::color::kSecond);
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
    plot_->plotLayout()->addElement(1, 1, scale);
    scale->setLabel(metric);
    map->setColorScale(scale);
    map->setGradient(QCPColorGradient::gpThermal);
    map->rescaleDataRange(true);
    plot_->legend->setVisible(false);
    plot_->rescaleAxes();
  }
  status_->setText(QString("%1 points; minimum %2 = %3 at %4")
                       .arg(r.points.size())
                       .arg(metric)
                       .arg(value(best), 0, 'g', 5)
                       .arg([&] {
                         QStringList parts;
                         for (std::size_t a = 0; a < r.axes.size(); ++a) {
                           parts << QString("%1 = %2")
                                        .arg(QString::fromStdString(r.axes[a].key))
                                        .arg(r.points[best][a], 0, 'g', 4);
                         }
                         return parts.join(", ");
                       }()));
  plot_->replot();
}

}  // namespace kfw
