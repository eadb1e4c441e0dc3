// model.modes.structure: blocks of states that the model keeps apart, declared, checked against
// the base model and every mode's (F and H must not couple blocks; Q, R and P0 neither, unless
// `approximate` drops their cross-block entries).
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

// The continuous forms' Q = ∫ e^{Aτ} G Qc Gᵀ e^{Aᵀτ}: with F keeping the blocks apart, it couples
// two blocks where G Qc Gᵀ does: (i, j) with some G(i, k) Qc(k, l) G(j, l) structurally non-zero
// (G absent: the identity).
std::string noise_coupling(const ModelSpec& m, const std::vector<int>& block_of) {
  const ProcessSpec& pr = m.process;
  if (pr.Qc.empty()) return {};
  const auto n = static_cast<int>(block_of.size());
  const auto g = [&](int i, int k) { return pr.G.empty() ? i == k : !zero(pr.G.at(i, k)); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (block_of[static_cast<std::size_t>(i)] == block_of[static_cast<std::size_t>(j)]) continue;
      for (int k = 0; k < pr.Qc.rows; ++k) {
        for (int l = 0; l < pr.Qc.cols; ++l) {
          if (g(i, k) && g(j, l) && !zero(pr.Qc.at(k, l))) {
            return pr.Qc.key + ": G Qc Gᵀ couples the states '" +
                   m.states[static_cast<std::size_t>(i)].name + "' and '" +
                   m.states[static_cast<std::size_t>(j)].name + "' of two blocks";
          }
        }
      }
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

Expected<std::shared_ptr<const StructureSpec>> parse_blocks(const Reader& p, const json& j,
                                                            const std::string& key,
                                                            const ModelSpec& base,
                                                            const ModesSpec& out) {
  if (j.is_string() && j.get<std::string>() == "none")
    return std::shared_ptr<const StructureSpec>();
  if (!j.is_object()) return p.error(key, "expected \"none\" or {\"blocks\", \"approximate\"}");
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
