// A dataset with some columns dropped, as a real log would come without them (truth, injected
// outliers). Names the dataset does not have are ignored.
#pragma once

#include <initializer_list>

#include "core/dataset.h"

namespace kfw::test {

inline Dataset without_columns(Dataset d, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    const int i = d.index(name);
    if (i < 0) continue;
    d.names.erase(d.names.begin() + i);
    d.columns.erase(d.columns.begin() + i);
  }
  return d;
}

}  // namespace kfw::test
