// MainWindow's file conveniences (issue 32, item 11): the File menu with recent files, Ctrl+S for
// the session, drag and drop of a CSV, preset or session onto the window, and the command line
// that reproduces the window's state.
#include <QApplication>
#include <QClipboard>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QSettings>

#include "document/command_line.h"
#include "document/session.h"
#include "main_window.h"
#include "window_report.h"

namespace kfw {

using window::q;
using window::report;

namespace {
const char* const kRecentKey = "recent/files";
}  // namespace

void MainWindow::buildFileMenu() {
  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("Open &preset…", this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open preset", q(preset_dir()), "Presets (*.json)");
    // Read first: a file that does not load is refused without asking to discard anything.
    if (!f.isEmpty()) report(this, "Open preset", openAnyFile(f, OpenAs::kPreset));
  });
  file->addAction("&Open CSV…", QKeySequence::Open, this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open dataset", QString(), "CSV (*.csv);;All files (*)");
    if (!f.isEmpty()) report(this, "Open CSV", openAnyFile(f, OpenAs::kData));
  });
  recent_menu_ = file->addMenu("Open &recent");
  recent_menu_->setObjectName("recentMenu");
  connect(recent_menu_, &QMenu::aboutToShow, this, &MainWindow::fillRecentMenu);
  fillRecentMenu();
  file->addAction("Use &simulated data", data_, &DataController::useSimulatedData);
  file->addAction("&Save preset as…", QKeySequence::SaveAs, this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save preset", QString(), "Presets (*.json)");
    if (!f.isEmpty()) report(this, "Save preset", savePreset(f));
  });
  file->addAction("Open s&ession…", this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open session", QString(), "Sessions (*.json)");
    if (!f.isEmpty()) report(this, "Open session", openAnyFile(f, OpenAs::kSession));
  });
  file->addAction("Save s&ession", QKeySequence::Save, this,
                  [this] { report(this, "Save session", saveSessionHere()); });
  file->addAction("Save session &as…", this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save session", "session.json", "Sessions (*.json)");
    if (!f.isEmpty()) report(this, "Save session", saveSessionAs(f));
  });
  file->addAction("&Export plots…", QKeySequence(Qt::CTRL | Qt::Key_E), export_,
                  &ExportController::exportWithDialog);
  file->addAction("Export filter as &C…", this, &MainWindow::exportFilterAsCWithDialog);
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);
  setAcceptDrops(true);
}

Status MainWindow::saveSessionHere() {
  if (session_path_.isEmpty()) {
    const QString f =
        QFileDialog::getSaveFileName(this, "Save session", "session.json", "Sessions (*.json)");
    if (f.isEmpty()) return Ok{};
    return saveSessionAs(f);
  }
  return saveSessionAs(session_path_);
}

Status MainWindow::saveSessionAs(const QString& path) {
  Status st = saveSession(path);
  if (st) {
    session_path_ = path;
    rememberRecent(path);
  }
  return st;
}

MainWindow::OpenAs MainWindow::openAsFor(const QString& path) {
  const QString suffix = QFileInfo(path).suffix().toLower();
  if (suffix != "json") return OpenAs::kData;
  // A session names its format in its first lines; anything else .json is a preset. Only a
  // regular file is read here (a FIFO would block): the loader refuses the others, naming them.
  QFile f(path);
  if (QFileInfo(path).isFile() && f.open(QIODevice::ReadOnly) &&
      QString::fromUtf8(f.read(4096)).contains(kSessionFormat))
    return OpenAs::kSession;
  return OpenAs::kPreset;
}

Status MainWindow::openAnyFile(const QString& path, std::optional<OpenAs> as) {
  const OpenAs kind = as ? *as : openAsFor(path);
  Status st = Ok{};
  if (kind == OpenAs::kData) {
    st = openDataset(path);
  } else if (kind == OpenAs::kPreset) {
    st = loadPreset(path, {}, {}, {}, "Open preset");
    if (st) session_path_.clear();
  } else {
    st = loadSession(path, "Open session");
    if (st) session_path_ = path;
  }
  if (st) rememberRecent(path);
  return st;
}

QStringList MainWindow::recentFiles() {
  return QSettings("kfw", "kfw").value(kRecentKey).toStringList();
}

void MainWindow::rememberRecent(const QString& path) {
  QStringList list = recentFiles();
  const QString abs = QFileInfo(path).absoluteFilePath();
  list.removeAll(abs);
  list.prepend(abs);
  while (list.size() > kRecentFiles)
    list.removeLast();
  QSettings("kfw", "kfw").setValue(kRecentKey, list);
}

void MainWindow::fillRecentMenu() {
  recent_menu_->clear();
  const QStringList list = recentFiles();
  for (const QString& f : list) {
    QAction* a = recent_menu_->addAction(
        QFileInfo(f).fileName(), this, [this, f] { report(this, "Open recent", openAnyFile(f)); });
    a->setToolTip(f);
    a->setEnabled(QFileInfo::exists(f));
  }
  if (list.isEmpty()) recent_menu_->addAction("(none yet)")->setEnabled(false);
  recent_menu_->addSeparator();
  recent_menu_->addAction("Clear the list", this,
                          [] { QSettings("kfw", "kfw").remove(kRecentKey); });
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  const QList<QUrl> urls = event->mimeData()->urls();
  if (urls.size() == 1 && urls.front().isLocalFile()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  const QList<QUrl> urls = event->mimeData()->urls();
  if (urls.size() != 1 || !urls.front().isLocalFile()) return;
  event->acceptProposedAction();
  const QString path = urls.front().toLocalFile();
  if (const Status st = openAnyFile(path); !st) showError(q(st.error()));
}

QString MainWindow::commandLine() const {
  return document() ? q(command_lines(*document())) : QString();
}

void MainWindow::copyCommandLine() {
  const QString text = commandLine();
  if (text.isEmpty()) return;
  QApplication::clipboard()->setText(text);
  status_->setText("Copied: " + text.section('\n', 0, 0) + " (and kfw --export …)");
}

}  // namespace kfw
