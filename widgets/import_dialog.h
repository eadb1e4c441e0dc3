// The import dialog: opens on every Open CSV… — a preview of the file's first rows, a small plot
// of the chosen columns, and per role (time first) a column, the unit the column is in, a scale,
// an offset and a sign flip. Starts from the guess (import.h) over the remembered mapping; shows
// what was guessed; refuses OK while a required role has no column or a column has two roles.
#pragma once

#include <QDialog>
#include <QString>
#include <memory>
#include <vector>

#include "core/dataset.h"
#include "core/mapping.h"
#include "core/table.h"

class QCheckBox;
class QComboBox;
class QCustomPlot;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QTableWidget;

namespace kfw {

class ImportDialog : public QDialog {
  Q_OBJECT
 public:
  // `roles` without "t" (time is added first); `start` the mapping shown, `guess` the guesser's.
  ImportDialog(std::shared_ptr<const Table> table, const std::vector<ColumnSpec>& roles,
               const Mapping& start, const Mapping& guess, QWidget* parent = nullptr);

  // What a user does, role by role ("t" is time). An empty column is "none"; an empty unit is
  // "already in the role's unit".
  void setColumn(const std::string& role, const std::string& column);
  void setUnit(const std::string& role, const std::string& unit);
  void setScale(const std::string& role, double scale);
  void setOffset(const std::string& role, double offset);
  void setFlip(const std::string& role, bool flip);

  Mapping mapping() const;
  // Why OK is refused (a required role unassigned, a column assigned twice, or the import's own
  // error: a decreasing time, text in a mapped column, ...); empty when not.
  QString problem() const;
  void accept() override;

  QTableWidget* preview() const { return preview_; }
  // The mapped roles over time (converted, as they will load; over the row number until the
  // mapping imports).
  QCustomPlot* plot() const { return plot_; }
  QPushButton* okButton() const { return ok_; }

 private:
  struct Row {
    ColumnSpec role;
    QComboBox* column = nullptr;
    QComboBox* unit = nullptr;
    QDoubleSpinBox* scale = nullptr;
    QDoubleSpinBox* offset = nullptr;
    QCheckBox* flip = nullptr;
  };
  Row* row(const std::string& role);
  QString roleProblem() const;
  void refresh();
  void plotRows(const Mapping& m);

  std::shared_ptr<const Table> table_;
  std::vector<ColumnSpec> roles_;
  QLineEdit* zone_ = nullptr;  // time zone of an ISO time column without offsets
  QString import_error_;
  std::vector<Row> rows_;
  QTableWidget* preview_ = nullptr;
  QCustomPlot* plot_ = nullptr;
  QLabel* problem_ = nullptr;
  QPushButton* ok_ = nullptr;
};

}  // namespace kfw
