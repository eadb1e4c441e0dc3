#include "import_dialog.h"

#include <qcustomplot.h>
#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalBlocker>
#include <QTableWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "data/import.h"
#include "plot_kit.h"
#include "plot_look.h"

namespace kfw {

namespace {
QString q(const std::string& s) {
  return QString::fromStdString(s);
}
constexpr int kPreviewRows = 20;
// The preview draws the whole file, each curve reduced to its per-bucket min and max.
constexpr std::size_t kPlotBuckets = 1500;

// x, y of the whole series, at most 2 × kPlotBuckets points: the shape of a long log kept.
void envelope(const std::vector<double>& x, const std::vector<double>& y, QVector<double>& ox,
              QVector<double>& oy) {
  const std::size_t n = std::min(x.size(), y.size());
  ox.clear();
  oy.clear();
  if (n <= 2 * kPlotBuckets) {
    for (std::size_t i = 0; i < n; ++i) {
      ox << x[i];
      oy << y[i];
    }
    return;
  }
  for (std::size_t b = 0; b < kPlotBuckets; ++b) {
    const std::size_t s = b * n / kPlotBuckets, e = (b + 1) * n / kPlotBuckets;
    std::size_t lo = s, hi = s;
    for (std::size_t i = s; i < e; ++i) {
      if (y[i] < y[lo]) lo = i;
      if (y[i] > y[hi]) hi = i;
    }
    for (std::size_t i : {std::min(lo, hi), std::max(lo, hi)}) {
      ox << x[i];
      oy << y[i];
    }
  }
}

bool isTruth(const std::string& role) {
  return role.find("truth") != std::string::npos;
}
const QColor kColors[] = {QColor(31, 119, 180), QColor(214, 39, 40), QColor(44, 160, 44),
                          QColor(148, 103, 189), QColor(255, 127, 14)};

// The units a role's column may be in: those kfw converts to the role's unit (and "iso" for t).
QStringList units_for(const ColumnSpec& r) {
  QStringList u;
  for (const auto& name : known_units()) {
    if (name != r.unit && !r.unit.empty() && unit_factor(name, r.unit).ok()) u << q(name);
  }
  if (r.name == "t") u << kIsoTime;
  return u;
}

QString describe(const RoleMapping& g) {
  QString s = q(g.column);
  if (!g.unit.empty()) s += " [" + q(g.unit) + "]";
  return s;
}
}  // namespace

ImportDialog::ImportDialog(std::shared_ptr<const Table> table, const std::vector<ColumnSpec>& roles,
                           const Mapping& start, const Mapping& guess, QWidget* parent)
    : QDialog(parent), table_(std::move(table)), roles_(roles) {
  setWindowTitle("Import " + QFileInfo(q(table_->source)).fileName());
  setObjectName("importDialog");
  auto* lay = new QVBoxLayout(this);
  auto* format = new QHBoxLayout;
  sep_ = new QComboBox(this);
  sep_->setObjectName("importSeparator");
  sep_->addItem("detected", 0);
  for (char c : {',', ';', '\t', kWhitespaceSeparator})
    sep_->addItem(q(separator_key(c)), static_cast<int>(c));
  header_ = new QComboBox(this);
  header_->setObjectName("importHeader");
  header_->addItem("detected", static_cast<int>(HeaderRow::detect));
  header_->addItem("first row: column names", static_cast<int>(HeaderRow::first));
  header_->addItem("none: col1, col2, …", static_cast<int>(HeaderRow::none));
  header_->setToolTip(
      "Detected: a first row of numbers only is data (columns named col1, col2, ... by "
      "position); otherwise it names the columns.");
  sep_->setCurrentIndex(std::max(sep_->findData(static_cast<int>(start.separator)), 0));
  header_->setCurrentIndex(std::max(header_->findData(static_cast<int>(start.header)), 0));
  format->addWidget(new QLabel("Separator:"));
  format->addWidget(sep_);
  format->addSpacing(12);
  format->addWidget(new QLabel("Header:"));
  format->addWidget(header_);
  format->addStretch(1);
  lay->addLayout(format);
  info_ = new QLabel(this);
  info_->setObjectName("importInfo");
  lay->addWidget(info_);
  preview_ = new QTableWidget(this);
  preview_->setObjectName("importPreview");
  preview_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  preview_->setMaximumHeight(200);
  lay->addWidget(preview_);

  auto* grid = new QGridLayout;
  const QStringList head{"role", "column", "unit in file", "scale", "offset", "flip", "guess"};
  for (int i = 0; i < head.size(); ++i)
    grid->addWidget(new QLabel("<b>" + head[i] + "</b>"), 0, i);
  int line = 1;
  for (const auto& role : roles_with_time(roles)) {
    Row row{role};
    const QString key = q(role.name);
    row.column = new QComboBox(this);
    row.column->setObjectName("column." + key);
    row.unit = new QComboBox(this);
    row.unit->setObjectName("unit." + key);
    row.unit->addItem(role.unit.empty() ? QString("as is") : "= " + q(role.unit), QString());
    for (const auto& u : units_for(role))
      row.unit->addItem(u, u);
    row.scale = new QDoubleSpinBox(this);
    row.scale->setObjectName("scale." + key);
    row.offset = new QDoubleSpinBox(this);
    row.offset->setObjectName("offset." + key);
    for (auto* s : {row.scale, row.offset}) {
      s->setDecimals(9);
      s->setRange(-1e12, 1e12);
    }
    row.scale->setValue(1.0);
    row.flip = new QCheckBox(this);
    row.flip->setObjectName("flip." + key);
    row.guess = new QLabel(this);
    row.guess->setObjectName("guess." + key);
    QString label = key + (role.unit.empty() ? "" : " [" + q(role.unit) + "]");
    if (!role.required) label += " (optional)";
    auto* name = new QLabel(label);
    name->setToolTip(q(role.meaning));
    grid->addWidget(name, line, 0);
    grid->addWidget(row.column, line, 1);
    if (role.name == "t") {
      // iso@ZONE: an ISO time column without offsets holds local times of ZONE.
      zone_ = new QLineEdit(this);
      zone_->setObjectName("zone.t");
      zone_->setPlaceholderText("UTC, or a zone: Europe/Berlin");
      zone_->setToolTip(
          "Time zone of ISO date-times written without an offset (IANA name); "
          "daylight saving is honoured. Empty: UTC.");
      auto* unit_box = new QHBoxLayout;
      unit_box->setContentsMargins(0, 0, 0, 0);
      unit_box->addWidget(row.unit);
      unit_box->addWidget(zone_);
      grid->addLayout(unit_box, line, 2);
    } else {
      grid->addWidget(row.unit, line, 2);
    }
    grid->addWidget(row.scale, line, 3);
    grid->addWidget(row.offset, line, 4);
    grid->addWidget(row.flip, line, 5);
    grid->addWidget(row.guess, line, 6);
    ++line;
    rows_.push_back(row);
  }
  lay->addLayout(grid);
  // The house plot: its legend in a row of its own, never over the data.
  plot_ = plot::makePlot(this, "Preview", "t (s)", "value (the role's unit)");
  plot_->setObjectName("importPlot");
  plot_->setMinimumHeight(200);
  lay->addWidget(plot_, 1);
  problem_ = new QLabel(this);
  problem_->setObjectName("importProblem");
  problem_->setStyleSheet("color: #a01e14");
  problem_->setWordWrap(true);
  lay->addWidget(problem_);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
  ok_ = buttons->button(QDialogButtonBox::Ok);
  connect(buttons, &QDialogButtonBox::accepted, this, &ImportDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  lay->addWidget(buttons);

  for (auto& row : rows_) {
    auto g = guess.find(row.role.name);
    row.guess->setText(g == guess.end() ? QString("—") : describe(g->second));
  }
  showTable(start);
  for (auto& row : rows_) {
    connect(row.column, &QComboBox::currentIndexChanged, this, &ImportDialog::refresh);
    connect(row.unit, &QComboBox::currentIndexChanged, this, &ImportDialog::refresh);
    connect(row.scale, &QDoubleSpinBox::valueChanged, this, &ImportDialog::refresh);
    connect(row.offset, &QDoubleSpinBox::valueChanged, this, &ImportDialog::refresh);
    connect(row.flip, &QCheckBox::toggled, this, &ImportDialog::refresh);
  }
  if (zone_) connect(zone_, &QLineEdit::textChanged, this, &ImportDialog::refresh);
  connect(sep_, &QComboBox::currentIndexChanged, this, &ImportDialog::reread);
  connect(header_, &QComboBox::currentIndexChanged, this, &ImportDialog::reread);
  refresh();
}

QString ImportDialog::summary() const {
  const Table& t = *table_;
  return QString("<b>%1</b>: %2 rows, %3 columns, %4-separated%5, %6")
      .arg(QFileInfo(q(t.source)).fileName())
      .arg(t.rows())
      .arg(t.columns())
      .arg(q(t.separator_name()))
      .arg(t.decimal_comma ? ", decimal comma" : "")
      .arg(t.has_header() ? QString("header on line %1").arg(t.header_line)
                          : QString("no header (columns named by position: col1, col2, …)"));
}

// Fills what depends on the file's reading (preview, columns, the "detected" labels) and sets
// each role from `keep` (else the column of the role's own name, else none).
void ImportDialog::showTable(const Mapping& keep) {
  const bool sep_detected = sep_->currentData().toInt() == 0;
  sep_->setItemText(0, sep_detected ? "detected: " + q(table_->separator_name()) : "detected");
  const bool head_detected = header_->currentData().toInt() == static_cast<int>(HeaderRow::detect);
  header_->setItemText(0, !head_detected         ? QString("detected")
                          : table_->has_header() ? QString("detected: first row")
                                                 : QString("detected: none (col1, col2, …)"));
  info_->setText(summary());
  const int nrows = static_cast<int>(std::min<std::size_t>(table_->rows(), kPreviewRows));
  preview_->clear();
  preview_->setRowCount(nrows);
  preview_->setColumnCount(static_cast<int>(table_->columns()));
  QStringList headers;
  for (const auto& n : table_->names)
    headers << q(n);
  preview_->setHorizontalHeaderLabels(headers);
  for (int r = 0; r < nrows; ++r) {
    for (int c = 0; c < static_cast<int>(table_->columns()); ++c) {
      preview_->setItem(r, c,
                        new QTableWidgetItem(q(table_->cell(static_cast<std::size_t>(r),
                                                            static_cast<std::size_t>(c)))));
    }
  }
  preview_->resizeColumnsToContents();
  for (auto& row : rows_) {
    const QSignalBlocker block(row.column);
    row.column->clear();
    row.column->addItem("(none)", QString());
    for (const auto& n : table_->names)
      row.column->addItem(q(n), q(n));
  }
  for (const auto& row : rows_) {
    auto it = keep.find(row.role.name);
    RoleMapping m;
    if (it != keep.end())
      m = it->second;
    else if (table_->index(row.role.name) >= 0)
      m.column = row.role.name;
    setColumn(row.role.name, m.column);
    setUnit(row.role.name, m.unit);
    setScale(row.role.name, m.scale);
    setOffset(row.role.name, m.offset);
    setFlip(row.role.name, m.flip);
  }
}

void ImportDialog::reread() {
  Mapping keep = mapping();
  auto t = read_table(table_->source, keep.table_options());
  if (!t) {
    read_error_ = q(t.error());
    refresh();
    return;
  }
  read_error_.clear();
  table_ = std::make_shared<const Table>(std::move(*t));
  // Roles keep their columns where the new reading has them, else take the new guess.
  const Mapping guess = guess_mapping(*table_, roles_);
  for (auto& row : rows_) {
    const std::string& role = row.role.name;
    auto g = guess.find(role);
    row.guess->setText(g == guess.end() ? QString("—") : describe(g->second));
    auto k = keep.find(role);
    if (k != keep.end() && table_->index(k->second.column) >= 0) continue;
    if (g != guess.end())
      keep[role] = g->second;
    else if (k != keep.end())
      keep.erase(k);
  }
  {
    std::vector<QSignalBlocker> blocks;
    for (auto& row : rows_) {
      blocks.emplace_back(row.column);
      blocks.emplace_back(row.unit);
      blocks.emplace_back(row.scale);
      blocks.emplace_back(row.offset);
      blocks.emplace_back(row.flip);
    }
    if (zone_) blocks.emplace_back(zone_);
    showTable(keep);
  }
  refresh();
}

void ImportDialog::setSeparator(char sep) {
  sep_->setCurrentIndex(std::max(sep_->findData(static_cast<int>(sep)), 0));
}

void ImportDialog::setHeader(HeaderRow header) {
  header_->setCurrentIndex(std::max(header_->findData(static_cast<int>(header)), 0));
}

ImportDialog::Row* ImportDialog::row(const std::string& role) {
  for (auto& r : rows_) {
    if (r.role.name == role) return &r;
  }
  return nullptr;
}

void ImportDialog::setColumn(const std::string& role, const std::string& column) {
  if (Row* r = row(role)) {
    const int i = r->column->findData(q(column));
    r->column->setCurrentIndex(std::max(i, 0));
  }
}

void ImportDialog::setUnit(const std::string& role, const std::string& unit) {
  if (Row* r = row(role)) {
    if (zone_ && role == "t") zone_->setText(q(iso_zone(unit)));
    const std::string base = is_iso_unit(unit) ? std::string(kIsoTime) : unit;
    const bool same = base.empty() || base == r->role.unit;
    const int i = same ? 0 : r->unit->findData(q(base));
    r->unit->setCurrentIndex(std::max(i, 0));
  }
}

void ImportDialog::setScale(const std::string& role, double scale) {
  if (Row* r = row(role)) r->scale->setValue(scale);
}

void ImportDialog::setOffset(const std::string& role, double offset) {
  if (Row* r = row(role)) r->offset->setValue(offset);
}

void ImportDialog::setFlip(const std::string& role, bool flip) {
  if (Row* r = row(role)) r->flip->setChecked(flip);
}

Mapping ImportDialog::mapping() const {
  Mapping m;
  m.separator = static_cast<char>(sep_->currentData().toInt());
  m.header = static_cast<HeaderRow>(header_->currentData().toInt());
  for (const auto& r : rows_) {
    const std::string col = r.column->currentData().toString().toStdString();
    if (col.empty()) continue;
    RoleMapping rm;
    rm.column = col;
    rm.unit = r.unit->currentData().toString().toStdString();
    if (zone_ && r.role.name == "t" && rm.unit == kIsoTime && !zone_->text().trimmed().isEmpty()) {
      rm.unit += "@" + zone_->text().trimmed().toStdString();
    }
    rm.scale = r.scale->value();
    rm.offset = r.offset->value();
    rm.flip = r.flip->isChecked();
    m[r.role.name] = rm;
  }
  return m;
}

QString ImportDialog::problem() const {
  if (!read_error_.isEmpty()) return read_error_;
  const QString p = roleProblem();
  return p.isEmpty() ? import_error_ : p;
}

QString ImportDialog::roleProblem() const {
  std::map<std::string, std::string> owner;
  for (const auto& r : rows_) {
    const std::string col = r.column->currentData().toString().toStdString();
    if (col.empty()) {
      if (r.role.required) return "choose a column for '" + q(r.role.name) + "' (required)";
      continue;
    }
    if (auto [it, fresh] = owner.emplace(col, r.role.name); !fresh) {
      return "column '" + q(col) + "' is assigned to both '" + q(it->second) + "' and '" +
             q(r.role.name) + "'";
    }
    if (r.scale->value() == 0.0) return "the scale of '" + q(r.role.name) + "' is 0";
  }
  return {};
}

void ImportDialog::accept() {
  if (!problem().isEmpty()) return;  // OK is refused; the reason is shown
  QDialog::accept();
}

void ImportDialog::refresh() {
  const Mapping m = mapping();
  if (Row* t = row("t"); t && zone_) {
    zone_->setEnabled(t->unit->currentData().toString() == QString(kIsoTime));
  }
  import_error_.clear();
  plot_->clearGraphs();
  std::optional<Dataset> d;
  if (roleProblem().isEmpty()) {
    // The import itself (what OK will load): its error refuses OK, its data are plotted.
    auto imported = import_table(*table_, m, roles_);
    if (imported) {
      if (auto st = require_some_value(*imported, roles_); !st) imported = st.err();
    }
    if (imported) {
      d = std::move(*imported);
    } else {
      import_error_ = q(imported.error());
    }
  }
  const QString why = problem();
  problem_->setText(why);
  ok_->setEnabled(why.isEmpty());
  if (d) {
    const auto& t = d->col("t");
    // Truth last, dashed, on top: it was hidden under the measurement it follows.
    std::vector<const ColumnSpec*> order;
    for (const auto& r : roles_) {
      if (r.name != "t" && m.count(r.name) && d->index(r.name) >= 0 && !isTruth(r.name))
        order.push_back(&r);
    }
    for (const auto& r : roles_) {
      if (m.count(r.name) && d->index(r.name) >= 0 && isTruth(r.name)) order.push_back(&r);
    }
    int k = 0;
    for (const ColumnSpec* r : order) {
      QVector<double> x, y;
      envelope(t, d->col(r->name), x, y);
      addPreviewGraph(x, y, q(r->name) + (r->unit.empty() ? "" : " (" + q(r->unit) + ")"),
                      isTruth(r->name) ? plot::color::kTruth : kColors[k++ % 5], isTruth(r->name));
    }
    plot_->xAxis->setLabel("t (s)");
    const double span = t.empty() ? 0.0 : t.back() - t.front();
    setTitle(plot_, QString("Preview: the whole file, %1 s in %2 rows")
                        .arg(span, 0, 'f', span < 10 ? 2 : 1)
                        .arg(t.size()));
  } else {
    plotRows(m);
  }
  plot_->rescaleAxes();
  plot_->replot();
}

// Before the mapping imports: each mapped role's column (converted) over the row number.
void ImportDialog::plotRows(const Mapping& m) {
  int k = 0;
  for (const auto& r : rows_) {
    auto it = m.find(r.role.name);
    if (r.role.name == "t" || it == m.end()) continue;
    const int c = table_->index(it->second.column);
    if (c < 0) continue;
    const auto& v = table_->values[static_cast<std::size_t>(c)];
    double f = 1.0;
    if (auto u = unit_factor(it->second.unit, r.role.unit); u) f = *u;
    const double sign = it->second.flip ? -1.0 : 1.0;
    std::vector<double> rows(v.size()), y(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      rows[i] = static_cast<double>(i + 1);
      y[i] = sign * (it->second.scale * (f * v[i]) + it->second.offset);
    }
    QVector<double> ox, oy;
    envelope(rows, y, ox, oy);
    addPreviewGraph(ox, oy,
                    q(r.role.name) + (r.role.unit.empty() ? "" : " (" + q(r.role.unit) + ")"),
                    kColors[k++ % 5], false);
  }
  plot_->xAxis->setLabel("row");
  setTitle(
      plot_,
      QString("Preview: the whole file by row (%1 rows; no time read yet)").arg(table_->rows()));
}

void ImportDialog::addPreviewGraph(const QVector<double>& x, const QVector<double>& y,
                                   const QString& name, const QColor& c, bool dashed) {
  auto* g = plot::addGraph(plot_, name, c, dashed ? plot::Style::kDashed : plot::Style::kLine);
  g->setData(x, y, true);
}

}  // namespace kfw
