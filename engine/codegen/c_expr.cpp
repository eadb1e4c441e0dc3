// Model expressions as C: a small recursive-descent reader of the expression language into a
// tree, and a writer with common sub-expressions shared (c_expr.h).
#include "codegen/c_expr.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace kfw::codegen {

namespace {

enum class Kind { kNum, kSym, kNeg, kAdd, kSub, kMul, kDiv, kPow, kCall };

struct Node {
  Kind kind = Kind::kNum;
  std::string text;       // a number's or symbol's text, a call's function name
  std::vector<int> args;  // children
};

// Precedence of a node as printed: sums 1, products 2, a sign 3, atoms (calls, pow) 4.
int precedence(Kind k) {
  switch (k) {
    case Kind::kAdd:
    case Kind::kSub:
      return 1;
    case Kind::kMul:
    case Kind::kDiv:
      return 2;
    case Kind::kNeg:
      return 3;
    default:
      return 4;
  }
}

// The shortest text that reads back to the same value (std::to_chars, as document/command_line.cpp
// and data/csv.cpp write numbers), with a decimal point or an exponent.
std::string shortest(double v, bool single) {
  char buf[64];
  const auto r = single ? std::to_chars(buf, buf + sizeof buf, static_cast<float>(v))
                        : std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}
}  // namespace

std::string c_number(double v, bool single) {
  if (single) {
    const float f = static_cast<float>(v);
    if (std::isinf(f)) return f > 0 ? "HUGE_VALF" : "(-HUGE_VALF)";
    const std::string s = shortest(static_cast<double>(f), true) + "f";
    return f < 0 ? "(" + s + ")" : s;
  }
  if (std::isinf(v)) return v > 0 ? "HUGE_VAL" : "(-HUGE_VAL)";
  const std::string s = shortest(v, false);
  return v < 0 ? "(" + s + ")" : s;
}

struct CExprSet::Impl {
  bool single;
  std::function<std::string(const std::string&)> symbol;
  std::vector<Node> nodes;
  std::vector<int> roots;
  std::set<std::string>* helpers = nullptr;

  // --- reading ---------------------------------------------------------------------------
  const std::string* src = nullptr;
  std::size_t pos = 0;

  void skip() {
    while (pos < src->size() && ((*src)[pos] == ' ' || (*src)[pos] == '\t'))
      ++pos;
  }
  bool eat(char c) {
    skip();
    if (pos < src->size() && (*src)[pos] == c) {
      ++pos;
      return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(what + " at position " + std::to_string(pos + 1));
  }
  int make(Kind k, std::string text, std::vector<int> args = {}) {
    nodes.push_back({k, std::move(text), std::move(args)});
    return static_cast<int>(nodes.size()) - 1;
  }

  int sum() {
    int a = product();
    for (;;) {
      if (eat('+')) {
        a = make(Kind::kAdd, "", {a, product()});
      } else if (eat('-')) {
        a = make(Kind::kSub, "", {a, product()});
      } else {
        return a;
      }
    }
  }
  int product() {
    int a = unary();
    for (;;) {
      if (eat('*')) {
        a = make(Kind::kMul, "", {a, unary()});
      } else if (eat('/')) {
        a = make(Kind::kDiv, "", {a, unary()});
      } else {
        return a;
      }
    }
  }
  // A sign binds looser than ^ (−x^2 = −(x²)), as both of the language's readers take it.
  int unary() {
    if (eat('-')) return make(Kind::kNeg, "", {unary()});
    if (eat('+')) return unary();
    return power();
  }
  int power() {
    const int base = primary();
    if (eat('^')) return make(Kind::kPow, "", {base, unary()});
    return base;
  }
  int primary() {
    skip();
    if (pos >= src->size()) fail("unexpected end");
    const char c = (*src)[pos];
    if (c == '(') {
      ++pos;
      const int e = sum();
      if (!eat(')')) fail("')' expected");
      return e;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = src->c_str() + pos;
      char* end = nullptr;
      (void)std::strtod(begin, &end);
      if (end == begin) fail("a number expected");
      pos += static_cast<std::size_t>(end - begin);
      return make(Kind::kNum, std::string(begin, static_cast<std::size_t>(end - begin)));
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::size_t start = pos;
      while (pos < src->size() &&
             (std::isalnum(static_cast<unsigned char>((*src)[pos])) || (*src)[pos] == '_'))
        ++pos;
      std::string name = src->substr(start, pos - start);
      if (!eat('(')) return make(Kind::kSym, std::move(name));
      std::vector<int> args;
      if (!eat(')')) {
        do {
          args.push_back(sum());
        } while (eat(','));
        if (!eat(')')) fail("')' expected after the arguments of " + name);
      }
      return make(Kind::kCall, std::move(name), std::move(args));
    }
    fail(std::string("unexpected '") + c + "'");
  }

  // --- writing ---------------------------------------------------------------------------
  std::string fn(const std::string& name) const { return single ? name + "f" : name; }

  std::string call_name(const std::string& name, std::size_t arity) {
    static const std::set<std::string> kMath = {"sin",  "cos",   "tan",  "asin", "acos",
                                                "atan", "atan2", "sinh", "cosh", "tanh",
                                                "exp",  "log",   "sqrt", "pow"};
    if (kMath.count(name)) return fn(name);
    if (name == "abs") return fn("fabs");
    if (name == "min") return fn("fmin");
    if (name == "max") return fn("fmax");
    if (name == "sinc" || name == "dsinc" || name == "heaviside" || name == "sign" ||
        name == "step") {
      helpers->insert("kfw_" + name);
      return "kfw_" + name;
    }
    throw std::runtime_error("the function '" + name + "' (" + std::to_string(arity) +
                             " arguments) has no C counterpart");
  }

  // The C text of node i; `temps` maps a sub-tree's text to its temporary.
  std::string text_of(int i, const std::map<std::string, std::string>& temps,
                      std::unordered_map<int, std::string>& memo) {
    if (auto it = memo.find(i); it != memo.end()) return it->second;
    const auto t = temps.empty() ? temps.end() : temps.find(plain_key(i));
    std::string s = t != temps.end() ? t->second : plain(i, temps, memo);
    memo[i] = s;
    return s;
  }

  std::string child(int parent, int c, bool right, const std::map<std::string, std::string>& temps,
                    std::unordered_map<int, std::string>& memo) {
    const std::string s = text_of(c, temps, memo);
    const Kind pk = nodes[static_cast<std::size_t>(parent)].kind;
    Kind ck = nodes[static_cast<std::size_t>(c)].kind;
    if (temps.count(plain_key(c))) ck = Kind::kSym;
    const int pp = precedence(pk), cp = precedence(ck);
    // A sign as a right operand or under another sign is parenthesised: a - (-b), -(-b).
    const bool wrap =
        cp < pp || (right && cp == pp) || (ck == Kind::kNeg && (right || pk == Kind::kNeg));
    return wrap ? "(" + s + ")" : s;
  }

  std::unordered_map<int, std::string> keys;  // node -> its plain text (no temporaries)
  std::string plain_key(int i) {
    if (auto it = keys.find(i); it != keys.end()) return it->second;
    std::unordered_map<int, std::string> memo;
    const std::map<std::string, std::string> none;
    std::string s = plain(i, none, memo);
    keys[i] = s;
    return s;
  }

  std::string plain(int i, const std::map<std::string, std::string>& temps,
                    std::unordered_map<int, std::string>& memo) {
    const Node& n = nodes[static_cast<std::size_t>(i)];
    const auto arg = [&](std::size_t a) { return n.args[a]; };
    switch (n.kind) {
      case Kind::kNum:
        return c_number(std::strtod(n.text.c_str(), nullptr), single);
      case Kind::kSym:
        if (n.text == "pi") return single ? "3.14159265f" : "3.141592653589793";
        return symbol(n.text);
      case Kind::kNeg:
        return "-" + child(i, arg(0), false, temps, memo);
      case Kind::kAdd:
      case Kind::kSub:
      case Kind::kMul:
      case Kind::kDiv: {
        const char* op = n.kind == Kind::kAdd   ? " + "
                         : n.kind == Kind::kSub ? " - "
                         : n.kind == Kind::kMul ? " * "
                                                : " / ";
        return child(i, arg(0), false, temps, memo) + op + child(i, arg(1), true, temps, memo);
      }
      case Kind::kPow: {
        const Node& e = nodes[static_cast<std::size_t>(arg(1))];
        const std::string b = text_of(arg(0), temps, memo);
        if (e.kind == Kind::kNum) {
          const double v = std::strtod(e.text.c_str(), nullptr);
          if (v == 2.0 || v == 3.0) {
            const std::string h = v == 2.0 ? "kfw_sq" : "kfw_cube";
            helpers->insert(h);
            return h + "(" + b + ")";
          }
          if (v == 0.5) return fn("sqrt") + "(" + b + ")";
        }
        return fn("pow") + "(" + b + ", " + text_of(arg(1), temps, memo) + ")";
      }
      case Kind::kCall: {
        std::string s = call_name(n.text, n.args.size()) + "(";
        for (std::size_t a = 0; a < n.args.size(); ++a)
          s += (a ? ", " : "") + text_of(arg(a), temps, memo);
        return s + ")";
      }
    }
    return "";
  }

  // Pre-order over every root: a sub-tree met again is counted, not entered again.
  void count(int i, std::map<std::string, int>& seen, std::vector<int>& order) {
    const Node& n = nodes[static_cast<std::size_t>(i)];
    if (n.kind == Kind::kNum || n.kind == Kind::kSym) return;
    const std::string key = plain_key(i);
    if (seen[key]++ > 0) return;
    order.push_back(i);
    for (int a : n.args)
      count(a, seen, order);
  }
};

CExprSet::CExprSet(bool single, std::function<std::string(const std::string&)> symbol)
    : impl_(std::make_unique<Impl>()) {
  impl_->single = single;
  impl_->symbol = std::move(symbol);
  impl_->helpers = &helpers_;
}

CExprSet::~CExprSet() = default;

Expected<int> CExprSet::add(const std::string& text, const std::string& key) {
  Impl& m = *impl_;
  m.src = &text;
  m.pos = 0;
  try {
    const int root = m.sum();
    m.skip();
    if (m.pos != text.size()) m.fail("unexpected text");
    m.roots.push_back(root);
  } catch (const std::exception& e) {
    return Error{key + ": cannot write \"" + text + "\" as C: " + e.what()};
  }
  return static_cast<int>(m.roots.size()) - 1;
}

std::string CExprSet::emit(const std::string& indent, std::vector<std::string>& texts,
                           const std::string& temp_prefix) {
  Impl& m = *impl_;
  std::map<std::string, int> seen;
  std::vector<int> order;
  for (int r : m.roots)
    m.count(r, seen, order);
  // Repeated sub-trees, innermost first (a temporary is defined before the ones that read it).
  std::vector<int> shared;
  for (int i : order) {
    if (seen[m.plain_key(i)] > 1) shared.push_back(i);
  }
  std::map<std::string, std::string> temps;
  std::string out;
  const char* type = m.single ? "float" : "double";
  std::vector<bool> done(shared.size(), false);
  // Define each temporary once every shared sub-tree inside it is defined.
  std::function<void(std::size_t)> define = [&](std::size_t s) {
    if (done[s]) return;
    done[s] = true;
    const int node = shared[s];
    for (std::size_t o = 0; o < shared.size(); ++o) {
      if (o == s || done[o]) continue;
      // o inside s: its text is a part of s's tree.
      const std::string& key = m.plain_key(shared[o]);
      std::vector<int> stack{node};
      bool inside = false;
      while (!stack.empty() && !inside) {
        const int c = stack.back();
        stack.pop_back();
        if (c != node && m.plain_key(c) == key) inside = true;
        for (int a : m.nodes[static_cast<std::size_t>(c)].args)
          stack.push_back(a);
      }
      if (inside) define(o);
    }
    std::unordered_map<int, std::string> memo;
    const std::string body = m.plain(node, temps, memo);
    const std::string name = temp_prefix + std::to_string(temps.size());
    out += indent + "const " + type + " " + name + " = " + body + ";\n";
    temps[m.plain_key(node)] = name;
  };
  for (std::size_t s = 0; s < shared.size(); ++s)
    define(s);
  texts.clear();
  for (int r : m.roots) {
    std::unordered_map<int, std::string> memo;
    texts.push_back(m.text_of(r, temps, memo));
  }
  return out;
}

}  // namespace kfw::codegen
