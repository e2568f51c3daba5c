// The expression layer (src/models/expression.cpp), through the Simulator and directly: what muparser would
// crash on, or evaluate with undefined behaviour, is an InputError naming the file, field and
// column; well-formed expressions keep their meaning.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"
#include "models/expression.hpp"
#include "support/messages.hpp"

using namespace sets;
using sets::test::contains;
using sets::test::input_error_of;

namespace {

Recording two_columns() {
  Recording r;
  r.source = "r.csv";
  r.add("u", {1.0, -2.0, 0.5, 3.0});
  r.add("y", {0.0, 0.0, 0.0, 0.0});
  return r;
}

// A model whose sampled signal z is `expression` (over u, x, a), simulated over four samples.
ModelFile model_with(const std::string& expression) {
  ModelFile m;
  m.source = "m.json";
  m.sample_time = 0.1;
  m.inputs = {{"u", "u"}};
  m.parameters = {{"a", 0.5, false}};
  m.states = {{"x", 1.0, ""}};
  m.sampled = {{"z", expression}};
  m.derivatives = {{"x", "0"}};
  m.outputs = {{"z", "y"}};
  return m;
}

double first_value(const std::string& expression) {
  Simulator s(model_with(expression), two_columns());
  return s.simulate(s.parameter_values()).series("z")[0];
}

std::string error_of(const std::string& expression) {
  return input_error_of([&] { Simulator s(model_with(expression), two_columns()); });
}

}  // namespace

TEST(Expression, PrevWithAHugeLagIsAnInputErrorNotOutOfRange) {
  // std::stoi threw an uncaught std::out_of_range here.
  const std::string m = error_of("prev(u, 99999999999)");
  EXPECT_TRUE(contains(m, "m.json: sampled.z: column 9: prev(u, 99999999999): n must be at most 1000000000")) << m;
  EXPECT_TRUE(contains(error_of("prev(u, 0)"), "n must be >= 1"));
  EXPECT_TRUE(contains(error_of("prev(u, 1.5)"), "prev(x, n) needs a symbol x and a whole number"));
  EXPECT_TRUE(contains(error_of("prev(nothing, 1)"), "unknown symbol \"nothing\" in prev()"));
  EXPECT_EQ(first_value("prev(u, 1000000000)"), 1.0);  // the first sample while there is no earlier one
}

TEST(Expression, LogicalOperatorsOnConstantsHaveNoUndefinedBehaviour) {
  // muparser's constant folding computes (int)1e10 && (int)1: undefined behaviour, and
  // (int)0.5 == 0 made 0.5 && 1 false while the same with a variable was true.
  EXPECT_EQ(first_value("1e10&&1"), 1.0);
  EXPECT_EQ(first_value("0.5 && 1"), 1.0);
  EXPECT_EQ(first_value("a && 1"), 1.0);  // a = 0.5: the same meaning as the constant
  EXPECT_EQ(first_value("0.25 || 0"), 1.0);
  EXPECT_EQ(first_value("(1/0) && 1"), 1.0);  // inf is true
}

TEST(Expression, NumbersOutsideDoubleRangeAreRefused) {
  EXPECT_TRUE(contains(error_of("u + 1e400"), "column 5: the number 1e400 is outside the range of double precision"));
  EXPECT_EQ(first_value("1e-400 + u"), 1.0);  // underflow is 0
  EXPECT_TRUE(contains(error_of("2x"), "malformed number \"2x\""));
}

TEST(Expression, WhatMuparserMishandlesIsRefusedWithItsColumn) {
  EXPECT_TRUE(contains(error_of("x = 5"), "column 3: '=' (assignment) is not allowed"));
  EXPECT_TRUE(contains(error_of("sum(0?1,2,3,4:5)"), "expected ':' of 'condition ? a : b', found ','"));
  EXPECT_TRUE(contains(error_of("\"\",\"\",9"), "strings are not allowed"));
  EXPECT_TRUE(contains(error_of("1, 2"), "unexpected ',' after a complete expression"));
  EXPECT_TRUE(contains(error_of("sin(1, 2)"), "sin() takes 1 argument, not 2"));
  EXPECT_TRUE(contains(error_of("atan2(1)"), "atan2() takes 2 arguments, not 1"));
  EXPECT_TRUE(contains(error_of("max()"), "expected a number, a symbol, a function or '('"));
  EXPECT_TRUE(contains(error_of("foo(1)"), "\"foo\" is not a function"));
  EXPECT_TRUE(contains(error_of("-+-u"), "column 2"));
  EXPECT_TRUE(contains(error_of("(u"), "expected ')' to close the '(' at column 1"));
  EXPECT_TRUE(contains(error_of(""), "the expression is empty"));
  EXPECT_TRUE(contains(error_of(std::string(1000, '(') + "u" + std::string(1000, ')')),
                       "nested more than 100 levels deep"));
  EXPECT_TRUE(contains(error_of("u" + std::string(20000, '+') ), "more than 10000"));
  const std::string raw = error_of("u + \x1b[2J");
  EXPECT_TRUE(contains(raw, "unexpected character '\\x1b'")) << raw;
  EXPECT_FALSE(sets::test::has_raw_control_bytes(raw)) << raw;
}

TEST(Expression, WellFormedExpressionsKeepTheirMeaning) {
  EXPECT_DOUBLE_EQ(first_value("-2^2"), -4.0);
  EXPECT_DOUBLE_EQ(first_value("2^-1"), 0.5);
  EXPECT_DOUBLE_EQ(first_value("3--u"), 4.0);
  EXPECT_DOUBLE_EQ(first_value("u > 0 ? 10 : 20"), 10.0);
  EXPECT_DOUBLE_EQ(first_value("0 ? 1 : 0 ? 2 : 3"), 3.0);
  EXPECT_DOUBLE_EQ(first_value("sum(0 ? 1 : 2, 3)"), 5.0);
  EXPECT_DOUBLE_EQ(first_value("sin (0) + max(u, 2, a)"), 2.0);  // a blank before '(' is fine here
  EXPECT_DOUBLE_EQ(first_value("atan2(1, 1)*4"), std::atan2(1.0, 1.0) * 4);
  EXPECT_EQ(first_value("_pi"), M_PI);  // muparser's own _pi is 3.141592653589
  EXPECT_EQ(first_value("_e"), M_E);
  EXPECT_DOUBLE_EQ(first_value("1.5e1 + .5 + 1."), 16.5);
  EXPECT_DOUBLE_EQ(first_value("x\n+\tu"), 2.0);  // blanks include line breaks and tabs
}

// ---- x^2, x^3, x^4 of a symbol reach muparser as products (its pow was a quarter of a
// simulation's time). The values must be pow's within the products' roundings, and exactly pow's
// on signed zeros, infinities and NaN; every other power stays pow.

namespace {

// `text` over the symbol x, checked and compiled as the simulator does, evaluated at `x`.
struct Compiled_x {
  explicit Compiled_x(const std::string& text)
      : e(check_expression(text, [](const std::string& n) { return n == "x" || n.size() > 50; }, "test")) {
    compile_expression(parser, e, [&](const std::string& n) { return n == "x" ? &x : &other; });
  }
  double operator()(double value) {
    x = value;
    return parser.Eval();
  }
  Checked_expression e;
  mu::Parser parser;
  double x = 0, other = 0;
};

const std::vector<double>& hostile_values() {
  static const std::vector<double> v = {0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 1.5, -3.7, 1e-3, -7e5,
                                        1e-100, -1e-100, 1e70, -1e70, 1e-300, -1e-300,
                                        std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::max(),
                                        std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                        std::numeric_limits<double>::quiet_NaN()};
  return v;
}

// Equal as pow gives it: NaN as NaN, zeros and infinities with their sign, finite values within
// the products' `roundings` roundings and pow's own (plus the smallest subnormal per rounding
// where they underflow).
::testing::AssertionResult same_as_pow(double got, double want, int roundings) {
  if (std::isnan(want)) return std::isnan(got) ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << got << " is not NaN";
  if (want == 0 || std::isinf(want) || got == 0 || std::isinf(got)) {
    if (got == want && std::signbit(got) == std::signbit(want)) return ::testing::AssertionSuccess();
    if (std::isfinite(want) && std::isfinite(got) &&
        std::abs(got - want) <= roundings * std::numeric_limits<double>::denorm_min())
      return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << got << " is not " << want;
  }
  const double tol = (roundings + 1) * std::numeric_limits<double>::epsilon() * std::abs(want) +
                     roundings * std::numeric_limits<double>::denorm_min();
  if (std::abs(got - want) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << got << " differs from pow's " << want << " by " << std::abs(got - want);
}

}  // namespace

TEST(Expression, SmallPowersOfASymbolArePowsValuesAsProducts) {
  struct Case {
    std::string text;
    std::string for_muparser;
    std::function<double(double)> want;
    int roundings;
  };
  const std::vector<Case> cases = {
      {"x^2", "( x * x )", [](double x) { return std::pow(x, 2); }, 1},
      {"x^3", "( x * x * x )", [](double x) { return std::pow(x, 3); }, 2},
      {"x ^ 4.0", "( x * x * x * x )", [](double x) { return std::pow(x, 4); }, 3},
      {"-x^2", "- ( x * x )", [](double x) { return -std::pow(x, 2); }, 1},  // ^ binds tighter than a sign
      {"2*-x^3+1", "2 * - ( x * x * x ) + 1", [](double x) { return 2 * -std::pow(x, 3) + 1; }, 4},
      {"(x^2 < 4) ? x^3 : x", "( ( x * x ) < 4 ) ? ( x * x * x ) : x",
       [](double x) { return std::pow(x, 2) < 4 ? std::pow(x, 3) : x; }, 2},
  };
  for (const auto& c : cases) {
    Compiled_x f(c.text);
    EXPECT_EQ(f.e.text, c.for_muparser) << c.text;
    for (double x : hostile_values()) EXPECT_TRUE(same_as_pow(f(x), c.want(x), c.roundings)) << c.text << " at x = " << x;
  }
}

TEST(Expression, OtherPowersStayPow) {
  // x^0 is 1 even for NaN and x^1 is x: no product is that; negative and fractional exponents,
  // larger ones, signed or parenthesised exponents, chains (whichever way muparser groups them)
  // and bases other than one symbol keep muparser's pow.
  for (const std::string text : {"x^0", "x^1", "x^-2", "x^2.5", "x^5", "x^+2", "x^(2)", "x^2^3", "2^x^2", "(x+1)^2",
                                 "2^3", "abs(x)^3", "x^x"}) {
    Compiled_x f(text);
    EXPECT_NE(f.e.text.find('^'), std::string::npos) << text << " became " << f.e.text;
  }
  Compiled_x zeroth("x^0");
  EXPECT_EQ(zeroth(std::numeric_limits<double>::quiet_NaN()), 1.0);
  Compiled_x negative("x^-2");
  EXPECT_EQ(negative(-0.0), std::numeric_limits<double>::infinity());
}

TEST(Expression, PowersInTextsNearTheLengthLimitStayPowAndStillCompile) {
  // The products repeat the name: 95 terms of a 99-character name to the fourth power are within
  // our 10 000 characters but past muparser's 20 000 once written as products.
  const std::string name = "n" + std::string(98, 'a');
  std::string text;
  for (int i = 0; i < 95; ++i) text += (i ? "+" : "") + name + "^4";
  ASSERT_LE(text.size(), max_expression_length);
  Compiled_x f(text);
  EXPECT_NE(f.e.text.find('^'), std::string::npos);
  f.other = 1.5;
  EXPECT_DOUBLE_EQ(f.parser.Eval(), 95 * std::pow(1.5, 4));
}
