// What the two halves of the expression language share (expression.cpp reads and evaluates with
// muparser, expression_symbolic.cpp reads and differentiates with GiNaC). Internal to the model
// room.
#pragma once

#include <string>
#include <string_view>

#include "core/expected.h"
#include "model/expression.h"

namespace kfw::model::detail {

// The first line of a library's message, cut to a readable length.
std::string first_line(std::string_view what);
// The text as written, cut and made printable, in quotes.
std::string quoted(const std::string& text);
// "<key>: <what> at position P: "<text>"", P counting characters from 1.
Error at(const std::string& key, const std::string& what, std::size_t pos0,
         const std::string& text);
// " (did you mean 'px'?)": the function (`call`), or the symbol of a kind in `allowed` (or pi),
// nearest to a misspelt name; "" when none is near.
std::string nearest_name(const std::string& name, bool call, const Symbols& symbols,
                         KindMask allowed);
// The position of the first use of identifier `name` in `text` (numbers skipped), or npos.
std::size_t find_identifier(const std::string& text, const std::string& name);
// GiNaC reads `expanded` (the user's `text` with its sub-expressions expanded) as muparser does,
// or the error names the key and a position in `text`.
Status check_symbolic(const std::string& text, const std::string& expanded, const std::string& key,
                      const Symbols& symbols);

}  // namespace kfw::model::detail
