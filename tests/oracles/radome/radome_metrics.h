// Test-only: seed 001's metrics as the retired built-in radome scenario computed them from a run
// of the oracle IMM — moved from engine/scenarios/radome/radome_scenario.cpp (issue 30) so the
// model file's `metrics` block (presets/radome.json) is still compared with the code it replaced,
// under the same names. Error metrics skip the first 10 s, as seed 001 does.
#pragma once

#include "core/dataset.h"
#include "core/expected.h"
#include "core/scenario.h"
#include "oracles/radome/radome_imm.h"

namespace kfw::radome {

// Adds to `r`, a run_radome_imm over `d`, the truth series of `d` (absent columns: NaN), the NEES
// of the combined position, the metrics and the reasons for those without a value; then moves
// non-finite metrics to `undefined`, as finalize_run does after a scenario's run.
void add_radome_metrics(RadomeResult& r, const Dataset& d);

// The built-in scenario's run: run_radome_imm on the dataset's columns (the aircraft acceleration
// ax/ay/az_mps2 where present), then add_radome_metrics.
Expected<RadomeResult> run_radome_with_metrics(const Dataset& d, const FilterParams& p,
                                               const RunControl& control = {});

}  // namespace kfw::radome
