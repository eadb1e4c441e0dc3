// How a CSV's columns become roles, from the command line: --map, --unit, --time, --scale,
// --offset, --flip, --sep, --header and --mapping (README "Importing logs"), over the preset's
// mapping. Declared once (import_args_cli.h) for kfw-cli's commands and for kfw, applied here.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "data/mapping.h"

namespace kfw {

struct Workspace;

struct ImportArgs {
  std::vector<std::string> map, unit, scale, offset, flip;  // ROLE=COLUMN, ROLE=UNIT, ...; ROLE
  std::optional<std::string> time, sep, mapping_file;       // COLUMN[:UNIT|:iso], SEP, FILE
  std::optional<std::string> header;                        // first, none, detect
  bool any() const { return any_role() || time || sep || header; }
  // An option that names a role other than time, or a mapping file (which may name any role).
  bool any_role() const {
    return !map.empty() || !unit.empty() || !scale.empty() || !offset.empty() || !flip.empty() ||
           mapping_file;
  }
};

// The options over mapping `m` for these roles (time "t" is always one): a --mapping file
// replaces the roles it names, then each option changes one field of one role. Unknown roles and
// units, bad numbers and a bad mapping file are errors naming the option or the file's key.
Status apply_import_args(const ImportArgs& imp, const std::vector<ColumnSpec>& roles, Mapping& m);
// The options over the workspace's mapping; refused (naming the option) when the workspace has
// no file data in force (--data or the preset's "data"): the run would simulate.
Status apply_import_args(const ImportArgs& imp, Workspace& ws);

}  // namespace kfw
