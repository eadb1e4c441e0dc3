// GUI latency: parameter change → run → every plot replotted, over many changes.
#pragma once

#include <vector>

namespace kfw {

class MainWindow;

struct LatencyStats {
  double p50_ms = 0, p95_ms = 0, max_ms = 0;
  std::vector<double> samples_ms;
};

// Sweeps the first log-scale parameter (Q) across its slider `changes` times, one change at a
// time, and measures request → plots redrawn (including the repaint).
LatencyStats measureLatency(MainWindow& w, int changes);

}  // namespace kfw
