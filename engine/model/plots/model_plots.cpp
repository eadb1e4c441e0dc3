#include "model/plots/model_plots.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/suggest.h"
#include "model/imm/imm_spec.h"
#include "model/model_reader.h"
#include "model/model_spec.h"

namespace kfw::model {

using nlohmann::json;

const std::vector<PlotKind>& plot_kinds() {
  // The one registry of plot block kinds: a new kind is a line here, its reader in
  // plot_<kind>.cpp and its drawer in widgets/plots/<kind>_block.cpp (registered there in
  // widgets/plots/block_registry.cpp).
  static const std::vector<PlotKind> kinds = {
      {"gain_curve",
       {"sweep", "x", "y", "y2", "log", "range", "operating_point"},
       &parse_gain_curve_block},
      {"series", {"y"}, &parse_series_block},
      {"trajectory", {"x", "y", "points", "equal_scale"}, &parse_trajectory_block},
      {"covariance", {"series", "design", "instants", "exclude"}, &parse_covariance_block},
  };
  return kinds;
}

namespace {

// The panel ids the generic model view gives its own plots (a block may not take one).
bool reserved_id(const std::string& id) {
  return id == "gain" || id == "gain_curve";
}

Status check_keys(const detail::Reader& p, const json& j, const std::string& key,
                  const PlotKind& kind) {
  std::vector<std::string> known = {"kind", "id", "title"};
  known.insert(known.end(), kind.keys.begin(), kind.keys.end());
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
    std::string list;
    for (const auto& k : known)
      list += (list.empty() ? "" : ", ") + k;
    const auto near = nearest(it.key(), known);
    return p.error(key + "." + truncate_token(it.key()),
                   near ? "unknown key of a " + kind.name + " block (did you mean '" + *near + "'?)"
                        : "unknown key of a " + kind.name + " block (known: " + list + ")");
  }
  return Ok{};
}

Expected<PlotBlockSpec> parse_block(const detail::Reader& p, const json& j, const std::string& key,
                                    const ModelSpec& m, const ParamTable& params) {
  if (!j.is_object()) return p.error(key, "expected {\"kind\": ..., \"id\": ..., ...}");
  auto kind = p.string(j, "kind", key, true);
  if (!kind) return kind.err();
  const auto& kinds = plot_kinds();
  const auto it =
      std::find_if(kinds.begin(), kinds.end(), [&](const PlotKind& k) { return k.name == *kind; });
  if (it == kinds.end()) {
    std::vector<std::string> names;
    for (const auto& k : kinds)
      names.push_back(k.name);
    return p.error(key + ".kind", unknown_message("kind of plot", *kind, names));
  }
  if (auto st = check_keys(p, j, key, *it); !st) return st.err();
  PlotBlockSpec b;
  b.kind = *kind;
  auto id = p.string(j, "id", key, true);
  if (!id) return id.err();
  if (!is_identifier(*id)) {
    return p.error(key + ".id", quote_token(*id) +
                                    " is not a name (letters, digits and _): it names the panel "
                                    "and its exported file");
  }
  if (reserved_id(*id)) {
    return p.error(key + ".id", quote_token(*id) + " is a panel of the model view already");
  }
  b.id = *id;
  auto title = p.string(j, "title", key, false);
  if (!title) return title.err();
  b.title = *title;
  if (auto st = it->parse(p, j, key, m, params, b); !st) return st.err();
  return b;
}

}  // namespace

Status parse_plots(const detail::Reader& p, const json& block, const ParamTable& params,
                   ModelSpec& m) {
  if (!block.is_array()) {
    return p.error("model.plots", "expected a list of blocks [{\"kind\": ..., \"id\": ...}, ...]");
  }
  for (std::size_t i = 0; i < block.size(); ++i) {
    const std::string key = detail::idx("model.plots", i);
    auto b = parse_block(p, block[i], key, m, params);
    if (!b) return b.err();
    for (const auto& other : m.plots) {
      if (other.id == b->id) {
        return p.error(key + ".id", quote_token(b->id) + " is the id of another block");
      }
    }
    m.plots.push_back(std::move(*b));
  }
  return Ok{};
}

namespace detail {

Expected<std::vector<std::string>> name_list(const Reader& p, const json& j,
                                             const std::string& key) {
  std::vector<std::string> out;
  if (j.is_string()) return std::vector<std::string>{j.get<std::string>()};
  if (!j.is_array() || j.empty()) return p.error(key, "expected a name or a non-empty list");
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_string()) return p.error(idx(key, i), "expected a name");
    out.push_back(j[i].get<std::string>());
  }
  return out;
}

Expected<PlotLine> plot_line(const Reader& p, const std::string& name, const std::string& key,
                             const ModelSpec& m, const std::vector<std::string>& known,
                             const char* what) {
  std::string k = name;
  if (std::find(known.begin(), known.end(), k) == known.end() &&
      std::find(known.begin(), known.end(), "derived." + name) != known.end()) {
    k = "derived." + name;  // a derived quantity by its own name
  }
  if (std::find(known.begin(), known.end(), k) == known.end()) {
    std::vector<std::string> near = known;  // a derived quantity by its own name too
    for (const auto& c : known) {
      if (c.rfind("derived.", 0) == 0 && name.rfind("derived.", 0) != 0)
        near.push_back(c.substr(8));
    }
    std::string msg = unknown_message(what, name, near);
    if (msg.find("did you mean") == std::string::npos) {
      std::string list;
      for (const auto& c : known)
        list += (list.empty() ? "" : ", ") + c;
      msg += list.empty() ? " (this model has none)" : " (known: " + list + ")";
    }
    return p.error(key, msg);
  }
  PlotLine line{k, k, ""};
  if (const int s = m.state_index(k); s >= 0) {
    line.label = m.states[static_cast<std::size_t>(s)].label;
    line.unit = m.states[static_cast<std::size_t>(s)].unit;
  }
  for (const auto& d : m.derived) {
    if ("derived." + d.name == k) {
      line.label = d.label;
      line.unit = d.unit;
    }
  }
  return line;
}

}  // namespace detail

std::vector<std::string> panel_names(const ModelSpec& m) {
  std::vector<std::string> out;
  for (const auto& st : m.states)
    out.push_back("state." + st.name);
  for (const auto& c : m.channels) {
    for (const auto& r : c.comps) {
      out.push_back("measured." + c.name + "." + r.name);
      out.push_back("innovation." + c.name + "." + r.name);
    }
    out.push_back("nis." + c.name);
  }
  out.push_back("gain");
  if (m.time_invariant()) out.push_back("gain_curve");
  if (m.modes) {
    out.push_back("mode_probabilities");
    if (m.modes->grid.size() == 2) out.push_back("mode_heatmap");
    for (const auto& a : m.modes->grid)
      out.push_back("grid." + a.param);
  }
  for (const auto& b : m.plots)
    out.push_back(b.id);
  return out;
}

Status parse_first_panels(const detail::Reader& p, const nlohmann::json& list, ModelSpec& m) {
  const std::string key = "model.first_panels";
  if (!list.is_array()) return p.error(key, "expected a list of panel names");
  const std::vector<std::string> names = panel_names(m);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string k = detail::idx(key, i);
    if (!list[i].is_string()) return p.error(k, "expected a panel's name");
    const std::string name = list[i].get<std::string>();
    if (std::find(names.begin(), names.end(), name) == names.end())
      return p.error(k, unknown_message("panel", name, names));
    if (std::find(m.first_panels.begin(), m.first_panels.end(), name) != m.first_panels.end())
      return p.error(k, "'" + name + "' twice");
    m.first_panels.push_back(name);
  }
  return Ok{};
}

}  // namespace kfw::model
