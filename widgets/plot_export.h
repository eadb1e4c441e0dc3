// Writes plots to PNG / PDF / SVG at a fixed size, with or without a display.
#pragma once

#include <QList>
#include <QString>
#include <QStringList>

#include "core/expected.h"
#include "scenario_view.h"

namespace kfw {

inline constexpr int kExportWidth = 1200;
inline constexpr int kExportHeight = 700;

// One plot to one file; the format comes from the extension (.png, .pdf, .svg).
Status exportPlot(QCustomPlot* plot, const QString& path, int width = kExportWidth,
                  int height = kExportHeight);
// Every panel in every format into dir (created if needed); returns the files written.
Expected<QStringList> exportPanels(const QList<PlotPanel>& panels, const QString& dir,
                                   const QStringList& formats, const QString& prefix = {});
// Parses "png,pdf,svg"; the message names an unknown format.
Expected<QStringList> parseFormats(const QString& list);

}  // namespace kfw
