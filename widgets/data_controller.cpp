#include "data_controller.h"

#include <QCryptographicHash>
#include <QFileInfo>
#include <QSettings>
#include <filesystem>

#include "data/csv.h"
#include "data/import.h"
#include "document/workspace.h"
#include "document_controller.h"
#include "import_dialog.h"
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

DataController::DataController(DocumentController* doc, RunController* runs, QWidget* window)
    : QObject(window), doc_(doc), runs_(runs), window_(window) {
  // A new document's data file is read before it is adopted: a file that does not read leaves
  // the open document as it was.
  doc_->addAdoptStep([this](const Document& d) -> Expected<DocumentController::Commit> {
    std::shared_ptr<const Dataset> file;
    if (d.data()) {
      auto ds = load_dataset_file(d.scenario(), d.data()->path, d.data()->mapping);
      // The preset's own data file: name the preset and its key, as kfw-cli does.
      const auto& own = d.preset().data_path;
      if (!ds && own && *own == d.data()->path && !d.preset().path.empty()) {
        return Error{d.preset().path + ": data: " + ds.error(), ds.err().exit_code};
      }
      if (!ds) return ds.err();
      file = std::make_shared<const Dataset>(std::move(*ds));
    }
    return DocumentController::Commit([this, file] {
      file_data_ = file;
      loaded_data_ = doc_->document()->data();
      runs_->setFileDataset(file_data_);
    });
  });
  connect(doc_, &DocumentController::changed, this, &DataController::syncFromDocument);
}

bool DataController::runDialog(ImportDialog& dialog) {
  return import_hook_ ? import_hook_(dialog) && dialog.problem().isEmpty()
                      : dialog.exec() == QDialog::Accepted;
}

Expected<Dataset> DataController::readMapped(const QString& path, const Mapping* map,
                                             Mapping& used) {
  const auto scenario_ptr = doc_->scenario();
  const Scenario& scenario = *scenario_ptr;
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
    auto d = import_dataset(scenario, *shared, used);
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
  if (!interactive_ && !import_hook_) return import_dataset(scenario, *shared, used);
  // The dialog starts from the guess, overridden by the preset's and the remembered mapping.
  const Mapping guess = guess_mapping(*shared, scenario.columns());
  Mapping start = guess;
  start.override_with(used);
  ImportDialog dialog(shared, scenario.columns(), start, guess, window_);
  if (!runDialog(dialog)) return Error{file + ": import cancelled", kExitOk};  // not a failure
  used = dialog.mapping();  // the file as the dialog last read it (its separator and header)
  auto d = import_dataset(scenario, dialog.table(), used);
  if (d) remember(dialog.table(), used);
  return d;
}

Status DataController::openDataset(const QString& path) {
  return openFile(path, nullptr);
}

Status DataController::openDatasetMapped(const QString& path, const ColumnMap& map) {
  const Mapping m = to_mapping(map);
  return openFile(path, &m);
}

Status DataController::openDatasetMapped(const QString& path, const Mapping& map) {
  return openFile(path, &map);
}

Status DataController::openFile(const QString& path, const Mapping* map) {
  if (!doc_->scenario()) return Error{"load a preset first"};
  Mapping used;
  auto ds = readMapped(path, map, used);
  if (!ds) {
    if (ds.exit_code() == kExitOk) return Ok{};  // the dialog was cancelled: nothing changes
    emit problem(q(ds.error()));
    return ds.err();
  }
  file_data_ = std::make_shared<const Dataset>(std::move(*ds));
  loaded_data_ = DataRef{path.toStdString(), used};
  doc_->setData(loaded_data_);
  runs_->setFileDataset(file_data_);
  emit fileOpened();
  emit dataChanged();
  doc_->requestRun();
  return Ok{};
}

void DataController::useSimulatedData() {
  if (!file_data_) return;
  file_data_.reset();
  loaded_data_.reset();
  doc_->setData(std::nullopt);
  runs_->setFileDataset(nullptr);
  emit dataChanged();
  doc_->requestRun();
}

void DataController::syncFromDocument() {
  const Document* d = doc_->document();
  if (!d || d->data() == loaded_data_) return;
  if (!d->data()) {
    file_data_.reset();
  } else {
    auto ds = load_dataset_file(d->scenario(), d->data()->path, d->data()->mapping);
    if (ds) {
      file_data_ = std::make_shared<const Dataset>(std::move(*ds));
    } else {
      emit problem(q(ds.error()));
    }
  }
  loaded_data_ = d->data();
  runs_->setFileDataset(file_data_);
  emit dataChanged();
}

Status DataController::editMapping() {
  const Document* doc = doc_->document();
  if (!doc || !doc->data()) return Error{"no file loaded (the data are simulated)"};
  const Scenario& scenario = doc->scenario();
  const DataRef current = *doc->data();
  auto table = read_table(current.path, current.mapping.table_options());
  if (!table) return table.err();
  const auto shared = std::make_shared<const Table>(std::move(*table));
  ImportDialog dialog(shared, scenario.columns(), current.mapping,
                      guess_mapping(*shared, scenario.columns()), window_);
  if (!runDialog(dialog)) return Ok{};
  const Mapping m = dialog.mapping();
  auto d = import_dataset(scenario, dialog.table(), m);
  if (!d) {
    emit problem(q(d.error()));
    return d.err();
  }
  // The file is read again with the new mapping; undo restores the old one.
  if (auto st = doc_->setMapping(m); !st) return st;
  remember(dialog.table(), m);
  return Ok{};
}

Status DataController::forgetMapping() {
  const Document* doc = doc_->document();
  if (!doc || !doc->data()) return Error{"no file loaded (the data are simulated)"};
  auto table = read_table(doc->data()->path, doc->data()->mapping.table_options());
  if (!table) return table.err();
  QSettings("kfw", "kfw").remove(mapKey(*table));
  emit status("Forgot the mapping remembered for " + QFileInfo(q(doc->data()->path)).fileName() +
              "'s header; the next Open CSV starts from the guess.");
  return Ok{};
}

Status DataController::saveConvertedCsv(const QString& path) const {
  if (!file_data_) return Error{"no file loaded (the data are simulated)"};
  std::error_code ec;
  if (std::filesystem::equivalent(path.toStdString(), file_data_->source, ec)) {
    return Error{path.toStdString() + ": is the file the data were read from; choose another"};
  }
  return write_csv_file(path.toStdString(), *file_data_);
}

std::optional<Scenario::DataUnused> DataController::unused() const {
  const auto scenario = doc_->scenario();
  return scenario ? scenario->data_unused(doc_->values()) : std::nullopt;
}

void DataController::useFileMode() {
  const auto u = unused();
  if (!u) return;
  ParamValues v = doc_->values();
  if (doc_->scenario()->params().apply_assignment(u->fix, v)) doc_->setValues(v, "apply values");
}

}  // namespace kfw
