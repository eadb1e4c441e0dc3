// Screen-speed drawing of the dense plottables a parameter change redraws: a band's fill as one
// rectangle per pixel column (Qt's polygon filler took ≈ 0.3 ms a band for a 1 400-vertex
// envelope) and dots written straight into an image (QCustomPlot blits a pixmap per dot). The
// picture is the one QCustomPlot draws; exports (antialiased or vector painters, vector dot
// styles) take QCustomPlot's own path.
#pragma once

class QCPAxis;
class QCPGraph;

namespace kfw::plot {

// The lower graph of a band: fills down to its channel-fill graph (the upper edge).
QCPGraph* newBandFill(QCPAxis* key, QCPAxis* value);
// A graph of 2 × 2-pixel dots (a pixmap scatter style with lsNone).
QCPGraph* newDotGraph(QCPAxis* key, QCPAxis* value);

}  // namespace kfw::plot
