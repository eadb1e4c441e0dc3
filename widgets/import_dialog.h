// The import dialog: opens on every Open CSV… — the separator and header row (detected, or
// chosen: the file is read again at once), a preview of the file's first rows, a small plot of
// the chosen columns, and per role (time first) a column, the unit the column is in, a scale, an
// offset and a sign flip. Starts from the guess (import.h) over the remembered mapping; shows
// what was guessed; refuses OK while a required role has no column or a column has two roles.
#pragma once

#include <QColor>
#include <QDialog>
#include <QString>
#include <QVector>
#include <memory>
#include <vector>

#include "core/dataset.h"
#include "data/mapping.h"
#include "data/table.h"

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
  // The file's format: 0 / HeaderRow::detect is "detected". Re-reads the file and the preview;
  // roles keep their columns where the new reading has them.
  void setSeparator(char sep);
  void setHeader(HeaderRow header);

  Mapping mapping() const;
  // Why OK is refused (a required role unassigned, a column assigned twice, or the import's own
  // error: a decreasing time, text in a mapped column, ...); empty when not.
  QString problem() const;
  void accept() override;

  QTableWidget* preview() const { return preview_; }
  // The file as currently read (with the chosen separator and header row).
  const Table& table() const { return *table_; }
  // "<file>: N rows, M columns, comma-separated, header on line 1" (or "no header").
  QString summary() const;
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
    QLabel* guess = nullptr;
  };
  Row* row(const std::string& role);
  QString roleProblem() const;
  void refresh();
  void reread();  // the separator or header choice changed
  void showTable(const Mapping& keep);
  void plotRows(const Mapping& m);
  void addPreviewGraph(const QVector<double>& x, const QVector<double>& y, const QString& name,
                       const QColor& c, bool dashed);

  std::shared_ptr<const Table> table_;
  std::vector<ColumnSpec> roles_;
  QComboBox* sep_ = nullptr;     // data: the separator character, 0 = detected
  QComboBox* header_ = nullptr;  // data: HeaderRow
  QLabel* info_ = nullptr;
  QLineEdit* zone_ = nullptr;  // time zone of an ISO time column without offsets
  QString read_error_;         // the file does not read with the chosen format
  QString import_error_;
  std::vector<Row> rows_;
  QTableWidget* preview_ = nullptr;
  QCustomPlot* plot_ = nullptr;
  QLabel* problem_ = nullptr;
  QPushButton* ok_ = nullptr;
};

}  // namespace kfw
