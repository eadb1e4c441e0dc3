#include "model/expression.h"

#include <ginac/ginac.h>
#include <muParser.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <mutex>
#include <numbers>
#include <regex>
#include <stdexcept>

#include "core/suggest.h"

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

}  // namespace kfw::model::symbolic

namespace kfw::model {

namespace {

double step_fn(double x) {
  return x > 0.0 ? 1.0 : (x < 0.0 ? 0.0 : 0.5);
}
double sign_fn(double x) {
  return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0);
}

// The language's functions in muparser (its own built-ins are cleared so that the two libraries
// read the same set). sign and step appear only in printed derivatives (GiNaC's csgn, step).
void setup_parser(mu::Parser& p) {
  p.ClearFun();
  p.ClearConst();
  p.DefineFun(
      "sin", +[](double x) { return std::sin(x); });
  p.DefineFun(
      "cos", +[](double x) { return std::cos(x); });
  p.DefineFun(
      "tan", +[](double x) { return std::tan(x); });
  p.DefineFun(
      "asin", +[](double x) { return std::asin(x); });
  p.DefineFun(
      "acos", +[](double x) { return std::acos(x); });
  p.DefineFun(
      "atan", +[](double x) { return std::atan(x); });
  p.DefineFun(
      "atan2", +[](double y, double x) { return std::atan2(y, x); });
  p.DefineFun(
      "sinh", +[](double x) { return std::sinh(x); });
  p.DefineFun(
      "cosh", +[](double x) { return std::cosh(x); });
  p.DefineFun(
      "tanh", +[](double x) { return std::tanh(x); });
  p.DefineFun(
      "exp", +[](double x) { return std::exp(x); });
  p.DefineFun(
      "log", +[](double x) { return std::log(x); });
  p.DefineFun(
      "sqrt", +[](double x) { return std::sqrt(x); });
  p.DefineFun(
      "abs", +[](double x) { return std::fabs(x); });
  p.DefineFun(
      "pow", +[](double x, double y) { return std::pow(x, y); });
  p.DefineFun(
      "min", +[](double a, double b) { return std::fmin(a, b); });
  p.DefineFun(
      "max", +[](double a, double b) { return std::fmax(a, b); });
  p.DefineFun("sign", &sign_fn);
  p.DefineFun("step", &step_fn);
  p.DefineConst("pi", std::numbers::pi);
}

// GiNaC keeps global state (function registry, shared constants) and counts references without
// atomics: every use goes through this lock. Runs never touch GiNaC.
std::mutex& ginac_mutex() {
  static std::mutex m;
  return m;
}

struct SymbolicScope {
  GiNaC::symtab table;
  std::vector<GiNaC::realsymbol> symbols;  // by slot
};

SymbolicScope make_scope(const Symbols& s) {
  SymbolicScope scope;
  for (const auto& name : s.names) {
    scope.symbols.emplace_back(name);
    scope.table[name] = scope.symbols.back();
  }
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
  auto join = [&](const char* op) {
    std::string s = "(";
    for (std::size_t i = 0; i < e.nops(); ++i) {
      if (i) s += op;
      s += to_muparser(e.op(i));
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
    bool known = name == "sign" || name == "step";
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

// The first line of a library's message, cut to a readable length.
std::string first_line(std::string_view what) {
  return truncate_token(what.substr(0, what.find('\n')), 200);
}

// The text as written, cut and made printable (an expression may hold a newline or be 10 MB).
std::string quoted(const std::string& text) {
  return "\"" + truncate_token(text, 200) + "\"";
}

Error at(const std::string& key, const std::string& what, std::size_t pos0,
         const std::string& text) {
  return Error{key + ": " + what + " at position " + std::to_string(pos0 + 1) + ": " +
               quoted(text)};
}

// " (did you mean 'px'?)": the function, or the symbol usable here (or pi), nearest to a
// misspelt name.
std::string nearest_name(const std::string& name, bool call, const Symbols& symbols,
                         KindMask allowed) {
  std::vector<std::string> names;
  if (call) {
    for (const auto& f : language_functions())
      names.emplace_back(f.name);
  } else {
    for (std::size_t i = 0; i < symbols.names.size(); ++i) {
      if (symbols.kinds[i] & allowed) names.push_back(symbols.names[i]);
    }
    names.emplace_back("pi");
  }
  return did_you_mean(name, names);
}

// The position of the first use of identifier `name` in `text` (numbers skipped), or npos.
std::size_t find_identifier(const std::string& text, const std::string& name) {
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      while (i < text.size() &&
             (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.'))
        ++i;
      if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
        while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])))
          ++i;
      }
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::size_t start = i;
      while (i < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_'))
        ++i;
      if (text.compare(start, i - start, name) == 0 && i - start == name.size()) return start;
    } else {
      ++i;
    }
  }
  return std::string::npos;
}

const char* kind_name(SymbolKind k) {
  switch (k) {
    case kParamSymbol:
      return "parameter";
    case kDtSymbol:
      return "dt";
    case kTimeSymbol:
      return "t";
    case kStateSymbol:
      return "state";
    case kInputSymbol:
      return "input";
  }
  return "symbol";
}

Dep dep_of(SymbolKind k) {
  switch (k) {
    case kParamSymbol:
      return Dep::kParam;
    case kDtSymbol:
      return Dep::kDt;
    case kTimeSymbol:
    case kInputSymbol:
      return Dep::kStep;
    case kStateSymbol:
      return Dep::kState;
  }
  return Dep::kState;
}

}  // namespace

int Symbols::add(const std::string& name, SymbolKind kind) {
  names.push_back(name);
  kinds.push_back(kind);
  return static_cast<int>(names.size()) - 1;
}

int Symbols::find(std::string_view name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<int> Symbols::slots(SymbolKind kind) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    if (kinds[i] == kind) out.push_back(static_cast<int>(i));
  }
  return out;
}

const std::vector<LanguageFunction>& language_functions() {
  static const std::vector<LanguageFunction> f = {
      {"sin", 1},   {"cos", 1},  {"tan", 1},  {"asin", 1}, {"acos", 1}, {"atan", 1},
      {"atan2", 2}, {"sinh", 1}, {"cosh", 1}, {"tanh", 1}, {"exp", 1},  {"log", 1},
      {"sqrt", 1},  {"abs", 1},  {"pow", 2},  {"min", 2},  {"max", 2}};
  return f;
}

bool is_identifier(std::string_view name) {
  if (name.empty()) return false;
  if (!(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  }
  return true;
}

bool is_reserved_name(std::string_view name) {
  static const char* const kReserved[] = {"t", "dt", "pi", "Pi", "sign", "step"};
  for (const char* r : kReserved) {
    if (name == r) return true;
  }
  for (const auto& f : language_functions()) {
    if (f.name == name) return true;
  }
  return false;
}

Expected<Expr> compile_expr(const std::string& text, const std::string& key, const Symbols& symbols,
                            KindMask allowed, std::string_view allowed_what) {
  // Characters of the language only: muparser's comparison, logic and ternary operators are not
  // in GiNaC, so they are refused here with their position.
  int depth = 0;
  bool any = false;
  char prev = '(';
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ' ' || c == '\t') continue;
    any = true;
    // GiNaC's reader takes the whole rest of a sum as the operand of a sign that follows an
    // operator (2*-x + y reads as 2*(-(x + y))): such a sign must be parenthesised.
    if ((c == '-' || c == '+') && std::string_view("+-*/^").find(prev) != std::string_view::npos) {
      return at(
          key,
          std::string("a sign right after an operator must be in parentheses, e.g. 2*(") + c + "x)",
          i, text);
    }
    prev = c;
    if (c == '(') ++depth;
    if (c == ')') --depth;
    if (c == ',' && depth == 0) return at(key, "a comma outside a function's arguments", i, text);
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' ||
                    std::string_view("+-*/^(),").find(c) != std::string_view::npos;
    if (!ok) {
      return at(key, quote_token(std::string(1, c)) + " is not part of the expression language", i,
                text);
    }
  }
  if (!any) return Error{key + ": empty expression"};

  std::vector<double> dummy(symbols.names.size(), 0.0);
  mu::Parser p;
  Expr out;
  out.text = text;
  try {
    setup_parser(p);
    for (std::size_t i = 0; i < symbols.names.size(); ++i)
      p.DefineVar(symbols.names[i], &dummy[i]);
    p.SetExpr(text);
    out.value = p.Eval();
  } catch (const mu::Parser::exception_type& e) {
    const std::string tok = e.GetToken();
    const auto pos = static_cast<std::size_t>(std::max(0, e.GetPos()));
    if (is_identifier(tok) && text.compare(pos, tok.size(), tok) == 0) {
      std::size_t after = pos + tok.size();
      while (after < text.size() && text[after] == ' ')
        ++after;
      const bool call = after < text.size() && text[after] == '(';
      bool is_fn = false;
      for (const auto& f : language_functions())
        is_fn = is_fn || f.name == tok;
      if (!is_fn && symbols.find(tok) < 0 && tok != "pi") {
        Error err =
            at(key, std::string(call ? "unknown function '" : "unknown symbol '") + tok + "'", pos,
               text);
        err.message += nearest_name(tok, call, symbols, allowed);
        return err;
      }
    }
    static const std::regex kWhere(R"(\s*(found\s+)?at (expression )?position \d+\.?)");
    std::string msg = std::regex_replace(e.GetMsg(), kWhere, "");
    while (!msg.empty() && (msg.back() == '.' || msg.back() == ' '))
      msg.pop_back();
    return at(key, "syntax error: " + msg, pos, text);
  }
  Dep dep = Dep::kConst;
  for (const auto& [name, ptr] : p.GetUsedVar()) {
    const int slot = symbols.find(name);
    if (slot < 0) continue;
    const SymbolKind kind = symbols.kinds[static_cast<std::size_t>(slot)];
    if (!(kind & allowed)) {
      const std::size_t pos = find_identifier(text, name);
      return at(key,
                std::string(kind_name(kind)) +
                    (kind == kDtSymbol || kind == kTimeSymbol ? "" : " '" + name + "'") +
                    " cannot be used here (" + std::string(allowed_what) + ")",
                pos == std::string::npos ? 0 : pos, text);
    }
    dep = std::max(dep, dep_of(kind));
  }
  out.dep = dep;
  if (dep != Dep::kConst) out.value = 0.0;

  // The same text must mean the same to GiNaC (e.g. a^b^c is ambiguous there).
  std::lock_guard lock(ginac_mutex());
  try {
    const auto scope = make_scope(symbols);
    (void)parse_symbolic(text, scope);
  } catch (const std::exception& e) {
    // GiNaC's message: its first line (the rest is the reader's call stack).
    const std::string what = first_line(e.what());
    static const std::regex kNoFunction(R"(no function \"(\w+)\")");
    if (std::smatch m; std::regex_search(what, m, kNoFunction)) {
      const std::size_t pos = find_identifier(text, m[1].str());
      Error err = at(key, "unknown function '" + m[1].str() + "'",
                     pos == std::string::npos ? 0 : pos, text);
      err.message += nearest_name(m[1].str(), true, symbols, allowed);
      return err;
    }
    return Error{key + ": not accepted by the symbolic differentiator (" + what +
                 "); add parentheses: " + quoted(text)};
  }
  return out;
}

Expected<std::vector<Expr>> derivatives(const Expr& e, const std::string& key,
                                        const Symbols& symbols, const std::vector<int>& wrt) {
  std::vector<std::string> texts;
  std::vector<Expr> out(wrt.size());
  {
    std::lock_guard lock(ginac_mutex());
    try {
      const auto scope = make_scope(symbols);
      const GiNaC::ex f = parse_symbolic(e.text, scope);
      for (std::size_t i = 0; i < wrt.size(); ++i) {
        const GiNaC::ex d = f.diff(scope.symbols[static_cast<std::size_t>(wrt[i])]);
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
    const auto scope = make_scope(symbols);
    const GiNaC::ex d = parse_symbolic(a.text, scope) - parse_symbolic(b.text, scope);
    return d.expand().normal().is_zero();
  } catch (const std::exception&) {
    return false;
  }
}

ExprGroup::ExprGroup() = default;
ExprGroup::~ExprGroup() = default;
ExprGroup::ExprGroup(ExprGroup&&) noexcept = default;
ExprGroup& ExprGroup::operator=(ExprGroup&&) noexcept = default;

void ExprGroup::add(const std::string& text, double* target) {
  if (!source_.empty()) source_ += ",";
  source_ += text;
  targets_.push_back(target);
}

Status ExprGroup::bind(const Symbols& symbols, double* vars) {
  if (targets_.empty()) return Ok{};
  parser_ = std::make_unique<mu::Parser>();
  try {
    setup_parser(*parser_);
    for (std::size_t i = 0; i < symbols.names.size(); ++i)
      parser_->DefineVar(symbols.names[i], vars + i);
    parser_->SetExpr(source_);
    int n = 0;
    parser_->Eval(n);
    if (static_cast<std::size_t>(n) != targets_.size()) {
      return Error{"internal: expression group yields " + std::to_string(n) + " values, expected " +
                   std::to_string(targets_.size())};
    }
  } catch (const mu::Parser::exception_type& e) {
    return Error{"internal: expression group: " + e.GetMsg()};
  }
  return Ok{};
}

void ExprGroup::eval() {
  if (targets_.empty()) return;
  int n = 0;
  const double* r = parser_->Eval(n);
  for (std::size_t i = 0; i < targets_.size(); ++i)
    *targets_[i] = r[i];
}

}  // namespace kfw::model
