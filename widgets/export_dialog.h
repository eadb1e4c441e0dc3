// File → Export plots…: what `kfw --export` takes, in a dialog — the folder, the plots (all by
// default), the formats, the size (screen, column, page or W×H with a unit), the dpi, the text
// scale and the theme. The export itself is the controller's (ExportController::exportAll).
#pragma once

#include <QDialog>
#include <QStringList>

#include "core/expected.h"
#include "plot_export.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLineEdit;
class QListWidget;

namespace kfw {

class ExportDialog : public QDialog {
  Q_OBJECT
 public:
  ExportDialog(const QStringList& plots, QWidget* parent = nullptr);

  QString folder() const;
  void setFolder(const QString& dir);
  QStringList chosenPlots() const;  // empty: none; every plot when all are checked
  void setChosenPlots(const QStringList& names);
  QStringList formats() const;
  void setFormats(const QStringList& formats);
  void setSize(const QString& size);  // "screen", "column", "page" or what --size takes
  void setDpi(double dpi);
  // The spec the fields describe; the message names a bad size.
  Expected<ExportSpec> spec() const;

 private:
  QLineEdit* folder_ = nullptr;
  QListWidget* plots_ = nullptr;
  QCheckBox *png_ = nullptr, *pdf_ = nullptr, *svg_ = nullptr;
  QComboBox* size_ = nullptr;
  QDoubleSpinBox* dpi_ = nullptr;
  QDoubleSpinBox* font_ = nullptr;
  QComboBox* theme_ = nullptr;
};

}  // namespace kfw
