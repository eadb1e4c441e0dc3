#include "run_controller.h"

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QMetaObject>
#include <QPointer>
#include <chrono>
#include <ctime>

namespace kfw {

struct RunController::Outcome {
  std::uint64_t generation = 0;
  ParamValues values;
  std::shared_ptr<const Dataset> dataset;
  ParamValues sim_key;
  bool simulated = false;
  std::shared_ptr<const RunResult> result;
  std::string error;
  double ms = 0.0;
  double cpu_ms = 0.0;  // CPU time of the worker thread
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
  ++generation_;
}

void RunController::setFileDataset(std::shared_ptr<const Dataset> data) {
  file_ = std::move(data);
  ++generation_;
}

void RunController::request(const ParamValues& values) {
  if (!scenario_) return;
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
    timespec cpu0{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu0);
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
      }
    }
    out->ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    timespec cpu1{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu1);
    out->cpu_ms = static_cast<double>(cpu1.tv_sec - cpu0.tv_sec) * 1e3 +
                  static_cast<double>(cpu1.tv_nsec - cpu0.tv_nsec) / 1e6;
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
  last_cpu_ms_ = out->cpu_ms;
  if (out->generation == generation_) {
    if (out->simulated) {
      sim_cache_ = out->dataset;
      sim_key_ = out->sim_key;
    }
    if (out->result) {
      if (out->dataset != last_dataset_) {
        last_dataset_ = out->dataset;
        emit datasetChanged(last_dataset_);
      }
      emit finished(out->result, out->values, out->ms);
    } else {
      emit failed(QString::fromStdString(out->error));
    }
  }
  if (pending_) {
    ParamValues next = std::move(*pending_);
    pending_.reset();
    start(next);
  }
}

bool RunController::waitIdle(int timeout_ms) {
  QDeadlineTimer deadline(timeout_ms);
  while (busy_ || pending_) {
    if (deadline.hasExpired()) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents, 5);
  }
  return true;
}

}  // namespace kfw
