#include "model/model_gates.h"

#include <cmath>

#include "model/model_result.h"

namespace kfw::model {

std::vector<MetricSpec> gate_metric_specs(const ModelSpec& spec) {
  std::vector<MetricSpec> out;
  bool outliers = false;
  for (const auto& c : spec.channels) {
    if (c.has_gate()) {
      out.push_back({"gated." + c.name, "updates gated out (" + c.label + ")", "",
                     "measurements rejected by the channel's gate", MetricGroup::kConsistency,
                     Direction::kLower});
    }
    outliers = outliers || (c.has_gate() && !c.outlier_column.empty());
    if (c.missing.on()) {
      out.push_back(
          {"flagged." + c.name, "samples flagged missing (" + c.label + ")", "",
           "samples whose update the channel's missing flag took out (" + c.missing.column + ")",
           MetricGroup::kScenario, Direction::kNone});
      out.push_back({"flagged_fraction." + c.name, "fraction flagged missing (" + c.label + ")", "",
                     "flagged samples over the channel's samples", MetricGroup::kScenario,
                     Direction::kNone});
    }
  }
  if (!outliers) return out;
  using G = MetricGroup;
  using D = Direction;
  out.push_back({"outliers_injected", "outliers injected", "",
                 "samples marked as outliers in the channels' outlier columns", G::kScenario,
                 D::kLower});
  out.push_back({"outliers_detected", "outliers detected", "",
                 "marked outliers that the gate rejected (Han et al. 2016, Table 14)", G::kScenario,
                 D::kHigher});
  out.push_back({"outliers_false_alarm", "false alarms", "",
                 "samples not marked as outliers that the gate rejected", G::kScenario, D::kLower});
  return out;
}

void add_gate_metrics(const ModelSpec& spec, const ModelResult& r, Metrics& m,
                      UndefinedMetrics& undefined) {
  bool declared = false, known = false;
  double injected = 0, detected = 0, false_alarm = 0;
  auto marked = [](double v) { return std::isfinite(v) && v != 0.0; };
  for (std::size_t c = 0; c < r.chans.size(); ++c) {
    const ChannelSpec& cs = spec.channels[c];
    const ChannelSeries& ch = r.chans[c];
    if (cs.missing.on()) {
      const auto all = static_cast<double>(ch.flagged + ch.updates + ch.gated + ch.skipped);
      m["flagged." + ch.name] = static_cast<double>(ch.flagged);
      m["flagged_fraction." + ch.name] = all > 0 ? static_cast<double>(ch.flagged) / all : 0.0;
    }
    if (!cs.has_gate()) continue;
    m["gated." + ch.name] = static_cast<double>(ch.gated);
    if (cs.outlier_column.empty()) continue;
    declared = true;
    if (ch.outlier.empty()) continue;
    known = true;
    for (double v : ch.outlier)
      injected += marked(v) ? 1 : 0;
    for (std::size_t k : ch.gated_rows)
      ++(marked(ch.outlier[k]) ? detected : false_alarm);
  }
  if (!declared) return;
  const char* keys[] = {"outliers_injected", "outliers_detected", "outliers_false_alarm"};
  if (!known) {
    for (const char* k : keys) {
      m[k] = kNoSample;
      undefined.emplace(k, "no outlier column of the channels in the data");
    }
    return;
  }
  m[keys[0]] = injected;
  m[keys[1]] = detected;
  m[keys[2]] = false_alarm;
}

}  // namespace kfw::model
