// The Data tab: any column of the plots' dataset over time (the raw file or the simulation).
#pragma once

#include <QWidget>
#include <memory>

#include "core/dataset.h"

class QComboBox;
class QCustomPlot;

namespace kfw {

class DataTab : public QWidget {
  Q_OBJECT
 public:
  explicit DataTab(QWidget* parent = nullptr);
  // The dataset to show; the chosen column stays when the new one has it. Cheap when unchanged.
  void setDataset(std::shared_ptr<const Dataset> dataset);
  QComboBox* columnCombo() const { return column_; }
  QCustomPlot* plot() const { return plot_; }

 private:
  void plotColumn();

  QComboBox* column_ = nullptr;
  QCustomPlot* plot_ = nullptr;
  std::shared_ptr<const Dataset> data_;
};

}  // namespace kfw
