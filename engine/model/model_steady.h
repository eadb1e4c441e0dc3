// The steady state of a linear time-invariant model (F, B, Q, H, R of parameters and dt only):
// the DARE of the m-step model F^m, Σ_{i<m} F^i Q F^iᵀ when every channel updates every m-th row,
// all channels stacked. `kfw-cli gain` reports it; `filter = steady` (issue 30) runs with its gain.
#pragma once

#include <string>
#include <vector>

#include "core/expected.h"
#include "core/types.h"
#include "filter/dare.h"
#include "model/model_eval.h"

namespace kfw::model {

struct ModelSteadyState {
  SteadyState dare;                // K (n × Σ m), P_pred, P_post, iterations
  int every = 1;                   // the channels' common rate m
  std::vector<std::string> roles;  // the stacked components, in channel order
};

// At the evaluator's current dt. An Error names the file: not time-invariant, channels at
// different rates, or the DARE failing.
Expected<ModelSteadyState> model_steady_state(const ModelSpec& s, const ModelEval& ev);

// The m-step model of a channel updated every m-th step: F^m and Σ_{i<m} F^i Q F^iᵀ.
void m_step(const MatX& F, const MatX& Q, int m, MatX& Fm, MatX& Qm);

}  // namespace kfw::model
