// Model expressions as C (the C export, issue 31): the language of model/expression.h — numbers,
// symbols, + - * / ^, unary minus, parentheses and the language's functions — read from a
// checked expression's text (sub-expressions expanded; derivatives as GiNaC printed them) and
// written as C99 in double or single precision. The expressions of one function share their
// common sub-expressions: each repeated sub-tree is computed once into a named temporary.
#pragma once

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/expected.h"

namespace kfw::codegen {

// The C text of a number: the shortest decimal that reads back exactly, with a decimal point
// (so 1/2 stays a division of doubles), and `f` in single precision.
std::string c_number(double v, bool single);

// The expressions of one generated function.
class CExprSet {
 public:
  // `symbol` gives the C text of a model symbol (a state x[0], a constant par_Q, dt, t).
  CExprSet(bool single, std::function<std::string(const std::string&)> symbol);
  ~CExprSet();
  CExprSet(const CExprSet&) = delete;
  CExprSet& operator=(const CExprSet&) = delete;

  // Reads one expression; its index in emit()'s output. An Error names the key.
  Expected<int> add(const std::string& text, const std::string& key);
  // The temporaries (`const double c0 = …;` lines at `indent`) and each expression's C text.
  std::string emit(const std::string& indent, std::vector<std::string>& texts,
                   const std::string& temp_prefix = "c");
  // The helper functions the texts call (kfw_sq, kfw_sinc, …), for the runtime to emit.
  const std::set<std::string>& helpers() const { return helpers_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::set<std::string> helpers_;
};

}  // namespace kfw::codegen
