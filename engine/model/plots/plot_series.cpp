// The series plot block: states (their estimates) and derived series over time, drawn with the
// replay cursor like the other time plots; the data are the run's own arrays.
#include <nlohmann/json.hpp>

#include "model/model_reader.h"
#include "model/model_result.h"
#include "model/model_spec.h"
#include "model/plots/model_plots.h"

namespace kfw::model {

using nlohmann::json;

Status parse_series_block(const detail::Reader& p, const json& j, const std::string& key,
                          const ModelSpec& m, const ParamTable&, PlotBlockSpec& out) {
  auto it = j.find("y");
  if (it == j.end()) return p.error(key, "missing key 'y'");
  std::vector<std::string> known;
  for (const auto& s : m.states)
    known.push_back(s.name);
  for (const auto& d : m.derived) {
    if (d.series()) known.push_back("derived." + d.name);
  }
  auto names = detail::name_list(p, *it, key + ".y");
  if (!names) return names.err();
  for (std::size_t i = 0; i < names->size(); ++i) {
    const std::string at = it->is_array() ? detail::idx(key + ".y", i) : key + ".y";
    const std::string& name = (*names)[i];
    for (const auto& d : m.derived) {
      if (!d.series() && (name == d.name || name == "derived." + d.name)) {
        return p.error(at, "derived." + d.name +
                               " is a scalar (parameters and dt only), one number per run: a "
                               "series uses states, truth, t or inputs");
      }
    }
    auto line = detail::plot_line(p, name, at, m, known, "state or derived series");
    if (!line) return line.err();
    out.series.push_back(*line);
  }
  return Ok{};
}

std::vector<SeriesData> series_block_data(const PlotBlockSpec& b, const ModelResult& r) {
  std::vector<SeriesData> out;
  for (const auto& line : b.series) {
    SeriesData s{line, nullptr};
    for (std::size_t i = 0; i < r.state_keys.size(); ++i) {
      if (r.state_keys[i] == line.key) s.y = &r.x[i];
    }
    for (std::size_t i = 0; i < r.derived_names.size(); ++i) {
      if ("derived." + r.derived_names[i] == line.key) s.y = &r.derived[i];
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace kfw::model
