// Maps a CSV's columns to the scenario's roles (gyro, angle, truth, ...) when the names differ.
#pragma once

#include <QDialog>
#include <QList>

#include "core/dataset.h"
#include "core/session.h"

class QComboBox;

namespace kfw {

class ColumnMapDialog : public QDialog {
  Q_OBJECT
 public:
  ColumnMapDialog(const std::vector<ColumnSpec>& roles, const Dataset& file, const ColumnMap& guess,
                  QWidget* parent = nullptr);
  ColumnMap mapping() const;

 private:
  std::vector<ColumnSpec> roles_;
  QList<QComboBox*> combos_;
};

}  // namespace kfw
