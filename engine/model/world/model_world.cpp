#include "model/world/model_world.h"

#include <nlohmann/json.hpp>
#include <set>

namespace kfw::model {

using nlohmann::json;

namespace {

// "PATH: model.KEY: what" from the world's own parse -> "PATH: model.world.KEY: what" (a message
// already about model.world as a whole stays).
Error under_world(const Error& e, const std::string& path) {
  const std::string from = path + ": model.";
  std::string msg = e.message;
  if (msg.rfind(path + ": model.world: ", 0) == 0) return e;  // about the world as a whole
  if (msg.rfind(from, 0) == 0) {
    msg = path + ": model.world." + msg.substr(from.size());
  } else if (msg.rfind(path + ": ", 0) == 0) {
    msg = path + ": model.world: " + msg.substr(path.size() + 2);
  }
  return Error{msg, e.exit_code};
}

// Every column the world writes: t, its inputs, its sensors' roles and outlier columns, its truth
// columns (of states and of sub-expressions).
std::set<std::string> written(const ModelSpec& w) {
  std::set<std::string> out{"t"};
  for (const auto& in : w.inputs)
    out.insert(in.name);
  for (const auto& c : w.channels) {
    for (const auto& r : c.roles)
      out.insert(r.name);
  }
  for (const auto& col : w.truth) {
    if (!col.empty()) out.insert(col);
  }
  for (const auto& [col, e] : w.truth_exprs)
    out.insert(col);
  for (const auto& c : w.channels) {
    if (!c.sensor.outlier_column.empty()) out.insert(c.sensor.outlier_column);
    if (!c.sensor.impulse_flag.empty()) out.insert(c.sensor.impulse_flag);
  }
  return out;
}

// The sensors of one outlier group share its count (or rate) and size.
Status check_outlier_groups(const ModelSpec& w, const std::string& path) {
  for (std::size_t a = 0; a < w.channels.size(); ++a) {
    const SensorSpec& s = w.channels[a].sensor;
    if (!s.outliers) continue;
    for (std::size_t b = 0; b < a; ++b) {
      const SensorSpec& o = w.channels[b].sensor;
      if (!o.outliers || o.outlier_group != s.outlier_group) continue;
      if (o.outlier_count != s.outlier_count || o.outlier_amount.text != s.outlier_amount.text ||
          o.outlier_size.text != s.outlier_size.text) {
        return Error{path + ": model.world.measurements." + w.channels[a].name +
                     ".outliers: the group '" + s.outlier_group + "' is declared by '" +
                     w.channels[b].name + "' with another count, rate or size"};
      }
    }
  }
  return Ok{};
}

}  // namespace

Expected<std::shared_ptr<const ModelSpec>> parse_world(const json& model, const ParamTable& params,
                                                       const std::string& path,
                                                       const ModelSpec& filter) {
  json w = model.at("world");
  if (!w.is_object()) {
    return Error{path +
                 ": model.world: expected an object (a model block: states, x0, P0, "
                 "process, measurements as its sensors, truth)"};
  }
  if (w.contains("version")) {
    return Error{path + ": model.world.version: the world has the model's version; remove it"};
  }
  w["version"] = filter.version;
  auto spec = parse_model(w, params, path, true);
  if (!spec) return under_world(spec.err(), path);
  spec->sim_dt_key = filter.sim_dt_key;
  const auto made = written(*spec);
  auto missing = [&](const std::string& column, const std::string& reader) -> Error {
    return Error{path + ": model.world: writes no column '" + column + "', which " + reader +
                 " reads (declare a sensor role, an input or a truth column of that name)"};
  };
  if (auto st = check_outlier_groups(*spec, path); !st) return st.err();
  for (std::size_t i = 0; i < filter.inputs.size(); ++i) {
    if (!made.count(filter.inputs[i].name)) {
      return missing(filter.inputs[i].name, "model.inputs[" + std::to_string(i) + "]");
    }
  }
  for (const auto& c : filter.channels) {
    for (const auto& r : c.roles) {
      if (!made.count(r.name)) return missing(r.name, "model.measurements." + c.name);
    }
    if (c.missing.on() && !made.count(c.missing.column)) {
      return missing(c.missing.column, "model.measurements." + c.name + ".missing");
    }
  }
  for (std::size_t i = 0; i < filter.truth.size(); ++i) {
    if (!filter.truth[i].empty() && !made.count(filter.truth[i])) {
      return missing(filter.truth[i], "model.truth." + filter.states[i].name);
    }
  }
  return std::shared_ptr<const ModelSpec>(std::make_shared<ModelSpec>(std::move(*spec)));
}

}  // namespace kfw::model
