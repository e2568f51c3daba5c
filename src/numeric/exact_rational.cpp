#include "numeric/exact_rational.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace sets::detail {

bool solve_exact(std::vector<Rational> M, std::vector<Rational> b, int n, std::vector<Rational>& x) {
  const auto at = [n](int i, int j) { return static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j); };
  std::vector<int> perm(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) perm[static_cast<std::size_t>(i)] = i;
  for (int k = 0; k < n; ++k) {
    int piv = -1;
    for (int i = k; i < n && piv < 0; ++i)
      if (sgn(M[at(i, k)]) != 0) piv = i;
    if (piv < 0) return false;
    if (piv != k) {
      for (int j = 0; j < n; ++j) std::swap(M[at(k, j)], M[at(piv, j)]);
      std::swap(b[static_cast<std::size_t>(k)], b[static_cast<std::size_t>(piv)]);
    }
    for (int i = k + 1; i < n; ++i) {
      if (sgn(M[at(i, k)]) == 0) continue;
      const Rational f = M[at(i, k)] / M[at(k, k)];
      for (int j = k; j < n; ++j) M[at(i, j)] -= f * M[at(k, j)];
      b[static_cast<std::size_t>(i)] -= f * b[static_cast<std::size_t>(k)];
    }
  }
  x.assign(static_cast<std::size_t>(n), Rational(0));
  for (int i = n - 1; i >= 0; --i) {
    Rational s = b[static_cast<std::size_t>(i)];
    for (int j = i + 1; j < n; ++j) s -= M[at(i, j)] * x[static_cast<std::size_t>(j)];
    x[static_cast<std::size_t>(i)] = s / M[at(i, i)];
  }
  return true;
}

Interval enclose(const Rational& q) {
  const double d = q.get_d();  // truncated towards zero
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (std::isinf(d)) return d > 0 ? Interval(std::numeric_limits<double>::max(), inf)
                                   : Interval(-inf, -std::numeric_limits<double>::max());
  const int c = cmp(q, Rational(d));
  if (c == 0) return Interval(d);
  return c > 0 ? Interval(d, std::nextafter(d, inf)) : Interval(std::nextafter(d, -inf), d);
}

}  // namespace sets::detail
