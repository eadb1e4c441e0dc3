// Shared QCustomPlot conventions: one look for every scenario's plots (titles, units, legends,
// colours), and NaN-aware series setters that reveal data up to the replay cursor.
#pragma once

#include <QColor>
#include <QString>
#include <cstddef>
#include <initializer_list>
#include <vector>

class QCustomPlot;
class QCPGraph;
class QCPCurve;
class QCPAbstractPlottable;
class QCPAxis;
class QCPItemStraightLine;
class QCPItemTracer;
class QWidget;

namespace kfw::plot {

// Colours with fixed meanings across the workbench.
namespace color {
inline const QColor kTruth{0, 0, 0};
inline const QColor kSensor{150, 150, 150};
inline const QColor kEstimate{31, 119, 180};
inline const QColor kSecond{214, 39, 40};
inline const QColor kThird{44, 160, 44};
inline const QColor kFourth{255, 127, 14};
inline const QColor kFifth{148, 103, 189};
inline const QColor kBound{120, 120, 120};
QColor cycle(int i);  // a distinct colour for series i
// The faded colour of pinned snapshot i (0, 1, ...): the same in every scenario, none of the
// colours with a fixed meaning above.
QColor ghost(int i);
}  // namespace color

// A plot with title, axis labels (units in them), legend and the house fonts. The legend sits in
// its own row between the title and the axis rect (it never covers data), wrapped into as many
// columns as the plot's width holds.

QCustomPlot* makePlot(QWidget* parent, const QString& title, const QString& xLabel,
                      const QString& yLabel);
enum class Style { kLine, kDots, kStep, kDashed };
// A curve the user hid by clicking its legend entry (a band: both edges): it stays hidden through
// the view's redraws until clicked again; its entry is greyed.
bool userHidden(const QCPAbstractPlottable* c);
void setUserHidden(QCPAbstractPlottable* c, bool hidden);
void keepUserHidden(QCustomPlot* p);
// Pens wider than 1 px go through Qt's stroker, several times slower on dense data: keep data
// pens at 1 px unless a curve has few points (width > 1 is for those).
QCPGraph* addGraph(QCustomPlot* p, const QString& name, const QColor& c, Style s = Style::kLine,
                   double width = 1.0);
// A graph drawn on the right-hand y axis (which the call turns on, labelled).
QCPGraph* addGraphRight(QCustomPlot* p, const QString& name, const QColor& c,
                        const QString& rightLabel);
// Exports draw antialiased, with vector dots; the screen draws without antialiasing and blits
// dots (a slider drag redraws every plot). Switches a plot between the two looks.
void setExportLook(QCustomPlot* p, bool exporting);
// Wraps a makePlot legend (in its row under the title) into as many columns as `width` pixels
// hold, entries filling rows first: before every replot at the plot's width, and by an export at
// the figure's (a plot never drawn in the window has not been wrapped at all).
void fitLegend(QCustomPlot* p, int width);
// Log scale with decade ticks.
void setLog(QCPAxis* axis);

// Sets the first n points (n clipped to the data). skipNaN: drop non-finite points (the line
// joins across them); otherwise a non-finite y draws a gap (kept when a dense series is reduced).
void setSeries(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y,
               std::size_t n, bool skipNaN = true);
// Dots in any order (a raster of events, say), reduced to one per 2 × 2-pixel cell when dense.
void setDots(QCPGraph* g, const std::vector<double>& x, const std::vector<double>& y);
// A parametric curve (a trajectory) through the first n points, without the points that stay
// inside the last kept point's cell of a grid finer than the screen.
void setCurve(QCPCurve* c, const std::vector<double>& keys, const std::vector<double>& values,
              std::size_t n);
inline constexpr std::size_t kAll = static_cast<std::size_t>(-1);

// A shaded band center ± halfwidth (two graphs, the lower filled to the upper).
struct Band {
  QCPGraph* upper = nullptr;
  QCPGraph* lower = nullptr;
};
// Add bands first: an opaque band hides what is under it. `overlaps`: the band shares its area
// with other bands (a translucent fill, slower to draw).
Band addBand(QCustomPlot* p, const QString& name, const QColor& c, bool overlaps = false);
void setBand(const Band& b, const std::vector<double>& x, const std::vector<double>& center,
             const std::vector<double>& halfwidth, std::size_t n);
// A band center ± k·√variance (center null: 0 ± k·√variance); a negative or non-finite variance
// leaves its step out. The square roots are taken only for the steps drawn.
void setSigmaBand(const Band& b, const std::vector<double>& x, const std::vector<double>* center,
                  const std::vector<double>& variance, double k, std::size_t n);
// Bands that overlap others (drawn translucent): both edges drawn in the band's own colour,
// opaque, `width` px, in `style` (solid, dashed, dotted: one per band), so each band reads where
// the fills blend; the legend swatch shows the same edge lines.
void outlineBand(const Band& b, Qt::PenStyle style, double width = 1.5);
// A band between two given curves. `gaps`: a step with a non-finite limit breaks the band
// (otherwise it is left out and the band joins across it).
void setBandLimits(const Band& b, const std::vector<double>& x, const std::vector<double>& lo,
                   const std::vector<double>& hi, std::size_t n, bool gaps = false);

// The curve of pinned snapshot i (0, 1, ...): 2 px, dashed, its own faded colour; `name` is its
// legend entry and should name the snapshot.
QCPGraph* addGhost(QCustomPlot* p, const QString& name, int i, Style s = Style::kLine);

// Removes plottables (ghost curves, ...) from whichever plot holds each.
void removePlottables(std::initializer_list<QCPAbstractPlottable*> plottables);

// A vertical line at the replay cursor.
QCPItemStraightLine* addCursor(QCustomPlot* p);
void setCursorAt(QCPItemStraightLine* line, double x, bool visible);
// A horizontal reference line (χ² bound, set-point, ...) that stays put when rescaling.
QCPItemStraightLine* addHLine(QCustomPlot* p, double y, const QColor& c,
                              Qt::PenStyle s = Qt::DashLine);
void setHLine(QCPItemStraightLine* line, double y);

// The user's view: an axis the user zoomed or panned keeps its range through rescale() until
// the zoom is reset (widgets/plot_zoom.h links the time axes and handles the mouse).
bool userZoomedX(const QCustomPlot* p);
bool userZoomedY(const QCustomPlot* p);
void setUserZoom(QCustomPlot* p, bool x, bool y);
// The plot layout's row that holds the axis rect (makePlot puts a title and a legend row above).
int axisRectRow(QCustomPlot* p);
// True for a plot whose x axis is the run's time (rescale() was given [x0, x1]).
bool isTimePlot(const QCustomPlot* p);

// The source arrays behind a graph that setSeries() reduced for drawing (the readout reads
// exact values from them); null when the graph holds every point itself.
struct SeriesSource {
  const std::vector<double>* x = nullptr;
  const std::vector<double>* y = nullptr;
  std::size_t n = 0;
};
SeriesSource seriesSource(const QCPGraph* g);
// The exact limits behind a band that setBand / setSigmaBand / setBandLimits filled (drawn as its
// per-column envelope when dense), at the last step at or before t; false when `upper` is no
// such band's upper edge or t is before its first step.
bool bandLimitsAt(const QCPGraph* upper, double t, double& lo, double& hi);

// Rescales both axes to the visible data with a small margin (an axis the user zoomed keeps its
// range); keeps x fixed to [x0, x1] when
// x1 > x0 (so replay does not squeeze the time axis). With settle > x0 the value axes hold only
// the data from `settle` on, so a start-up transient does not flatten the rest (the transient
// runs off the top).
void rescale(QCustomPlot* p, double x0 = 0.0, double x1 = 0.0, double settle = 0.0);
// rescale() ignoring the user's zoom.
void rescaleAuto(QCustomPlot* p, double x0 = 0.0, double x1 = 0.0, double settle = 0.0);
// Where a start-up transient is over, for rescale(): 5 % into [t0, t1].
inline double settleTime(double t0, double t1) {
  return t0 + 0.05 * (t1 - t0);
}
void replot(QCustomPlot* p);

}  // namespace kfw::plot
