#include "draw_batch.h"

#include <qcustomplot.h>

#include <QEvent>
#include <QSet>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace kfw::plot {

namespace {

struct Job {
  QCustomPlot* plot = nullptr;
  std::function<void()> compute, apply;
  std::atomic<int> state{0};  // 0 waiting, 1 computing, 2 computed
};

// One helper thread, started with the first batch that has work for it.
class Helper {
 public:
  ~Helper() {
    {
      std::lock_guard lock(m_);
      stop_ = true;
    }
    work_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  void post(const std::shared_ptr<Job>& job) {
    {
      std::lock_guard lock(m_);
      if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
      queue_.push_back(job);
    }
    work_.notify_one();
  }

  // Computes the job unless another thread has taken it.
  void run(Job& job) {
    int waiting = 0;
    if (!job.state.compare_exchange_strong(waiting, 1)) return;
    job.compute();
    {
      std::lock_guard lock(m_);
      job.state.store(2);
    }
    done_.notify_all();
  }

  // Until `job` is computed: computes waiting jobs (any plot's), else sleeps.
  void waitFor(Job& job) {
    while (job.state.load() != 2) {
      std::shared_ptr<Job> other;
      {
        std::lock_guard lock(m_);
        if (!queue_.empty()) {
          other = std::move(queue_.front());
          queue_.pop_front();
        }
      }
      if (other) {
        run(*other);
        continue;
      }
      std::unique_lock lock(m_);
      done_.wait(lock, [&] { return job.state.load() == 2; });
    }
  }

 private:
  void loop() {
    for (;;) {
      std::shared_ptr<Job> job;
      {
        std::unique_lock lock(m_);
        work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      run(*job);
    }
  }

  std::mutex m_;
  std::condition_variable work_, done_;
  std::deque<std::shared_ptr<Job>> queue_;
  std::thread thread_;
  bool stop_ = false;
};

Helper& helper() {
  static Helper h;
  return h;
}

// A plot that is not on screen (another tab, scrolled out of the plot area, a hidden window)
// is not drawn when asked: it is marked, and drawn before it is next painted (exports draw at
// their own size and do not need it). A slider drag then draws only the panels in view.
class DeferredReplots final : public QObject {
 public:
  static DeferredReplots& instance() {
    static auto* d = new DeferredReplots;  // lives as long as the application's plots
    return *d;
  }
  void replot(QCustomPlot* p, QCustomPlot::RefreshPriority priority) {
    if (!watched_.contains(p)) {
      watched_.insert(p);
      p->installEventFilter(this);
      connect(p, &QObject::destroyed, this, [this, p] {
        watched_.remove(p);
        stale_.remove(p);
      });
    }
    if (inView(p)) {
      stale_.remove(p);
      p->replot(priority);
      return;
    }
    stale_.insert(p);
  }

 protected:
  bool eventFilter(QObject* o, QEvent* e) override {
    auto* p = static_cast<QCustomPlot*>(o);
    if (e->type() == QEvent::Paint || e->type() == QEvent::Show) {
      if (stale_.remove(p)) p->replot(QCustomPlot::rpQueuedRefresh);
    } else if (e->type() == QEvent::Resize && !inView(p)) {
      // QCustomPlot redraws on every resize (a relayout after a run resizes every panel): out
      // of view, only its viewport follows now.
      p->setViewport(p->rect());
      stale_.insert(p);
      return true;
    }
    return false;
  }

  static bool inView(const QCustomPlot* p) {
    return p->isVisible() && !p->visibleRegion().isEmpty();
  }

 private:
  QSet<QCustomPlot*> watched_, stale_;
};

void replotNow(QCustomPlot* p) {
  DeferredReplots::instance().replot(p, QCustomPlot::rpQueuedRefresh);
}

// GUI-thread state of the open batch.
int g_depth = 0;
std::vector<std::shared_ptr<Job>> g_pending;  // in submission order
std::vector<QPointer<QCustomPlot>> g_replots;

void finish(Job& job) {
  helper().run(job);
  helper().waitFor(job);
  job.apply();
}

}  // namespace

DrawBatch::DrawBatch() {
  ++g_depth;
}

DrawBatch::~DrawBatch() {
  if (--g_depth > 0) return;
  // Every job, in order (a job may still run on the helper: wait for it).
  auto pending = std::move(g_pending);
  g_pending.clear();
  for (const auto& job : pending)
    finish(*job);
  auto replots = std::move(g_replots);
  g_replots.clear();
  for (const auto& p : replots) {
    if (p) replotNow(p);
  }
}

void submitDraw(QCustomPlot* plot, std::function<void()> compute, std::function<void()> apply) {
  if (g_depth == 0) {
    if (compute) compute();
    apply();
    return;
  }
  auto job = std::make_shared<Job>();
  job->plot = plot;
  job->apply = std::move(apply);
  if (compute) {
    job->compute = std::move(compute);
    g_pending.push_back(job);
    helper().post(job);
  } else {
    job->state.store(2);  // nothing to compute: only its turn to apply
    g_pending.push_back(job);
  }
}

void settleDraws(QCustomPlot* plot) {
  if (g_pending.empty()) return;
  std::vector<std::shared_ptr<Job>> rest;
  rest.reserve(g_pending.size());
  auto pending = std::move(g_pending);
  g_pending.clear();
  for (auto& job : pending) {
    if (job->plot == plot) {
      finish(*job);
    } else {
      rest.push_back(std::move(job));
    }
  }
  // Jobs submitted by an apply (none today) come after the ones still waiting.
  rest.insert(rest.end(), g_pending.begin(), g_pending.end());
  g_pending = std::move(rest);
}

void requestReplot(QCustomPlot* plot) {
  if (g_depth == 0) {
    settleDraws(plot);
    replotNow(plot);
    return;
  }
  settleDraws(plot);  // the plot's jobs end with its drawing code (their arrays live that long)
  for (const auto& p : g_replots) {
    if (p == plot) return;
  }
  g_replots.emplace_back(plot);
}

void replotQueued(QCustomPlot* plot) {
  DeferredReplots::instance().replot(plot, QCustomPlot::rpQueuedReplot);
}

}  // namespace kfw::plot
