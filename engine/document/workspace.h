// What both front ends (kfw, kfw-cli) do first: a preset, an optional dataset override and
// --set assignments become a scenario, validated parameter values and a dataset.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"
#include "core/scenario.h"
#include "data/table.h"
#include "document/preset.h"

namespace kfw {

struct Workspace {
  Preset preset;
  std::shared_ptr<const Scenario> scenario;
  ParamValues values;                    // preset values with --set applied
  std::optional<std::string> data_path;  // --data, else the preset's; none = simulate
  bool data_from_preset = false;         // the path is the preset's "data" key
  Mapping mapping;  // the preset's mapping and file format (command-line options override)
  std::optional<std::string> mapping_path;  // --mapping FILE (an input, never an output)
};

// `preset` may be a path, or a name in presets/ ("helicopter"). Errors name the file or key.
Expected<Workspace> open_workspace(const std::string& preset,
                                   const std::optional<std::string>& data,
                                   const std::vector<std::string>& assignments);
// The file's dataset (checked against the scenario's columns), or a simulated one.
Expected<Dataset> load_dataset(const Workspace& ws);
// Reads a CSV (table.h, with the mapping's separator and header row) through the mapping
// (import.h) and checks it against the scenario's columns (the data policy of dataset.h: only
// columns bound to a role are validated). A required role with no column is named with the
// mapping the guesser proposes.
Expected<Dataset> load_dataset_file(const Scenario& scenario, const std::string& path,
                                    const Mapping& mapping = {});
Expected<Dataset> import_dataset(const Scenario& scenario, const Table& table,
                                 const Mapping& mapping);
// The command-line options that give a mapping: "--time time_ms:ms --map gyro=omega ...", each
// shell-quoted (command_line.h writes them).
std::string mapping_options(const Mapping& m);

}  // namespace kfw
