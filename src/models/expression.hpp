#pragma once
// The expression language of model files (docs/model-format.md), checked by our own parser before
// muparser sees it. muparser 2.3.3 (Debian) is not safe on hostile text: it folds `&&`/`||` of
// constants through a float->int cast (undefined behaviour for 1e10 or NaN), accepts assignments
// that would overwrite model variables, and its fuzzing history is a list of crashes on malformed
// if-then-else, strings and argument lists. So muparser only ever receives a well-formed
// expression of this small grammar, rebuilt token by token:
//
//   expression := binary ['?' expression ':' expression]
//   binary     := operand {binop operand}          binop: || && < > <= >= == != + - * / ^
//   operand    := ['+' | '-'] primary
//   primary    := number | symbol | _pi | _e | '(' expression ')'
//               | function '(' expression {',' expression} ')'     (muparser's built-ins, arity checked)
//               | prev '(' symbol ',' n ')'                         (n: whole number, 1 <= n <= max_prev_lag)
//
// Numbers are finite decimal literals; blanks are spaces, tabs and line breaks. Everything else
// (strings, '=', ';', other characters) is an InputError naming the column.

#include <muParser.h>

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace sets {

inline constexpr std::size_t max_expression_length = 10000;  // muparser's own limit is 20000
inline constexpr std::size_t max_name_length = 100;          // muparser's identifier limit
inline constexpr int max_expression_depth = 100;             // nested parentheses and calls
inline constexpr long max_prev_lag = 1000000000;

struct Prev_reference {
  std::string symbol;    // x in prev(x, n)
  int lag = 0;           // n
  std::string variable;  // the generated variable that replaces prev(x, n) in the text for muparser
};

struct Checked_expression {
  std::string text;                  // for muparser
  std::vector<std::string> symbols;  // model symbols used (prev(x, n) counts as a use of x), first use first
  std::vector<Prev_reference> prevs;  // distinct (x, n) pairs
};

/// Checks `text` against the grammar above. The text for muparser has x^2, x^3 and x^4 of a
/// symbol x written as products (the optimiser that would do it is off, see compile_expression). `is_symbol` says which names the model defines;
/// `where` names the file and field for messages ("model.json: derivatives.v").
Checked_expression check_expression(const std::string& text, const std::function<bool(const std::string&)>& is_symbol,
                                    const std::string& where);

/// A name the model may define: [A-Za-z_][A-Za-z0-9_]*, at most max_name_length characters, and
/// not a built-in function or constant of muparser, `prev`, or a generated `prev__` name.
bool is_symbol_name(std::string_view name);
/// Why `name` is not a symbol name (empty if it is one).
std::string symbol_name_problem(std::string_view name);

/// Gives `parser` the checked expression, with every symbol and prev variable bound to the double
/// that `address` returns for its name. muparser's optimiser is off: its constant folding is where
/// the float->int undefined behaviour lives, and without it `&&` and `||` mean the same thing on
/// constants as on variables.
void compile_expression(mu::Parser& parser, const Checked_expression& e,
                        const std::function<double*(const std::string&)>& address);

}  // namespace sets
