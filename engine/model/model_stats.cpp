#include "model/model_stats.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "model/model_result.h"
#include "model/model_spec.h"
#include "model/plots/model_plots.h"

namespace kfw::model {

namespace {

// A number, or null when it is not finite (too few samples).
nlohmann::json number(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

nlohmann::json matrix(const std::vector<double>& a, std::size_t n) {
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t i = 0; i < n && a.size() == n * n; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (std::size_t j = 0; j < n; ++j)
      row.push_back(number(a[i * n + j]));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json block_json(const PlotBlockSpec& b, const ModelResult& r) {
  const CovarianceData c = covariance_block_data(b, r);
  nlohmann::json j;
  j["title"] = b.title;
  j["series"] = nlohmann::json::array();
  j["labels"] = nlohmann::json::array();
  for (const auto& line : b.series) {
    j["series"].push_back(line.key);
    j["labels"].push_back(line.label);
  }
  j["samples"] = c.count;
  if (b.instants) j["excluded"] = c.excluded;
  j["mean"] = nlohmann::json::array();
  for (double x : c.mean)
    j["mean"].push_back(number(x));
  j["covariance"] = matrix(c.sample, c.n);
  j["design"] = matrix(c.design, c.n);
  return j;
}

}  // namespace

const std::vector<std::string>& model_commands() {
  static const std::vector<std::string> commands = {"stats"};
  return commands;
}

bool model_offers(const ModelSpec& m, const std::string& command) {
  if (command != "stats") return false;
  for (const auto& b : m.plots) {
    if (b.kind == "covariance") return true;
  }
  return false;
}

std::string stats_json(const ModelSpec& m, const ModelResult& r, const std::string& source) {
  nlohmann::json j;
  j["source"] = source;
  j["blocks"] = nlohmann::json::object();
  for (const auto& b : m.plots) {
    if (b.kind == "covariance") j["blocks"][b.id] = block_json(b, r);
  }
  // The channels' outlier counts: null when the data lacks every outlier column.
  for (const char* k : {"outliers_injected", "outliers_detected", "outliers_false_alarm"}) {
    if (auto it = r.metrics.find(k); it != r.metrics.end()) {
      j[k] = it->second;
    } else if (r.undefined.count(k)) {
      j[k] = nullptr;
    }
  }
  return j.dump(2);
}

}  // namespace kfw::model
