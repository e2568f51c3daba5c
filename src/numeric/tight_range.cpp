#include "sets/numeric/tight_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "sets/core/error.hpp"

namespace sets {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Piece {
  Interval x;
  Interval enclosure;
  bool exact = false;  // monotone piece: enclosure is the range up to rounding
};

}  // namespace

RangeResult branch_and_bound_range(const IntervalFunction& extension, const IntervalFunction& derivative,
                                   const Interval& X, const RangeOptions& options) {
  if (!extension) throw InputError("branch_and_bound_range: no interval extension given");
  if (!std::isfinite(X.lower()) || !std::isfinite(X.upper()))
    throw InputError("branch_and_bound_range: the interval must be finite");
  if (!(options.tolerance >= 0)) throw InputError("branch_and_bound_range: tolerance must be >= 0");
  if (X.lower() == X.upper()) return {extension(X), true, 1};

  // Point evaluations give an upper bound on the minimum (min_up) and a lower bound on the
  // maximum (max_lo); the pieces' enclosures give the other side.
  double min_up = kInf, max_lo = -kInf;
  auto probe = [&](double x) {
    const Interval v = extension(Interval(x));
    min_up = std::min(min_up, v.upper());
    max_lo = std::max(max_lo, v.lower());
  };
  auto make_piece = [&](const Interval& x) {
    Piece p{x, extension(x), false};
    if (derivative) {
      const Interval d = derivative(x);
      if (d.lower() >= 0 || d.upper() <= 0) {
        // Monotone: the range is spanned by the two end values.
        const Interval fa = extension(Interval(x.lower())), fb = extension(Interval(x.upper()));
        const Interval h = hull(fa, fb);
        p.enclosure = boost::numeric::intersect(p.enclosure, h);
        p.exact = true;
        probe(x.lower());
        probe(x.upper());
      } else {
        // Mean-value form f(m) + f'(X)(X - m): second-order tight on small pieces.
        const double m = midpoint(x);
        const Interval mv = extension(Interval(m)) + d * (x - Interval(m));
        if (boost::numeric::overlap(mv, p.enclosure)) p.enclosure = boost::numeric::intersect(mv, p.enclosure);
      }
    }
    return p;
  };

  probe(X.lower());
  probe(X.upper());
  probe(midpoint(X));
  std::vector<Piece> pieces{make_piece(X)};
  int examined = 1;
  for (;;) {
    double L = kInf, U = -kInf;
    for (const Piece& p : pieces) {
      L = std::min(L, p.enclosure.lower());
      U = std::max(U, p.enclosure.upper());
    }
    const double tol_lo = options.tolerance * std::max(1.0, std::abs(L));
    const double tol_hi = options.tolerance * std::max(1.0, std::abs(U));
    const bool lo_done = L >= min_up - tol_lo;
    const bool hi_done = U <= max_lo + tol_hi;
    if ((lo_done && hi_done) || examined >= options.max_pieces) return {Interval(L, U), lo_done && hi_done, examined};

    // Split every piece that could still hold a value beyond what the probes have reached.
    std::vector<Piece> next;
    next.reserve(pieces.size() * 2);
    bool split_any = false;
    for (const Piece& p : pieces) {
      const bool relevant = (!lo_done && p.enclosure.lower() < min_up - tol_lo) ||
                            (!hi_done && p.enclosure.upper() > max_lo + tol_hi);
      const double a = p.x.lower(), b = p.x.upper(), m = midpoint(p.x);
      if (!relevant || p.exact || !(a < m && m < b) || examined >= options.max_pieces) {
        next.push_back(p);
        continue;
      }
      probe(m);
      next.push_back(make_piece(Interval(a, m)));
      next.push_back(make_piece(Interval(m, b)));
      ++examined;
      split_any = true;
    }
    pieces.swap(next);
    if (!split_any) {
      // Nothing left to split (exact pieces or pieces at machine resolution): report as is.
      double L2 = kInf, U2 = -kInf;
      for (const Piece& p : pieces) {
        L2 = std::min(L2, p.enclosure.lower());
        U2 = std::max(U2, p.enclosure.upper());
      }
      const bool tight = L2 >= min_up - options.tolerance * std::max(1.0, std::abs(L2)) &&
                         U2 <= max_lo + options.tolerance * std::max(1.0, std::abs(U2));
      return {Interval(L2, U2), tight, examined};
    }
  }
}

namespace {

std::vector<double> trimmed(std::vector<double> c) {
  while (c.size() > 1 && c.back() == 0) c.pop_back();
  if (c.empty()) c.push_back(0);
  return c;
}

Interval horner(const std::vector<double>& c, const Interval& X) {
  Interval r(c.back());
  for (std::size_t k = c.size() - 1; k-- > 0;) r = r * X + Interval(c[k]);
  return r;
}

double horner(const std::vector<double>& c, double x) {
  double r = c.back();
  for (std::size_t k = c.size() - 1; k-- > 0;) r = r * x + c[k];
  return r;
}

// Derivative coefficients as intervals (k * c[k] may round).
Interval derivative_horner(const std::vector<double>& c, const Interval& X) {
  if (c.size() < 2) return Interval(0.0);
  Interval r = Interval(static_cast<double>(c.size() - 1)) * Interval(c.back());
  for (std::size_t k = c.size() - 1; k-- > 1;) r = r * X + Interval(static_cast<double>(k)) * Interval(c[k]);
  return r;
}

std::string polynomial_name(const std::vector<double>& c) {
  std::string s;
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (c[k] == 0) continue;
    char coeff[32];
    std::snprintf(coeff, sizeof coeff, "%g", c[k]);
    std::string term = k == 0 ? coeff : (c[k] == 1 ? std::string() : std::string(coeff) + "*") + "x";
    if (k >= 2) {
      term += '^';
      term += std::to_string(k);
    }
    if (!s.empty()) s += " + ";
    s += term;
  }
  return s.empty() ? "0" : s;
}

}  // namespace

RangeResult polynomial_range(const std::vector<double>& coefficients, const Interval& X, const RangeOptions& options) {
  const std::vector<double> c = trimmed(coefficients);
  for (double v : c)
    if (!std::isfinite(v)) throw InputError("polynomial_range: coefficients must be finite");
  const std::size_t degree = c.size() - 1;
  if (degree == 0) return {Interval(c[0]), true, 1};
  // c_n x^n: X occurs once, and Boost's pow is tight (even powers across 0 start at 0).
  std::size_t nonzero = 0;
  for (double v : c) nonzero += v != 0;
  if (nonzero == 1) return {Interval(c[degree]) * pow(X, static_cast<int>(degree)), true, 1};
  if (degree == 1) return {Interval(c[0]) + Interval(c[1]) * X, true, 1};
  if (degree == 2) {
    // c2 (x + h)^2 + k with h = c1 / (2 c2), k = c0 - c1^2 / (4 c2): X occurs once.
    const Interval c2(c[2]), c1(c[1]), c0(c[0]);
    const Interval h = c1 / (Interval(2.0) * c2);
    const Interval k = c0 - c1 * c1 / (Interval(4.0) * c2);
    return {c2 * pow(X + h, 2) + k, true, 1};
  }
  return branch_and_bound_range([&](const Interval& x) { return horner(c, x); },
                                [&](const Interval& x) { return derivative_horner(c, x); }, X, options);
}

// ---------------------------------------------------------------- UnivariateFunction

UnivariateFunction UnivariateFunction::polynomial(std::vector<double> c, std::string name) {
  c = trimmed(std::move(c));
  for (double v : c)
    if (!std::isfinite(v)) throw InputError("polynomial basis function: coefficients must be finite");
  UnivariateFunction f;
  f.name_ = name.empty() ? polynomial_name(c) : std::move(name);
  f.shape_ = Shape::polynomial;
  f.coeffs_ = c;
  f.value_ = [c](double x) { return horner(c, x); };
  f.extension_ = [c](const Interval& x) { return horner(c, x); };
  f.derivative_ = [c](const Interval& x) { return derivative_horner(c, x); };
  return f;
}

UnivariateFunction UnivariateFunction::monomial(int n) {
  if (n < 0) throw InputError("monomial basis function: the power must be >= 0 (got " + std::to_string(n) + ")");
  std::vector<double> c(static_cast<std::size_t>(n) + 1, 0.0);
  c.back() = 1;
  return polynomial(c, n == 0 ? "1" : n == 1 ? "x" : "x^" + std::to_string(n));
}

UnivariateFunction UnivariateFunction::monotone(std::string name, RealFunction value, IntervalFunction extension,
                                                bool increasing) {
  if (!value || !extension) throw InputError("monotone basis function '" + name + "': value and extension are required");
  UnivariateFunction f;
  f.name_ = std::move(name);
  f.shape_ = increasing ? Shape::increasing : Shape::decreasing;
  f.value_ = std::move(value);
  f.extension_ = std::move(extension);
  return f;
}

UnivariateFunction UnivariateFunction::general(std::string name, RealFunction value, IntervalFunction extension,
                                               IntervalFunction derivative) {
  if (!value || !extension) throw InputError("basis function '" + name + "': value and extension are required");
  UnivariateFunction f;
  f.name_ = std::move(name);
  f.shape_ = Shape::general;
  f.value_ = std::move(value);
  f.extension_ = std::move(extension);
  f.derivative_ = std::move(derivative);
  return f;
}

UnivariateFunction UnivariateFunction::builtin(const std::string& name) {
  using boost::numeric::cos;
  using boost::numeric::sin;
  if (name == "sin")
    return general("sin", [](double x) { return std::sin(x); }, [](const Interval& x) { return sin(x); },
                   [](const Interval& x) { return cos(x); });
  if (name == "cos")
    return general("cos", [](double x) { return std::cos(x); }, [](const Interval& x) { return cos(x); },
                   [](const Interval& x) { return -sin(x); });
  if (name == "exp")
    return monotone("exp", [](double x) { return std::exp(x); },
                    [](const Interval& x) { return boost::numeric::exp(x); }, true);
  if (name == "tanh")
    return monotone("tanh", [](double x) { return std::tanh(x); },
                    [](const Interval& x) { return boost::numeric::tanh(x); }, true);
  if (name == "atan")
    return monotone("atan", [](double x) { return std::atan(x); },
                    [](const Interval& x) { return boost::numeric::atan(x); }, true);
  throw InputError("unknown basis function '" + name + "' (built-ins: sin, cos, exp, tanh, atan)");
}

UnivariateFunction UnivariateFunction::product(const UnivariateFunction& f, const UnivariateFunction& g) {
  auto is_unit_monomial = [](const UnivariateFunction& h) {
    if (h.shape_ != Shape::polynomial) return false;
    for (std::size_t k = 0; k + 1 < h.coeffs_.size(); ++k)
      if (h.coeffs_[k] != 0) return false;
    return h.coeffs_.back() == 1;
  };
  if (is_unit_monomial(f) && is_unit_monomial(g))
    return monomial(static_cast<int>(f.coeffs_.size() + g.coeffs_.size() - 2));
  IntervalFunction d;
  if (f.derivative_ && g.derivative_)
    d = [f, g](const Interval& x) { return f.derivative_(x) * g.extension_(x) + f.extension_(x) * g.derivative_(x); };
  return general(f.name_ + "*" + g.name_, [f, g](double x) { return f.value_(x) * g.value_(x); },
                 [f, g](const Interval& x) { return f.extension_(x) * g.extension_(x); }, d);
}

RangeResult UnivariateFunction::range(const Interval& X, const RangeOptions& options) const {
  switch (shape_) {
    case Shape::polynomial:
      return polynomial_range(coeffs_, X, options);
    case Shape::increasing:
    case Shape::decreasing: {
      const Interval fa = extension_(Interval(X.lower())), fb = extension_(Interval(X.upper()));
      // The hull of the end values is the range of a monotone function (either direction).
      return {hull(fa, fb), true, 1};
    }
    default:
      return branch_and_bound_range(extension_, derivative_, X, options);
  }
}

}  // namespace sets
