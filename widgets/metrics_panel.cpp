#include "metrics_panel.h"

#include <QBrush>
#include <QColor>
#include <QEvent>
#include <QFont>
#include <QHash>
#include <QHeaderView>
#include <QPainter>
#include <QPixmap>
#include <QScrollBar>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "plot_text.h"

namespace kfw {

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// Where a key is declared: the shared vocabulary first (its order), then the scenario's own.
int declaredIndex(const Scenario& s, const std::string& key) {
  const auto& shared = shared_metric_specs();
  for (std::size_t i = 0; i < shared.size(); ++i) {
    const std::string& k = shared[i].key;
    const auto lt = k.find('<');
    if (lt == std::string::npos ? k == key : key.size() > lt && key.compare(0, lt, k, 0, lt) == 0) {
      return static_cast<int>(i);
    }
  }
  const auto own = s.metric_specs();
  for (std::size_t i = 0; i < own.size(); ++i) {
    if (own[i].key == key) return 1000 + static_cast<int>(i);
  }
  return 100000;
}

// The good/bad marks, drawn once.
QIcon mark(bool good) {
  static const auto draw = [](const QColor& c) {
    QPixmap pm(10, 10);
    pm.fill(Qt::transparent);
    QPainter p(&pm);
    p.setRenderHint(QPainter::Antialiasing);
    p.setPen(Qt::NoPen);
    p.setBrush(c);
    p.drawEllipse(1, 1, 8, 8);
    return QIcon(pm);
  };
  static const QIcon good_icon = draw(QColor(40, 150, 60)), bad_icon = draw(QColor(190, 40, 30));
  return good ? good_icon : bad_icon;
}

QString bounds(const MetricSpec& spec) {
  return QString("[%1, %2]")
      .arg(spec.good_lo ? MetricsPanel::format(*spec.good_lo) : QString("−∞"),
           spec.good_hi ? MetricsPanel::format(*spec.good_hi) : QString("∞"));
}

// Sets a value cell from a run. Only what differs is set (an unchanged cell is not repainted,
// and the table's re-runs during a slider drag cost only the cells that changed).
constexpr int kVerdictRole = Qt::UserRole + 10;
void setValue(QTableWidgetItem* item, const RunResult* r, const MetricSpec& spec) {
  QString text, tip, verdict;
  QVariant value;
  if (!r) {
    text = "–";
    tip = "no run";
  } else if (auto it = r->metrics.find(spec.key); it == r->metrics.end()) {
    text = "—";
    auto u = r->undefined.find(spec.key);
    tip = u == r->undefined.end() ? "not reported" : "undefined: " + q(u->second);
  } else {
    const double v = it->second;
    text = MetricsPanel::format(v);
    value = v;
    tip = QString::number(v, 'g', 10);
    verdict = q(judge(spec, v));
    if (!verdict.isEmpty()) {
      const bool good = verdict == "good";
      tip += QString(" · %1: %2 %3").arg(verdict, good ? "inside" : "outside", bounds(spec));
    }
  }
  if (item->text() != text) item->setText(text);
  if (item->toolTip() != tip) item->setToolTip(tip);
  item->setData(MetricsPanel::kValueRole, value);
  if (item->data(kVerdictRole).toString() != verdict || !item->data(kVerdictRole).isValid()) {
    item->setData(kVerdictRole, verdict);
    // No mark: no decoration data at all (a null QIcon still reserves the decoration's room).
    item->setData(Qt::DecorationRole,
                  verdict.isEmpty() ? QVariant() : QVariant(mark(verdict == "good")));
    item->setData(Qt::ForegroundRole,
                  verdict == "bad" ? QVariant(QBrush(QColor(170, 30, 20))) : QVariant());
  }
}

QTableWidgetItem* valueItem(const RunResult* r, const MetricSpec& spec) {
  auto* item = new QTableWidgetItem;
  item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
  setValue(item, r, spec);
  return item;
}

}  // namespace

MetricsPanel::MetricsPanel(QWidget* parent) : QTableWidget(0, 2, parent) {
  setObjectName("metrics");
  setHorizontalHeaderLabels({"metric", "live"});
  verticalHeader()->setVisible(false);
  // Compact rows; a name too long for its column wraps instead of being cut ("nees_in_bou…").
  verticalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  verticalHeader()->setMinimumSectionSize(fontMetrics().height() + 2);
  setWordWrap(true);
  setTextElideMode(Qt::ElideNone);
  horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
  setEditTriggers(QAbstractItemView::NoEditTriggers);
  setSelectionMode(QAbstractItemView::NoSelection);
  setFocusPolicy(Qt::NoFocus);
  setMinimumHeight(120);
}

QString MetricsPanel::format(double v) {
  if (v == 0.0) return "0";
  const double a = std::abs(v);
  if (a >= 1e-3 && a < 1e5) {
    // Fixed notation with four significant digits, trailing zeros dropped.
    const int decimals = std::max(0, 3 - static_cast<int>(std::floor(std::log10(a))));
    QString s = QString::number(v, 'f', decimals);
    if (s.contains('.')) {
      while (s.endsWith('0'))
        s.chop(1);
      if (s.endsWith('.')) s.chop(1);
    }
    return s;
  }
  return QString::number(v, 'g', 4);
}

void MetricsPanel::setRuns(const Scenario& scenario, std::shared_ptr<const RunResult> live,
                           const Columns& snapshots, const std::string& primary) {
  QStringList headers{"metric", "live"};
  for (const auto& c : snapshots)
    headers << c.first;
  setColumnCount(static_cast<int>(headers.size()));
  setHorizontalHeaderLabels(headers);
  for (int c = 1; c < columnCount(); ++c)
    horizontalHeader()->setSectionResizeMode(c, QHeaderView::ResizeToContents);
  if (!live) {
    setRowCount(0);
    primary_.clear();
    layout_.clear();
    return;
  }
  struct Row {
    MetricSpec spec;
    int order;
  };
  std::vector<Row> rows;
  for (const auto& [k, x] : live->metrics)
    rows.push_back({describe_metric(scenario, k, live.get()), declaredIndex(scenario, k)});
  for (const auto& [k, why] : live->undefined)
    rows.push_back({describe_metric(scenario, k, live.get()), declaredIndex(scenario, k)});
  std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
    if (a.spec.group != b.spec.group) return a.spec.group < b.spec.group;
    if (a.order != b.order) return a.order < b.order;
    return a.spec.key < b.spec.key;
  });
  // The primary metric: the one asked for when the run reports it, else the first declared
  // shared metric it reports.
  std::string first;
  if (!primary.empty() && live->metrics.count(primary)) {
    first = primary;
  } else {
    for (const auto& spec : shared_metric_specs()) {
      if (spec.key.find('<') == std::string::npos && live->metrics.count(spec.key)) {
        first = spec.key;
        break;
      }
    }
  }
  primary_ = q(first);

  // The same rows and columns as the last call (a re-run with new values): update the value
  // cells in place.
  QStringList layout = headers;
  layout << primary_;
  for (const auto& r : rows)
    layout << q(r.spec.key);
  if (layout == layout_ && rowCount() > 0) {
    // One change notice for the whole update: the headers fit their sections to the contents
    // once, not once per changed cell (each notice re-measures every row).
    model()->blockSignals(true);
    QHash<QString, const MetricSpec*> specs;
    for (const auto& r : rows)
      specs.insert(q(r.spec.key), &r.spec);
    for (int row = 0; row < rowCount(); ++row) {
      const QTableWidgetItem* name = item(row, 0);
      const MetricSpec* spec = name ? specs.value(name->data(kKeyRole).toString()) : nullptr;
      if (!spec) continue;  // a group header
      setValue(item(row, 1), live.get(), *spec);
      for (int j = 0; j < snapshots.size(); ++j)
        setValue(item(row, 2 + j), snapshots[j].second.get(), *spec);
    }
    model()->blockSignals(false);
    emit model()->dataChanged(model()->index(0, 1),
                              model()->index(rowCount() - 1, columnCount() - 1));
    return;
  }
  layout_ = layout;

  setRowCount(0);                                  // drops the old items and spans
  setRowCount(static_cast<int>(rows.size()) + 4);  // + one header per group at most

  auto nameItem = [](const MetricSpec& spec) {
    QString label = plot::typeset(q(spec.label));
    if (!spec.unit.empty()) label = plot::withUnit(label, spec.unit);
    auto* name = new QTableWidgetItem(label);
    name->setData(kKeyRole, q(spec.key));
    QString sense = QString(direction_name(spec.direction)) + " is better";
    if (spec.direction == Direction::kTarget) sense = "target " + format(spec.target);
    if (spec.direction == Direction::kNone) sense = "informational";
    QString tip = "<b>" + q(spec.key) + "</b> · " + group_name(spec.group) + " · " + sense;
    if (spec.good_lo || spec.good_hi) tip += " · good inside " + bounds(spec);
    if (!spec.description.empty()) tip += "<br>" + q(spec.description).toHtmlEscaped();
    name->setToolTip(tip);
    return name;
  };
  auto fill = [&](int row, const MetricSpec& spec) {
    setItem(row, 0, nameItem(spec));
    setItem(row, 1, valueItem(live.get(), spec));
    for (int j = 0; j < snapshots.size(); ++j)
      setItem(row, 2 + j, valueItem(snapshots[j].second.get(), spec));
  };
  int row = 0;
  for (const auto& r : rows) {
    if (r.spec.key != first) continue;
    fill(row, r.spec);
    for (int c = 0; c < columnCount(); ++c) {
      QTableWidgetItem* it = item(row, c);
      it->setBackground(QColor(255, 244, 196));
      it->setData(kPrimaryRole, true);
    }
    item(row, 0)->setToolTip("★ primary (the tuned objective, else the first declared metric)<br>" +
                             item(row, 0)->toolTip());
    item(row, 0)->setText("★ " + item(row, 0)->text());
    ++row;
  }
  std::optional<MetricGroup> group;
  for (const auto& r : rows) {
    const MetricSpec& spec = r.spec;
    if (spec.key == first) continue;
    if (group != spec.group) {
      group = spec.group;
      // A group header: the group's name across the table.
      auto* head = new QTableWidgetItem(QString(group_name(spec.group)).toUpper());
      head->setData(kGroupRole, QString(group_name(spec.group)));
      head->setForeground(QColor(90, 90, 90));
      head->setBackground(QColor(236, 236, 236));
      head->setToolTip(QString("%1 metrics").arg(group_name(spec.group)));
      setItem(row, 0, head);
      if (columnCount() > 1) setSpan(row, 0, 1, columnCount());
      ++row;
    }
    fill(row, spec);
    ++row;
  }
  setRowCount(row);
  styleItems();
  primary_group_.clear();
  for (const auto& r : rows) {
    if (r.spec.key == first) primary_group_ = group_name(r.spec.group);
  }
}

void MetricsPanel::styleItems() {
  QFont bold = font();
  bold.setBold(true);
  QFont head = bold;
  head.setPointSizeF(bold.pointSizeF() * 0.85);
  for (int r = 0; r < rowCount(); ++r) {
    for (int c = 0; c < columnCount(); ++c) {
      QTableWidgetItem* it = item(r, c);
      if (!it) continue;
      if (it->data(kPrimaryRole).toBool()) {
        it->setFont(bold);
      } else if (it->data(kGroupRole).isValid()) {
        it->setFont(head);
      }
    }
  }
}

void MetricsPanel::changeEvent(QEvent* event) {
  QTableWidget::changeEvent(event);
  if (event->type() == QEvent::FontChange) styleItems();
}

int MetricsPanel::primaryGroupEnd() const {
  if (rowCount() == 0) return -1;
  int end = 0;
  bool inside = false;
  for (int r = 1; r < rowCount(); ++r) {
    const QVariant g = item(r, 0) ? item(r, 0)->data(kGroupRole) : QVariant();
    if (g.isValid()) {
      if (inside) break;  // the next group's header
      inside = g.toString() == primary_group_;
      if (!inside) continue;
    }
    if (inside) end = r;
  }
  return end;
}

int MetricsPanel::heightThrough(int row) const {
  int h = 2 * frameWidth() + (horizontalHeader()->isVisible() ? horizontalHeader()->height() : 0);
  for (int r = 0; r <= row && r < rowCount(); ++r)
    h += std::max({rowHeight(r), sizeHintForRow(r), verticalHeader()->minimumSectionSize()});
  if (horizontalScrollBar()->isVisible()) h += horizontalScrollBar()->height();
  return h;
}

}  // namespace kfw
