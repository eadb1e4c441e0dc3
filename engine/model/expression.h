// Model expressions: checked and evaluated by muparser, differentiated by GiNaC. The language is
// what both libraries read with the same meaning (presets/models/README.md, "Expressions"):
// numbers, symbols, + - * / ^, unary minus, parentheses and the functions of
// language_functions(). GiNaC is used only while a model is loaded; runs use muparser only.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/expected.h"
#include "core/limits.h"

namespace mu {
class Parser;
}

namespace kfw::model {

// What a symbol stands for; a mask of these says which symbols an expression may use.
enum SymbolKind : unsigned {
  kParamSymbol = 1u,   // a parameter (slider, --set key)
  kDtSymbol = 2u,      // dt, the sample interval t[k] − t[k−1], s
  kTimeSymbol = 4u,    // t, the time of the row, s
  kStateSymbol = 8u,   // a state
  kInputSymbol = 16u,  // an input (a known signal, e.g. a gyro rate)
  kSubSymbol = 32u,    // a sub-expression (model.expressions): stands for its own text
  kTruthSymbol = 64u,  // a truth column (model.truth), in derived quantities only
  kMeasuredSymbol =
      128u  // a channel's role: its column as read (NaN where no sample), derived only
};
using KindMask = unsigned;
// Every kind but truth: what the model's own expressions may use.
inline constexpr KindMask kAllSymbols = 63u;

// When an expression must be re-evaluated. Ordered: each class includes what comes before.
enum class Dep {
  kConst,  // a number
  kParam,  // parameters only: once per run
  kDt,     // parameters and dt: when dt changes
  kStep,   // t or inputs: every step
  kState,  // states: at every linearisation or sigma point
};

struct Expr {
  std::string text;  // muparser source: the user's text (sub-expressions expanded), or a derivative
  Dep dep = Dep::kConst;
  double value = 0.0;  // the value when dep == kConst
  KindMask uses = 0;   // the kinds of symbol it uses, through its sub-expressions too
  std::string source;  // the user's text, sub-expressions by name (compile_expr)
  // An expression of states (or a sub-expression of parameters, dt and inputs) that uses
  // sub-expressions of parameters, dt and inputs only (not t): `text` with those left as their
  // symbols, which ModelEval evaluates once per step, each once, instead of at every
  // linearisation or sigma point (`step_subs` their slots, nested ones included); empty when
  // there are none. Seed 004's heading at mid-interval and its rotation are such sub-expressions.
  std::string state_text;
  std::vector<int> step_subs;
};

// The symbols of one model; an expression's symbol binds to vars[slot] when evaluated. A
// sub-expression is a symbol too: compile_expr replaces it by its own (expanded) text in
// parentheses, so values, classes and derivatives follow from the symbols it uses.
struct Symbols {
  std::vector<std::string> names;
  std::vector<SymbolKind> kinds;
  std::vector<Expr> subs;                      // per slot: the sub-expression (kSubSymbol only)
  std::unordered_map<std::string, int> index;  // name -> first slot (add keeps it; find reads it)
  int add(const std::string& name, SymbolKind kind);
  int add_sub(const std::string& name, Expr e);
  int find(std::string_view name) const;  // the slot, or -1
  std::vector<int> slots(SymbolKind kind) const;
};

// The identifiers of an expression, in order of first use (numbers skipped).
std::vector<std::string> identifiers(const std::string& text);
// A sub-expression's expanded text beyond this many characters is refused (a chain of
// sub-expressions that each use the previous one twice doubles at every link).
inline constexpr std::size_t kMaxExpandedText = limits::kMaxExpandedText;

// sin(x)/x (1 at 0) and its derivative (cos x − sinc x)/x (0 at 0): the language's function for
// removable singularities, as muparser evaluates it.
double sinc(double x);
double dsinc(double x);

// The functions of the expression language, with their arity.
struct LanguageFunction {
  std::string_view name;
  int arity;
};
const std::vector<LanguageFunction>& language_functions();
// Names that cannot name a state, input or parameter: t, dt, pi, the functions, GiNaC's own.
bool is_reserved_name(std::string_view name);
// [A-Za-z_][A-Za-z0-9_]*
bool is_identifier(std::string_view name);

// Compiles one expression: syntax, symbols (only the kinds in `allowed`; `allowed_what` says
// which, for the message), a single value. Errors read "<key>: <what> at position P: "<text>""
// with P counting characters from 1.
Expected<Expr> compile_expr(const std::string& text, const std::string& key, const Symbols& symbols,
                            KindMask allowed, std::string_view allowed_what);

// ∂e/∂(symbol at slot) for each slot of `wrt`: exact, by GiNaC, printed for muparser.
Expected<std::vector<Expr>> derivatives(const Expr& e, const std::string& key,
                                        const Symbols& symbols, const std::vector<int>& wrt);

// True when a and b are the same function of the symbols (GiNaC: normal(a − b) == 0).
bool same_function(const Expr& a, const Expr& b, const Symbols& symbols);

// The slots of the symbols `text` names (a compiled text names no sub-expression), ascending.
std::vector<int> symbols_used(const std::string& text, const Symbols& symbols);

// The text muparser evaluates for `text` (a checked expression): a parenthesised base or a call
// raised to the literal power 2 or 3 — (15 - x)^2 — becomes a product (_pow2(15 - x)), since
// muparser calls std::pow for it (its own x^2 fast path takes a plain symbol only). The same
// values to the last bit or two; seed 004's ranges run ≈ 1.4× faster.
std::string fast_powers(const std::string& text);

// Evaluates a set of expressions into target doubles in one muparser pass (a comma-separated
// list, one byte-code program; fast_powers applied). Not copyable; one per run and thread.
class ExprGroup {
 public:
  ExprGroup();
  ~ExprGroup();
  ExprGroup(ExprGroup&&) noexcept;
  ExprGroup& operator=(ExprGroup&&) noexcept;

  void add(const std::string& text, double* target);
  bool empty() const { return targets_.empty(); }
  std::size_t size() const { return targets_.size(); }
  // Binds every symbol to vars[slot] and compiles; call once, after the adds.
  Status bind(const Symbols& symbols, double* vars);
  // Evaluates every expression and writes each result to its target.
  void eval();

  // The native path (native/native_model.h): the expressions as added (kept only while a hook is
  // installed), and a compiled function that computes them all from the symbols' values by slot
  // (out[i]: the i-th expression).
  using NativeFn = void (*)(const double* vars, double* out);
  const std::vector<std::string>& texts() const { return texts_; }
  void set_native(NativeFn fn) {
    native_ = fn;
    out_.assign(targets_.size(), 0.0);
  }
  bool native() const { return native_ != nullptr; }

 private:
  std::unique_ptr<mu::Parser> parser_;
  std::string source_;
  std::vector<std::string> texts_;
  std::vector<double*> targets_;
  double* vars_ = nullptr;
  NativeFn native_ = nullptr;
  std::vector<double> out_;
};

// Called by every model evaluator once its expressions are bound, with its groups and symbols:
// the native path installs itself here (native/native_model.h; empty: muparser evaluates).
using ExprGroupsHook = std::function<void(const std::vector<ExprGroup*>&, const Symbols&)>;
void set_expr_groups_hook(ExprGroupsHook hook);
const ExprGroupsHook& expr_groups_hook();

}  // namespace kfw::model
