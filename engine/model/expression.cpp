#include "model/expression.h"

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

#include "core/limits.h"
#include "core/suggest.h"
#include "model/expression_detail.h"

namespace kfw::model {

namespace {

double step_fn(double x) {
  return x > 0.0 ? 1.0 : (x < 0.0 ? 0.0 : 0.5);
}
double sign_fn(double x) {
  return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0);
}

}  // namespace

// sin(x)/x: exact to rounding for every x ≠ 0 (sin is accurate relative to its value), 1 at 0.
double sinc(double x) {
  return x == 0.0 ? 1.0 : std::sin(x) / x;
}

// (cos x − sinc x)/x; below |x| = 0.1, where the difference would cancel (a relative error of
// up to ε/x²), its series −x/3 + x³/30 − x⁵/840 + x⁷/45360 − x⁹/3991680 + x¹¹/518918400 (next
// term below 1e-20 of the value there).
double dsinc(double x) {
  if (std::fabs(x) < 0.1) {
    const double x2 = x * x;
    return x * (-1.0 / 3.0 +
                x2 * (1.0 / 30.0 +
                      x2 * (-1.0 / 840.0 +
                            x2 * (1.0 / 45360.0 + x2 * (-1.0 / 3991680.0 + x2 / 518918400.0)))));
  }
  return (std::cos(x) - std::sin(x) / x) / x;
}

namespace {

// The language's functions in muparser (its own built-ins are cleared so that the two libraries
// read the same set). sign, step and dsinc appear only in printed derivatives (GiNaC's csgn,
// step, the derivative of sinc).
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
  p.DefineFun("sinc", &sinc);
  p.DefineFun(
      "heaviside", +[](double x) { return x >= 0.0 ? 1.0 : (x < 0.0 ? 0.0 : x); });
  p.DefineFun("dsinc", &dsinc);
  p.DefineFun("sign", &sign_fn);
  p.DefineFun("step", &step_fn);
  // fast_powers's products (reserved names, never in a user's text).
  p.DefineFun(
      "_pow2", +[](double x) { return x * x; });
  p.DefineFun(
      "_pow3", +[](double x) { return x * x * x; });
  p.DefineFun(
      "_rsqrt", +[](double x) {
        // pow's answer where 1/√x would differ (±0, −∞, negatives).
        return x > 0.0 && x < HUGE_VAL ? 1.0 / std::sqrt(x) : std::pow(x, -0.5);
      });
  p.DefineConst("pi", std::numbers::pi);
}

// Calls visit(start, length) for each identifier of `text` in order (numbers skipped) until it
// returns true; returns that identifier's start, or npos.
template <class Visit>
std::size_t for_each_identifier(const std::string& text, Visit visit) {
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
      if (visit(start, i - start)) return start;
    } else {
      ++i;
    }
  }
  return std::string::npos;
}

}  // namespace

std::vector<int> symbols_used(const std::string& text, const Symbols& symbols) {
  std::vector<int> out;
  for_each_identifier(text, [&](std::size_t start, std::size_t len) {
    const int slot = symbols.find(std::string_view(text).substr(start, len));
    if (slot >= 0 && std::find(out.begin(), out.end(), slot) == out.end()) out.push_back(slot);
    return false;
  });
  std::sort(out.begin(), out.end());
  return out;
}

namespace {

// The text with every sub-expression replaced by its own text in parentheses (theirs are
// expanded already, so one pass does).
std::string expand_subs(const std::string& text, const Symbols& symbols) {
  std::string out;
  std::size_t done = 0;
  for_each_identifier(text, [&](std::size_t start, std::size_t len) {
    const int slot = symbols.find(std::string_view(text).substr(start, len));
    if (slot >= 0 && symbols.kinds[static_cast<std::size_t>(slot)] == kSubSymbol) {
      out.append(text, done, start - done);
      out += "(" + symbols.subs[static_cast<std::size_t>(slot)].text + ")";
      done = start + len;
    }
    return false;
  });
  return out + text.substr(done);
}

// A sub-expression that a state expression may keep as its symbol: one of dt or inputs (and
// parameters), not of t (the RK4 stages move t within a step). One of parameters only stays
// expanded: muparser folds it into the entry, and a run keeps its last bit.
bool step_level(const Expr& sub) {
  return (sub.dep == Dep::kDt || sub.dep == Dep::kStep) && !(sub.uses & kTimeSymbol) &&
         !sub.source.empty();
}

// `text` with its step-level sub-expressions kept by name (their slots added to `kept`, with the
// sub-expressions they use) and the others expanded from their own source the same way.
std::string expand_state_subs(const std::string& text, const Symbols& symbols,
                              std::vector<int>& kept) {
  std::string out;
  std::size_t done = 0;
  for_each_identifier(text, [&](std::size_t start, std::size_t len) {
    const int slot = symbols.find(std::string_view(text).substr(start, len));
    if (slot < 0 || symbols.kinds[static_cast<std::size_t>(slot)] != kSubSymbol) return false;
    const Expr& sub = symbols.subs[static_cast<std::size_t>(slot)];
    if (step_level(sub)) {
      for (int s : sub.step_subs)
        kept.push_back(s);
      kept.push_back(slot);
      return false;
    }
    out.append(text, done, start - done);
    out += "(" + expand_state_subs(sub.source, symbols, kept) + ")";
    done = start + len;
    return false;
  });
  return out + text.substr(done);
}

// The first symbol of `e` (expanded) whose kind is outside `allowed`: its name and kind.
std::pair<std::string, SymbolKind> first_disallowed(const Expr& e, const Symbols& symbols,
                                                    KindMask allowed) {
  for (const auto& id : identifiers(e.text)) {
    const int slot = symbols.find(id);
    if (slot < 0) continue;
    const SymbolKind k = symbols.kinds[static_cast<std::size_t>(slot)];
    if (!(k & allowed)) return {id, k};
  }
  return {"", kStateSymbol};
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
    case kSubSymbol:
      return "sub-expression";
    case kTruthSymbol:
      return "truth column";
    case kMeasuredSymbol:
      return "measurement";
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
    case kMeasuredSymbol:  // a channel's column: once per sample
      return Dep::kStep;
    case kStateSymbol:
    case kTruthSymbol:
    case kSubSymbol:  // not reached: a sub-expression's class is its own
      return Dep::kState;
  }
  return Dep::kState;
}

}  // namespace

namespace detail {

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
  return for_each_identifier(text, [&](std::size_t start, std::size_t len) {
    return len == name.size() && text.compare(start, len, name) == 0;
  });
}

}  // namespace detail

using detail::at;
using detail::find_identifier;
using detail::first_line;
using detail::nearest_name;
using detail::quoted;

int Symbols::add(const std::string& name, SymbolKind kind) {
  index.emplace(name, static_cast<int>(names.size()));
  names.push_back(name);
  kinds.push_back(kind);
  subs.emplace_back();
  return static_cast<int>(names.size()) - 1;
}

int Symbols::add_sub(const std::string& name, Expr e) {
  const int slot = add(name, kSubSymbol);
  subs.back() = std::move(e);
  return slot;
}

std::vector<std::string> identifiers(const std::string& text) {
  std::vector<std::string> out;
  for_each_identifier(text, [&](std::size_t start, std::size_t len) {
    std::string id = text.substr(start, len);
    if (std::find(out.begin(), out.end(), id) == out.end()) out.push_back(std::move(id));
    return false;
  });
  return out;
}

int Symbols::find(std::string_view name) const {
  const auto it = index.find(std::string(name));
  return it == index.end() ? -1 : it->second;
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
      {"sin", 1},  {"cos", 1},   {"tan", 1},  {"asin", 1},     {"acos", 1},
      {"atan", 1}, {"atan2", 2}, {"sinh", 1}, {"cosh", 1},     {"tanh", 1},
      {"exp", 1},  {"log", 1},   {"sqrt", 1}, {"abs", 1},      {"pow", 2},
      {"min", 2},  {"max", 2},   {"sinc", 1}, {"heaviside", 1}};
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
  static const char* const kReserved[] = {"t",    "dt",    "pi",    "Pi",    "sign",
                                          "step", "dsinc", "_pow2", "_pow3", "_rsqrt"};
  for (const char* r : kReserved) {
    if (name == r) return true;
  }
  for (const auto& f : language_functions()) {
    if (f.name == name) return true;
  }
  return false;
}

namespace {

// Characters of the language only: muparser's comparison, logic and ternary operators are not
// in GiNaC, so they are refused here with their position; so is an empty text.
Status check_characters(const std::string& text, const std::string& key) {
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
  return Ok{};
}

}  // namespace

Expected<Expr> compile_expr(const std::string& text, const std::string& key, const Symbols& symbols,
                            KindMask allowed, std::string_view allowed_what) {
  if (text.size() > limits::kMaxExpressionChars) {
    return Error{key + ": " + std::to_string(text.size()) + " characters: longer than the limit " +
                 "of " + std::to_string(limits::kMaxExpressionChars) + " (docs/limits.md)"};
  }
  if (auto st = check_characters(text, key); !st) return st.err();
  // A plain finite number (most entries of a large F or Q are 0) needs no parser: a muparser
  // and a GiNaC reader per entry were 25 µs, 2 s of every 100 000 entries.
  if (!text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.') &&
      text.find_first_of("xXpP") == std::string::npos) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() + text.size() && std::isfinite(v)) {
      Expr out;
      out.text = text;
      out.source = text;
      out.value = v;
      return out;
    }
  }

  // Only the symbols the text names are defined: defining every symbol for every expression made
  // loading a model quadratic in its size (300 states: 74 s).
  const std::vector<std::string> named = identifiers(text);
  std::vector<double> dummy(named.size(), 0.0);
  mu::Parser p;
  Expr out;
  out.text = text;
  try {
    setup_parser(p);
    for (std::size_t i = 0; i < named.size(); ++i) {
      if (symbols.find(named[i]) >= 0) p.DefineVar(named[i], &dummy[i]);
    }
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
  bool any_sub = false;
  for (const auto& [name, ptr] : p.GetUsedVar()) {
    const int slot = symbols.find(name);
    if (slot < 0) continue;
    const SymbolKind kind = symbols.kinds[static_cast<std::size_t>(slot)];
    const std::size_t pos = find_identifier(text, name);
    if (kind == kSubSymbol) {
      const Expr& sub = symbols.subs[static_cast<std::size_t>(slot)];
      if (sub.uses & ~allowed) {
        const auto [what, k] = first_disallowed(sub, symbols, allowed);
        return at(key,
                  "sub-expression '" + name + "' uses " + kind_name(k) +
                      (k == kDtSymbol || k == kTimeSymbol ? "" : " '" + what + "'") +
                      ", which cannot be used here (" + std::string(allowed_what) + ")",
                  pos == std::string::npos ? 0 : pos, text);
      }
      any_sub = true;
      dep = std::max(dep, sub.dep);
      out.uses |= sub.uses;
      continue;
    }
    if (!(kind & allowed)) {
      return at(key,
                std::string(kind_name(kind)) +
                    (kind == kDtSymbol || kind == kTimeSymbol ? "" : " '" + name + "'") +
                    " cannot be used here (" + std::string(allowed_what) + ")",
                pos == std::string::npos ? 0 : pos, text);
    }
    dep = std::max(dep, dep_of(kind));
    out.uses |= kind;
  }
  out.dep = dep;
  if (any_sub) {
    out.text = expand_subs(text, symbols);
    if (out.text.size() > kMaxExpandedText) {
      return Error{key + ": its sub-expressions expand to " + std::to_string(out.text.size()) +
                   " characters (at most " + std::to_string(kMaxExpandedText) +
                   "): " + quoted(text)};
    }
    if (dep == Dep::kConst) {
      try {
        p.SetExpr(out.text);
        out.value = p.Eval();
      } catch (const mu::Parser::exception_type& e) {
        return Error{key + ": internal: the expanded text does not read: " + e.GetMsg()};
      }
    }
  }
  if (dep != Dep::kConst) out.value = 0.0;
  out.source = text;
  if (any_sub) {
    // Sub-expressions a step-level sub-expression uses are evaluated with it (its slots first).
    std::vector<int> kept;
    std::string partial = expand_state_subs(text, symbols, kept);
    std::sort(kept.begin(), kept.end());
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    if (!kept.empty() && (dep == Dep::kState || step_level(out))) {
      // A state entry's text for the filter; a step-level sub-expression's for its own slot,
      // evaluated after the slots it reads.
      out.state_text = std::move(partial);
      out.step_subs = std::move(kept);
    }
  }

  // A constant is the same at every step: not finite means never usable (found at load, not at
  // the first step of a simulation).
  if (dep == Dep::kConst && !std::isfinite(out.value)) {
    return Error{key + ": " + quoted(text) + " is the constant " + std::to_string(out.value) +
                 ", not a finite number"};
  }
  // The same text must mean the same to GiNaC (e.g. a^b^c is ambiguous there).
  if (auto st = detail::check_symbolic(text, out.text, key, symbols); !st) return st.err();
  return out;
}

ExprGroup::ExprGroup() = default;
ExprGroup::~ExprGroup() = default;
ExprGroup::ExprGroup(ExprGroup&&) noexcept = default;
ExprGroup& ExprGroup::operator=(ExprGroup&&) noexcept = default;

void ExprGroup::add(const std::string& text, double* target) {
  if (!source_.empty()) source_ += ",";
  source_ += fast_powers(text);
  if (expr_groups_hook()) texts_.push_back(text);  // only the native path reads them
  targets_.push_back(target);
}

Status ExprGroup::bind(const Symbols& symbols, double* vars) {
  if (targets_.empty()) return Ok{};
  vars_ = vars;
  parser_ = std::make_unique<mu::Parser>();
  try {
    setup_parser(*parser_);
    // Only the symbols the group reads: an IMM binds an evaluator per mode, and defining every
    // symbol of a large model in every group was most of that.
    for (const std::string& name : identifiers(source_)) {
      const int slot = symbols.find(name);
      if (slot >= 0) parser_->DefineVar(name, vars + slot);
    }
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
  if (native_) {
    native_(vars_, out_.data());
    for (std::size_t i = 0; i < targets_.size(); ++i)
      *targets_[i] = out_[i];
    return;
  }
  int n = 0;
  const double* r = parser_->Eval(n);
  for (std::size_t i = 0; i < targets_.size(); ++i)
    *targets_[i] = r[i];
}

namespace {
ExprGroupsHook& hook_slot() {
  static ExprGroupsHook hook;
  return hook;
}
}  // namespace

void set_expr_groups_hook(ExprGroupsHook hook) {
  hook_slot() = std::move(hook);
}

const ExprGroupsHook& expr_groups_hook() {
  return hook_slot();
}

}  // namespace kfw::model
