#include "export_dialog.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLineEdit>
#include <QListWidget>
#include <QPushButton>
#include <QVBoxLayout>

namespace kfw {

ExportDialog::ExportDialog(const QStringList& plots, QWidget* parent) : QDialog(parent) {
  setWindowTitle("Export plots");
  setObjectName("exportDialog");
  auto* lay = new QVBoxLayout(this);
  auto* form = new QFormLayout;
  auto* folder_row = new QHBoxLayout;
  folder_ = new QLineEdit(this);
  folder_->setObjectName("export.folder");
  auto* browse = new QPushButton("Choose…", this);
  folder_row->addWidget(folder_, 1);
  folder_row->addWidget(browse);
  form->addRow("folder", folder_row);
  connect(browse, &QPushButton::clicked, this, [this] {
    const QString d = QFileDialog::getExistingDirectory(this, "Export plots to", folder());
    if (!d.isEmpty()) setFolder(d);
  });
  auto* format_row = new QHBoxLayout;
  png_ = new QCheckBox("PNG", this);
  pdf_ = new QCheckBox("PDF", this);
  svg_ = new QCheckBox("SVG", this);
  for (QCheckBox* c : {png_, pdf_, svg_}) {
    c->setChecked(true);
    format_row->addWidget(c);
  }
  format_row->addStretch(1);
  form->addRow("formats", format_row);
  size_ = new QComboBox(this);
  size_->setObjectName("export.size");
  size_->setEditable(true);
  size_->addItem("screen (1200 × 700 px)", "");
  size_->addItem("column (3.5 × 2.5 in)", "column");
  size_->addItem("page (7 × 4 in)", "page");
  size_->setToolTip("a named size, or W×H with a unit: 90x60mm, 3.5inx2.5in, 1200x700px");
  form->addRow("size", size_);
  dpi_ = new QDoubleSpinBox(this);
  dpi_->setRange(50, 1200);
  dpi_->setValue(kLayoutDpi);
  form->addRow("dpi (PNG)", dpi_);
  font_ = new QDoubleSpinBox(this);
  font_->setRange(0.5, 4.0);
  font_->setSingleStep(0.1);
  font_->setValue(1.0);
  form->addRow("text ×", font_);
  theme_ = new QComboBox(this);
  theme_->addItem("light", "light");
  theme_->addItem("dark", "dark");
  form->addRow("theme", theme_);
  lay->addLayout(form);
  plots_ = new QListWidget(this);
  plots_->setObjectName("export.plots");
  for (const QString& name : plots) {
    auto* it = new QListWidgetItem(name, plots_);
    it->setFlags(it->flags() | Qt::ItemIsUserCheckable);
    it->setCheckState(Qt::Checked);
  }
  lay->addWidget(plots_, 1);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
  buttons->button(QDialogButtonBox::Ok)->setText("Export");
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  lay->addWidget(buttons);
}

QString ExportDialog::folder() const {
  return folder_->text();
}

void ExportDialog::setFolder(const QString& dir) {
  folder_->setText(dir);
}

QStringList ExportDialog::chosenPlots() const {
  QStringList out;
  for (int i = 0; i < plots_->count(); ++i) {
    if (plots_->item(i)->checkState() == Qt::Checked) out << plots_->item(i)->text();
  }
  return out;
}

void ExportDialog::setChosenPlots(const QStringList& names) {
  for (int i = 0; i < plots_->count(); ++i)
    plots_->item(i)->setCheckState(names.contains(plots_->item(i)->text()) ? Qt::Checked
                                                                           : Qt::Unchecked);
}

QStringList ExportDialog::formats() const {
  QStringList out;
  if (png_->isChecked()) out << "png";
  if (pdf_->isChecked()) out << "pdf";
  if (svg_->isChecked()) out << "svg";
  return out;
}

void ExportDialog::setFormats(const QStringList& formats) {
  png_->setChecked(formats.contains("png"));
  pdf_->setChecked(formats.contains("pdf"));
  svg_->setChecked(formats.contains("svg"));
}

void ExportDialog::setSize(const QString& size) {
  const int i = size_->findData(size == "screen" ? QString() : size);
  if (i >= 0) {
    size_->setCurrentIndex(i);
  } else {
    size_->setEditText(size);
  }
}

void ExportDialog::setDpi(double dpi) {
  dpi_->setValue(dpi);
}

Expected<ExportSpec> ExportDialog::spec() const {
  ExportSpec spec;
  spec.dpi = dpi_->value();
  spec.font_scale = font_->value();
  auto theme = parseTheme(theme_->currentData().toString());
  if (!theme) return theme.err();
  spec.theme = *theme;
  // A named entry carries its key; typed text is what --size takes.
  const int i = size_->findText(size_->currentText());
  const QString size = i >= 0 ? size_->itemData(i).toString() : size_->currentText().trimmed();
  if (!size.isEmpty()) {
    if (auto st = parseSize(size, spec.dpi, spec); !st) return st.err();
  }
  return spec;
}

}  // namespace kfw
