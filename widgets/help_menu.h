// Orientation: Help → Usage (the README's "Using it" section) and About, and where the README is.
#pragma once

#include <QString>

class QMainWindow;

namespace kfw::help {

// The README: in the source tree beside presets/, else installed beside the executable.
QString readmePath();
// The README's usage section as Markdown; empty when no README is found.
QString usageText();
// The About text: version and licences.
QString aboutText();
// Adds the Help menu (Usage, About) to `window`'s menu bar.
void addMenu(QMainWindow* window);

}  // namespace kfw::help
