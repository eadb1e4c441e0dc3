#include "column_map_dialog.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QLabel>
#include <QVBoxLayout>

namespace kfw {

ColumnMapDialog::ColumnMapDialog(const std::vector<ColumnSpec>& roles, const Dataset& file,
                                 const ColumnMap& guess, QWidget* parent)
    : QDialog(parent), roles_(roles) {
  setWindowTitle("Map columns");
  auto* lay = new QVBoxLayout(this);
  lay->addWidget(new QLabel(QString("Which column of %1 plays each role? The mapping is remembered "
                                    "for files with the same header.")
                                .arg(QFileInfo(QString::fromStdString(file.source)).fileName())));
  auto* form = new QFormLayout;
  for (const auto& r : roles_) {
    auto* c = new QComboBox(this);
    c->setObjectName("map." + QString::fromStdString(r.name));
    if (!r.required) c->addItem("(none)", QString());
    for (const auto& n : file.names)
      c->addItem(QString::fromStdString(n), QString::fromStdString(n));
    QString pick = QString::fromStdString(r.name);
    if (auto it = guess.find(r.name); it != guess.end()) pick = QString::fromStdString(it->second);
    if (const int i = c->findData(pick); i >= 0) c->setCurrentIndex(i);
    combos_ << c;
    form->addRow(QString::fromStdString(r.name + (r.unit.empty() ? "" : " (" + r.unit + ")") +
                                        (r.required ? "" : ", optional")),
                 c);
  }
  lay->addLayout(form);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  lay->addWidget(buttons);
}

ColumnMap ColumnMapDialog::mapping() const {
  ColumnMap m;
  for (int i = 0; i < combos_.size(); ++i) {
    const QString col = combos_[i]->currentData().toString();
    if (!col.isEmpty()) m[roles_[static_cast<std::size_t>(i)].name] = col.toStdString();
  }
  return m;
}

}  // namespace kfw
