// Expressions evaluated for several lanes at once (src/data/lane_expression.hpp): every lane's value
// is bit for bit muparser's (NaN for NaN), for every operator and built-in function of the
// expression grammar, where the lanes agree at a condition and where they part.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "data/lane_expression.hpp"
#include "models/expression.hpp"

using namespace sets;

namespace {

// The same double bit for bit; any NaN matches any NaN. Which of two NaN operands a sum passes on
// depends on the order the compiler puts a commutative operation's operands in (the sanitizer
// build differs from Release there), and no result reads a NaN's payload: a NaN state is a
// blow-up either way.
bool same_value(double a, double b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

// The expression over x, y, z compiled as the simulator compiles it, evaluated for `lanes` draws
// of (x, y, z) both ways; the number of lanes that differ in any bit.
int lanes_that_differ(const std::string& text, int lanes, std::mt19937& rng) {
  std::vector<double> scalar(3);  // the parser's variables
  const std::vector<std::string> names{"x", "y", "z"};
  const Checked_expression e = check_expression(
      text, [](const std::string& n) { return n == "x" || n == "y" || n == "z"; }, "test");
  mu::Parser parser;
  compile_expression(parser, e, [&](const std::string& n) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return &scalar[i];
    return static_cast<double*>(nullptr);
  });
  parser.Eval();
  const Lane_expression lanes_of(parser, [&](const double* a) { return static_cast<int>(a - scalar.data()); });
  // Values with exact zeros, signs and magnitudes from 1e-3 to 1e3, so conditions and sign() part.
  std::uniform_int_distribution<int> kind(0, 5);
  std::uniform_real_distribution<double> u(-1, 1), decade(-3, 3);
  const auto draw = [&] {
    switch (kind(rng)) {
      case 0: return 0.0;
      case 1: return std::pow(10.0, decade(rng));
      case 2: return -std::pow(10.0, decade(rng));
      default: return u(rng);
    }
  };
  const auto L = static_cast<std::size_t>(lanes);
  std::vector<double> values(3 * L), out(L);
  for (double& v : values) v = draw();
  lanes_of.eval(values.data(), lanes, out.data());
  int differ = 0;
  for (std::size_t l = 0; l < L; ++l) {
    for (std::size_t i = 0; i < 3; ++i) scalar[i] = values[i * L + l];
    differ += same_value(parser.Eval(), out[l]) ? 0 : 1;
  }
  return differ;
}

}  // namespace

TEST(LaneExpression, EveryLaneIsMuparsersValueBitForBit) {
  const std::vector<std::string> expressions{
      "x",
      "2.5",
      "x + y * z - x / y",
      "-x^2 + y^3 - z^4 + x^1.5 + y^z",
      "x < y && y >= z || (x == 0) + (x != y) + (x <= z) + (x > z)",
      "x > 0 ? y : z",
      "x > 0 ? (y > 0 ? x * y : -z) : (z < 0 ? 1 : y / x)",
      "sin(x) + cos(y) + tan(z) + asin(x / 1000) + acos(y / 1000) + atan(z)",
      "sinh(x / 100) + cosh(y / 100) + tanh(z) + asinh(x) + acosh(y) + atanh(z)",
      "log2(x) + log10(y) + log(z) + ln(x) + exp(y / 100) + sqrt(z)",
      "sign(x) * abs(y) + rint(z) + atan2(x, y) + _pi * _e",
      "sum(x) + avg(x, y) + min(x, y, z) + max(x, y, z, x * y) + sum(x, y, z, 1, 2)",
      "x * sign(y) * (abs(y) > z ? 1 : 0) - min(x, 0) + max(z, 0) * (y < 0 ? -1 : 1)",
  };
  std::mt19937 rng(20261201);
  for (const auto& text : expressions)
    for (int lanes : {1, 2, 3, 5, 8})
      for (int draw = 0; draw < 20; ++draw) EXPECT_EQ(lanes_that_differ(text, lanes, rng), 0) << text << ", " << lanes << " lanes";
}
