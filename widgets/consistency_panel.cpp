#include "consistency_panel.h"

#include <qcustomplot.h>

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QVBoxLayout>
#include <cmath>

#include "core/statistics.h"
#include "filter/consistency.h"
#include "plot_kit.h"

namespace kfw {

namespace {
constexpr std::size_t kLags = 20;
}

ConsistencyPanel::ConsistencyPanel(QWidget* parent) : QWidget(parent) {
  using namespace plot;
  auto* lay = new QVBoxLayout(this);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("channel"));
  channel_ = new QComboBox(this);
  channel_->setObjectName("consistency.channel");
  row->addWidget(channel_, 1);
  row->addWidget(new QLabel("moving-average window"));
  window_ = new QSpinBox(this);
  window_->setObjectName("consistency.window");
  window_->setRange(1, 5000);
  window_->setValue(50);
  window_->setSuffix(" updates");
  row->addWidget(window_);
  lay->addLayout(row);
  summary_ = new QLabel(this);
  summary_->setObjectName("consistency.summary");
  summary_->setWordWrap(true);
  lay->addWidget(summary_);

  nis_ = makePlot(this, "NIS per update with two-sided 95 % χ² bounds", "time (s)", "NIS (–)");
  setLog(nis_->yAxis);
  nis_y_ = addGraph(nis_, "NIS", color::kEstimate, Style::kDots);
  nis_lo_ = addGraph(nis_, "χ²(dof) 2.5 % / 97.5 %", color::kBound, Style::kDashed);
  nis_hi_ = addGraph(nis_, "", color::kBound, Style::kDashed);
  nis_hi_->removeFromLegend();
  nis_avg_ = addGraph(nis_, "moving average", color::kSecond);
  avg_lo_ = addGraph(nis_, "bounds of the average", color::kSecond, Style::kDashed);
  avg_hi_ = addGraph(nis_, "", color::kSecond, Style::kDashed);
  avg_hi_->removeFromLegend();

  acf_ = makePlot(this, "Whiteness: autocorrelation of y/√S at the channel's own rate",
                  "lag (updates of this channel)", "autocorrelation (–)");
  acf_bars_ = new QCPBars(acf_->xAxis, acf_->yAxis);
  acf_bars_->setName("autocorrelation");
  acf_bars_->setPen(QPen(color::kEstimate));
  acf_bars_->setBrush(QBrush(color::kEstimate));
  acf_bars_->setWidth(0.5);
  acf_lo_ = addGraph(acf_, "± 1.96/√N", color::kSecond, Style::kDashed);
  acf_hi_ = addGraph(acf_, "", color::kSecond, Style::kDashed);
  acf_hi_->removeFromLegend();

  nees_plot_ = makePlot(this, "NEES against truth with 95 % χ² bounds", "time (s)", "NEES (–)");
  setLog(nees_plot_->yAxis);
  nees_y_ = addGraph(nees_plot_, "NEES", color::kEstimate, Style::kDots);
  nees_avg_ = addGraph(nees_plot_, "moving average", color::kSecond);
  nees_lo_ = addGraph(nees_plot_, "χ²(n) 2.5 % / 97.5 %", color::kBound, Style::kDashed);
  nees_hi_ = addGraph(nees_plot_, "", color::kBound, Style::kDashed);
  nees_hi_->removeFromLegend();

  nis_title_ = nis_->findChild<QCPTextElement*>("title");
  acf_title_ = acf_->findChild<QCPTextElement*>("title");
  auto* plots = new QHBoxLayout;
  plots->addWidget(nis_, 1);
  plots->addWidget(acf_, 1);
  lay->addLayout(plots, 1);
  lay->addWidget(nees_plot_, 1);
  connect(channel_, &QComboBox::currentIndexChanged, this, [this] { refresh(); });
  connect(window_, &QSpinBox::valueChanged, this, [this] { refresh(); });
}

void ConsistencyPanel::setResult(std::shared_ptr<const RunResult> result) {
  // Only kept here: the channels are copied out of the result when the panel is drawn, not on
  // every slider move while the tab is hidden.
  result_ = std::move(result);
  loaded_ = false;
  dirty_ = true;
  if (isVisible()) refresh();
}

void ConsistencyPanel::load() {
  if (loaded_) return;
  loaded_ = true;
  channels_ = result_ ? result_->channels() : std::vector<InnovationChannel>{};
  nees_ = result_ ? result_->nees_series() : NeesSeries{};
  const QString keep = channel_->currentText();
  {
    const QSignalBlocker b(channel_);
    channel_->clear();
    for (const auto& c : channels_) {
      channel_->addItem(QString("%1 (%2 dof)").arg(QString::fromStdString(c.display())).arg(c.dof));
    }
    const int i = channel_->findText(keep);
    channel_->setCurrentIndex(i >= 0 ? i : 0);
  }
}

void ConsistencyPanel::setWindow(int updates) {
  window_->setValue(updates);
}
void ConsistencyPanel::setChannel(int index) {
  load();
  channel_->setCurrentIndex(index);
}
int ConsistencyPanel::channel() const {
  return channel_->currentIndex();
}

QList<ExportItem> ConsistencyPanel::exportItems() {
  load();
  QList<ExportItem> out;
  if (!result_) return out;
  for (int i = 0; i < static_cast<int>(channels_.size()); ++i) {
    const InnovationChannel& c = channels_[static_cast<std::size_t>(i)];
    const QString key = QString::fromStdString(c.name), label = QString::fromStdString(c.display());
    auto draw = [this, i] {
      const QSignalBlocker b(channel_);
      channel_->setCurrentIndex(i);
      refresh();
    };
    out << ExportItem{"consistency_nis." + key, "Consistency: NIS of " + label, nis_, draw};
    if (!c.normalized.empty() || !c.components.empty()) {
      out << ExportItem{"consistency_whiteness." + key, "Consistency: whiteness of " + label, acf_,
                        draw};
    }
  }
  if (count_finite(nees_.nees) > 0) {
    out << ExportItem{"consistency_nees", "Consistency: NEES", nees_plot_, [this] { refresh(); }};
  }
  return out;
}

QString ConsistencyPanel::summary() const {
  return summary_->text();
}

QList<PlotPanel> ConsistencyPanel::plots() const {
  return {{"consistency_nis", "Consistency: NIS", nis_},
          {"consistency_whiteness", "Consistency: whiteness", acf_},
          {"consistency_nees", "Consistency: NEES", nees_plot_}};
}

void ConsistencyPanel::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  if (dirty_) refresh();
}

void ConsistencyPanel::refresh() {
  load();
  dirty_ = false;
  const int ci = channel_->currentIndex();
  if (!result_ || ci < 0 || ci >= static_cast<int>(channels_.size())) {
    summary_->setText(result_ ? "This scenario offers no innovation channels." : QString());
    return;
  }
  const InnovationChannel& c = channels_[static_cast<std::size_t>(ci)];
  // The channel in the titles: exported plots of several channels tell which is which.
  const QString cname = QString::fromStdString(c.display());
  if (nis_title_)
    nis_title_->setText("NIS of " + cname + " per update with two-sided 95 % χ² bounds");
  if (acf_title_) {
    acf_title_->setText(!c.normalized.empty()
                            ? "Whiteness of " + cname +
                                  ": autocorrelation of y/√S at the channel's own rate"
                        : !c.components.empty()
                            ? "Whiteness of " + cname + ": autocorrelation of each component's y/√S"
                            : QString("Whiteness: autocorrelation of y/√S of each scalar channel"));
  }
  const auto& t = result_->t;
  const auto w = static_cast<std::size_t>(window_->value());
  const std::vector<double> span{t.empty() ? 0.0 : t.front(), t.empty() ? 1.0 : t.back()};
  const auto b1 = nis_bounds(c.dof, 1), bw = nis_bounds(c.dof, w);
  plot::setSeries(nis_y_, t, c.nis, plot::kAll);
  plot::setSeries(nis_avg_, t, moving_average_finite(c.nis, w), plot::kAll);
  plot::setSeries(nis_lo_, span, {b1.lo, b1.lo}, 2);
  nis_lo_->setName(QString("χ²(%1) 2.5 % / 97.5 %").arg(c.dof));
  plot::setSeries(nis_hi_, span, {b1.hi, b1.hi}, 2);
  plot::setSeries(avg_lo_, span, {bw.lo, bw.lo}, 2);
  plot::setSeries(avg_hi_, span, {bw.hi, bw.hi}, 2);
  nis_avg_->setName(QString("moving average (%1)").arg(w));
  plot::rescale(nis_, span[0], span[1]);  // a time plot: the replay window applies
  plot::replot(nis_);

  QString text = QString(
                     "<b>%1</b>: %2 updates, mean NIS %3 (expected %4), %5 % inside the 95 % "
                     "bounds")
                     .arg(QString::fromStdString(c.display()))
                     .arg(count_finite(c.nis))
                     .arg(mean_finite(c.nis), 0, 'g', 4)
                     .arg(c.dof)
                     .arg(100.0 * fraction_inside(c.nis, c.dof), 0, 'f', 1);
  QVector<double> lag, acf;
  for (QCPGraph* g : acf_lines_)
    acf_->removeGraph(g);
  acf_lines_.clear();
  double top = 0.1;
  // A scalar channel: its own bars. A vector channel: each component's autocorrelation (when
  // the scenario reports its components), else each scalar channel's.
  struct Series {
    std::string name;
    const std::vector<double>* normalized;
    bool bars;  // the channel itself: drawn as bars
  };
  std::vector<Series> scalar;
  if (!c.normalized.empty()) {
    scalar.push_back({c.name, &c.normalized, true});
  } else if (!c.components.empty()) {
    for (const auto& comp : c.components)
      scalar.push_back({comp.name, &comp.normalized, false});
  } else {
    for (const auto& other : channels_) {
      if (!other.normalized.empty()) scalar.push_back({other.name, &other.normalized, false});
    }
  }
  double worst_p = std::nan(""), band = 0.0;
  QStringList per_channel;
  for (const Series& sc : scalar) {
    const auto wt = ljung_box(*sc.normalized, kLags);
    band = std::max(band, wt.band);
    if (!(wt.p_value >= worst_p)) worst_p = wt.p_value;
    per_channel << QString("%1 %2").arg(QString::fromStdString(sc.name)).arg(wt.p_value, 0, 'g', 3);
    QVector<double> l, a;
    for (std::size_t k = 1; k < wt.acf.size(); ++k) {
      if (!std::isfinite(wt.acf[k])) continue;
      l << static_cast<double>(k);
      a << wt.acf[k];
      top = std::max(top, std::abs(wt.acf[k]));
    }
    if (sc.bars) {
      lag = l;
      acf = a;
    } else {
      auto* g = plot::addGraph(acf_, QString::fromStdString(sc.name),
                               plot::color::cycle(static_cast<int>(acf_lines_.size()) + 2));
      g->setScatterStyle(QCPScatterStyle(QCPScatterStyle::ssCircle, 5));
      g->setData(l, a, true);
      acf_lines_.push_back(g);
    }
  }
  if (!scalar.empty()) {
    plot::setSeries(acf_lo_, {0.5, kLags + 0.5}, {-band, -band}, 2);
    plot::setSeries(acf_hi_, {0.5, kLags + 0.5}, {band, band}, 2);
    const QString per = c.components.empty() ? "channel" : "component";
    text += scalar.size() > 1 ? QString("; Ljung–Box p per %1: %2").arg(per, per_channel.join(", "))
                              : QString("; Ljung–Box p = %1").arg(worst_p, 0, 'g', 3);
    if (worst_p < 0.01) {
      text +=
          " — <span style='color:#a01010'>innovations not white: a tuning without truth "
          "(NLL / NIS) is not trustworthy</span>";
    }
  } else {
    acf_lo_->data()->clear();
    acf_hi_->data()->clear();
    text += "; no scalar channel to test for whiteness";
  }
  acf_bars_->setData(lag, acf, true);
  acf_bars_->setVisible(!acf.isEmpty());
  if (acf.isEmpty()) {
    acf_bars_->removeFromLegend();
  } else {
    acf_bars_->addToLegend();
  }
  acf_->xAxis->setRange(0, kLags + 1);
  acf_->yAxis->setRange(-1.15 * top, 1.3 * top);
  plot::replot(acf_);

  const bool have_nees = count_finite(nees_.nees) > 0;
  nees_plot_->setVisible(have_nees);
  if (have_nees) {
    const auto nb = nis_bounds(nees_.dof, 1);
    plot::setSeries(nees_y_, t, nees_.nees, plot::kAll);
    plot::setSeries(nees_avg_, t, moving_average_finite(nees_.nees, w), plot::kAll);
    plot::setSeries(nees_lo_, span, {nb.lo, nb.lo}, 2);
    nees_lo_->setName(QString("χ²(%1) 2.5 % / 97.5 %").arg(nees_.dof));
    plot::setSeries(nees_hi_, span, {nb.hi, nb.hi}, 2);
    plot::rescale(nees_plot_, span[0], span[1]);
    plot::replot(nees_plot_);
    text += QString("<br>NEES (%1 dof): mean %2, %3 % inside the 95 % bounds")
                .arg(nees_.dof)
                .arg(mean_finite(nees_.nees), 0, 'g', 4)
                .arg(100.0 * fraction_inside(nees_.nees, nees_.dof), 0, 'f', 1);
  }
  summary_->setText(text);
}

}  // namespace kfw
