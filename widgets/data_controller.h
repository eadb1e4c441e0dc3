// The data the runs use: simulated from the sim.* parameters, or a file opened through the
// import dialog (or a mapping given, or one remembered for the file's header). Changes go
// through the document (undoable); an undo that changes the data reads the file again. Also the
// Data menu's actions: edit the mapping, forget the remembered one, save the converted data.
#pragma once

#include <QObject>
#include <QString>
#include <functional>
#include <memory>
#include <optional>

#include "core/expected.h"
#include "core/scenario.h"
#include "data/mapping.h"
#include "document/session.h"

class QWidget;

namespace kfw {

class DocumentController;
class ImportDialog;
class RunController;

class DataController : public QObject {
  Q_OBJECT
 public:
  // Reads a new document's data before it is adopted (a DocumentController adopt step).
  DataController(DocumentController* doc, RunController* runs, QWidget* window = nullptr);

  // Loads a CSV for the current scenario. On failure the loaded dataset stays and problem()
  // says why; a cancelled import dialog changes nothing and returns Ok.
  Status openDataset(const QString& path);
  // A CSV whose columns are named otherwise, with role -> column; remembered per header.
  Status openDatasetMapped(const QString& path, const ColumnMap& map);
  Status openDatasetMapped(const QString& path, const Mapping& map);
  // Switches back to data simulated from the sim.* parameters.
  void useSimulatedData();
  // The import dialog on the current file (an undoable mapping change); forget the mapping
  // remembered for its header; write the converted data in kfw's CSV format.
  Status editMapping();
  Status forgetMapping();
  Status saveConvertedCsv(const QString& path) const;
  // When true, openDataset opens the import dialog (the GUI); tests and exports stay silent and
  // use the preset's or the remembered mapping.
  void setInteractive(bool on) { interactive_ = on; }
  // Tests drive the import dialog through this instead of exec(): set roles, return true for OK
  // (refused while the dialog reports a problem). Set, it opens on every openDataset().
  void setImportHook(std::function<bool(ImportDialog&)> hook) { import_hook_ = std::move(hook); }

  // The file's data; null while the data are simulated.
  std::shared_ptr<const Dataset> fileData() const { return file_data_; }
  // Why the current values ignore a file (a mode that simulates), and the assignment that fixes
  // it; none when a file would be used.
  std::optional<Scenario::DataUnused> unused() const;
  // Applies unused()'s fix as one undo step.
  void useFileMode();

 signals:
  // The file data changed (opened, back to simulated, read again after an undo).
  void dataChanged();
  // A file opened without error (an error shown before is resolved).
  void fileOpened();
  void problem(const QString& message);
  void status(const QString& message);

 private:
  // Reads `path` for the scenario; with no mapping, tries the file as it is, then a mapping
  // remembered for its header, then (interactive) the mapping dialog. `used` gets the mapping.
  Expected<Dataset> readMapped(const QString& path, const Mapping* map, Mapping& used);
  Status openFile(const QString& path, const Mapping* map);
  // After undo / redo: reads the file the document now names, if it changed.
  void syncFromDocument();
  bool runDialog(ImportDialog& dialog);

  DocumentController* doc_;
  RunController* runs_;
  QWidget* window_;
  std::shared_ptr<const Dataset> file_data_;
  std::optional<DataRef> loaded_data_;  // what file_data_ was read from
  bool interactive_ = false;
  std::function<bool(ImportDialog&)> import_hook_;
};

}  // namespace kfw
