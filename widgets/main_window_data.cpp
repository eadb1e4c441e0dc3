// MainWindow, the data side: opening a CSV through the import dialog, the Data menu (mapping,
// forget, save as kfw CSV), the Data tab (any raw column over time) and the data label that says
// honestly whether the plots show the file. Mapping changes go through the Document (undoable).
#include <qcustomplot.h>

#include <QComboBox>
#include <QCryptographicHash>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QSettings>
#include <QTabWidget>
#include <QVBoxLayout>
#include <filesystem>

#include "data/csv.h"
#include "data/import.h"
#include "document/workspace.h"
#include "import_dialog.h"
#include "main_window.h"
#include "param_panel.h"
#include "run_controller.h"

namespace kfw {

namespace {
QString q(const std::string& s) {
  return QString::fromStdString(s);
}

// Mappings are remembered per header (the column names in order), as the preset's block.
QString mapKey(const Table& t) {
  std::string k;
  for (const auto& n : t.names)
    k += (k.empty() ? "" : ",") + n;
  return "columnMaps/" +
         QCryptographicHash::hash(QByteArray::fromStdString(k), QCryptographicHash::Md5).toHex();
}

std::optional<Mapping> remembered(const Table& t) {
  const QString text = QSettings("kfw", "kfw").value(mapKey(t)).toString();
  if (text.isEmpty()) return std::nullopt;
  auto j = nlohmann::json::parse(text.toStdString(), nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  auto m = mapping_from_json(j, "remembered mapping");
  if (!m) return std::nullopt;
  return *m;
}

void remember(const Table& t, const Mapping& m) {
  QSettings("kfw", "kfw").setValue(mapKey(t), q(mapping_to_json(m).dump()));
}
}  // namespace

Expected<Dataset> MainWindow::readMapped(const QString& path, const Mapping* map, Mapping& used) {
  const std::string file = path.toStdString();
  // Read with the given mapping's format (separator, header row), else the preset's; a mapping
  // remembered for the file's header may choose another, and the file is then read again.
  used = map ? *map : doc_->preset().mapping;
  auto table = read_table(file, used.table_options());
  const bool ask = !map && (interactive_ || import_hook_);
  if (!table && ask && !Mapping{}.same_format(used)) {
    used.separator = 0;  // the dialog starts from the detected format
    used.header = HeaderRow::detect;
    table = read_table(file);
  }
  if (!table) return table.err();
  auto shared = std::make_shared<const Table>(std::move(*table));
  if (map) {
    auto d = import_dataset(*scenario_, *shared, used);
    if (d && !map->blank()) remember(*shared, used);
    return d;
  }
  if (auto r = remembered(*shared)) {
    const Mapping before = used;
    used.override_with(*r);
    if (!before.same_format(used)) {
      auto again = read_table(file, used.table_options());
      if (!again) return again.err();
      shared = std::make_shared<const Table>(std::move(*again));
    }
  }
  if (!interactive_ && !import_hook_) return import_dataset(*scenario_, *shared, used);
  // The dialog starts from the guess, overridden by the preset's and the remembered mapping.
  const Mapping guess = guess_mapping(*shared, scenario_->columns());
  Mapping start = guess;
  start.override_with(used);
  ImportDialog dialog(shared, scenario_->columns(), start, guess, this);
  const bool accepted = import_hook_ ? import_hook_(dialog) && dialog.problem().isEmpty()
                                     : dialog.exec() == QDialog::Accepted;
  if (!accepted) return Error{file + ": import cancelled", kExitOk};  // exit 0: not a failure
  used = dialog.mapping();  // the file as the dialog last read it (its separator and header)
  auto d = import_dataset(*scenario_, dialog.table(), used);
  if (d) remember(dialog.table(), used);
  return d;
}

Status MainWindow::openDataset(const QString& path) {
  return openFile(path, nullptr);
}

Status MainWindow::openDatasetMapped(const QString& path, const ColumnMap& map) {
  const Mapping m = to_mapping(map);
  return openFile(path, &m);
}

Status MainWindow::openDatasetMapped(const QString& path, const Mapping& map) {
  return openFile(path, &map);
}

Status MainWindow::openFile(const QString& path, const Mapping* map) {
  if (!scenario_) return Error{"load a preset first"};
  Mapping used;
  auto ds = readMapped(path, map, used);
  if (!ds) {
    if (ds.exit_code() == kExitOk) return Ok{};  // the dialog was cancelled: nothing changes
    showError(q(ds.error()));
    return ds.err();
  }
  file_data_ = std::make_shared<const Dataset>(std::move(*ds));
  loaded_data_ = DataRef{path.toStdString(), used};
  doc_->set_data(loaded_data_);
  runner_->setFileDataset(file_data_);
  clearError();
  updateDataLabel();
  updateUndoActions();
  requestRun();
  return Ok{};
}

Status MainWindow::editMapping() {
  if (!doc_ || !doc_->data()) return Error{"no file loaded (the data are simulated)"};
  const DataRef current = *doc_->data();
  auto table = read_table(current.path, current.mapping.table_options());
  if (!table) return table.err();
  const auto shared = std::make_shared<const Table>(std::move(*table));
  ImportDialog dialog(shared, scenario_->columns(), current.mapping,
                      guess_mapping(*shared, scenario_->columns()), this);
  const bool accepted = import_hook_ ? import_hook_(dialog) && dialog.problem().isEmpty()
                                     : dialog.exec() == QDialog::Accepted;
  if (!accepted) return Ok{};
  const Mapping m = dialog.mapping();
  auto d = import_dataset(*scenario_, dialog.table(), m);
  if (!d) {
    showError(q(d.error()));
    return d.err();
  }
  if (auto st = doc_->set_mapping(m); !st) return st;
  remember(dialog.table(), m);
  syncFromDocument();  // reads the file with the new mapping; undo restores the old one
  return Ok{};
}

Status MainWindow::forgetMapping() {
  if (!doc_ || !doc_->data()) return Error{"no file loaded (the data are simulated)"};
  auto table = read_table(doc_->data()->path, doc_->data()->mapping.table_options());
  if (!table) return table.err();
  QSettings("kfw", "kfw").remove(mapKey(*table));
  status_->setText("Forgot the mapping remembered for " +
                   QFileInfo(q(doc_->data()->path)).fileName() +
                   "'s header; the next Open CSV starts from the guess.");
  return Ok{};
}

Status MainWindow::saveConvertedCsv(const QString& path) const {
  if (!file_data_) return Error{"no file loaded (the data are simulated)"};
  std::error_code ec;
  if (std::filesystem::equivalent(path.toStdString(), file_data_->source, ec)) {
    return Error{path.toStdString() + ": is the file the data were read from; choose another"};
  }
  return write_csv_file(path.toStdString(), *file_data_);
}

void MainWindow::setImportHook(std::function<bool(ImportDialog&)> hook) {
  import_hook_ = std::move(hook);
}

void MainWindow::buildDataMenu() {
  QMenu* menu = menuBar()->addMenu("&Data");
  auto report = [this](const char* title, const Status& st) {
    if (!st) QMessageBox::warning(this, title, q(st.error()));
  };
  menu->addAction("&Mapping…", this, [this, report] { report("Mapping", editMapping()); });
  menu->addAction("&Forget remembered mapping", this,
                  [this, report] { report("Forget mapping", forgetMapping()); });
  menu->addAction("&Save as kfw CSV…", this, [this, report] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save as kfw CSV", QString(), "CSV (*.csv)");
    if (!f.isEmpty()) report("Save as kfw CSV", saveConvertedCsv(f));
  });
}

void MainWindow::buildDataTab(QTabWidget* tabs) {
  auto* host = new QWidget;
  auto* lay = new QVBoxLayout(host);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("Column:"));
  data_column_ = new QComboBox;
  data_column_->setObjectName("dataColumn");
  row->addWidget(data_column_, 1);
  lay->addLayout(row);
  data_plot_ = new QCustomPlot;
  data_plot_->setObjectName("dataPlot");
  data_plot_->xAxis->setLabel("t [s]");
  lay->addWidget(data_plot_, 1);
  tabs->addTab(host, "Data");
  connect(data_column_, &QComboBox::currentIndexChanged, this, [this] { plotDataColumn(); });
  connect(this, &MainWindow::resultApplied, this, [this] {
    refreshDataTab();
    updateDataLabel();
  });
}

void MainWindow::refreshDataTab() {
  const auto d = dataset();
  if (d == data_tab_source_) return;
  data_tab_source_ = d;
  const QString keep = data_column_->currentText();
  data_column_->blockSignals(true);
  data_column_->clear();
  if (d) {
    for (const auto& n : d->names) {
      if (n != "t") data_column_->addItem(q(n));
    }
  }
  const int i = data_column_->findText(keep);
  data_column_->setCurrentIndex(i >= 0 ? i : 0);
  data_column_->blockSignals(false);
  plotDataColumn();
}

void MainWindow::plotDataColumn() {
  data_plot_->clearGraphs();
  const auto d = data_tab_source_;
  const std::string name = data_column_->currentText().toStdString();
  if (d && d->has("t") && d->has(name)) {
    const auto& t = d->col("t");
    const auto& v = d->col(name);
    QVector<double> x(static_cast<int>(t.size())), y(static_cast<int>(t.size()));
    std::copy(t.begin(), t.end(), x.begin());
    std::copy(v.begin(), v.end(), y.begin());
    auto* g = data_plot_->addGraph();
    g->setData(x, y, true);
    g->setName(q(name));
    data_plot_->yAxis->setLabel(q(name));
    data_plot_->xAxis->setLabel(d->time_origin.empty() ? QString("t [s]")
                                                       : "t [s] from " + q(d->time_origin));
  }
  data_plot_->rescaleAxes();
  data_plot_->replot();
}

void MainWindow::updateDataLabel() {
  const bool file = static_cast<bool>(file_data_);
  std::optional<Scenario::DataUnused> unused;
  if (file && scenario_ && doc_) unused = scenario_->data_unused(values());
  const QString name = file ? QFileInfo(q(file_data_->source)).fileName() : QString();
  if (file && unused) {
    data_label_->setText(QString("<b>Data:</b> %1 is loaded but <b>not used</b>: %2; the plots "
                                 "show the simulation.")
                             .arg(name, q(unused->why)));
  } else if (file) {
    QString text = QString("<b>Data:</b> %1 (%2 rows)").arg(name).arg(file_data_->rows());
    if (!file_data_->time_origin.empty()) text += ", t = 0 at " + q(file_data_->time_origin);
    data_label_->setText(text);
  } else {
    data_label_->setText("<b>Data:</b> simulated from the Simulator parameters");
  }
  data_label_->setToolTip(file ? q(file_data_->source) : QString());
  if (!data_fix_) {
    data_fix_ = new QPushButton(this);
    data_fix_->setObjectName("useDataMode");
    left_->insertWidget(left_->indexOf(data_label_) + 1, data_fix_);
    connect(data_fix_, &QPushButton::clicked, this, [this] {
      auto u = scenario_ ? scenario_->data_unused(values()) : std::nullopt;
      if (!u) return;
      ParamValues v = values();
      if (scenario_->params().apply_assignment(u->fix, v)) applyValues(v);
    });
  }
  data_fix_->setVisible(file && unused);
  if (unused) data_fix_->setText("Use the file: set " + q(unused->fix));
  sim_button_->setEnabled(file);
  if (panel_) {
    const bool sim_off = file && !unused;
    panel_->setGroupEnabled("Simulator", !sim_off, sim_off ? "off: data from file" : QString());
  }
}

}  // namespace kfw
