// The look of plots beyond plot_kit's house style: a light or dark theme applied to an existing
// QCustomPlot and to the window's palette, the presentation look (fonts and pens scaled, bands and
// ghosts strong enough for a projector), and titles wrapped to fit instead of cut.
//
// Every change records what it replaced (dynamic properties on the element), so applying the
// light theme or a scale of 1 gives back the plot exactly as plot_kit made it.
#pragma once

#include <QFont>
#include <QString>

class QCustomPlot;
class QWidget;

namespace kfw {

enum class Theme { kLight, kDark };

// What a plot looks like beyond plot_kit: theme, every font × font_scale, and the projector look
// (strong: wider pens, opaque ghosts, saturated bands).
struct PlotLook {
  Theme theme = Theme::kLight;
  double font_scale = 1.0;
  bool strong = false;
};
PlotLook plotLook(const QCustomPlot* plot);
// Restyles every element of the plot from its original (plot_kit's) look. Does not replot.
void setPlotLook(QCustomPlot* plot, const PlotLook& look);

// Background, axes, grid, text and legend colours; in the dark theme the black truth curve turns
// light. Does not replot.
void applyTheme(QCustomPlot* plot, Theme theme);
Theme currentTheme(const QCustomPlot* plot);
// The window's palette for a theme (Fusion style colours; light: the platform's).
void applyWindowTheme(QWidget* window, Theme theme);

// The presentation look: every font × `font_scale`, axis, grid and data pens wider, band fills
// and ghost curves opaque and saturated. scale 1 and strong false: plot_kit's look. Does not
// replot.
void applyPresentationLook(QCustomPlot* plot, double font_scale, bool strong);

// Breaks `text` at spaces into lines no wider than `width` px in `font` (a single word wider
// than that stays whole on its line).
QString wrapText(const QString& text, const QFont& font, int width);
// Wraps every title of the plot to its current width (after a resize or a font change), from the
// title's unwrapped text. Returns true when a title changed.
bool wrapTitlesToWidth(QCustomPlot* plot);
// Sets a makePlot title (unwrapped text; wrapped again before the next replot); nothing when the
// title is already that.
void setTitle(QCustomPlot* plot, const QString& title);
// Set on a plot while an export draws it: its titles are wrapped to the export's width, and
// wrapTitlesToWidth leaves them so.
inline constexpr const char* kExportingProperty = "kfwExporting";

}  // namespace kfw
