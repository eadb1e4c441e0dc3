// The document controller without a window: values set as a slider would set them (a drag is one
// undo step), undo and redo, pins with their runs, sessions with their view state, adopt steps
// that refuse a document, and the question before unsaved work is thrown away.
#include <gtest/gtest.h>

#include <QFile>
#include <QJsonObject>
#include <QSignalSpy>
#include <QTemporaryDir>

#include "document_controller.h"
#include "run_controller.h"

namespace kfw::document_controller_test {
namespace {

// A document over its runs: the constant-velocity model on 20 s of simulated data.
struct Loaded {
  RunController runs;
  DocumentController doc{&runs};
  Loaded() {
    const Status st = doc.loadPreset("models/cv1d", {}, {"sim.duration=20"});
    EXPECT_TRUE(st.ok()) << (st ? "" : st.error());
    EXPECT_TRUE(runs.waitSettled());
  }
};

TEST(DocumentController, SetUndoRedoWithAPresetLoaded) {
  Loaded l;
  ASSERT_NE(l.doc.document(), nullptr);
  ASSERT_TRUE(l.runs.result());
  const ParamValues start = l.doc.values();
  QSignalSpy history(&l.doc, &DocumentController::historyChanged);
  QSignalSpy changed(&l.doc, &DocumentController::changed);
  l.doc.setValue("sigma_r", 50.0);
  EXPECT_EQ(l.doc.values().at("sigma_r"), 50.0);
  EXPECT_EQ(history.count(), 1);
  EXPECT_EQ(changed.count(), 0);  // the control that set it shows it already
  EXPECT_EQ(l.doc.undoText(), "&Undo set sigma_r");
  ParamValues ran;
  QObject::connect(
      &l.runs, &RunController::finished,
      [&](std::shared_ptr<const RunResult>, const ParamValues& v, double) { ran = v; });
  ASSERT_TRUE(l.runs.waitSettled());
  EXPECT_EQ(ran.at("sigma_r"), 50.0);  // the change asked for a run with it

  ASSERT_TRUE(l.doc.undo());
  EXPECT_EQ(l.doc.values(), start);
  EXPECT_EQ(changed.count(), 1);
  EXPECT_EQ(l.doc.redoText(), "&Redo set sigma_r");
  EXPECT_FALSE(l.doc.undo());
  ASSERT_TRUE(l.doc.redo());
  EXPECT_EQ(l.doc.values().at("sigma_r"), 50.0);
  ASSERT_TRUE(l.runs.waitSettled());
}

TEST(DocumentController, ASliderDragsLaterValuesJoinOneUndoStepAndABadValueIsRefused) {
  Loaded l;
  const double r0 = l.doc.values().at("sigma_r");
  for (double r : {10.0, 20.0, 30.0})
    l.doc.setValue("sigma_r", r);
  EXPECT_EQ(l.doc.values().at("sigma_r"), 30.0);
  ASSERT_TRUE(l.doc.undo());  // the drag, back to where it started
  EXPECT_EQ(l.doc.values().at("sigma_r"), 10.0);
  ASSERT_TRUE(l.doc.undo());
  EXPECT_EQ(l.doc.values().at("sigma_r"), r0);

  QSignalSpy problem(&l.doc, &DocumentController::problem);
  QSignalSpy changed(&l.doc, &DocumentController::changed);
  l.doc.setValue("sigma_r", -1.0);
  EXPECT_EQ(problem.count(), 1);
  EXPECT_EQ(changed.count(), 1);  // the controls go back to the document's value
  EXPECT_EQ(l.doc.values().at("sigma_r"), r0);
  ASSERT_TRUE(l.runs.waitSettled());
}

TEST(DocumentController, NamedValuesAndResetAreOneStepEachAndKeepThePins) {
  Loaded l;
  const ParamValues start = l.doc.values();
  l.doc.pin("base");
  ASSERT_EQ(l.doc.pinCount(), 1);
  EXPECT_TRUE(l.doc.pins().front().result);
  l.doc.setValues({{"sigma_a", 5.0}, {"sigma_r", 0.5}}, "tune");
  EXPECT_EQ(l.doc.undoText(), "&Undo tune");
  ASSERT_TRUE(l.runs.waitSettled());
  l.doc.resetToPreset();  // the preset's own values (without the --set of the load)
  EXPECT_EQ(l.doc.values().at("sigma_a"), start.at("sigma_a"));
  EXPECT_EQ(l.doc.values().at("sigma_r"), start.at("sigma_r"));
  EXPECT_EQ(l.doc.undoText(), "&Undo reset to preset");
  EXPECT_EQ(l.doc.pinCount(), 1);
  ASSERT_TRUE(l.runs.waitSettled());
  l.doc.clearPins();
  EXPECT_EQ(l.doc.pinCount(), 0);
  ASSERT_TRUE(l.doc.undo());  // the pin comes back, with its run
  ASSERT_EQ(l.doc.pinCount(), 1);
  EXPECT_TRUE(l.doc.pins().front().result);
  EXPECT_EQ(l.doc.pinnedRuns(false).size(), 1);
  ASSERT_TRUE(l.runs.waitSettled());
}

TEST(DocumentController, SessionSavesAndLoadsValuesPinsAndViewState) {
  QTemporaryDir dir;
  const QString path = dir.filePath("s.json");
  {
    Loaded l;
    l.doc.addViewStatePart(
        "probe", [] { return QJsonValue(42); }, [](const QJsonValue&) {});
    l.doc.setValue("sigma_a", 10.0);
    ASSERT_TRUE(l.runs.waitSettled());
    l.doc.pin("tuned");
    EXPECT_TRUE(l.doc.document()->dirty());
    ASSERT_TRUE(l.doc.saveSession(path).ok());
    EXPECT_FALSE(l.doc.document()->dirty());
  }
  RunController runs;
  DocumentController doc(&runs);
  QJsonValue restored;
  doc.addViewStatePart(
      "probe", [] { return QJsonValue(); }, [&](const QJsonValue& v) { restored = v; });
  QSignalSpy replaced(&doc, &DocumentController::documentReplaced);
  ASSERT_TRUE(doc.loadSession(path).ok());
  EXPECT_EQ(replaced.count(), 1);
  EXPECT_EQ(doc.values().at("sigma_a"), 10.0);
  ASSERT_EQ(doc.pinCount(), 1);
  EXPECT_EQ(doc.pins().front().snap.name, "tuned");
  EXPECT_TRUE(doc.pins().front().result);  // run on the session's data once it loaded
  EXPECT_EQ(restored.toInt(), 42);
  EXPECT_FALSE(doc.loadSession(dir.filePath("missing.json")).ok());
  EXPECT_EQ(doc.values().at("sigma_a"), 10.0);
}

TEST(DocumentController, OldViewStatesRestoreTheirGeometryAndSplitters) {
  RunController runs;
  DocumentController doc(&runs);
  QJsonValue geometry, splitters;
  doc.addViewStatePart(
      "geometry", [] { return QJsonValue(); }, [&](const QJsonValue& v) { geometry = v; });
  doc.addViewStatePart(
      "splitters", [] { return QJsonValue(); }, [&](const QJsonValue& v) { splitters = v; });
  doc.restoreViewState("R0VP:TUFJTg==:TEVGVA==");
  EXPECT_EQ(geometry.toString(), "R0VP");
  EXPECT_EQ(splitters.toObject()["mainSplit"].toString(), "TUFJTg==");
  EXPECT_EQ(splitters.toObject()["leftSplit"].toString(), "TEVGVA==");
}

TEST(DocumentController, AFailingAdoptStepLeavesTheOpenDocument) {
  Loaded l;
  bool refuse = true;
  int committed = 0;
  l.doc.addAdoptStep([&](const Document&) -> Expected<DocumentController::Commit> {
    if (refuse) return Error{"no plots for this one"};
    return DocumentController::Commit([&] { ++committed; });
  });
  QSignalSpy replaced(&l.doc, &DocumentController::documentReplaced);
  const Status st = l.doc.loadPreset("models/cv1d", {}, {"sim.duration=5"});
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error(), "no plots for this one");
  EXPECT_EQ(l.doc.values().at("sim.duration"), 20.0);
  EXPECT_EQ(replaced.count(), 0);
  EXPECT_EQ(committed, 0);
  refuse = false;
  ASSERT_TRUE(l.doc.loadPreset("models/cv1d", {}, {"sim.duration=5"}).ok());
  EXPECT_EQ(committed, 1);
  EXPECT_EQ(replaced.count(), 1);
  ASSERT_TRUE(l.runs.waitSettled());
}

TEST(DocumentController, AsksBeforeDiscardingOnlyUnsavedWorkOrPins) {
  Loaded l;
  QStringList asked;
  l.doc.setConfirmHandler([&](const QString& q) {
    asked << q;
    return false;
  });
  EXPECT_TRUE(l.doc.confirmDiscard("Quit"));
  EXPECT_TRUE(asked.isEmpty());
  l.doc.setValue("sigma_r", 5.0);
  ASSERT_TRUE(l.runs.waitSettled());
  l.doc.pin("a");
  EXPECT_FALSE(l.doc.confirmDiscard("Switch preset"));
  ASSERT_EQ(asked.size(), 1);
  EXPECT_EQ(asked.front(), "Switch preset: discard unsaved changes and 1 pinned snapshot?");
}

// Issue 32, item 10: no question where nothing would be lost — after Reset, after opening the
// session that holds the pins — and none before a file that does not load.
TEST(DocumentController, AsksOnlyWhenSomethingWouldBeLost) {
  RunController runs;
  DocumentController doc(&runs);
  ASSERT_TRUE(doc.loadPreset("models/cv1d").ok());
  ASSERT_TRUE(runs.waitSettled());
  QStringList asked;
  doc.setConfirmHandler([&](const QString& q) {
    asked << q;
    return false;
  });
  doc.setValue("sigma_r", 5.0);
  ASSERT_TRUE(runs.waitSettled());
  EXPECT_TRUE(doc.document()->dirty());
  doc.resetToPreset();
  ASSERT_TRUE(runs.waitSettled());
  EXPECT_FALSE(doc.document()->dirty());
  EXPECT_TRUE(doc.confirmDiscard("Quit"));
  EXPECT_TRUE(asked.isEmpty());
  doc.pin("a");  // a pin on a preset is saved nowhere
  EXPECT_FALSE(doc.confirmDiscard("Quit"));
  ASSERT_EQ(asked.size(), 1);
  QTemporaryDir dir;
  const QString path = dir.filePath("s.json");
  ASSERT_TRUE(doc.saveSession(path).ok());
  EXPECT_TRUE(doc.confirmDiscard("Quit"));
  doc.setConfirmHandler([](const QString&) { return true; });
  ASSERT_TRUE(doc.loadSession(path, "Open session").ok());
  ASSERT_TRUE(runs.waitSettled());
  doc.setConfirmHandler([&](const QString& q) {
    asked << q;
    return false;
  });
  EXPECT_EQ(doc.document()->snapshots().size(), 1u);
  EXPECT_TRUE(doc.confirmDiscard("Open preset"));  // the pin is in the session file
  EXPECT_EQ(asked.size(), 1);
  // Unsaved work, then a file that does not load: refused before any question, nothing changes.
  doc.setValue("sigma_r", 7.0);
  ASSERT_TRUE(runs.waitSettled());
  const QString bad = dir.filePath("bad.json");
  QFile f(bad);
  ASSERT_TRUE(f.open(QIODevice::WriteOnly));
  f.write("{ not json");
  f.close();
  EXPECT_FALSE(doc.loadPreset(bad, {}, {}, {}, "Open preset").ok());
  EXPECT_EQ(asked.size(), 1);
  EXPECT_EQ(doc.values().at("sigma_r"), 7.0);
  // A file that loads asks, and a "no" keeps the open document.
  EXPECT_TRUE(doc.loadPreset("models/ca1d", {}, {}, {}, "Open preset").ok());
  EXPECT_EQ(asked.size(), 2);
  EXPECT_EQ(doc.values().at("sigma_r"), 7.0);
}

}  // namespace
}  // namespace kfw::document_controller_test
