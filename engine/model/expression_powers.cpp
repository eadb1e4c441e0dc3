// fast_powers (expression.h): the products muparser evaluates for powers it would hand to
// std::pow. The functions _pow2, _pow3 and _rsqrt are defined with the language's (expression.cpp,
// setup_parser), reserved names that no user text can hold.
#include <cctype>
#include <string>

#include "model/expression.h"

namespace kfw::model {

namespace {

bool name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// The start of the base that ends at `end` (exclusive, the ')' before a '^'): its matching '('
// and a function name before it; npos when the text does not balance.
std::size_t base_start(const std::string& s, std::size_t end) {
  int depth = 0;
  std::size_t i = end;
  while (i > 0) {
    --i;
    if (s[i] == ')') ++depth;
    if (s[i] == '(' && --depth == 0) break;
  }
  if (depth != 0) return std::string::npos;
  while (i > 0 && name_char(s[i - 1]))
    --i;
  return i;
}

}  // namespace

std::string fast_powers(const std::string& text) {
  std::string s = text;
  for (std::size_t hat = s.find('^'); hat != std::string::npos; hat = s.find('^', hat + 1)) {
    std::size_t b = hat;  // the base ends before spaces
    while (b > 0 && s[b - 1] == ' ')
      --b;
    std::size_t e = hat + 1;  // the exponent: a literal 2 or 3, or a printed derivative's (-0.5)
    while (e < s.size() && s[e] == ' ')
      ++e;
    const char* fn = nullptr;
    std::size_t len = 1;
    if (s.compare(e, 6, "(-0.5)") == 0) {
      fn = "_rsqrt(";
      len = 6;
    } else if (e < s.size() && (s[e] == '2' || s[e] == '3')) {
      fn = s[e] == '2' ? "_pow2(" : "_pow3(";
    }
    if (b == 0 || !fn) continue;
    std::size_t after = e + len;
    if (len == 1 && after < s.size() && (name_char(s[after]) || s[after] == '.')) continue;
    while (after < s.size() && s[after] == ' ')
      ++after;
    if (after < s.size() && s[after] == '^') continue;  // right-associative: x^2^3 = x^8
    std::size_t start = std::string::npos;
    if (s[b - 1] == ')') {
      start = base_start(s, b);
    } else if (len > 1 && name_char(s[b - 1])) {  // a symbol (x^2 is muparser's own fast path)
      start = b;
      while (start > 0 && name_char(s[start - 1]))
        --start;
      if (std::isdigit(static_cast<unsigned char>(s[start]))) start = std::string::npos;
    }
    if (start == std::string::npos) continue;
    const std::string call = fn + s.substr(start, b - start) + ")";
    s.replace(start, e + len - start, call);
    hat = start;  // rescan from the new call (its base may hold more powers)
  }
  return s;
}

}  // namespace kfw::model
