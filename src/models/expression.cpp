#include "models/expression.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numbers>

#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"

namespace sets {

namespace {

struct Builtin {
  const char* name;
  int min_args;
  int max_args;  // -1: any number
};

// muparser 2.3.3's built-in functions (mu::Parser::InitFun) with their arities.
constexpr std::array<Builtin, 26> builtins{{
    {"sin", 1, 1},  {"cos", 1, 1},   {"tan", 1, 1},   {"asin", 1, 1},  {"acos", 1, 1},  {"atan", 1, 1},
    {"sinh", 1, 1}, {"cosh", 1, 1},  {"tanh", 1, 1},  {"asinh", 1, 1}, {"acosh", 1, 1}, {"atanh", 1, 1},
    {"log2", 1, 1}, {"log10", 1, 1}, {"log", 1, 1},   {"ln", 1, 1},    {"exp", 1, 1},   {"sqrt", 1, 1},
    {"sign", 1, 1}, {"rint", 1, 1},  {"abs", 1, 1},   {"atan2", 2, 2}, {"sum", 1, -1},  {"avg", 1, -1},
    {"min", 1, -1}, {"max", 1, -1},
}};
constexpr std::array<const char*, 2> constants{"_pi", "_e"};

const Builtin* builtin(std::string_view name) {
  for (const auto& b : builtins)
    if (name == b.name) return &b;
  return nullptr;
}

bool is_constant(std::string_view name) {
  return std::any_of(constants.begin(), constants.end(), [&](const char* c) { return name == c; });
}

bool name_start(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
bool name_char(char c) { return name_start(c) || (c >= '0' && c <= '9'); }
bool digit(char c) { return c >= '0' && c <= '9'; }
bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

enum class Kind { number, name, op, end };

struct Token {
  Kind kind = Kind::end;
  std::string text;     // for muparser (numbers: canonical, see lex_number)
  std::string written;  // as in the file
  std::size_t at = 0;
};

class Checker {
 public:
  Checker(const std::string& text, const std::function<bool(const std::string&)>& is_symbol, const std::string& where,
          bool rewrite_powers)
      : s_(text), is_symbol_(is_symbol), where_(where), rewrite_powers_(rewrite_powers) {}

  Checked_expression run() {
    if (s_.size() > max_expression_length)
      fail(0, "the expression has " + std::to_string(s_.size()) + " characters, more than " +
                  std::to_string(max_expression_length));
    next();
    if (tok_.kind == Kind::end) fail(0, "the expression is empty");
    expression();
    if (tok_.kind != Kind::end) fail(tok_.at, "unexpected " + describe(tok_) + " after a complete expression");
    return std::move(out_);
  }

 private:
  // ---- grammar
  // What binary() needs to know of an operand: where its primary starts in the text for
  // muparser, and whether it is a sign, one symbol or one number.
  struct Operand {
    std::size_t at = 0;
    bool sign = false;
    std::string name;    // one symbol or prev() variable
    std::string number;  // one number literal, canonical
  };

  void expression() {
    Depth d(*this);
    binary();
    if (is_op("?")) {
      emit_and_next();
      expression();
      if (!is_op(":")) fail(tok_.at, "expected ':' of 'condition ? a : b', found " + describe(tok_));
      emit_and_next();
      expression();
    }
  }

  void binary() {
    Operand left = operand();
    bool after_power = false;
    static const char* const binops[] = {"||", "&&", "<", ">", "<=", ">=", "==", "!=", "+", "-", "*", "/", "^"};
    while (tok_.kind == Kind::op &&
           std::any_of(std::begin(binops), std::end(binops), [&](const char* o) { return tok_.text == o; })) {
      const bool power = is_op("^");
      emit_and_next();
      const Operand right = operand();
      // A chain a^b^c is left as it is: which way muparser groups it does not matter then.
      if (power && !after_power && !is_op("^")) power_as_product(left, right);
      after_power = power;
      left = right;
    }
  }

  // x^2, x^3, x^4 of a symbol become (x * x ...): muparser's pow is a quarter of a simulation's
  // time, and the optimiser that would do this is off (compile_expression). `^` binds tighter
  // than a sign in muparser (-x^2 is -(x^2)), so the sign stays outside the product. Products
  // agree with pow within n - 1 roundings and exactly on signed zeros, infinities and NaN;
  // x^0, x^1, negative, fractional and larger exponents, and any other base, stay pow.
  void power_as_product(const Operand& base, const Operand& exponent) {
    if (!rewrite_powers_ || base.name.empty() || exponent.sign || exponent.number.empty()) return;
    int n = 0;
    if (exponent.number == "2") n = 2;
    else if (exponent.number == "3") n = 3;
    else if (exponent.number == "4") n = 4;
    else return;
    std::string product = "(";
    for (int i = 0; i < n; ++i) product += (i ? " * " : " ") + base.name;
    out_.text.resize(base.at);
    emit(product + " )");
  }

  Operand operand() {
    Operand o;
    if (is_op("-") || is_op("+")) {
      o.sign = true;
      emit_and_next();
    }
    o.at = out_.text.size();
    primary(o);
    return o;
  }

  void primary(Operand& o) {
    const Token t = tok_;
    if (t.kind == Kind::number) {
      o.number = t.text;
      emit_and_next();
      return;
    }
    if (is_op("(")) {
      emit_and_next();
      expression();
      expect_op(")", "to close the '(' at column " + std::to_string(t.at + 1));
      return;
    }
    if (t.kind != Kind::name) fail(t.at, "expected a number, a symbol, a function or '(', found " + describe(t));
    if (t.text == "prev") {
      o.name = prev();
      return;
    }
    if (const Builtin* f = builtin(t.text)) return call(*f);
    next();
    if (is_op("(")) fail(t.at, "\"" + t.text + "\" is not a function");
    if (is_constant(t.text)) {
      // As numbers: muparser 2.3.3's _pi is 3.141592653589, wrong in the 13th digit.
      emit(shortest(t.text == "_pi" ? std::numbers::pi : std::numbers::e));
      return;
    }
    if (!is_symbol_(t.text)) fail(t.at, "unknown symbol \"" + t.text + "\"");
    use(t.text);
    emit(t.text);
    o.name = t.text;
  }

  void call(const Builtin& f) {
    const Token name = tok_;
    next();
    if (!is_op("(")) fail(tok_.at, "the function " + name.text + " needs '(' after its name");
    emit(name.text + "(");  // muparser wants no blank between a function's name and '('
    next();
    int args = 1;
    expression();
    while (is_op(",")) {
      emit_and_next();
      expression();
      ++args;
    }
    expect_op(")", "to close the call of " + name.text + " at column " + std::to_string(name.at + 1));
    if (args < f.min_args || (f.max_args >= 0 && args > f.max_args)) {
      const std::string wanted = f.max_args < 0 ? "at least " + std::to_string(f.min_args)
                                                : std::to_string(f.min_args);
      fail(name.at, name.text + "() takes " + wanted + " argument" + (f.min_args == 1 && f.max_args == 1 ? "" : "s") +
                        ", not " + std::to_string(args));
    }
  }

  std::string prev() {
    const std::string usage = "prev(x, n) needs a symbol x and a whole number of samples n >= 1";
    next();
    if (!is_op("(")) fail(tok_.at, usage);
    next();
    const Token x = tok_;
    if (x.kind != Kind::name || builtin(x.text) || is_constant(x.text) || x.text == "prev") fail(x.at, usage);
    if (!is_symbol_(x.text)) fail(x.at, "unknown symbol \"" + x.text + "\" in prev()");
    next();
    if (!is_op(",")) fail(tok_.at, usage);
    next();
    const Token n = tok_;
    if (n.kind != Kind::number || !std::all_of(n.written.begin(), n.written.end(), digit)) fail(n.at, usage);
    long lag = 0;
    const auto r = std::from_chars(n.written.data(), n.written.data() + n.written.size(), lag);
    if (r.ec != std::errc() || lag > max_prev_lag)
      fail(n.at, "prev(" + x.text + ", " + printable(n.written, 40) + "): n must be at most " +
                     std::to_string(max_prev_lag) + " samples");
    if (lag < 1) fail(n.at, "prev(" + x.text + ", " + n.written + "): n must be >= 1");
    next();
    if (!is_op(")")) fail(tok_.at, usage);
    next();
    const std::string var = "prev__" + x.text + "__" + std::to_string(lag);
    use(x.text);
    if (std::none_of(out_.prevs.begin(), out_.prevs.end(), [&](const Prev_reference& r) { return r.variable == var; }))
      out_.prevs.push_back({x.text, static_cast<int>(lag), var});
    emit(var);
    return var;
  }

  // ---- tokens
  void next() {
    while (pos_ < s_.size() && blank(s_[pos_])) ++pos_;
    tok_ = Token{};
    tok_.at = pos_;
    if (pos_ >= s_.size()) return;
    const char c = s_[pos_];
    if (digit(c) || (c == '.' && pos_ + 1 < s_.size() && digit(s_[pos_ + 1]))) return lex_number();
    if (name_start(c)) {
      const std::size_t b = pos_;
      while (pos_ < s_.size() && name_char(s_[pos_])) ++pos_;
      tok_.kind = Kind::name;
      tok_.text = s_.substr(b, pos_ - b);
      tok_.written = tok_.text;
      if (tok_.text.size() > max_name_length)
        fail(b, "a name longer than " + std::to_string(max_name_length) + " characters");
      return;
    }
    static const char* const ops[] = {"<=", ">=", "==", "!=", "&&", "||", "<", ">", "+", "-",
                                      "*",  "/",  "^",  "?",  ":",  "(",  ")", ","};
    for (const char* o : ops) {
      const std::size_t n = std::strlen(o);
      if (s_.compare(pos_, n, o) == 0) {
        tok_.kind = Kind::op;
        tok_.text = o;
        tok_.written = o;
        pos_ += n;
        return;
      }
    }
    if (c == '=') fail(pos_, "'=' (assignment) is not allowed in an expression; a comparison is '=='");
    if (c == '"') fail(pos_, "strings are not allowed in an expression");
    fail(pos_, "unexpected character '" + printable(std::string_view(&s_[pos_], 1)) + "'");
  }

  // digits ['.' digits] [('e'|'E') ['+'|'-'] digits], or '.' digits ...; finite as a double.
  void lex_number() {
    const std::size_t b = pos_;
    while (pos_ < s_.size() && digit(s_[pos_])) ++pos_;
    if (pos_ < s_.size() && s_[pos_] == '.') {
      ++pos_;
      while (pos_ < s_.size() && digit(s_[pos_])) ++pos_;
    }
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      std::size_t k = pos_ + 1;
      if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
      if (k < s_.size() && digit(s_[k])) {
        pos_ = k;
        while (pos_ < s_.size() && digit(s_[pos_])) ++pos_;
      }
    }
    tok_.kind = Kind::number;
    tok_.written = s_.substr(b, pos_ - b);
    if (pos_ < s_.size() && (name_char(s_[pos_]) || s_[pos_] == '.'))
      fail(b, "malformed number \"" + printable(s_.substr(b, pos_ - b + 1), 40) + "\"");
    double v = 0;
    const auto r = std::from_chars(tok_.written.data(), tok_.written.data() + tok_.written.size(), v);
    if (r.ec == std::errc::result_out_of_range) v = std::strtod(tok_.written.c_str(), nullptr);  // 0 or +-inf
    if ((r.ec != std::errc() && r.ec != std::errc::result_out_of_range) || !std::isfinite(v))
      fail(b, "the number " + printable(tok_.written, 40) + " is outside the range of double precision");
    tok_.text = shortest(v);  // canonical: 1e-400 is 0, 1.50 is 1.5
  }

  // The shortest text that reads back as the same double.
  static std::string shortest(double v) {
    char buf[32];
    const auto w = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, w.ptr);
  }

  // ---- helpers
  bool is_op(const char* o) const { return tok_.kind == Kind::op && tok_.text == o; }

  void expect_op(const char* o, const std::string& why) {
    if (!is_op(o)) fail(tok_.at, std::string("expected '") + o + "' " + why + ", found " + describe(tok_));
    emit_and_next();
  }

  void emit(const std::string& t) {
    if (!out_.text.empty()) out_.text += ' ';
    out_.text += t;
  }
  void emit_and_next() {
    emit(tok_.text);
    next();
  }
  void use(const std::string& symbol) {
    if (std::find(out_.symbols.begin(), out_.symbols.end(), symbol) == out_.symbols.end()) out_.symbols.push_back(symbol);
  }

  static std::string describe(const Token& t) {
    switch (t.kind) {
      case Kind::end: return "the end of the expression";
      case Kind::number: return "the number " + printable(t.written, 40);
      case Kind::name: return "\"" + t.text + "\"";
      case Kind::op: return "'" + t.text + "'";
    }
    return "?";
  }

  struct Depth {
    explicit Depth(Checker& c) : c_(c) {
      if (++c_.depth_ > max_expression_depth)
        c_.fail(c_.tok_.at, "the expression is nested more than " + std::to_string(max_expression_depth) + " levels deep");
    }
    ~Depth() { --c_.depth_; }
    Checker& c_;
  };

  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    // Column of a one-line expression; line and column when it spans several lines.
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < at && i < s_.size(); ++i) {
      if (s_[i] == '\n') ++line, column = 1;
      else ++column;
    }
    const std::string place = line > 1 || s_.find('\n') != std::string::npos
                                  ? "line " + std::to_string(line) + ", column " + std::to_string(column)
                                  : "column " + std::to_string(column);
    throw InputError(where_ + ": " + place + ": " + what + " in \"" + printable(s_, 120) + "\"");
  }

  const std::string& s_;
  const std::function<bool(const std::string&)>& is_symbol_;
  const std::string& where_;
  bool rewrite_powers_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  Token tok_;
  Checked_expression out_;
};

}  // namespace

Checked_expression check_expression(const std::string& text, const std::function<bool(const std::string&)>& is_symbol,
                                    const std::string& where) {
  Checked_expression e = Checker(text, is_symbol, where, true).run();
  // A product repeats its symbol's name: past muparser's length limit, the powers stay pow.
  if (e.text.size() >= static_cast<std::size_t>(mu::MaxLenExpression)) e = Checker(text, is_symbol, where, false).run();
  return e;
}

std::string symbol_name_problem(std::string_view name) {
  if (name.empty()) return "an empty name";
  if (name.size() > max_name_length) return "a name longer than " + std::to_string(max_name_length) + " characters";
  if (!name_start(name[0]) || !std::all_of(name.begin(), name.end(), name_char))
    return "\"" + printable(name, 60) + "\" is not a name (letters, digits and '_', not starting with a digit)";
  if (builtin(name)) return "\"" + std::string(name) + "\" is a built-in function";
  if (is_constant(name)) return "\"" + std::string(name) + "\" is a built-in constant";
  if (name == "prev" || name.substr(0, 6) == "prev__") return "\"" + std::string(name) + "\" is reserved for prev(x, n)";
  return {};
}

bool is_symbol_name(std::string_view name) { return symbol_name_problem(name).empty(); }

void compile_expression(mu::Parser& parser, const Checked_expression& e,
                        const std::function<double*(const std::string&)>& address) {
  parser.EnableOptimizer(false);
  for (const auto& s : e.symbols) parser.DefineVar(s, address(s));
  for (const auto& p : e.prevs) parser.DefineVar(p.variable, address(p.variable));
  parser.SetExpr(e.text);
}

}  // namespace sets
