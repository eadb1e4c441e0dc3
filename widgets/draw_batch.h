// Two cores for one redraw. While a DrawBatch is open on the GUI thread (a run's result or a
// replay frame being drawn), the reductions of dense series that setSeries() and the band setters
// start (series_reduce.h: pure, Qt-free) run on a helper thread as well as on this one; each
// job's result is handed to its graph on the GUI thread, in the order the jobs were started,
// when the plot needs its data (rescale, replot) or when the batch closes. The plots' replots
// are held until the batch closes. Outside a batch every job runs at once, as before.
#pragma once

#include <functional>

class QCustomPlot;

namespace kfw::plot {

class DrawBatch {
 public:
  DrawBatch();   // nested batches join the outer one
  ~DrawBatch();  // hands every result to its graph, then replots the plots that asked for it
  DrawBatch(const DrawBatch&) = delete;
  DrawBatch& operator=(const DrawBatch&) = delete;
};

// `compute` may run on any thread; `apply` runs on the GUI thread after it. Outside a batch:
// both now. Inside, a job reads its arrays later: they must live until the plot's next
// rescale() or replot() (a run's arrays, a view's members — not a temporary).
void submitDraw(QCustomPlot* plot, std::function<void()> compute, std::function<void()> apply);
// Applies the plot's started jobs (helping with any not yet started), in order.
void settleDraws(QCustomPlot* plot);
// Inside a batch: replot when the batch closes (once); outside: settle and replot now. A plot
// out of view (another tab, scrolled away, hidden) is drawn before it is next painted instead.
void requestReplot(QCustomPlot* plot);
// QCustomPlot's queued replot (after the event loop's turn: a resize settles first), or, out of
// view, the same deferral.
void replotQueued(QCustomPlot* plot);

}  // namespace kfw::plot
