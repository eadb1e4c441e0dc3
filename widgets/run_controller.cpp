#include "run_controller.h"

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QEventLoop>
#include <QMessageBox>
#include <QMetaObject>
#include <QPointer>
#include <QTimer>
#include <chrono>
#include <ctime>

#include "experiment/tuning.h"
#include "monte_carlo_dialog.h"
#include "sweep_dialog.h"
#include "tune_dialog.h"

namespace kfw {

struct RunController::Outcome {
  std::uint64_t generation = 0;
  ParamValues values;
  std::shared_ptr<const Dataset> dataset;
  ParamValues sim_key;
  bool simulated = false;
  std::shared_ptr<const RunResult> result;
  std::string error;
  int exit_code = 0;  // the failed run's (core/expected.h: 2 refused, 1 broke down)
  double ms = 0.0;
};

namespace {
ParamValues sim_subset(const ParamValues& v) {
  ParamValues out;
  for (const auto& [k, x] : v) {
    if (is_sim_key(k)) out[k] = x;
  }
  return out;
}
}  // namespace

RunController::RunController(QObject* parent) : QObject(parent) {
  pool_.setMaxThreadCount(1);
}

RunController::~RunController() {
  if (cancel_) cancel_->store(true);
  pool_.waitForDone();
}

void RunController::setScenario(std::shared_ptr<const Scenario> scenario) {
  if (cancel_) cancel_->store(true);
  scenario_ = std::move(scenario);
  sim_cache_.reset();
  sim_key_.clear();
  pending_.reset();
  result_.reset();
  ++generation_;
}

void RunController::setFileDataset(std::shared_ptr<const Dataset> data) {
  file_ = std::move(data);
  ++generation_;
}

void RunController::request(const ParamValues& values) {
  if (!scenario_) return;
  // The latency runs from the first request after the last settled one (a burst is one wait).
  if (settled_) since_request_.start();
  settled_ = false;
  emit requested();
  if (busy_) {
    pending_ = values;
    return;
  }
  start(values);
}

void RunController::start(const ParamValues& values) {
  busy_ = true;
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  auto scenario = scenario_;
  auto file = file_;
  auto cache = sim_cache_;
  auto cache_key = sim_key_;
  auto cancel = cancel_;
  const auto gen = generation_;
  QPointer<RunController> self(this);
  pool_.start([=]() {
    auto out = std::make_shared<Outcome>();
    out->generation = gen;
    out->values = values;
    const auto t0 = std::chrono::steady_clock::now();
    std::shared_ptr<const Dataset> data = file;
    if (!data) {
      out->sim_key = sim_subset(values);
      if (cache && cache_key == out->sim_key) {
        data = cache;
      } else {
        auto sim = scenario->simulate(values);
        if (sim) {
          data = std::make_shared<const Dataset>(std::move(*sim));
          out->simulated = true;
        } else {
          out->error = sim.error();
          out->exit_code = sim.exit_code();
        }
      }
    }
    if (data) {
      out->dataset = data;
      RunControl ctl;
      ctl.cancel = cancel.get();
      auto r = scenario->run(*data, values, ctl);
      if (r) {
        out->result = *r;
      } else {
        out->error = r.error();
        out->exit_code = r.exit_code();
      }
    }
    out->ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    QMetaObject::invokeMethod(
        QCoreApplication::instance(),
        [self, out]() {
          if (self) self->onDone(out);
        },
        Qt::QueuedConnection);
  });
}

void RunController::onDone(const std::shared_ptr<Outcome>& out) {
  busy_ = false;
  if (out->generation == generation_) {
    if (out->simulated) {
      sim_cache_ = out->dataset;
      sim_key_ = out->sim_key;
    }
    last_exit_code_ = out->result ? 0 : out->exit_code;
    if (out->result) {
      last_dataset_ = out->dataset;
      result_ = out->result;
      last_wall_ms_ = out->ms;
      emit finished(out->result, out->values, out->ms);
      settle(true);
    } else {
      emit failed(QString::fromStdString(out->error));
      settle(false);
    }
  }
  if (pending_) {
    ParamValues next = std::move(*pending_);
    pending_.reset();
    start(next);
  }
}

void RunController::settle(bool ok) {
  settled_ = !busy_;
  if (ok && settled_) last_latency_ms_ = sinceRequestMs();
  emit applied(ok);
}

bool RunController::waitSettled(int timeout_ms) {
  // A nested event loop that sleeps until the run lands (no busy polling: the worker keeps a core).
  QDeadlineTimer deadline(timeout_ms);
  while (!settled_ || busy_ || (drawing_ && drawing_())) {
    if (deadline.hasExpired()) return false;
    QEventLoop loop;
    connect(this, &RunController::applied, &loop, &QEventLoop::quit);
    connect(this, &RunController::drawingFinished, &loop, &QEventLoop::quit);
    QTimer::singleShot(std::max<qint64>(1, std::min<qint64>(deadline.remainingTime(), 50)), &loop,
                       &QEventLoop::quit);
    loop.exec();
  }
  return true;
}

TuneDialog* RunController::openTune(const Preset& preset, const ParamValues& values,
                                    const QString& data_name,
                                    const std::vector<DataRef>& tuning_set, QWidget* parent) {
  if (!scenario_ || !last_dataset_) return nullptr;
  auto* d = new TuneDialog(preset, last_dataset_, data_name, result_, values, parent);
  d->setAttribute(Qt::WA_DeleteOnClose);
  // The document's tuning set comes back with the dialog (files that no longer read are skipped
  // with their message).
  for (const auto& ref : tuning_set) {
    if (auto st = d->addLog(QString::fromStdString(ref.path)); !st) {
      emit problem(QString::fromStdString(st.error()));
    }
  }
  connect(d, &TuneDialog::tuned, this, [this, d](const ParamValues& v) {
    // The tuned objective's metric goes first in the metrics table (rmse+nis ranks rmse).
    if (auto obj = make_objective(*scenario_, d->objective().toStdString(), result_.get())) {
      emit objectiveChosen(QString::fromStdString(obj->spec.key));
    }
    emit valuesChosen(v, "tune");
  });
  connect(d, &TuneDialog::reverted, this,
          [this](const ParamValues& v) { emit valuesChosen(v, "revert tuning"); });
  connect(d, &TuneDialog::tuningSetChanged, this, &RunController::tuningSetChosen);
  d->show();
  return d;
}

SweepDialog* RunController::openSweep(const ParamValues& values, QWidget* parent) {
  if (!scenario_ || !last_dataset_ || !result_) return nullptr;
  auto* d = new SweepDialog(scenario_, last_dataset_, values, result_->metrics, parent);
  d->setAttribute(Qt::WA_DeleteOnClose);
  connect(d, &SweepDialog::pointChosen, this,
          [this](const ParamValues& v) { emit valuesChosen(v, "sweep point"); });
  d->show();
  return d;
}

MonteCarloDialog* RunController::openMonteCarlo(const ParamValues& values, QWidget* parent) {
  if (!scenario_) return nullptr;
  if (file_) {  // seeds simulate; the Simulator group is off for data from a file
    QMessageBox::information(parent, "Monte Carlo",
                             "Monte Carlo simulates each seed: use "
                             "simulated data (File → Use simulated data).");
    return nullptr;
  }
  auto* d = new MonteCarloDialog(scenario_, values, parent);
  d->setAttribute(Qt::WA_DeleteOnClose);
  d->show();
  return d;
}

}  // namespace kfw
