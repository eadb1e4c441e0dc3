#include "tune_dialog.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleValidator>
#include <QFileDialog>
#include <QFormLayout>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>
#include <QtConcurrent>
#include <algorithm>
#include <cmath>

#include "document/workspace.h"

namespace kfw {

namespace {

QString q(const std::string& s) {
  return QString::fromStdString(s);
}

QString num(double v) {
  return QString::number(v, 'g', 4);
}

}  // namespace

TuneDialog::TuneDialog(const Preset& preset, std::shared_ptr<const Dataset> dataset,
                       const QString& name, std::shared_ptr<const RunResult> probe,
                       const ParamValues& start, QWidget* parent)
    : QDialog(parent),
      preset_(preset),
      scenario_(preset.instance),
      probe_(std::move(probe)),
      start_(start) {
  setWindowTitle("Auto-tune");
  logs_.push_back({name.isEmpty() ? QString("current data") : name, std::move(dataset)});
  auto* lay = new QVBoxLayout(this);
  lay->addWidget(
      new QLabel("Search these parameters (the preset's tunable keys; log space for "
                 "log-scale keys) between these bounds:"));
  auto* grid = new QGridLayout;
  const auto search = default_search(preset_);
  for (const auto& p : search) {
    const ParamSpec* spec = scenario_->params().find(p.key);
    KeyUi ui{p.key};
    ui.param = p;
    ui.check = new QCheckBox(q(p.key + " — " + spec->label), this);
    ui.check->setObjectName("tune." + q(p.key));
    ui.check->setChecked(true);
    ui.lo = new QLineEdit(num(p.lo), this);
    ui.hi = new QLineEdit(num(p.hi), this);
    ui.lo->setObjectName("tune.lo." + q(p.key));
    ui.hi->setObjectName("tune.hi." + q(p.key));
    for (auto* e : {ui.lo, ui.hi}) {
      e->setValidator(new QDoubleValidator(e));
      e->setMaximumWidth(90);
    }
    const int row = static_cast<int>(keys_.size());
    grid->addWidget(ui.check, row, 0);
    grid->addWidget(ui.lo, row, 1);
    grid->addWidget(ui.hi, row, 2);
    if (!p.scale_group.empty())
      grid->addWidget(new QLabel(q("scale group " + p.scale_group)), row, 3);
    keys_.push_back(ui);
  }
  lay->addLayout(grid);
  auto* form = new QFormLayout;
  objective_ = new QComboBox(this);
  objective_->setObjectName("tune.objective");
  for (const auto& n : objective_names(*scenario_, probe_.get())) {
    if (n == "nis") continue;  // nis_mean is listed
    QString text = q(n);
    const auto& combined = combined_objectives();
    const auto c = std::find_if(combined.begin(), combined.end(),
                                [&](const CombinedObjective& o) { return o.name == n; });
    if (c != combined.end()) {
      text += " — " + QString::fromUtf8(c->label.data(), static_cast<qsizetype>(c->label.size()));
    } else {
      const MetricSpec spec = describe_metric(*scenario_, n, probe_.get());
      text += " — " + q(spec.label) + " (" +
              (spec.direction == Direction::kTarget ? "target " + num(spec.target)
                                                    : QString(direction_name(spec.direction))) +
              ")";
    }
    objective_->addItem(text, q(n));
  }
  if (probe_) {
    const DefaultObjective d = default_objective(preset_, *probe_, search);
    setObjective(q(d.name));
    objective_->setToolTip("Default: " + q(d.name) + " (" + q(d.why) + ")");
  }
  form->addRow("objective", objective_);
  method_ = new QComboBox(this);
  method_->setObjectName("tune.method");
  method_->addItem("BOBYQA — local (default)", "bobyqa");
  method_->addItem("Sbplx — local", "sbplx");
  method_->addItem("DIRECT-L — global, then local", "direct");
  method_->addItem("CRS2 — global, then local", "crs");
  form->addRow("method", method_);
  budget_ = new QSpinBox(this);
  budget_->setObjectName("tune.budget");
  budget_->setRange(10, 100000);
  budget_->setValue(400);
  form->addRow("budget (evaluations)", budget_);
  tol_ = new QLineEdit("1e-6", this);
  tol_->setValidator(new QDoubleValidator(1e-15, 1.0, 20, tol_));
  form->addRow("tolerance (relative)", tol_);
  aggregate_ = new QComboBox(this);
  aggregate_->addItem("mean over the logs", "mean");
  aggregate_->addItem("worst log", "worst");
  form->addRow("several logs", aggregate_);
  lay->addLayout(form);
  log_list_ = new QListWidget(this);
  log_list_->setObjectName("tune.logs");
  log_list_->setMaximumHeight(70);
  log_list_->addItem(logs_.front().first);
  auto* add_log = new QPushButton("Add log…", this);
  auto* logs_row = new QHBoxLayout;
  logs_row->addWidget(log_list_, 1);
  logs_row->addWidget(add_log);
  lay->addWidget(new QLabel("tuning set:"));
  lay->addLayout(logs_row);
  progress_ = new QProgressBar(this);
  progress_->setRange(0, budget_->value());
  lay->addWidget(progress_);
  result_label_ = new QLabel(this);
  result_label_->setWordWrap(true);
  result_label_->setObjectName("tune.result");
  result_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  lay->addWidget(result_label_);
  auto* buttons = new QHBoxLayout;
  run_ = new QPushButton("Run", this);
  cancel_ = new QPushButton("Cancel", this);
  cancel_->setEnabled(false);
  apply_ = new QPushButton("Apply", this);
  revert_ = new QPushButton("Revert", this);
  apply_->setEnabled(false);
  revert_->setEnabled(false);
  apply_->setToolTip("keep the tuned values and close");
  revert_->setToolTip("restore the values the dialog started from (pinned snapshots stay)");
  buttons->addWidget(run_);
  buttons->addWidget(cancel_);
  buttons->addStretch(1);
  buttons->addWidget(apply_);
  buttons->addWidget(revert_);
  lay->addLayout(buttons);
  connect(run_, &QPushButton::clicked, this, &TuneDialog::start);
  connect(cancel_, &QPushButton::clicked, this, &TuneDialog::cancel);
  connect(apply_, &QPushButton::clicked, this, &TuneDialog::apply);
  connect(revert_, &QPushButton::clicked, this, &TuneDialog::revert);
  connect(add_log, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, "Add a log", {}, "CSV (*.csv)");
    if (f.isEmpty()) return;
    if (auto st = addLog(f); !st) result_label_->setText("⚠ " + q(st.error()));
  });
  connect(&watcher_, &QFutureWatcher<Expected<TuneResult>>::finished, this, &TuneDialog::finished);
}

TuneDialog::~TuneDialog() {
  cancel();
  watcher_.waitForFinished();
}

void TuneDialog::finished() {
  run_->setEnabled(true);
  cancel_->setEnabled(false);
  const auto r = watcher_.result();
  progress_->setValue(progress_->maximum());
  if (!r) {
    result_label_->setText("⚠ " + q(r.error()));
    return;
  }
  result_ = *r;
  QString text = QString("%1 = %2 after %3 runs (%4%5):")
                     .arg(q(running_objective_.spec.key))
                     .arg(r->value, 0, 'g', 5)
                     .arg(r->evaluations)
                     .arg(q(r->method))
                     .arg(r->cancelled ? ", cancelled" : "");
  for (const auto& ui : keys_) {
    if (ui.check->isChecked())
      text += QString("  %1 = %2").arg(q(ui.key)).arg(num(r->best.at(ui.key)));
  }
  bool warn = false;
  for (const auto& s : r->scales) {
    QStringList keys;
    for (const auto& k : s.keys)
      keys << q(k);
    if (!s.determined) {
      warn = true;
      text += QString(
                  "\n⚠ %1 does not change when %2 scale together: it sets their ratio "
                  "only. The scale was set by consistency: NIS mean / dof = %3.")
                  .arg(q(running_objective_.spec.key), keys.join(", "), num(s.nis_mean));
    } else if (s.by_consistency) {
      text += QString("\nThe scale of %1 was set by consistency: NIS mean / dof = %2.")
                  .arg(keys.join(", "), num(s.nis_mean));
    }
    if (!s.note.empty()) text += "\n⚠ " + q(s.note);
  }
  if (!r->at_bound.empty()) {
    warn = true;
    QStringList keys;
    for (const auto& k : r->at_bound)
      keys << q(k);
    text += "\n⚠ The optimum sits on a search bound for " + keys.join(", ") + ": widen the bounds.";
  }
  if (r->trade_off && r->trade_off->costly()) {
    // Both points, so the user chooses: Revert goes back to the start's values.
    warn = true;
    text += "\n⚠ " + q(r->trade_off->message()) + " (Revert).";
  }
  if (r->logs.size() > 1) {
    for (const auto& l : r->logs)
      text += QString("\n  %1: %2").arg(q(l.name)).arg(l.value, 0, 'g', 5);
  }
  auto w = r->metrics.find("whiteness_p");
  if (running_objective_.truth_free() && w != r->metrics.end() && w->second < 0.01) {
    warn = true;
    text += QString(
                "\n⚠ The innovations are not white (Ljung–Box p = %1): a tuning without truth "
                "is not trustworthy on these data.")
                .arg(w->second, 0, 'g', 3);
  }
  result_label_->setStyleSheet(warn ? "color: #8a1c13;" : "");
  result_label_->setText(text);
  apply_->setEnabled(true);
  revert_->setEnabled(true);
  emit tuned(r->best);
}

void TuneDialog::setObjective(const QString& name) {
  const int i = objective_->findData(name == "nis" ? "nis_mean" : name);
  if (i >= 0) objective_->setCurrentIndex(i);
}

QString TuneDialog::objective() const {
  return objective_->currentData().toString();
}

void TuneDialog::setSelected(const QStringList& keys) {
  for (auto& ui : keys_)
    ui.check->setChecked(keys.contains(q(ui.key)));
}

QStringList TuneDialog::selected() const {
  QStringList out;
  for (const auto& ui : keys_) {
    if (ui.check->isChecked()) out << q(ui.key);
  }
  return out;
}

void TuneDialog::setBounds(const QString& key, double lo, double hi) {
  for (auto& ui : keys_) {
    if (q(ui.key) != key) continue;
    ui.lo->setText(QString::number(lo, 'g', 12));
    ui.hi->setText(QString::number(hi, 'g', 12));
  }
}

void TuneDialog::setBudget(int evaluations) {
  budget_->setValue(evaluations);
}

Status TuneDialog::addLog(const QString& path) {
  auto d = load_dataset_file(*scenario_, path.toStdString(), preset_.mapping);
  if (!d) return d.err();
  logs_.push_back({path, std::make_shared<const Dataset>(std::move(*d))});
  log_list_->addItem(path);
  emit tuningSetChanged(logs());
  return Ok{};
}

QStringList TuneDialog::logs() const {
  QStringList out;
  for (std::size_t i = 1; i < logs_.size(); ++i)
    out << logs_[i].first;
  return out;
}

void TuneDialog::apply() {
  accept();
}

void TuneDialog::revert() {
  emit reverted(start_);
  revert_->setEnabled(false);
  apply_->setEnabled(false);
  result_label_->setText("reverted to the values before tuning");
}

int TuneDialog::progressValue() const {
  return progress_->value();
}

int TuneDialog::progressMaximum() const {
  return progress_->maximum();
}

QString TuneDialog::message() const {
  return result_label_->text();
}

void TuneDialog::cancel() {
  if (stop_) stop_->store(true);
}

void TuneDialog::start() {
  if (running()) return;
  std::vector<SearchParam> params;
  for (auto& ui : keys_) {
    if (!ui.check->isChecked()) continue;
    SearchParam p = ui.param;
    bool ok_lo = false, ok_hi = false;
    p.lo = ui.lo->text().toDouble(&ok_lo);
    p.hi = ui.hi->text().toDouble(&ok_hi);
    if (!ok_lo || !ok_hi || !(p.lo < p.hi) || (p.log && p.lo <= 0)) {
      result_label_->setText("⚠ " + q(ui.key) + ": the bounds need lo < hi" +
                             (p.log ? " and lo > 0 (a log-scale key)" : ""));
      return;
    }
    params.push_back(p);
  }
  auto chosen = make_objective(*scenario_, objective().toStdString(), probe_.get());
  if (params.empty() || !chosen) {
    result_label_->setText(
        "⚠ " + (params.empty() ? QString("choose at least one parameter") : q(chosen.error())));
    return;
  }
  running_objective_ = *chosen;
  stop_ = std::make_shared<std::atomic<bool>>(false);
  evals_ = std::make_shared<std::atomic<int>>(0);
  run_->setEnabled(false);
  cancel_->setEnabled(true);
  apply_->setEnabled(false);
  revert_->setEnabled(false);
  result_label_->setText("searching…");
  result_label_->setStyleSheet({});
  progress_->setRange(0, budget_->value());
  progress_->setValue(0);
  auto timer = new QTimer(this);
  connect(timer, &QTimer::timeout, this, [this, timer, evals = evals_] {
    if (!running()) {
      timer->deleteLater();
      return;
    }
    progress_->setValue(std::min(evals->load(), progress_->maximum()));
  });
  timer->start(50);
  TuneOptions opt;
  opt.method = *parse_tune_method(method_->currentData().toString().toStdString());
  opt.aggregate =
      aggregate_->currentData().toString() == "worst" ? Aggregate::kWorst : Aggregate::kMean;
  opt.budget = budget_->value();
  opt.tol = tol_->text().toDouble() > 0 ? tol_->text().toDouble() : 1e-6;
  opt.cancel = stop_.get();
  opt.progress = [evals = evals_](int n, double) { evals->store(n); };
  watcher_.setFuture(QtConcurrent::run(
      [s = scenario_, logs = logs_, v = start_, params, obj = *chosen, opt, stop = stop_]() {
        std::vector<TuneLog> set;
        for (const auto& [name, d] : logs)
          set.push_back({name.toStdString(), d.get()});
        return tune(*s, set, v, params, obj, opt);
      }));
}

}  // namespace kfw
