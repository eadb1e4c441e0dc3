// kfw-cli upgrade: an old preset or session (one that names a retired scenario included) rewritten
// in the current form. The file is replaced atomically and its original kept as FILE.bak, or the
// result goes to --out and FILE is left alone; --check writes nothing. A Monte Carlo or sweep part
// of version 1 cannot be upgraded: it lacks its preset's content hash.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_commands.h"
#include "core/suggest.h"
#include "data/input_file.h"
#include "data/json_io.h"
#include "data/output.h"
#include "document/document.h"
#include "document/preset.h"
#include "document/session.h"

namespace kfw {

namespace {

namespace fs = std::filesystem;

// What an upgrade changes (empty: the file is current) and the file in the current form.
struct Upgrade {
  std::vector<std::string> changes;
  std::string text;
  std::string note;  // said either way ("a model file", "its preset is old too")
};

std::string joined(const std::vector<std::string>& keys) {
  std::string s;
  for (const auto& k : keys)
    s += (s.empty() ? "" : " ") + truncate_token(k);
  return s;
}

// A preset: one naming a retired scenario becomes its model file; a version-1 preset version 2.
// A model file is current whatever its version (the writer writes the lowest that holds it).
Expected<Upgrade> upgrade_preset(const std::string& text, const std::string& path,
                                 const std::string& dest) {
  auto p = parse_preset(text, path);
  if (!p) return p.err();
  Upgrade u;
  if (!p->retired_from.empty()) {
    u.changes.push_back("scenario '" + p->retired_from + "' (retired) becomes the model file " +
                        retired_model_path(p->retired_from) + " with this file's values");
    if (!p->dropped_keys.empty()) {
      u.changes.push_back("dropped (not in the model file): " + joined(p->dropped_keys));
    }
  } else if (p->scenario == "model") {
    u.note = "a model file: the writer writes the lowest version that holds it";
    return u;
  } else if (p->version < kPresetVersion) {
    u.changes.push_back("preset version " + std::to_string(p->version) + " becomes " +
                        std::to_string(kPresetVersion));
  }
  if (u.changes.empty()) return u;
  Preset current = std::move(*p);
  current.path = dest;  // the data path is written relative to where the file goes
  u.text = preset_to_json(current);
  return u;
}

// A session: version 3, a retired scenario's keys and view state dropped, unknown keys dropped.
// Its preset and data paths are read relative to the current directory, as kfw reads them.
Expected<Upgrade> upgrade_session(const std::string& text, const std::string& path) {
  auto s = parse_session(text, path);
  if (!s) return s.err();
  auto d = Document::from_session(*s, path);
  if (!d) return d.err();
  Upgrade u;
  if (s->version < kSessionVersion) {
    u.changes.push_back("session version " + std::to_string(s->version) + " becomes " +
                        std::to_string(kSessionVersion));
  }
  for (const auto& n : d->notices())
    u.changes.push_back(n);
  if (!d->preset().retired_from.empty()) {
    u.note = "its preset " + d->preset().path + " names a retired scenario too: kfw-cli upgrade " +
             d->preset().path;
  }
  if (u.changes.empty()) return u;
  Session current = std::move(*s);
  current.version = kSessionVersion;
  current.scenario = d->preset().scenario;
  current.values = d->values();
  current.snapshots = d->snapshots();
  current.window_state = d->view_state();
  current.notices.clear();
  u.text = session_to_json(current);
  return u;
}

// The upgrade of whatever the file is, or why there is none.
Expected<Upgrade> upgrade_document(const std::string& text, const std::string& path,
                                   const std::string& dest) {
  auto j = parse_json_document(text, path);
  if (!j) return j.err();
  const std::string format = j->is_object() ? j->value("format", std::string()) : std::string();
  if (format == kPresetFormat) return upgrade_preset(text, path, dest);
  if (format == kSessionFormat) return upgrade_session(text, path);
  if (j->is_object() && j->contains("kind")) {
    const std::string kind = j->at("kind").is_string() ? j->at("kind").get<std::string>() : "";
    const std::string what = kind == "montecarlo" ? "Monte Carlo" : truncate_token(kind);
    return Error{path + ": a " + what + " part of version " +
                 j->value("version", nlohmann::json()).dump() +
                 " cannot be upgraded: it lacks its preset's content hash; run its shard again"};
  }
  return Error{path + ": not a kfw preset or session (format '" + truncate_token(format) +
               "'; kfw-cli upgrade reads '" + kPresetFormat + "' and '" + kSessionFormat + "')"};
}

}  // namespace

int cmd_upgrade(const UpgradeArgs& a, std::ostream& out, std::ostream& err) {
  // Under the input policy (data/input_file.h): a directory, FIFO or device is refused unread.
  auto text = read_input_file(a.file, limits::Input::kPreset);
  if (!text) return fail(err, text.err());
  const std::string dest = a.out ? *a.out : a.file;
  auto u = upgrade_document(*text, a.file, dest);
  if (!u) return fail(err, u.err());
  const std::string note = u->note.empty() ? "" : " (" + u->note + ")";
  if (u->changes.empty()) {
    out << a.file << ": already current" << note << "; nothing written\n";
    return kExitOk;
  }
  if (a.check) {
    out << a.file << ": an upgrade would change it" << note << ":\n";
    for (const auto& c : u->changes)
      out << "  " << one_line(c) << "\n";
    return kExitFailed;
  }
  OutputSet outs;
  const std::string backup = a.file + ".bak";
  if (a.out) {
    outs.add_input(a.file);
    if (auto st = outs.add(*a.out, "--out"); !st) return fail(err, st.err());
    if (auto st = outs.stage(*a.out, u->text); !st) return fail(err, st.err());
  } else {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(backup, ec))) {
      return fail(err, Error{backup + ": exists; move it away, or write the upgrade elsewhere "
                                      "with --out FILE"});
    }
    for (const auto& [path, content] : {std::pair{backup, *text}, std::pair{a.file, u->text}}) {
      if (auto st = outs.add(path); !st) return fail(err, st.err());
      if (auto st = outs.stage(path, content); !st) return fail(err, st.err());
    }
  }
  if (auto st = outs.commit(); !st) return fail(err, st.err());
  out << "upgraded " << a.file << (a.out ? " into " + *a.out : std::string()) << note << ":\n";
  for (const auto& c : u->changes)
    out << "  " << one_line(c) << "\n";
  if (!a.out) out << "the original is kept as " << backup << "\n";
  return kExitOk;
}

}  // namespace kfw
