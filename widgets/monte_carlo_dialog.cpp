#include "monte_carlo_dialog.h"

#include <qcustomplot.h>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>
#include <QtConcurrent>
#include <cmath>

#include "plot_kit.h"
#include "plot_text.h"

namespace kfw {

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// lo/hi = mean ∓ 2 sd; NaN where either is missing.
void two_sided(const std::vector<double>& c, const std::vector<double>& h, double sign,
               std::vector<double>& out) {
  out.assign(c.size(), std::nan(""));
  for (std::size_t k = 0; k < c.size() && k < h.size(); ++k)
    out[k] = c[k] + sign * 2.0 * h[k];
}

}  // namespace

MonteCarloDialog::MonteCarloDialog(std::shared_ptr<const Scenario> scenario,
                                   const ParamValues& values, QWidget* parent)
    : QDialog(parent), scenario_(std::move(scenario)), values_(values) {
  setWindowTitle("Monte Carlo over simulator seeds");
  resize(900, 700);
  auto* lay = new QVBoxLayout(this);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("first seed"));
  first_ = new QSpinBox(this);
  first_->setRange(0, 1000000);
  first_->setValue(1);
  row->addWidget(first_);
  row->addWidget(new QLabel("seeds"));
  count_ = new QSpinBox(this);
  count_->setObjectName("montecarlo.count");
  count_->setRange(2, 10000);
  count_->setValue(50);
  row->addWidget(count_);
  run_ = new QPushButton("Run", this);
  cancel_ = new QPushButton("Cancel", this);
  cancel_->setEnabled(false);
  row->addWidget(run_);
  row->addWidget(cancel_);
  progress_ = new QProgressBar(this);
  row->addWidget(progress_, 1);
  lay->addLayout(row);
  status_ = new QLabel(this);
  status_->setObjectName("montecarlo.status");
  status_->setWordWrap(true);
  lay->addWidget(status_);
  error_plot_ =
      plot::makePlot(this, "Error over the seeds vs the filter's ±2σ", "time (s)", "error");
  consistency_plot_ =
      plot::makePlot(this, "ANEES / ANIS over the seeds, 95 % bounds", "time (s)", "average");
  lay->addWidget(error_plot_, 1);
  lay->addWidget(consistency_plot_, 1);
  poll_ = new QTimer(this);
  poll_->setInterval(100);
  connect(poll_, &QTimer::timeout, this, [this] {
    if (done_) progress_->setValue(static_cast<int>(done_->load()));
  });
  connect(run_, &QPushButton::clicked, this, &MonteCarloDialog::start);
  connect(cancel_, &QPushButton::clicked, this, &MonteCarloDialog::cancel);
  connect(&watcher_, &QFutureWatcher<Expected<MonteCarloPart>>::finished, this, [this] {
    poll_->stop();
    run_->setEnabled(true);
    cancel_->setEnabled(false);
    const auto r = watcher_.result();
    if (!r) {
      status_->setText("⚠ " + q(r.error()));
    } else {
      progress_->setValue(progress_->maximum());
      showSummary(summarize_monte_carlo(*r));
    }
    emit runFinished();
  });
}

MonteCarloDialog::~MonteCarloDialog() {
  if (stop_) stop_->store(true);
  watcher_.waitForFinished();
}

void MonteCarloDialog::setSeeds(int first, int count) {
  first_->setValue(first);
  count_->setValue(count);
}

QString MonteCarloDialog::message() const {
  return status_->text();
}

void MonteCarloDialog::cancel() {
  if (stop_) stop_->store(true);
}

void MonteCarloDialog::start() {
  if (running()) return;
  std::vector<long long> seeds;
  for (int i = 0; i < count_->value(); ++i)
    seeds.push_back(first_->value() + i);
  stop_ = std::make_shared<std::atomic<bool>>(false);
  done_ = std::make_shared<std::atomic<std::size_t>>(0);
  progress_->setRange(0, count_->value());
  progress_->setValue(0);
  run_->setEnabled(false);
  cancel_->setEnabled(true);
  status_->setText(QString("running %1 seeds on every core…").arg(seeds.size()));
  poll_->start();
  watcher_.setFuture(
      QtConcurrent::run([s = scenario_, v = values_, seeds, stop = stop_, done = done_] {
        MonteCarloOptions opt;
        opt.cancel = stop.get();
        opt.progress = [done](std::size_t n, std::size_t) { done->store(n); };
        return run_monte_carlo(*s, v, seeds, {}, opt);
      }));
}

void MonteCarloDialog::showSummary(const MonteCarloSummary& s) {
  QString text = QString("%1 seeds, %2 completed").arg(s.seeds).arg(s.completed);
  if (!s.stopped.empty()) {
    text += QString(", %1 stopped (first: seed %2: %3)")
                .arg(s.stopped.size())
                .arg(s.stopped.front().seed)
                .arg(q(s.stopped.front().error));
  }
  if (auto it = s.metrics.find("rmse"); it != s.metrics.end()) {
    text += QString(". rmse %1 ± %2 (%3 – %4)")
                .arg(it->second.mean, 0, 'g', 4)
                .arg(it->second.sd, 0, 'g', 3)
                .arg(it->second.min, 0, 'g', 4)
                .arg(it->second.max, 0, 'g', 4);
  }
  auto line = [&](const QString& what, const ConsistencySummary& c) {
    text += QString("\n%1 (%2 runs): time average %3, bounds [%4, %5], %6 % of steps inside")
                .arg(what)
                .arg(c.runs)
                .arg(c.time_average, 0, 'g', 4)
                .arg(c.lo, 0, 'g', 4)
                .arg(c.hi, 0, 'g', 4)
                .arg(100.0 * c.inside, 0, 'f', 1);
  };
  if (s.nees) line("ANEES", *s.nees);
  for (const auto& c : s.nis)
    line("ANIS " + q(c.label), c);
  status_->setText(text);

  error_plot_->clearPlottables();
  if (s.error) {
    const ErrorBand& e = *s.error;
    error_plot_->yAxis->setLabel(plot::typeset(plot::withUnit(q(e.label) + " error", e.unit)));
    std::vector<double> lo, hi, f_lo, f_hi, zero(e.filter_sigma.size(), 0.0);
    two_sided(e.mean, e.sd, -1.0, lo);
    two_sided(e.mean, e.sd, 1.0, hi);
    two_sided(zero, e.filter_sigma, -1.0, f_lo);
    two_sided(zero, e.filter_sigma, 1.0, f_hi);
    const plot::Band band =
        plot::addBand(error_plot_, "mean ± 2 sd over the seeds", plot::color::kEstimate);
    plot::setBandLimits(band, s.t, lo, hi, plot::kAll);
    plot::setSeries(plot::addGraph(error_plot_, "mean error", plot::color::kTruth), s.t, e.mean,
                    plot::kAll);
    QCPGraph* up =
        plot::addGraph(error_plot_, "filter ±2σ", plot::color::kSecond, plot::Style::kDashed, 1.4);
    plot::setSeries(up, s.t, f_hi, plot::kAll);
    QCPGraph* down =
        plot::addGraph(error_plot_, "", plot::color::kSecond, plot::Style::kDashed, 1.4);
    plot::setSeries(down, s.t, f_lo, plot::kAll);
    down->removeFromLegend();
  }
  const double t0 = s.t.empty() ? 0.0 : s.t.front(), t1 = s.t.empty() ? 1.0 : s.t.back();
  plot::rescale(error_plot_, t0, t1, plot::settleTime(t0, t1));
  plot::replot(error_plot_);

  consistency_plot_->clearPlottables();
  int i = 0;
  auto series = [&](const QString& name, const ConsistencySummary& c) {
    const QColor col = plot::color::cycle(i++);
    plot::setSeries(plot::addGraph(consistency_plot_, name, col), s.t, c.average, plot::kAll);
    QCPGraph* lo =
        plot::addGraph(consistency_plot_, name + " 95 % bounds", col, plot::Style::kDashed);
    plot::setSeries(lo, s.t, c.lo_k, plot::kAll);
    QCPGraph* hi = plot::addGraph(consistency_plot_, "", col, plot::Style::kDashed);
    plot::setSeries(hi, s.t, c.hi_k, plot::kAll);
    hi->removeFromLegend();
  };
  if (s.nees) series(QString("ANEES (%1 dof)").arg(s.nees->dof), *s.nees);
  for (const auto& c : s.nis)
    series(QString("ANIS %1 (%2 dof)").arg(q(c.label)).arg(c.dof), c);
  plot::rescale(consistency_plot_, t0, t1, plot::settleTime(t0, t1));
  plot::replot(consistency_plot_);
}

}  // namespace kfw
