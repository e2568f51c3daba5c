#include "sets/numeric/safe_bound.hpp"

#include <cmath>
#include <limits>

#include "sets/core/error.hpp"
#include "sets/numeric/interval.hpp"

namespace sets {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using I = UnprotectedInterval;  // the callers below hold a RoundingScope

// inf{ m * v : m in M, v in [lo, hi] } with 0 * inf = 0 (a zero multiplier ignores the bound).
double inf_product(const I& m, double lo, double hi) {
  double best = kInf;
  for (double a : {m.lower(), m.upper()}) {
    for (double b : {lo, hi}) {
      double p;
      if (a == 0 || b == 0) {
        p = 0;
      } else if (std::isinf(b)) {
        p = (a > 0) == (b > 0) ? kInf : -kInf;
      } else {
        p = (I(a) * I(b)).lower();
      }
      best = std::min(best, p);
    }
  }
  return best;
}

}  // namespace

double safe_lower_bound(const Eigen::Ref<const Eigen::VectorXd>& c, const LpRows& rows,
                        const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                        const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                        const Eigen::Ref<const Eigen::VectorXd>& y) {
  const auto m = static_cast<Eigen::Index>(rows.entries.size());
  if (y.size() != m || static_cast<Eigen::Index>(rows.lo.size()) != m ||
      static_cast<Eigen::Index>(rows.hi.size()) != m || col_lo.size() != c.size() ||
      col_hi.size() != c.size())
    throw InputError("safe_lower_bound: dimensions do not match");
  // Interval work only from here: one rounding-mode switch for the whole bound (it was one
  // per operation, the largest single cost of certifying PUIs).
  RoundingScope upward;
  // r = c - A^T y, enclosed.
  std::vector<I> r(static_cast<std::size_t>(c.size()));
  for (Eigen::Index j = 0; j < c.size(); ++j) r[static_cast<std::size_t>(j)] = I(c[j]);
  I total(0.0);
  for (Eigen::Index i = 0; i < m; ++i) {
    const double yi = y[i];
    if (yi == 0 || std::isnan(yi)) continue;
    const auto k = static_cast<std::size_t>(i);
    const double term = inf_product(I(yi), rows.lo[k], rows.hi[k]);
    // A multiplier of the wrong sign for a one-sided row (solver noise, e.g. -1e-18) would make
    // the bound -inf. The bound holds for ANY y, so use y_i = 0 for that row instead.
    if (term == -kInf) continue;
    for (const auto& [j, a] : rows.entries[k]) r[static_cast<std::size_t>(j)] -= I(a) * I(yi);
    total += I(term);
  }
  for (Eigen::Index j = 0; j < c.size(); ++j) {
    double term = inf_product(r[static_cast<std::size_t>(j)], col_lo[j], col_hi[j]);
    if (term == -kInf) return -kInf;
    total += I(term);
  }
  return total.lower();
}

double safe_upper_bound(const Eigen::Ref<const Eigen::VectorXd>& c, const LpRows& rows,
                        const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                        const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                        const Eigen::Ref<const Eigen::VectorXd>& y) {
  const Eigen::VectorXd neg_c = -c;
  const Eigen::VectorXd neg_y = -y;
  return -safe_lower_bound(neg_c, rows, col_lo, col_hi, neg_y);
}

}  // namespace sets
