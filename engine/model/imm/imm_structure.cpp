// model.modes.structure: blocks of states that the model keeps apart, declared (or "detect": the
// finest that it keeps apart exactly), checked against the base model and every mode's (F and H
// must not couple blocks; Q, R and P0 neither, unless `approximate` drops their cross-block
// entries).
#include <nlohmann/json.hpp>

#include "model/imm/imm_spec.h"
#include "model/model_reader.h"
#include "model/model_spec.h"

namespace kfw::model {

const StructureSpec* StructureChoice::at(const ParamValues& v) const {
  if (param.empty()) return fixed.get();
  const auto it = v.find(param);
  if (it == v.end() || !(it->second >= 0.0)) return fixed.get();
  const auto i = static_cast<std::size_t>(it->second);
  return i < by_choice.size() ? by_choice[i].get() : fixed.get();
}

namespace detail {

namespace {

using nlohmann::json;

bool zero(const Expr& e) {
  return e.dep == Dep::kConst && e.value == 0.0;
}

// The first entry of a square matrix over the states that couples two blocks, or "".
std::string coupling(const MatrixSpec& m, const std::vector<int>& block_of) {
  if (m.empty() || m.rows != static_cast<int>(block_of.size()) || m.cols != m.rows) return {};
  for (int i = 0; i < m.rows; ++i) {
    for (int j = 0; j < m.cols; ++j) {
      if (block_of[static_cast<std::size_t>(i)] != block_of[static_cast<std::size_t>(j)] &&
          !zero(m.at(i, j))) {
        return idx(idx(m.key, static_cast<std::size_t>(i)), static_cast<std::size_t>(j));
      }
    }
  }
  return {};
}

// The states each noise input drives: column k of G (G absent: the identity).
std::vector<std::vector<int>> driven(const ProcessSpec& pr, int n) {
  std::vector<std::vector<int>> s(static_cast<std::size_t>(pr.Qc.rows));
  for (int k = 0; k < pr.Qc.rows; ++k) {
    for (int i = 0; i < n; ++i) {
      if (pr.G.empty() ? i == k : !zero(pr.G.at(i, k))) s[static_cast<std::size_t>(k)].push_back(i);
    }
  }
  return s;
}

// The continuous forms' Q = ∫ e^{Aτ} G Qc Gᵀ e^{Aᵀτ}: with F keeping the blocks apart, it couples
// two blocks where G Qc Gᵀ does: a state driven by input k and one driven by input l, Qc(k, l)
// structurally non-zero. Linear in the states per entry of Qc (a 1 000-state model loads at once).
std::string noise_coupling(const ModelSpec& m, const std::vector<int>& block_of) {
  const ProcessSpec& pr = m.process;
  if (pr.Qc.empty()) return {};
  const auto s = driven(pr, static_cast<int>(block_of.size()));
  const auto block = [&](int i) { return block_of[static_cast<std::size_t>(i)]; };
  for (int k = 0; k < pr.Qc.rows; ++k) {
    for (int l = 0; l < pr.Qc.cols; ++l) {
      const auto& a = s[static_cast<std::size_t>(k)];
      const auto& b = s[static_cast<std::size_t>(l)];
      if (a.empty() || b.empty() || zero(pr.Qc.at(k, l))) continue;
      int i = a.front(), j = -1;
      for (int c : b) {
        if (j < 0 && block(c) != block(i)) j = c;
      }
      for (std::size_t c = 0; j < 0 && c < a.size(); ++c) {
        if (block(a[c]) != block(b.front())) i = a[c], j = b.front();
      }
      if (j < 0) continue;
      return pr.Qc.key + ": G Qc Gᵀ couples the states '" +
             m.states[static_cast<std::size_t>(i)].name + "' and '" +
             m.states[static_cast<std::size_t>(j)].name + "' of two blocks";
    }
  }
  return {};
}

// Each component's block from its H row (symbolic for h); Error when a row reads two blocks or
// R couples components of two blocks without `approximate`.
Status channel_blocks(const Reader& p, const std::string& key, const ModelSpec& m,
                      StructureSpec& s) {
  s.component_block.clear();
  for (const ChannelSpec& c : m.channels) {
    std::vector<int> blocks;
    for (int r = 0; r < c.H.rows; ++r) {
      int b = -1;
      for (int i = 0; i < c.H.cols; ++i) {
        if (zero(c.H.at(r, i))) continue;
        const int bi = s.block_of[static_cast<std::size_t>(i)];
        if (b >= 0 && b != bi) {
          return p.error(key, idx(c.H.key, static_cast<std::size_t>(r)) +
                                  " reads states of two blocks: a component belongs to one");
        }
        b = bi;
      }
      blocks.push_back(b);
    }
    if (!s.approximate) {
      for (int a = 0; a < c.R.rows; ++a) {
        for (int b = 0; b < c.R.cols; ++b) {
          if (blocks[static_cast<std::size_t>(a)] != blocks[static_cast<std::size_t>(b)] &&
              !zero(c.R.at(a, b))) {
            return p.error(
                key, idx(idx(c.R.key, static_cast<std::size_t>(a)), static_cast<std::size_t>(b)) +
                         " couples components of two blocks (\"approximate\": true "
                         "drops such entries of Q, R and P0)");
          }
        }
      }
    } else if (c.R.dep() == Dep::kState) {
      return p.error(key, c.R.key + " depends on states: \"approximate\" cannot drop its entries");
    }
    s.component_block.push_back(std::move(blocks));
  }
  return Ok{};
}

// F (or A, or ∂f/∂x) and H must keep the blocks apart; Q and P0 too unless approximate.
Status check_model(const Reader& p, const std::string& key, const ModelSpec& m, StructureSpec& s) {
  const ProcessSpec& pr = m.process;
  for (const MatrixSpec* f : {&pr.F, &pr.A}) {
    if (auto at = coupling(*f, s.block_of); !at.empty()) {
      return p.error(key, at + " couples two blocks: F keeps the blocks apart");
    }
  }
  if (!s.approximate) {
    if (auto at = noise_coupling(m, s.block_of); !at.empty()) {
      return p.error(key, at + " (\"approximate\": true drops such entries of Q, R and P0)");
    }
    for (const MatrixSpec* q : {&pr.Q, &m.P0}) {
      if (auto at = coupling(*q, s.block_of); !at.empty()) {
        return p.error(key, at + " couples two blocks (\"approximate\": true drops such entries " +
                                "of Q, R and P0)");
      }
    }
  } else if (m.process_noise_at_state()) {
    return p.error(key, "Q depends on states: \"approximate\" cannot drop its entries");
  }
  return channel_blocks(p, key, m, s);
}

// Union–find over the states: detect() joins every pair that a model couples exactly.
struct Joined {
  std::vector<int> up;
  explicit Joined(std::size_t n) : up(n) {
    for (std::size_t i = 0; i < n; ++i)
      up[i] = static_cast<int>(i);
  }
  int root(int i) {
    while (up[static_cast<std::size_t>(i)] != i)
      i = up[static_cast<std::size_t>(i)] =
          up[static_cast<std::size_t>(up[static_cast<std::size_t>(i)])];
    return i;
  }
  void join(int a, int b) { up[static_cast<std::size_t>(root(a))] = root(b); }
  void join_square(const MatrixSpec& m) {
    if (m.empty() || m.rows != static_cast<int>(up.size()) || m.cols != m.rows) return;
    for (int i = 0; i < m.rows; ++i) {
      for (int j = 0; j < m.cols; ++j) {
        if (i != j && !zero(m.at(i, j))) join(i, j);
      }
    }
  }
};

// Joins what one model couples: F (or A, ∂f/∂x), Q, G Qc Gᵀ, P0, the states one H row reads and
// the components R correlates.
void join_model(const ModelSpec& m, Joined& s) {
  const ProcessSpec& pr = m.process;
  for (const MatrixSpec* f : {&pr.F, &pr.A, &pr.Q, &m.P0})
    s.join_square(*f);
  const auto in = driven(pr, static_cast<int>(s.up.size()));
  for (int k = 0; k < pr.Qc.rows; ++k) {
    for (int l = 0; l < pr.Qc.cols; ++l) {
      const auto& a = in[static_cast<std::size_t>(k)];
      const auto& b = in[static_cast<std::size_t>(l)];
      if (a.empty() || b.empty() || zero(pr.Qc.at(k, l))) continue;
      for (int i : a)
        s.join(i, b.front());
      for (int j : b)
        s.join(j, a.front());
    }
  }
  for (const ChannelSpec& c : m.channels) {
    std::vector<int> first(static_cast<std::size_t>(c.H.rows), -1);  // a state each row reads
    for (int r = 0; r < c.H.rows; ++r) {
      for (int i = 0; i < c.H.cols; ++i) {
        if (zero(c.H.at(r, i))) continue;
        int& f = first[static_cast<std::size_t>(r)];
        if (f >= 0) s.join(f, i);
        f = i;
      }
    }
    for (int a = 0; a < c.R.rows; ++a) {
      for (int b = 0; b < c.R.cols; ++b) {
        const int fa = first[static_cast<std::size_t>(a)], fb = first[static_cast<std::size_t>(b)];
        if (fa >= 0 && fb >= 0 && !zero(c.R.at(a, b))) s.join(fa, fb);
      }
    }
  }
}

// "detect": the finest blocks that the model and every mode keep apart exactly, as the blocks
// of a declared structure (in state order); an Error when everything is one block.
Expected<json> detect(const Reader& p, const std::string& key, const ModelSpec& base,
                      const ModesSpec& out) {
  Joined s(base.states.size());
  join_model(base, s);
  for (const ModeSpec& m : out.list) {
    if (m.model) join_model(*m.model, s);
  }
  json blocks = json::array();
  std::vector<int> block_of_root(base.states.size(), -1);
  for (std::size_t i = 0; i < base.states.size(); ++i) {
    int& b = block_of_root[static_cast<std::size_t>(s.root(static_cast<int>(i)))];
    if (b < 0) {
      b = static_cast<int>(blocks.size());
      blocks.push_back(json::array());
    }
    blocks[static_cast<std::size_t>(b)].push_back(base.states[i].name);
  }
  if (blocks.size() < 2) {
    return p.error(key,
                   "\"detect\": the model couples all its states (F, Q, P0, H or R), so "
                   "there are no blocks to filter apart; declare {\"blocks\", "
                   "\"approximate\": true} to drop cross-block terms, or \"none\"");
  }
  return json{{"blocks", std::move(blocks)}};
}

Expected<std::shared_ptr<const StructureSpec>> parse_blocks(const Reader& p, const json& j,
                                                            const std::string& key,
                                                            const ModelSpec& base,
                                                            const ModesSpec& out) {
  if (j.is_string() && j.get<std::string>() == "none")
    return std::shared_ptr<const StructureSpec>();
  if (j.is_string() && j.get<std::string>() == "detect") {
    auto found = detect(p, key, base, out);
    if (!found) return found.err();
    return parse_blocks(p, *found, key, base, out);
  }
  if (!j.is_object()) {
    return p.error(key, "expected \"none\", \"detect\" or {\"blocks\", \"approximate\"}");
  }
  if (auto st = p.only_keys(j, key, {"blocks", "approximate"}); !st) return st.err();
  auto s = std::make_shared<StructureSpec>();
  s->block_of.assign(base.states.size(), -1);
  const auto it = j.find("blocks");
  if (it == j.end() || !it->is_array() || it->size() < 2) {
    return p.error(key + ".blocks", "expected a list of two or more lists of states");
  }
  for (std::size_t b = 0; b < it->size(); ++b) {
    const json& block = (*it)[b];
    if (!block.is_array() || block.empty())
      return p.error(idx(key + ".blocks", b), "expected a list of states");
    for (const json& name : block) {
      const int i = name.is_string() ? base.state_index(name.get<std::string>()) : -1;
      if (i < 0) return p.error(idx(key + ".blocks", b), "unknown state " + name.dump());
      if (s->block_of[static_cast<std::size_t>(i)] >= 0)
        return p.error(idx(key + ".blocks", b), "state " + name.dump() + " is in two blocks");
      s->block_of[static_cast<std::size_t>(i)] = static_cast<int>(b);
    }
  }
  for (std::size_t i = 0; i < s->block_of.size(); ++i) {
    if (s->block_of[i] < 0) {
      return p.error(key + ".blocks", "state '" + base.states[i].name + "' is in no block");
    }
  }
  if (auto a = j.find("approximate"); a != j.end()) {
    if (!a->is_boolean()) return p.error(key + ".approximate", "expected true or false");
    s->approximate = a->get<bool>();
  }
  if (auto st = check_model(p, key, base, *s); !st) return st.err();
  for (const ModeSpec& m : out.list) {
    if (!m.model) continue;
    StructureSpec mode = *s;
    if (auto st = check_model(p, key + " (mode '" + m.name + "')", *m.model, mode); !st)
      return st.err();
    if (mode.component_block != s->component_block) {
      return p.error(key + " (mode '" + m.name + "')",
                     "a channel's components read other blocks than in the model: the blocks "
                     "of a component are the same in every mode");
    }
  }
  return std::shared_ptr<const StructureSpec>(std::move(s));
}

}  // namespace

Status parse_structure(const Reader& p, const json& j, const ParamTable& params,
                       const ModelSpec& base, ModesSpec& out) {
  const std::string key = "model.modes.structure";
  if (j.is_object() && j.contains("param")) {
    auto alt = choice_alternatives(p, j, key, params, "structure");
    if (!alt) return alt.err();
    out.structure.param = alt->param;
    for (std::size_t c = 0; c < alt->values.size(); ++c) {
      const std::string& label = params.find(alt->param)->choices[c];
      auto s = parse_blocks(p, *alt->values[c], key + "." + label, base, out);
      if (!s) return s.err();
      out.structure.by_choice.push_back(std::move(*s));
    }
    return Ok{};
  }
  auto s = parse_blocks(p, j, key, base, out);
  if (!s) return s.err();
  out.structure.fixed = std::move(*s);
  return Ok{};
}

}  // namespace detail

}  // namespace kfw::model
