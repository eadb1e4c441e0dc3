#include "tune_dialog.h"

#include <QCheckBox>
#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QTimer>
#include <QVBoxLayout>
#include <QtConcurrent>
#include <cmath>

namespace kfw {

namespace {
constexpr int kMaxEvaluations = 400;
}

TuneDialog::TuneDialog(std::shared_ptr<const Scenario> scenario,
                       std::shared_ptr<const Dataset> dataset, const ParamValues& start,
                       QWidget* parent)
    : QDialog(parent), scenario_(std::move(scenario)), data_(std::move(dataset)), start_(start) {
  setWindowTitle("Auto-tune");
  auto* lay = new QVBoxLayout(this);
  lay->addWidget(new QLabel("Search these parameters (log space for variances):"));
  for (const auto& s : scenario_->params().specs()) {
    if (is_sim_key(s.key) || s.scale == Scale::kChoice || s.scale == Scale::kToggle) continue;
    auto* c = new QCheckBox(QString::fromStdString(s.key + " — " + s.label), this);
    c->setObjectName("tune." + QString::fromStdString(s.key));
    c->setProperty("key", QString::fromStdString(s.key));
    c->setChecked(s.key == "Q" || s.key == "R");
    checks_ << c;
    lay->addWidget(c);
  }
  auto* form = new QFormLayout;
  objective_ = new QComboBox(this);
  objective_->setObjectName("tune.objective");
  objective_->addItem("rmse — against truth", "rmse");
  objective_->addItem("nll — innovation likelihood (no truth needed)", "nll");
  objective_->addItem("nis — NIS consistency (no truth needed)", "nis");
  form->addRow("objective", objective_);
  lay->addLayout(form);
  progress_ = new QProgressBar(this);
  progress_->setRange(0, kMaxEvaluations);
  lay->addWidget(progress_);
  result_ = new QLabel(this);
  result_->setWordWrap(true);
  result_->setObjectName("tune.result");
  lay->addWidget(result_);
  auto* buttons = new QHBoxLayout;
  run_ = new QPushButton("Run", this);
  cancel_ = new QPushButton("Cancel", this);
  cancel_->setEnabled(false);
  auto* close = new QPushButton("Close", this);
  buttons->addWidget(run_);
  buttons->addWidget(cancel_);
  buttons->addStretch(1);
  buttons->addWidget(close);
  lay->addLayout(buttons);
  connect(run_, &QPushButton::clicked, this, &TuneDialog::start);
  connect(cancel_, &QPushButton::clicked, this, &TuneDialog::cancel);
  connect(close, &QPushButton::clicked, this, [this] {
    cancel();
    accept();
  });
  connect(&watcher_, &QFutureWatcher<Expected<TuneResult>>::finished, this, [this] {
    run_->setEnabled(true);
    cancel_->setEnabled(false);
    const auto r = watcher_.result();
    if (!r) {
      result_->setText("⚠ " + QString::fromStdString(r.error()));
      return;
    }
    progress_->setValue(kMaxEvaluations);
    QString text = QString("%1 = %2 after %3 runs%4:")
                       .arg(objective_name_)
                       .arg(r->objective, 0, 'g', 5)
                       .arg(r->evaluations)
                       .arg(stop_->load() ? " (cancelled)" : "");
    for (const auto* c : checks_) {
      if (!c->isChecked()) continue;
      const auto key = c->property("key").toString().toStdString();
      text += QString("  %1 = %2").arg(QString::fromStdString(key)).arg(r->best.at(key), 0, 'g', 4);
    }
    auto w = r->metrics.find("whiteness_p");
    if (objective_name_ != "rmse" && w != r->metrics.end() && w->second < 0.01) {
      text += QString(
                  "\n⚠ The innovations are not white (Ljung–Box p = %1): a tuning without truth "
                  "is not trustworthy on these data.")
                  .arg(w->second, 0, 'g', 3);
      result_->setStyleSheet("color: #8a1c13;");
    } else {
      result_->setStyleSheet({});
    }
    result_->setText(text);
    emit tuned(r->best);
  });
}

TuneDialog::~TuneDialog() {
  cancel();
  watcher_.waitForFinished();
}

void TuneDialog::setObjective(const QString& name) {
  const int i = objective_->findData(name);
  if (i >= 0) objective_->setCurrentIndex(i);
}

void TuneDialog::setSelected(const QStringList& keys) {
  for (auto* c : checks_)
    c->setChecked(keys.contains(c->property("key").toString()));
}

QString TuneDialog::message() const {
  return result_->text();
}

void TuneDialog::cancel() {
  if (stop_) stop_->store(true);
}

void TuneDialog::start() {
  if (running()) return;
  std::vector<SearchParam> params;
  for (const auto* c : checks_) {
    if (!c->isChecked()) continue;
    const ParamSpec* s = scenario_->params().find(c->property("key").toString().toStdString());
    params.push_back({s->key, s->min, s->max, s->scale == Scale::kLog});
  }
  objective_name_ = objective_->currentData().toString();
  auto objective = objective_by_name(objective_name_.toStdString());
  if (params.empty() || !objective) {
    result_->setText("⚠ choose at least one parameter");
    return;
  }
  stop_ = std::make_shared<std::atomic<bool>>(false);
  evals_ = std::make_shared<std::atomic<int>>(0);
  run_->setEnabled(false);
  cancel_->setEnabled(true);
  result_->setText("searching…");
  progress_->setValue(0);
  auto timer = new QTimer(this);
  connect(timer, &QTimer::timeout, this, [this, timer, evals = evals_] {
    progress_->setValue(evals->load());
    if (!running()) timer->deleteLater();
  });
  timer->start(50);
  TuneOptions opt;
  opt.max_evaluations = kMaxEvaluations;
  opt.cancel = stop_.get();
  opt.progress = [evals = evals_](int n, double) { evals->store(n); };
  watcher_.setFuture(
      QtConcurrent::run([s = scenario_, d = data_, v = start_, params, obj = *objective, opt,
                         stop = stop_]() { return tune(*s, *d, v, params, obj, opt); }));
}

}  // namespace kfw
