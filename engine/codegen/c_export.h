// A model file's filter as dependency-free C (issue 31): NAME.h, NAME.c and NAME_example.c, C99
// with no allocation and nothing beyond <math.h> (the example adds <stdio.h> to read a CSV in
// kfw's format and write the estimates). The tuned parameters are baked in as named constants;
// an export is reproducible (no date), so the same preset and values give the same bytes.
// docs/c_export.md describes the API, what is exported and what is not.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/param_spec.h"
#include "core/scenario.h"

namespace kfw::codegen {

struct CExportOptions {
  std::string prefix;      // NAME: a C identifier, the files' and the functions' prefix
  bool single = false;     // --float: single precision throughout
  bool steady = false;     // --steady: the fixed DARE gain, no covariance on the target
  double steady_dt = 0.0;  // --steady: the fixed interval (s)
  // --params-struct: the parameters the filter reads in NAME_params, set at NAME_init (the
  // native path of the scale issue; one compiled filter, other values) instead of constants.
  bool runtime_params = false;
  std::string preset;  // the preset's file name, in the header comment (with kfw's version)
};

struct CExport {
  std::string header, source, example;  // NAME.h, NAME.c, NAME_example.c
};

// The export of a model scenario's filter at `values`. An Error (one line, exit 2) says why a
// model cannot be exported (an IMM, channel groups, --steady on a time-varying model, …);
// nothing is written then.
Expected<CExport> export_c(const Scenario& s, const ParamValues& values,
                           const CExportOptions& options);

// True when the export is the steady-state filter: `flag` (--steady), or the preset's
// `filter = steady`.
bool exports_steady(const Scenario& s, const ParamValues& values, bool flag);

// --steady's interval: `dt` when given, else the data's median interval (two rows or more), else
// the model's simulation step (sim.dt or the file's own key). An Error when not positive.
Expected<double> steady_interval(const Scenario& s, const ParamValues& values,
                                 std::optional<double> dt, const Dataset* data);

// The options every surface starts from for a preset file: the prefix from its name, the name
// in the header comment (the CLI and the window write the same bytes).
CExportOptions default_options(const std::string& preset_path);

// A prefix from a preset's file name: its stem with every character that cannot be in a C
// identifier replaced by '_' (a leading digit gets one too).
std::string default_prefix(const std::string& preset_path);
// True when `name` is a C identifier that is no C keyword.
bool is_c_identifier(const std::string& name);

// Declares the three files in `dir` (refused before any work, exit 2, like every output; an
// output that is one of `inputs`, the preset and its data, is refused too), and writes them
// together, each atomically (data/output.h).
Status write_c_export(const std::string& dir, const std::string& prefix, const CExport& files,
                      const std::vector<std::string>& inputs = {});

}  // namespace kfw::codegen
