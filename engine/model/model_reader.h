// The reader of a model block (model_spec.cpp, model_process.cpp): what each place may use, the
// key-naming helpers and the Reader that turns JSON into checked expressions and matrices with
// messages "PATH: KEY: what". Internal to the model room.
#pragma once

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "core/suggest.h"
#include "model/model_spec.h"

namespace kfw::model::detail {

using nlohmann::json;

// What each place in the model may use, for compile_expr and its messages.
inline constexpr KindMask kParamsOnly = kParamSymbol;
inline constexpr KindMask kLinear = kParamSymbol | kDtSymbol | kTimeSymbol;
inline constexpr KindMask kInputSim = kParamSymbol | kTimeSymbol;
inline constexpr const char* kParamsOnlyWhat = "parameters only";
inline constexpr const char* kLinearWhat =
    "parameters, dt and t: a matrix of a linear model cannot depend on states or inputs; "
    "declare f or h instead";
inline constexpr const char* kInputSimWhat = "parameters and t";

inline std::string idx(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

inline std::string number_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline std::string size_text(int r, int c) {
  return std::to_string(r) + "×" + std::to_string(c);
}

// "unknown key (did you mean 'measurements'?)", or the known keys when none is near.
inline std::string unknown_key(const std::string& word, std::initializer_list<const char*> known) {
  const std::vector<std::string> keys(known.begin(), known.end());
  if (auto near = nearest(word, keys)) return "unknown key (did you mean '" + *near + "'?)";
  std::string list;
  for (const auto& k : keys)
    list += (list.empty() ? "" : ", ") + k;
  return "unknown key (known: " + list + ")";
}

class Reader {
 public:
  Reader(std::string path, Symbols& symbols) : path_(std::move(path)), symbols_(symbols) {}

  Error error(const std::string& key, const std::string& what) const {
    return Error{path_ + ": " + key + ": " + what};
  }

  Expected<Expr> expr(const json& j, const std::string& key, KindMask allowed,
                      const char* what) const {
    std::string text;
    if (j.is_number()) {
      text = number_text(j.get<double>());
    } else if (j.is_string()) {
      text = j.get<std::string>();
    } else {
      return error(key, "expected an expression (a string or a number), got " + j.dump());
    }
    auto e = compile_expr(text, key, symbols_, allowed, what);
    if (!e) return Error{path_ + ": " + e.error()};
    return e;
  }

  // A rows × cols matrix: a list of rows; a flat list is a column (cols == 1) or, when `diag`,
  // the diagonal of a square matrix.
  Expected<MatrixSpec> matrix(const json& j, const std::string& key, int rows, int cols,
                              KindMask allowed, const char* what, bool diag = false) const {
    MatrixSpec m;
    m.key = key;
    m.rows = rows;
    m.cols = cols;
    if (!j.is_array()) return error(key, "expected a matrix (a list of rows), got " + j.dump());
    const bool flat =
        !j.empty() && std::none_of(j.begin(), j.end(), [](const json& e) { return e.is_array(); });
    const auto n = static_cast<std::size_t>(rows);
    if (flat && (cols == 1 || (diag && rows == cols))) {
      if (j.size() != n) {
        return error(key, "wrong dimensions: expected " + std::to_string(rows) +
                              (cols == 1 ? " entries (a column)" : " diagonal entries") + ", got " +
                              std::to_string(j.size()));
      }
      m.e.assign(n * static_cast<std::size_t>(cols), Expr{"0", Dep::kConst, 0.0});
      for (std::size_t i = 0; i < n; ++i) {
        auto e = expr(j[i], idx(key, i), allowed, what);
        if (!e) return e.err();
        m.e[i * static_cast<std::size_t>(cols) + (cols == 1 ? 0 : i)] = *e;
      }
      return m;
    }
    if (auto st = dimensions(j, key, rows, cols, flat); !st) return st.err();
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < static_cast<std::size_t>(cols); ++c) {
        auto e = expr(j[i][c], idx(idx(key, i), c), allowed, what);
        if (!e) return e.err();
        m.e.push_back(*e);
      }
    }
    return m;
  }

  // A list of rows has the shape rows × cols; else the message says how it differs: the count
  // of rows (and their common length), or the first row (counted from 0, as in KEY[i][j]) that
  // is not a list or has the wrong length.
  Status dimensions(const json& j, const std::string& key, int rows, int cols, bool flat) const {
    const auto n = static_cast<std::size_t>(rows), m = static_cast<std::size_t>(cols);
    const auto wrong = [&](const json& r) { return !r.is_array() || r.size() != m; };
    if (j.size() == n && std::none_of(j.begin(), j.end(), wrong)) return Ok{};
    const std::string expected = "wrong dimensions: expected " + size_text(rows, cols) + ", ";
    const bool same = !j.empty() && std::all_of(j.begin(), j.end(), [&](const json& r) {
      return r.is_array() && r.size() == j[0].size();
    });
    const std::string got = "got " + std::to_string(j.size()) + " rows";
    if (flat) return error(key, expected + got + " of single entries");
    if (j.size() != n || same) {
      return error(key, expected + got + (same ? " of " + std::to_string(j[0].size()) : ""));
    }
    const auto row = static_cast<std::size_t>(std::find_if(j.begin(), j.end(), wrong) - j.begin());
    const json& r = j[row];
    return error(
        key, expected + idx(key, row) +
                 (r.is_array()
                      ? " has " + std::to_string(r.size()) + (r.size() == 1 ? " entry" : " entries")
                      : " is not a row (a list of " + std::to_string(cols) + " entries)"));
  }

  // A covariance: square, symmetric (symbolically, by GiNaC).
  Status symmetric(const MatrixSpec& m) const {
    for (int i = 0; i < m.rows; ++i) {
      for (int j = i + 1; j < m.cols; ++j) {
        if (!same_function(m.at(i, j), m.at(j, i), symbols_)) {
          const auto key = [&](int a, int b) {
            return idx(idx(m.key, static_cast<std::size_t>(a)), static_cast<std::size_t>(b));
          };
          return error(m.key, "not symmetric: " + key(i, j) + " = \"" + m.at(i, j).text +
                                  "\" but " + key(j, i) + " = \"" + m.at(j, i).text + "\"");
        }
      }
    }
    return Ok{};
  }

  Expected<Angle> angle(const json& obj, const std::string& key) const {
    auto it = obj.find("angle");
    if (it == obj.end() || it->is_null() || (it->is_boolean() && !it->get<bool>())) {
      return Angle::kNone;
    }
    if (it->is_string() && it->get<std::string>() == "rad") return Angle::kRad;
    if (it->is_string() && it->get<std::string>() == "deg") return Angle::kDeg;
    return error(key + ".angle", "expected \"rad\" or \"deg\", got " + it->dump());
  }

  Status only_keys(const json& obj, const std::string& key,
                   std::initializer_list<const char*> known) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; })) {
        return error(key + "." + truncate_token(it.key()), unknown_key(it.key(), known));
      }
    }
    return Ok{};
  }

  Expected<std::string> string(const json& obj, const char* name, const std::string& key,
                               bool required, std::string def = {}) const {
    auto it = obj.find(name);
    if (it == obj.end() || it->is_null()) {
      if (required) return error(key, std::string("missing key '") + name + "'");
      return def;
    }
    if (!it->is_string()) return error(key + "." + name, "expected a string");
    return it->get<std::string>();
  }

 private:
  std::string path_;
  Symbols& symbols_;
};

// The process block, in any of its four forms (model_process.cpp).
Status parse_process(const Reader& p, const json& j, ModelSpec& m);

// Pre-processed measurements (model_preprocess.cpp): the columns of channels with `z` as symbols
// (before the sub-expressions, which may read them); a channel's `z` (or its roles as its
// components); an expression reading only channel c's columns; x0 entries naming a channel's
// component ("CHANNEL.COMPONENT", after the channels).
Status add_column_symbols(const Reader& p, const json& j, ModelSpec& m);
// One channel of model.measurements (roles read are recorded in `roles_seen`).
Expected<ChannelSpec> parse_channel(const Reader& p, const std::string& name, const json& j,
                                    const ModelSpec& m, const ParamTable& params,
                                    std::set<std::string>& roles_seen);
Status parse_preprocess(const Reader& p, const json& j, const std::string& key, const ModelSpec& m,
                        ChannelSpec& c);
Status check_own_columns(const Reader& p, const Expr& e, const std::string& key, const ModelSpec& m,
                         const ChannelSpec& c);
Status resolve_initial_channels(const Reader& p, ModelSpec& m);
// Before the derived quantities: each grid axis's parameter slot and its truth column as a symbol
// (ModelSpec::grid_param_slots, grid_truth_slots; the axes are checked with the modes).
void add_grid_symbols(const json& j, ModelSpec& m);

// A world's own keys (world/model_world_parse.cpp): its noise sources (symbols), its clocks, and a
// sensor's clock, dropout and outliers (`j` the channel's object, `key` its key).
Status parse_noise_sources(const Reader& p, const json& world, ModelSpec& m);
Status parse_clocks(const Reader& p, const json& world, ModelSpec& m);
Status parse_sensor(const Reader& p, const json& j, const std::string& key,
                    const ParamTable& params, ModelSpec& m, ChannelSpec& c);

// model_groups.cpp: a channel's "gate" (a χ² probability, or {"sigma": EXPR} in version 2 for a
// scalar channel) and "outlier_column" (version 2), from the channel's object `j` at `key`; and
// the "groups" block (version 2).
Status parse_gate(const Reader& p, const json& j, const std::string& key, int version,
                  ChannelSpec& c);
Status parse_groups(const Reader& p, const json& groups, const ParamTable& params, ModelSpec& m);

// {"param": CHOICE, LABEL: value, ...} (model_groups.cpp): a choice parameter and each of its
// labels' values in the parameter's order — every label given, no other key; `what` names a
// value in messages ("missing the clock for 'sim.clock' = 'asynchronous'").
struct ChoiceAlternatives {
  std::string param;
  std::vector<const json*> values;  // per choice index
};
Expected<ChoiceAlternatives> choice_alternatives(const Reader& p, const json& j,
                                                 const std::string& key, const ParamTable& params,
                                                 const char* what);
// "unknown choice parameter 'NAME' (did you mean ...)" at KEY.param.
Error unknown_choice_parameter(const Reader& p, const std::string& key, const std::string& name,
                               const ParamTable& params);

}  // namespace kfw::model::detail
