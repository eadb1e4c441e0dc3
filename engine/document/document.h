// The one Qt-free document: what a user has open — the preset, the datasets (the current one and
// a tuning set, each a path with its mapping), the current values, snapshots, an undo history, a
// dirty flag and an opaque view-state blob the GUI may store (zoom, replay position). The CLI,
// the tests and the GUI drive it; sessions serialise it, with data by path (never the data).
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/scenario.h"
#include "data/mapping.h"
#include "document/import_args.h"
#include "document/preset.h"
#include "document/session.h"

namespace kfw {

// How a value change joins the undo history.
enum class UndoMerge {
  kNewStep,      // a step of its own (a spin box, a tuning applied, a sweep click)
  kMergeSameKey  // joins the previous step when that changed the same key the same way (a drag)
};

class Document {
 public:
  // Opens a preset (path or name in presets/) with an optional dataset, --set assignments and
  // import options (how the file data in force is read; refused when the preset simulates).
  static Expected<Document> open(const std::string& preset, const std::optional<std::string>& data,
                                 const std::vector<std::string>& assignments = {},
                                 const ImportArgs& import = {});
  static Document from_preset(Preset preset);

  const Preset& preset() const { return preset_; }
  const Scenario& scenario() const { return *preset_.instance; }
  std::shared_ptr<const Scenario> scenario_ptr() const { return preset_.instance; }
  const ParamValues& values() const { return state_.values; }
  const std::optional<DataRef>& data() const { return state_.data; }
  const std::vector<DataRef>& tuning_set() const { return state_.tuning_set; }
  const std::vector<Snapshot>& snapshots() const { return state_.snapshots; }
  const std::string& view_state() const { return view_state_; }
  // Unsaved: the values, data, tuning set or snapshots differ from what was opened or last saved
  // (a change undone, or a Reset back to the opened preset's values, is clean again).
  bool dirty() const { return !(state_ == saved_); }
  // What opening changed that the user should know (a retired scenario loaded as its model file,
  // keys dropped, a session's unknown keys, a deleted view's state): one line each, shown by the
  // GUI and printed on stderr by the CLI. Empty for current files.
  const std::vector<std::string>& notices() const { return notices_; }

  // Each of these is validated (nothing changes on an error) and is one undo step.
  Status set_value(const std::string& key, double value, UndoMerge merge = UndoMerge::kNewStep);
  Status set_values(const ParamValues& values, const std::string& label);
  Status apply_assignment(const std::string& assignment);  // "key=value", as --set
  void set_data(std::optional<DataRef> data);  // none: simulate from the sim.* parameters
  Status set_mapping(const Mapping& mapping);  // of the current dataset
  void set_tuning_set(std::vector<DataRef> logs);
  void add_snapshot(Snapshot s);
  Status remove_snapshot(std::size_t index);
  void clear_snapshots();
  // Back to the preset's values (snapshots kept); one undo step.
  void reset_to_preset();
  // Not undoable: the GUI's own view (zoom, replay position), opaque to the engine.
  void set_view_state(std::string blob) { view_state_ = std::move(blob); }

  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }
  std::string undo_label() const { return undo_.empty() ? std::string() : undo_.back().label; }
  std::string redo_label() const { return redo_.empty() ? std::string() : redo_.back().label; }
  bool undo();
  bool redo();
  std::size_t undo_depth() const { return undo_.size(); }

  // Saved: the current state is what a discard would lose nothing of (the history stays).
  void mark_saved() { saved_ = state_; }

  // Sessions: the preset path, values, data (path, hash, mapping), tuning set, snapshots and
  // view state. Loading re-opens the preset file and validates every value against it. A session
  // of a retired built-in (core/retired.h) accepts its model file: keys the model lacks are
  // dropped, and so is the view state of the built-in's deleted view, each with a notice.
  Session to_session() const;
  static Expected<Document> from_session(const Session& s, const std::string& where);

 private:
  struct State {
    ParamValues values;
    std::optional<DataRef> data;
    std::vector<DataRef> tuning_set;
    std::vector<Snapshot> snapshots;
    bool operator==(const State&) const = default;
  };
  struct Step {
    std::string label;
    State before;
    std::string merge_key;  // non-empty: a later change of this key may join the step
  };
  void push(std::string label, std::string merge_key = {});

  Preset preset_;
  State state_;
  std::vector<Step> undo_, redo_;
  std::string view_state_;
  std::vector<std::string> notices_;
  State saved_;  // the state as opened or last saved (dirty() compares with it)
};

}  // namespace kfw
