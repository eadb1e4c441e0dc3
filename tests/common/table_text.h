// A CSV text parsed as a table, for engine tests of the import.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "data/table.h"

namespace kfw::testing {

// `text` as the file f.csv (a test failure and an empty table when it does not parse).
inline Table table(const std::string& text, const TableOptions& opt = {}) {
  auto t = parse_table(text, "f.csv", opt);
  EXPECT_TRUE(t.ok()) << t.error();
  return t.ok() ? *t : Table{};
}

}  // namespace kfw::testing
