// GUI latency: parameter change → run → every plot replotted, over many changes.
#pragma once

#include <vector>

namespace kfw {

class MainWindow;

struct LatencyStats {
  double p50_ms = 0, p95_ms = 0, max_ms = 0;
  std::vector<double> samples_ms;
  // The CPU time of the two threads at work per change (the worker's run, the GUI thread's
  // drawing and repaint): what the latency would be on an idle machine, when others load it.
  double cpu_p50_ms = 0, cpu_p95_ms = 0;
  // Mouse moves over the first time plot, each to the readout (cursor line on every time plot,
  // values on the hovered one) repainted.
  double readout_p50_ms = 0, readout_p95_ms = 0;
};

// Sweeps the first log-scale parameter (Q) across its slider `changes` times, one change at a
// time, and measures request → plots redrawn (including the repaint).
LatencyStats measureLatency(MainWindow& w, int changes);

}  // namespace kfw
