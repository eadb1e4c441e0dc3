// File → Export filter as C… (issue 31): the filter of the open preset at the window's values as
// NAME.h, NAME.c and NAME_example.c, the bytes `kfw-cli export-c` writes for the same preset and
// --set values (engine/codegen/c_export.h does the work; the window only asks where and how).
#include <QCheckBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDir>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>

#include "codegen/c_export.h"
#include "main_window.h"
#include "window_report.h"

namespace kfw {

using window::q;

Status MainWindow::exportFilterAsC(const QString& dir, const QString& prefix, bool single,
                                   bool steady) {
  if (!document()) return Error{"Export filter as C: no preset is open"};
  const Document& d = *document();
  codegen::CExportOptions o = codegen::default_options(d.preset().path);
  if (!prefix.isEmpty()) o.prefix = prefix.toStdString();
  o.single = single;
  o.steady = steady;
  if (codegen::exports_steady(d.scenario(), d.values(), steady)) {
    const auto file = data_->fileData();
    auto dt = codegen::steady_interval(d.scenario(), d.values(), std::nullopt, file.get());
    if (!dt) return dt.err();
    o.steady_dt = *dt;
  }
  auto files = codegen::export_c(d.scenario(), d.values(), o);
  if (!files) return files.err();
  std::vector<std::string> inputs{d.preset().path};
  if (d.data()) inputs.push_back(d.data()->path);
  if (auto st = codegen::write_c_export(dir.toStdString(), o.prefix, *files, inputs); !st)
    return st;
  status_->setText("Wrote " + q(o.prefix) + ".h, .c and _example.c to " + dir);
  return Ok{};
}

void MainWindow::exportFilterAsCWithDialog() {
  if (!document()) return;
  QDialog dlg(this);
  dlg.setWindowTitle("Export filter as C");
  auto* form = new QFormLayout(&dlg);
  auto* dir = new QLineEdit(QDir::currentPath(), &dlg);
  auto* browse = new QPushButton("Browse…", &dlg);
  auto* row = new QHBoxLayout;
  row->addWidget(dir, 1);
  row->addWidget(browse);
  form->addRow("Folder", row);
  auto* prefix = new QLineEdit(q(codegen::default_options(document()->preset().path).prefix), &dlg);
  prefix->setToolTip("The files' and the functions' prefix: a C identifier");
  form->addRow("Prefix", prefix);
  auto* single = new QCheckBox("Single precision (float), for targets without a double FPU", &dlg);
  auto* steady =
      new QCheckBox("Steady-state gain (fixed DARE gain; linear time-invariant models)", &dlg);
  form->addRow(single);
  form->addRow(steady);
  form->addRow(
      new QLabel("Writes PREFIX.h, PREFIX.c and PREFIX_example.c (C99, <math.h> only); "
                 "the same files as kfw-cli export-c.",
                 &dlg));
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, &dlg);
  form->addRow(buttons);
  connect(browse, &QPushButton::clicked, &dlg, [&] {
    const QString d = QFileDialog::getExistingDirectory(&dlg, "Export filter as C", dir->text());
    if (!d.isEmpty()) dir->setText(d);
  });
  connect(buttons, &QDialogButtonBox::rejected, &dlg, &QDialog::reject);
  connect(buttons, &QDialogButtonBox::accepted, &dlg, [&] {
    const Status st =
        exportFilterAsC(dir->text(), prefix->text(), single->isChecked(), steady->isChecked());
    if (st) {
      dlg.accept();
    } else {
      window::report(&dlg, "Export filter as C", st);  // the dialog stays for another try
    }
  });
  dlg.exec();
}

}  // namespace kfw
