#include "data_tab.h"

#include <qcustomplot.h>

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QVBoxLayout>

namespace kfw {

namespace {
QString q(const std::string& s) {
  return QString::fromStdString(s);
}
}  // namespace

DataTab::DataTab(QWidget* parent) : QWidget(parent) {
  auto* lay = new QVBoxLayout(this);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("Column:"));
  column_ = new QComboBox;
  column_->setObjectName("dataColumn");
  row->addWidget(column_, 1);
  lay->addLayout(row);
  plot_ = new QCustomPlot;
  plot_->setObjectName("dataPlot");
  plot_->xAxis->setLabel("t [s]");
  lay->addWidget(plot_, 1);
  connect(column_, &QComboBox::currentIndexChanged, this, [this] { plotColumn(); });
}

void DataTab::setDataset(std::shared_ptr<const Dataset> dataset) {
  if (dataset == data_) return;
  data_ = std::move(dataset);
  const QString keep = column_->currentText();
  column_->blockSignals(true);
  column_->clear();
  if (data_) {
    for (const auto& n : data_->names) {
      if (n != "t") column_->addItem(q(n));
    }
  }
  const int i = column_->findText(keep);
  column_->setCurrentIndex(i >= 0 ? i : 0);
  column_->blockSignals(false);
  plotColumn();
}

void DataTab::plotColumn() {
  plot_->clearGraphs();
  const std::string name = column_->currentText().toStdString();
  if (data_ && data_->has("t") && data_->has(name)) {
    const auto& t = data_->col("t");
    const auto& v = data_->col(name);
    QVector<double> x(static_cast<int>(t.size())), y(static_cast<int>(t.size()));
    std::copy(t.begin(), t.end(), x.begin());
    std::copy(v.begin(), v.end(), y.begin());
    auto* g = plot_->addGraph();
    g->setData(x, y, true);
    g->setName(q(name));
    plot_->yAxis->setLabel(q(name));
    plot_->xAxis->setLabel(data_->time_origin.empty() ? QString("t [s]")
                                                      : "t [s] from " + q(data_->time_origin));
  }
  plot_->rescaleAxes();
  plot_->replot();
}

}  // namespace kfw
