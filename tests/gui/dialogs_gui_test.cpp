// The dialogs a user meets, driven as a user would: the Pin button's name dialog (the default
// name, a typed name, cancel, a blank name), Help → Usage (the README's "Using it" section in a
// browser, closed by its button) and Help → About (version and licence).
#include <gtest/gtest.h>

#include <QAbstractButton>
#include <QAction>
#include <QApplication>
#include <QDialog>
#include <QDialogButtonBox>
#include <QElapsedTimer>
#include <QInputDialog>
#include <QMenuBar>
#include <QMessageBox>
#include <QPointer>
#include <QPushButton>
#include <QTextBrowser>
#include <QTimer>
#include <functional>

#include "main_window.h"

namespace kfw {
namespace {

// Runs `answer` on the first modal dialog that opens while `open` runs (polled from the event
// loop, as exec() spins it); true when one opened.
bool answerModal(const std::function<void()>& open, const std::function<void(QWidget*)>& answer) {
  bool seen = false;
  QTimer poll;
  poll.setInterval(10);
  QObject::connect(&poll, &QTimer::timeout, [&] {
    QWidget* m = QApplication::activeModalWidget();
    if (!m || seen) return;
    seen = true;
    poll.stop();
    answer(m);
  });
  poll.start();
  open();
  poll.stop();
  return seen;
}

QAction* menuAction(const MainWindow& w, const QString& menu, const QString& text) {
  for (QAction* m : w.menuBar()->actions()) {
    if (m->text().remove('&') != menu || !m->menu()) continue;
    for (QAction* a : m->menu()->actions()) {
      if (a->text().remove('&').startsWith(text)) return a;
    }
  }
  return nullptr;
}

class Dialogs : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(w.loadPreset("helicopter", {}, {"sim.duration=5"}).ok());
    w.resize(1366, 768);
    w.show();
    ASSERT_TRUE(w.waitForRun());
    pin = w.findChild<QPushButton*>("pinButton");
    ASSERT_NE(pin, nullptr);
  }
  MainWindow w;
  QPushButton* pin = nullptr;
};

TEST_F(Dialogs, PinAsksForANameWithANumberedDefault) {
  QString offered;
  ASSERT_TRUE(answerModal([&] { pin->click(); },
                          [&](QWidget* m) {
                            auto* d = qobject_cast<QInputDialog*>(m);
                            ASSERT_NE(d, nullptr) << m->metaObject()->className();
                            offered = d->textValue();
                            d->setTextValue("  tight R  ");
                            d->accept();
                          }));
  EXPECT_EQ(offered, "snapshot 1");
  ASSERT_EQ(w.snapshotCount(), 1);
  EXPECT_EQ(w.document()->snapshots().front().name, "tight R");  // trimmed
  // The default counts on; accepting it as offered pins under that name.
  ASSERT_TRUE(answerModal([&] { pin->click(); },
                          [&](QWidget* m) {
                            auto* d = qobject_cast<QInputDialog*>(m);
                            ASSERT_NE(d, nullptr);
                            offered = d->textValue();
                            d->accept();
                          }));
  EXPECT_EQ(offered, "snapshot 2");
  ASSERT_EQ(w.snapshotCount(), 2);
  EXPECT_EQ(w.document()->snapshots().back().name, "snapshot 2");
}

TEST_F(Dialogs, PinCancelledOrBlankPinsNothing) {
  ASSERT_TRUE(
      answerModal([&] { pin->click(); }, [](QWidget* m) { static_cast<QDialog*>(m)->reject(); }));
  EXPECT_EQ(w.snapshotCount(), 0);
  ASSERT_TRUE(answerModal([&] { pin->click(); },
                          [](QWidget* m) {
                            auto* d = qobject_cast<QInputDialog*>(m);
                            ASSERT_NE(d, nullptr);
                            d->setTextValue("   ");
                            d->accept();
                          }));
  EXPECT_EQ(w.snapshotCount(), 0);
}

TEST_F(Dialogs, UsageShowsTheReadmeSectionAndCloses) {
  QAction* usage = menuAction(w, "Help", "Usage");
  ASSERT_NE(usage, nullptr);
  EXPECT_EQ(usage->shortcut(), QKeySequence(QKeySequence::HelpContents));
  usage->trigger();
  QApplication::processEvents();
  auto* browser = w.findChild<QTextBrowser*>("usageBrowser");
  ASSERT_NE(browser, nullptr);
  QPointer<QDialog> dialog = qobject_cast<QDialog*>(browser->window());
  ASSERT_NE(dialog, nullptr);
  EXPECT_TRUE(dialog->isVisible());
  const QString text = browser->toPlainText();
  // The section and its subsections, not the next level-2 section.
  EXPECT_TRUE(text.contains("Using it")) << text.left(200).toStdString();
  EXPECT_TRUE(text.contains("Presentation mode"));
  EXPECT_TRUE(text.contains("Exit codes"));
  EXPECT_FALSE(text.contains("Quick start"));
  EXPECT_FALSE(text.contains("Scenario helicopter"));
  // Rendered Markdown: no heading marks left.
  EXPECT_FALSE(text.contains("## ")) << "markdown not rendered";
  auto* buttons = dialog->findChild<QDialogButtonBox*>();
  ASSERT_NE(buttons, nullptr);
  QAbstractButton* close = buttons->button(QDialogButtonBox::Close);
  ASSERT_NE(close, nullptr);
  close->click();
  QApplication::sendPostedEvents(nullptr, QEvent::DeferredDelete);
  QApplication::processEvents();
  EXPECT_TRUE(dialog.isNull()) << "the usage dialog is deleted on close";
}

TEST_F(Dialogs, AboutNamesVersionAndLicences) {
  QAction* about = menuAction(w, "Help", "About");
  ASSERT_NE(about, nullptr);
  QString text;
  ASSERT_TRUE(answerModal([&] { about->trigger(); },
                          [&](QWidget* m) {
                            auto* box = qobject_cast<QMessageBox*>(m);
                            ASSERT_NE(box, nullptr) << m->metaObject()->className();
                            text = box->text();
                            box->accept();
                          }));
  EXPECT_TRUE(text.contains("GPL-3.0-or-later")) << text.toStdString();
  EXPECT_TRUE(text.contains("QCustomPlot"));
  EXPECT_TRUE(text.contains("CC BY 4.0"));
  const QString version = QApplication::applicationVersion().isEmpty()
                              ? QString("0.1.0")
                              : QApplication::applicationVersion();
  EXPECT_TRUE(text.contains("kfw " + version)) << text.toStdString();
}

}  // namespace
}  // namespace kfw
