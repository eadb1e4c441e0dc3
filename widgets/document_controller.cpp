#include "document_controller.h"

#include <QInputDialog>
#include <QJsonDocument>
#include <QJsonObject>
#include <QMessageBox>
#include <QWidget>

#include "document/workspace.h"
#include "run_controller.h"

namespace kfw {

namespace {
const ParamValues kEmpty;
const Preset kNoPreset;
QString q(const std::string& s) {
  return QString::fromStdString(s);
}
}  // namespace

DocumentController::DocumentController(RunController* runs, QWidget* window)
    : QObject(window), runs_(runs), window_(window) {}

DocumentController::~DocumentController() = default;

Status DocumentController::loadPreset(const QString& preset,
                                      const std::optional<QString>& data_file,
                                      const QStringList& assignments, const ImportArgs& import,
                                      const QString& ask) {
  std::vector<std::string> sets;
  for (const auto& a : assignments)
    sets.push_back(a.toStdString());
  std::optional<std::string> d;
  if (data_file) d = data_file->toStdString();
  auto doc = Document::open(preset.toStdString(), d, sets, import);
  if (!doc) return doc.err();
  if (!ask.isEmpty() && !confirmDiscard(ask)) return Ok{};
  const std::vector<std::string> notices = doc->notices();
  if (auto st = adopt(std::move(*doc)); !st) return st;
  showNotices(notices);
  return Ok{};
}

void DocumentController::showNotices(const std::vector<std::string>& notices) {
  QStringList lines;
  for (const auto& n : notices)
    lines << q(n);
  if (!lines.isEmpty()) emit problem(lines.join("\n"));
}

Status DocumentController::adopt(Document doc) {
  std::vector<Commit> commits;
  for (const auto& step : steps_) {
    auto commit = step(doc);
    if (!commit) return commit.err();
    commits.push_back(std::move(*commit));
  }
  doc_ = std::make_unique<Document>(std::move(doc));
  pins_.clear();
  for (const auto& snap : doc_->snapshots())
    pins_.push_back({snap, nullptr, nullptr});
  runs_->setScenario(doc_->scenario_ptr());
  for (const auto& commit : commits)
    commit();
  emit documentReplaced();
  emit historyChanged();
  requestRun();
  return Ok{};
}

const Preset& DocumentController::preset() const {
  return doc_ ? doc_->preset() : kNoPreset;
}

const ParamValues& DocumentController::values() const {
  return doc_ ? doc_->values() : kEmpty;
}

std::shared_ptr<const Scenario> DocumentController::scenario() const {
  return doc_ ? doc_->scenario_ptr() : nullptr;
}

void DocumentController::setValue(const std::string& key, double value) {
  if (!doc_) return;
  const bool drag = key == last_edit_key_ && last_edit_.isValid() && last_edit_.elapsed() < 800;
  last_edit_key_ = key;
  last_edit_.start();
  if (auto st = doc_->set_value(key, value, drag ? UndoMerge::kMergeSameKey : UndoMerge::kNewStep);
      !st) {
    emit problem(q(st.error()));
    emit changed();  // the controls go back to the document's values
    return;
  }
  emit historyChanged();
  requestRun();
}

void DocumentController::setValues(const ParamValues& values, const QString& label) {
  if (!doc_) return;
  if (auto st = doc_->set_values(values, label.toStdString()); !st) {
    emit problem(q(st.error()));
    return;
  }
  emit changed();
  emit historyChanged();
  requestRun();
}

void DocumentController::setData(std::optional<DataRef> data) {
  if (!doc_) return;
  doc_->set_data(std::move(data));
  emit historyChanged();
}

Status DocumentController::setMapping(const Mapping& mapping) {
  if (!doc_) return Error{"load a preset first"};
  if (auto st = doc_->set_mapping(mapping); !st) return st;
  sync();  // the data are read with the new mapping; undo restores the old one
  return Ok{};
}

void DocumentController::setTuningSet(const QStringList& paths) {
  if (!doc_) return;
  std::vector<DataRef> logs;
  for (const auto& p : paths)
    logs.push_back({p.toStdString(), doc_->preset().mapping});
  doc_->set_tuning_set(std::move(logs));
  emit historyChanged();
}

bool DocumentController::undo() {
  if (!doc_ || !doc_->undo()) return false;
  sync();
  return true;
}

bool DocumentController::redo() {
  if (!doc_ || !doc_->redo()) return false;
  sync();
  return true;
}

void DocumentController::resetToPreset() {
  if (!doc_) return;
  doc_->reset_to_preset();  // one undo step; the snapshots stay
  sync();
}

void DocumentController::sync() {
  // Keep the runs of snapshots that are still there; re-run the ones that came back.
  std::vector<Pin> next;
  for (const auto& snap : doc_->snapshots()) {
    Pin p{snap, nullptr, nullptr};
    for (const auto& old : pins_) {
      if (old.snap == snap) p = old;
    }
    next.push_back(std::move(p));
  }
  pins_ = std::move(next);
  emit changed();
  refreshPins();
  emit historyChanged();
  requestRun();
}

QString DocumentController::undoText() const {
  return doc_ && doc_->can_undo() ? "&Undo " + q(doc_->undo_label()) : QString("&Undo");
}

QString DocumentController::redoText() const {
  return doc_ && doc_->can_redo() ? "&Redo " + q(doc_->redo_label()) : QString("&Redo");
}

void DocumentController::requestRun() {
  if (doc_) runs_->request(doc_->values());
}

void DocumentController::pin(const QString& name) {
  if (!doc_ || !runs_->result()) return;
  Snapshot snap{name.toStdString(), values()};
  doc_->add_snapshot(snap);
  pins_.push_back({snap, runs_->result(), runs_->dataset()});
  emit historyChanged();
  refreshPins();
}

void DocumentController::askPin(const QString& prompt, bool trimmed) {
  bool ok = false;
  QString name = QInputDialog::getText(window_, "Pin snapshot", prompt, QLineEdit::Normal,
                                       QString("snapshot %1").arg(pins_.size() + 1), &ok);
  if (trimmed) name = name.trimmed();
  if (ok && !name.isEmpty()) pin(name);
}

void DocumentController::clearPins() {
  if (doc_) doc_->clear_snapshots();
  pins_.clear();
  emit historyChanged();
  refreshPins();
}

bool DocumentController::pinsStale() const {
  return !pins_.empty() && pins_.front().data != runs_->dataset();
}

void DocumentController::refreshPins() {
  const auto current = runs_->dataset();
  for (auto& p : pins_) {
    if (doc_ && current && p.data != current) {
      auto r = doc_->scenario().run(*current, p.snap.values);
      p.result = r ? *r : nullptr;
      p.data = current;
    }
  }
  emit pinsChanged();
}

QList<QPair<QString, std::shared_ptr<const RunResult>>> DocumentController::pinnedRuns(
    bool with_unrun) const {
  QList<QPair<QString, std::shared_ptr<const RunResult>>> out;
  for (const auto& p : pins_) {
    if (with_unrun || p.result) out.append({q(p.snap.name), p.result});
  }
  return out;
}

Status DocumentController::saveSession(const QString& path) const {
  if (!doc_) return Error{"nothing to save"};
  Session s = doc_->to_session();
  s.window_state = viewState().toStdString();
  if (auto st = save_session(path.toStdString(), s); !st) return st;
  doc_->mark_saved();
  return Ok{};
}

Status DocumentController::loadSession(const QString& path, const QString& ask) {
  auto s = load_session(path.toStdString());
  if (!s) return s.err();
  auto doc = Document::from_session(*s, path.toStdString());
  if (!doc) return doc.err();
  if (!ask.isEmpty() && !confirmDiscard(ask)) return Ok{};
  QString warning;
  if (s->data_path) {
    auto h = file_hash(*s->data_path);
    if (h && !s->data_hash.empty() && *h != s->data_hash) {
      warning = q(*s->data_path) + " changed since the session was saved (hash differs)";
    }
  }
  doc->mark_saved();
  const std::vector<std::string> notices = doc->notices();
  if (auto st = adopt(std::move(*doc)); !st) {
    // The session's data file: name the session and its key, as kfw-cli does.
    if (s->data_path && st.error().rfind(*s->data_path, 0) == 0)
      return Error{path.toStdString() + ": data.path: " + st.error(), st.err().exit_code};
    return st;
  }
  runs_->waitSettled();
  refreshPins();
  restoreViewState(q(doc_->view_state()));
  showNotices(notices);
  if (!warning.isEmpty()) emit problem(warning);
  return Ok{};
}

Status DocumentController::savePreset(const QString& path) const {
  if (!doc_) return Error{"nothing to save"};
  Preset p = doc_->preset();
  p.values = values();
  if (doc_->data()) {
    p.data_path = doc_->data()->path;
    p.mapping = doc_->data()->mapping;
  } else {
    p.data_path.reset();
  }
  return save_preset(path.toStdString(), p);
}

QString DocumentController::viewState() const {
  QJsonObject o;
  for (const auto& part : view_parts_)
    o[part.key] = part.save();
  return QString::fromUtf8(QJsonDocument(o).toJson(QJsonDocument::Compact));
}

void DocumentController::restoreViewState(const QString& state) {
  QJsonObject o;
  if (state.startsWith('{')) {
    o = QJsonDocument::fromJson(state.toUtf8()).object();
  } else {
    // Sessions before the JSON form: geometry, then two splitters, base64, ':'-separated.
    const QStringList parts = state.split(':');
    if (!parts.isEmpty() && !parts[0].isEmpty()) o["geometry"] = parts[0];
    QJsonObject splits;
    const char* names[] = {"mainSplit", "leftSplit"};
    for (int i = 1; i < parts.size() && i <= 2; ++i)
      splits[names[i - 1]] = parts[i];
    o["splitters"] = splits;
  }
  for (const auto& part : view_parts_) {
    if (o.contains(part.key)) part.restore(o[part.key]);
  }
}

void DocumentController::addViewStatePart(const QString& key, std::function<QJsonValue()> save,
                                          std::function<void(const QJsonValue&)> restore) {
  view_parts_.push_back({key, std::move(save), std::move(restore)});
}

bool DocumentController::confirmDiscard(const QString& action) {
  // Only what a discard would lose: snapshots pinned on a preset are unsaved (dirty); those of a
  // session just opened or saved are in its file.
  if (!doc_ || !doc_->dirty()) return true;
  QString what;
  if (doc_->dirty()) what = "unsaved changes";
  if (!doc_->snapshots().empty()) {
    what +=
        QString(what.isEmpty() ? "" : " and ") + QString("%1 pinned snapshot%2")
                                                     .arg(doc_->snapshots().size())
                                                     .arg(doc_->snapshots().size() == 1 ? "" : "s");
  }
  const QString question = QString("%1: discard %2?").arg(action, what);
  if (confirm_) return confirm_(question);
  return QMessageBox::question(window_, action, question,
                               QMessageBox::Discard | QMessageBox::Cancel,
                               QMessageBox::Cancel) == QMessageBox::Discard;
}

}  // namespace kfw
