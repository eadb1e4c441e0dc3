// The symbolic half of the expression language: GiNaC reads every expression once when a model
// loads (the same meaning as muparser's, else refused), differentiates it, and prints derivatives
// back for muparser. Runs never touch GiNaC.
#include <ginac/ginac.h>
#include <algorithm>

#include <cmath>
#include <limits>
#include <mutex>
#include <regex>
#include <stdexcept>
#include <unordered_map>

#include "model/expression_detail.h"

// min and max for GiNaC, with the derivatives ∂min(a, b)/∂a = step(b − a) and so on (step(0) =
// 1/2, as GiNaC's and ours). Namespace scope: the GiNaC macros define types named after them.
namespace kfw::model::symbolic {

DECLARE_FUNCTION_2P(kfw_min)
DECLARE_FUNCTION_2P(kfw_max)

static GiNaC::ex min_deriv(const GiNaC::ex& a, const GiNaC::ex& b, unsigned i) {
  return i == 0 ? GiNaC::step(b - a) : GiNaC::step(a - b);
}
static GiNaC::ex max_deriv(const GiNaC::ex& a, const GiNaC::ex& b, unsigned i) {
  return i == 0 ? GiNaC::step(a - b) : GiNaC::step(b - a);
}

REGISTER_FUNCTION(kfw_min, derivative_func(min_deriv).set_name("min"))
REGISTER_FUNCTION(kfw_max, derivative_func(max_deriv).set_name("max"))

// sinc(x) = sin(x)/x, 1 at 0, for the removable singularity of steps such as the coordinated
// turn's v/ω·(sin(ψ + ω dt) − sin ψ) = v dt cos(ψ + ω dt/2) sinc(ω dt/2). Its derivative
// dsinc(x) = (cos x − sinc x)/x, 0 at 0, appears only in printed derivatives (no second
// derivative is ever taken).
DECLARE_FUNCTION_1P(kfw_sinc)
DECLARE_FUNCTION_1P(kfw_dsinc)

static GiNaC::ex sinc_deriv(const GiNaC::ex& x, unsigned) {
  return kfw_dsinc(x);
}

REGISTER_FUNCTION(kfw_sinc, derivative_func(sinc_deriv).set_name("sinc"))

// heaviside(x): 1 for x ≥ 0, else 0 (issue 30: a set-point step, a saturation's anti-windup);
// its derivative is 0 wherever it exists.
DECLARE_FUNCTION_1P(kfw_heaviside)

static GiNaC::ex heaviside_deriv(const GiNaC::ex&, unsigned) {
  return 0;
}

REGISTER_FUNCTION(kfw_heaviside, derivative_func(heaviside_deriv).set_name("heaviside"))
REGISTER_FUNCTION(kfw_dsinc, set_name("dsinc"))

}  // namespace kfw::model::symbolic

namespace kfw::model {

namespace {

// GiNaC keeps global state (function registry, shared constants) and counts references without
// atomics: every use goes through this lock. Runs never touch GiNaC.
std::mutex& ginac_mutex() {
  static std::mutex m;
  return m;
}

// The symbols of the texts read in one call (and of `extra` slots), each a GiNaC realsymbol named
// as the model's symbol: only those, not every symbol of the model — a scope of every symbol
// per expression made loading quadratic in the model's size.
struct SymbolicScope {
  GiNaC::symtab table;
  std::unordered_map<int, GiNaC::realsymbol> symbols;  // by slot
  const GiNaC::realsymbol& symbol(int slot) const { return symbols.at(slot); }
};

SymbolicScope make_scope(const Symbols& s, std::initializer_list<const std::string*> texts,
                         const std::vector<int>& extra = {}) {
  SymbolicScope scope;
  const auto add = [&](int slot) {
    if (slot < 0 || scope.symbols.count(slot)) return;
    const std::string& name = s.names[static_cast<std::size_t>(slot)];
    const auto it = scope.symbols.emplace(slot, GiNaC::realsymbol(name)).first;
    scope.table[name] = it->second;
  };
  for (const std::string* text : texts) {
    for (const auto& id : identifiers(*text))
      add(s.find(id));
  }
  for (int slot : extra)
    add(slot);
  scope.table["pi"] = GiNaC::Pi;
  return scope;
}

std::string number_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return v < 0.0 ? "(" + std::string(buf) + ")" : std::string(buf);
}

// A power with a constant exponent beyond this is refused: GiNaC raises exact numbers to exact
// powers at once, and 8888^6888888 (or 2^(2^(2^5))) would take hours and gigabytes.
constexpr double kMaxExponent = 1000.0;

// The numbers of an expression as symbols while GiNaC reads it (so it evaluates none of them),
// and the number each stands for.
struct Literals {
  std::string text;  // the expression with each number replaced by its symbol's name
  GiNaC::symtab table;
  GiNaC::exmap values;  // symbol -> the number as GiNaC reads it
  GiNaC::exmap floats;  // symbol -> the number as a double
};

Literals hide_literals(const std::string& text, const SymbolicScope& scope) {
  Literals out{"", scope.table, {}, {}};
  GiNaC::parser number_reader;
  auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  for (std::size_t i = 0; i < text.size();) {
    const bool starts =
        digit(text[i]) || (text[i] == '.' && i + 1 < text.size() && digit(text[i + 1]));
    if (!starts || (i > 0 && ident(text[i - 1]))) {
      out.text += text[i++];
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && digit(text[j]))
      ++j;
    if (j < text.size() && text[j] == '.') ++j;
    while (j < text.size() && digit(text[j]))
      ++j;
    if (j < text.size() && (text[j] == 'e' || text[j] == 'E')) {
      std::size_t k = j + 1;
      if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
      if (k < text.size() && digit(text[k])) {
        j = k;
        while (j < text.size() && digit(text[j]))
          ++j;
      }
    }
    const std::string number = text.substr(i, j - i);
    std::string name = "kfw_number_" + std::to_string(out.values.size());
    while (out.table.count(name))
      name += "_";
    const GiNaC::realsymbol sym(name);
    out.table[name] = sym;
    out.values[sym] = number_reader(number);
    const double d = std::strtod(number.c_str(), nullptr);
    out.floats[sym] = GiNaC::numeric(std::isfinite(d) ? d : std::numeric_limits<double>::max());
    out.text += " " + name + " ";
    i = j;
  }
  return out;
}

// Throws when a power's exponent is a constant beyond ±kMaxExponent (children first, so an
// exponent is evaluated only once its own powers have passed).
void check_powers(const GiNaC::ex& e, const Literals& lit) {
  for (std::size_t i = 0; i < e.nops(); ++i)
    check_powers(e.op(i), lit);
  if (!GiNaC::is_a<GiNaC::power>(e)) return;
  const GiNaC::ex exponent = e.op(1).subs(lit.floats).evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(exponent)) return;  // depends on symbols
  const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(exponent);
  const double v = n.is_real() ? n.to_double() : HUGE_VAL;
  if (!(std::fabs(v) <= kMaxExponent)) {
    throw std::runtime_error("a constant exponent beyond ±1000 (" +
                             (std::isfinite(v) ? number_text(v) : std::string("too large")) + ")");
  }
}

GiNaC::ex parse_symbolic(const std::string& text, const SymbolicScope& scope) {
  const Literals lit = hide_literals(text, scope);
  GiNaC::parser reader(lit.table, true);
  const GiNaC::ex e = reader(lit.text);
  check_powers(e, lit);
  return e.subs(lit.values);
}

// GiNaC expression -> muparser source, fully parenthesised, function names mapped.
std::string to_muparser(const GiNaC::ex& e) {
  using namespace GiNaC;
  if (is_a<numeric>(e)) {
    const numeric& n = ex_to<numeric>(e);
    if (!n.is_real()) throw std::runtime_error("a complex number");
    return number_text(n.to_double());
  }
  if (is_a<symbol>(e)) return ex_to<symbol>(e).get_name();
  if (is_a<constant>(e)) {
    if (e.is_equal(Pi)) return "pi";
    return number_text(ex_to<numeric>(e.evalf()).to_double());
  }
  // The terms of a sum or product in the order of their text: GiNaC orders them by hashes that
  // hold addresses, so its own order (and the rounding of the sum) changed from one process to
  // the next.
  auto join = [&](const char* op) {
    std::vector<std::string> terms;
    for (std::size_t i = 0; i < e.nops(); ++i)
      terms.push_back(to_muparser(e.op(i)));
    std::sort(terms.begin(), terms.end());
    std::string s = "(";
    for (std::size_t i = 0; i < terms.size(); ++i) {
      if (i) s += op;
      s += terms[i];
    }
    return s + ")";
  };
  if (is_a<add>(e)) return join("+");
  if (is_a<mul>(e)) return join("*");
  if (is_a<power>(e)) {
    const ex expo = e.op(1);
    if (expo.is_equal(numeric(1, 2))) return "sqrt(" + to_muparser(e.op(0)) + ")";
    if (expo.is_equal(numeric(-1))) return "(1/" + to_muparser(e.op(0)) + ")";
    return "(" + to_muparser(e.op(0)) + "^" + to_muparser(expo) + ")";
  }
  if (is_a<function>(e)) {
    std::string name = ex_to<function>(e).get_name();
    if (name == "csgn") name = "sign";
    bool known = name == "sign" || name == "step" || name == "dsinc";
    for (const auto& f : language_functions()) {
      if (f.name == name && static_cast<std::size_t>(f.arity) == e.nops()) known = true;
    }
    if (!known) throw std::runtime_error("the function '" + name + "'");
    std::string s = name + "(";
    for (std::size_t i = 0; i < e.nops(); ++i) {
      if (i) s += ",";
      s += to_muparser(e.op(i));
    }
    return s + ")";
  }
  throw std::runtime_error("a term of type " + std::string(ex_to<basic>(e).class_name()));
}

}  // namespace

namespace detail {

Status check_symbolic(const std::string& text, const std::string& expanded, const std::string& key,
                      const Symbols& symbols) {
  std::lock_guard lock(ginac_mutex());
  try {
    const auto scope = make_scope(symbols, {&expanded});
    (void)parse_symbolic(expanded, scope);
  } catch (const std::exception& e) {
    // GiNaC's message: its first line (the rest is the reader's call stack).
    const std::string what = first_line(e.what());
    static const std::regex kNoFunction(R"(no function \"(\w+)\")");
    if (std::smatch m; std::regex_search(what, m, kNoFunction)) {
      const std::size_t pos = find_identifier(text, m[1].str());
      Error err = at(key, "unknown function '" + m[1].str() + "'",
                     pos == std::string::npos ? 0 : pos, text);
      err.message += nearest_name(m[1].str(), true, symbols, 0);
      return err;
    }
    return Error{key + ": not accepted by the symbolic differentiator (" + what +
                 "); add parentheses: " + quoted(text)};
  }
  return Ok{};
}

}  // namespace detail

using detail::first_line;
using detail::quoted;

Expected<std::vector<Expr>> derivatives(const Expr& e, const std::string& key,
                                        const Symbols& symbols, const std::vector<int>& wrt) {
  std::vector<std::string> texts;
  std::vector<Expr> out(wrt.size());
  {
    std::lock_guard lock(ginac_mutex());
    try {
      const auto scope = make_scope(symbols, {&e.text}, wrt);
      const GiNaC::ex f = parse_symbolic(e.text, scope);
      for (std::size_t i = 0; i < wrt.size(); ++i) {
        const GiNaC::ex d = f.diff(scope.symbol(wrt[i]));
        if (GiNaC::is_a<GiNaC::numeric>(d)) {
          out[i].dep = Dep::kConst;
          out[i].value = GiNaC::ex_to<GiNaC::numeric>(d).to_double();
          out[i].text = number_text(out[i].value);
          texts.emplace_back();
        } else {
          texts.push_back(to_muparser(d));
        }
      }
    } catch (const std::exception& ex) {
      return Error{key + ": cannot differentiate " + quoted(e.text) + ": " + first_line(ex.what())};
    }
  }
  for (std::size_t i = 0; i < wrt.size(); ++i) {
    if (texts[i].empty()) continue;
    const std::string dkey = key + " (d/d" + symbols.names[static_cast<std::size_t>(wrt[i])] + ")";
    auto c = compile_expr(texts[i], dkey, symbols, kAllSymbols, "");
    if (!c) return Error{"internal: the derivative does not read back: " + c.error()};
    out[i] = *c;
  }
  return out;
}

bool same_function(const Expr& a, const Expr& b, const Symbols& symbols) {
  if (a.text == b.text) return true;
  std::lock_guard lock(ginac_mutex());
  try {
    const auto scope = make_scope(symbols, {&a.text, &b.text});
    const GiNaC::ex d = parse_symbolic(a.text, scope) - parse_symbolic(b.text, scope);
    return d.expand().normal().is_zero();
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace kfw::model
