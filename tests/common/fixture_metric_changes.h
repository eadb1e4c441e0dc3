// The differences between a seed preset's `kfw-cli metrics` listing today and the one saved in
// tests/fixtures/metrics/ that CHANGES.md lists (issue 27: presets/helicopter.json, broad_imu.json
// and underwater.json became model files; issue 28: radome.json; issue 30: ballbeam.json; the
// tables under "... is a model file"), and nothing else.
// tests/engine/format_fixtures_test.cpp and tests/cli/format_fixtures_cli_test.cpp read it.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace kfw::testing {

struct MetricChange {
  std::string key;
  bool added;  // true: new in the listing; false: gone from it
};

inline const std::vector<MetricChange>& fixture_metric_changes(const std::string& preset) {
  static const std::vector<MetricChange> helicopter_model = {
      {"rmse_sensor", false},      {"k1_final", false},    {"k1_steady", false},
      {"k1_closed_form", false},   {"beta", false},        {"K.theta.angle", true},
      {"K.bias.angle", true},      {"derived.beta", true}, {"derived.k1", true},
      {"derived.p11_over_R", true}};
  // presets/underwater.json (the same issue): the built-in's own counters and statistics went;
  // the gate's counts, the steady-state gains and the file's derived errors came. `rmse` stays
  // (the built-in listed it twice: the shared key and its own 3-D position RMSE).
  static const std::vector<MetricChange> underwater_model = [] {
    std::vector<MetricChange> c;
    for (const char* k : {"pos_mean", "pos_std", "pos_max", "ranges_used", "ranges_rejected",
                          "ranges_invalid", "depth_used", "steps", "stats_range_var_mean",
                          "stats_range_cov_mean", "stats_depth_var", "stats_instants"})
      c.push_back({k, false});
    const std::vector<std::string> channels = {"depth", "range1", "range2", "range3", "range4"};
    for (std::size_t i = 1; i < channels.size(); ++i)
      c.push_back({"gated." + channels[i], true});
    for (const char* s : {"x", "y", "z"}) {
      for (const auto& ch : channels)
        c.push_back({std::string("K.") + s + "." + ch, true});
    }
    for (const char* d : {"e_d", "e_r1", "e_r2", "e_r3", "e_r4", "pos_err"}) {
      c.push_back({std::string("derived.") + d + ".rms", true});
      c.push_back({std::string("derived.") + d + ".max", true});
    }
    return c;
  }();
  // presets/radome.json (issue 28): the built-in's counters went (imm.modes is the mode count);
  // the gains, the derived series, each axis's final estimate and RMSE and the pseudo-measurement's
  // component whiteness came. Every metric of the built-in's scenario is kept by name.
  static const std::vector<MetricChange> radome_model = [] {
    std::vector<MetricChange> c;
    for (const char* k : {"Ts", "modes", "steps", "updates"})
      c.push_back({k, false});
    for (const char* s : {"x", "vx", "ax", "y", "vy", "ay", "z", "vz", "az"}) {
      for (const char* y : {"Yx", "Yy", "Yz"})
        c.push_back({std::string("K.") + s + "." + y, true});
    }
    for (const char* d :
         {"alpha_est", "los_err_psi", "los_err_theta", "los_est_err_psi", "los_est_err_theta",
          "position_err", "refraction_err", "slope_err_psi", "slope_err_theta"}) {
      c.push_back({std::string("derived.") + d + ".rms", true});
      c.push_back({std::string("derived.") + d + ".max", true});
    }
    for (const char* k :
         {"imm.modes", "imm.R_psi.final", "imm.R_theta.final", "rmse.R_psi", "rmse.R_theta",
          "whiteness_p.seeker.Yx", "whiteness_p.seeker.Yy", "whiteness_p.seeker.Yz"})
      c.push_back({k, true});
    return c;
  }();
  static const std::vector<MetricChange> none;
  if (preset == "helicopter" || preset == "broad_imu") return helicopter_model;
  // presets/ballbeam.json (issue 30): one loop per run, so the three variants' figures went; the
  // built-in's names of the event, α, β and the sensor's counts moved (CHANGES.md's table).
  static const std::vector<MetricChange> ballbeam_model = [] {
    std::vector<MetricChange> c;
    for (const char* k :
         {"K1_final", "K2_final_times_Ts", "K_final_run", "Ts", "alpha", "alpha_dare", "beta",
          "beta_dare", "diverged", "fell", "lambda", "left_beam_at_s", "missing_fraction",
          "skipped_fraction", "steps", "tracking_excess_detect_off", "tracking_excess_detect_on"})
      c.push_back({k, false});
    for (const char* v : {"_detect_off", "_detect_on", "_noise_free"}) {
      for (const char* k :
           {"V_rms", "left_beam_at_s", "max_abs_pos", "max_abs_theta", "rmse_pos", "tracking_rmse"})
        c.push_back({std::string(k) + v, false});
    }
    for (const char* k :
         {"K.v.x_meas", "K.x.x_meas", "V_rms", "max_abs_pos", "max_abs_theta", "event.left_beam",
          "event.left_beam_at_s", "event.small_angle", "event.small_angle_at_s", "flagged.position",
          "flagged_fraction.position", "impulsive_fraction.position", "derived.alpha",
          "derived.beta", "derived.lambda"})
      c.push_back({k, true});
    for (const char* d :
         {"ball", "beam", "excess", "motor", "noise_free", "set_point", "track_err"}) {
      c.push_back({std::string("derived.") + d + ".rms", true});
      c.push_back({std::string("derived.") + d + ".max", true});
    }
    return c;
  }();
  if (preset == "radome") return radome_model;
  if (preset == "ballbeam") return ballbeam_model;
  return preset == "underwater" ? underwater_model : none;
}

// The keys in order, each once (a built-in could list a shared key again as its own).
inline std::vector<std::string> first_of_each(const std::vector<std::string>& keys) {
  std::vector<std::string> out;
  for (const auto& k : keys) {
    if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
  }
  return out;
}

// `keys` without those the changes list as `added` (true) or gone (false), in their order.
inline std::vector<std::string> without_changes(const std::vector<std::string>& keys,
                                                const std::vector<MetricChange>& changes,
                                                bool added) {
  std::vector<std::string> kept;
  for (const auto& k : keys) {
    const bool listed = std::any_of(changes.begin(), changes.end(), [&](const MetricChange& c) {
      return c.key == k && c.added == added;
    });
    if (!listed) kept.push_back(k);
  }
  return kept;
}

// Checks a listing against the saved one: every change happened, the rest is in saved order.
// Returns "" when it holds, else what differs.
inline std::string compare_with_changes(const std::vector<std::string>& listed,
                                        const std::vector<std::string>& saved,
                                        const std::vector<MetricChange>& changes) {
  std::string why;
  for (const auto& c : changes) {
    const bool now = std::find(listed.begin(), listed.end(), c.key) != listed.end();
    const bool then = std::find(saved.begin(), saved.end(), c.key) != saved.end();
    if (now != c.added || then == c.added) why += " " + c.key;
  }
  if (!why.empty()) return "changes not as listed:" + why;
  if (first_of_each(without_changes(listed, changes, true)) !=
      first_of_each(without_changes(saved, changes, false))) {
    return "keys other than the listed changes differ";
  }
  return {};
}

}  // namespace kfw::testing
