// The metrics table: the primary metric first and highlighted, then the metrics grouped as their
// declarations group them (accuracy, consistency, gains, scenario), each row the label and unit
// with the description as a tooltip, values to four significant digits with a good/bad mark
// where the declaration has bounds, one column per pinned snapshot. Nothing here knows a
// metric by name: everything comes from describe_metric() / shared_metric_specs().
#pragma once

#include <QList>
#include <QPair>
#include <QString>
#include <QStringList>
#include <QTableWidget>
#include <memory>
#include <string>

#include "core/scenario.h"

namespace kfw {

class MetricsPanel : public QTableWidget {
  Q_OBJECT
 public:
  // Item data: the metric key (name column), the exact value (value columns), the group name
  // (group header rows, which span the table and have no key).
  static constexpr int kKeyRole = Qt::UserRole;
  static constexpr int kValueRole = Qt::UserRole + 1;
  static constexpr int kGroupRole = Qt::UserRole + 2;
  static constexpr int kPrimaryRole = Qt::UserRole + 3;

  explicit MetricsPanel(QWidget* parent = nullptr);

  using Columns = QList<QPair<QString, std::shared_ptr<const RunResult>>>;
  // Fills the table from the live run and the snapshots' runs. `primary`: the metric to put
  // first (the last tuning's objective); empty or not reported: the first declared shared
  // metric the live run reports.
  void setRuns(const Scenario& scenario, std::shared_ptr<const RunResult> live,
               const Columns& snapshots, const std::string& primary);
  // The metric shown first, "" before a run.
  QString primaryKey() const { return primary_; }
  // The last row of the primary metric's group (the rows a user must see without scrolling:
  // the primary, the groups before its own, its own group); -1 before a run.
  int primaryGroupEnd() const;
  // The table's height (header, frame) that shows rows 0..row whole at the current column widths.
  int heightThrough(int row) const;
  // Four significant digits, no trailing zeros ("0.01235", "1.235e+06").
  static QString format(double v);

 protected:
  // The primary row's and the group headers' fonts follow the table's (presentation's scale in
  // and out; they are set per item, so they do not follow by themselves).
  void changeEvent(QEvent* event) override;

 private:
  void styleItems();
  QString primary_;
  QStringList layout_;     // headers, primary key and row keys of the table as built
  QString primary_group_;  // group_name() of the primary's group
};

}  // namespace kfw
