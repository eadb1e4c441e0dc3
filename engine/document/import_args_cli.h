// The import options (import_args.h) declared on a CLI11 command: one declaration for every
// kfw-cli command that reads data and for kfw. Header-only, for the programs (which link CLI11);
// the engine itself does not parse command lines.
#pragma once

#include <CLI/CLI.hpp>

#include "document/import_args.h"

namespace kfw {

inline void add_import_options(CLI::App* c, ImportArgs& m) {
  auto repeat = [c](const char* name, std::vector<std::string>& dst, const char* type,
                    const char* help) {
    c->add_option(name, dst, help)->type_name(type)->allow_extra_args(false)->take_all();
  };
  repeat("--map", m.map, "ROLE=COLUMN", "read a role from a column (repeatable)");
  repeat("--unit", m.unit, "ROLE=UNIT",
         "the unit the role's column is in, converted to the role's (repeatable)");
  c->add_option_function<std::string>(
       "--time", [&m](const std::string& v) { m.time = v; },
       "the time column, in s (default), ms, us, ns or iso (ISO-8601 date-time)")
      ->type_name("COLUMN[:UNIT]");
  repeat("--scale", m.scale, "ROLE=X", "multiply the role's values after unit conversion");
  repeat("--offset", m.offset, "ROLE=X", "add to the role's values after scaling");
  repeat("--flip", m.flip, "ROLE", "flip the sign of the role's values (repeatable)");
  c->add_option_function<std::string>(
       "--sep", [&m](const std::string& v) { m.sep = v; },
       "the separator: comma, semicolon, tab, whitespace (default: detected)")
      ->type_name("SEP");
  c->add_option_function<std::string>(
       "--header", [&m](const std::string& v) { m.header = v; },
       "the first row: first (the column names), none (data: columns col1, col2, ...), detect "
       "(default: no header when every cell is a number)")
      ->type_name("first|none|detect");
  c->add_option_function<std::string>(
       "--mapping", [&m](const std::string& v) { m.mapping_file = v; },
       "a mapping file (the preset's \"mapping\" block); options above override it")
      ->type_name("FILE.json");
}

}  // namespace kfw
