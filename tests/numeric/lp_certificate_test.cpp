// Exact certificates of LP (in)feasibility: never contradicted by CGAL's exact LP solver, decisive
// on ordinary problems, and not fooled where GLPK's "exact" simplex is.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/numeric/interval.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/lp_certificate.hpp"

namespace {

using sets::BoolInterval;
using sets::inf;
using sets::LinearProgram;

Eigen::VectorXd lower_bounds(const LinearProgram& lp) {
  Eigen::VectorXd v(lp.num_variables());
  for (int j = 0; j < lp.num_variables(); ++j) v[j] = lp.variable_lower(j);
  return v;
}
Eigen::VectorXd upper_bounds(const LinearProgram& lp) {
  Eigen::VectorXd v(lp.num_variables());
  for (int j = 0; j < lp.num_variables(); ++j) v[j] = lp.variable_upper(j);
  return v;
}

// Feasibility of the same double data decided by CGAL's exact solver.
bool exactly_feasible(const Eigen::MatrixXd& A, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                      const Eigen::VectorXd& xlo, const Eigen::VectorXd& xhi) {
  const int n = static_cast<int>(A.cols());
  CGAL::Quadratic_program<double> qp(CGAL::SMALLER, false, 0, false, 0);
  int row = 0;
  for (int i = 0; i < A.rows(); ++i)
    for (int side = 0; side < 2; ++side) {
      const double b = side == 0 ? hi[i] : lo[i];
      if (std::isinf(b)) continue;
      for (int j = 0; j < n; ++j) qp.set_a(j, row, side == 0 ? A(i, j) : -A(i, j));
      qp.set_b(row, side == 0 ? b : -b);
      ++row;
    }
  for (int j = 0; j < n; ++j) {
    qp.set_l(j, std::isfinite(xlo[j]), std::isfinite(xlo[j]) ? xlo[j] : 0.0);
    qp.set_u(j, std::isfinite(xhi[j]), std::isfinite(xhi[j]) ? xhi[j] : 0.0);
  }
  // Bland's rule: CGAL's default pricing cycled (seemingly forever) on some of these degenerate,
  // near-parallel systems; Bland's rule provably terminates.
  CGAL::Quadratic_program_options options;
  options.set_pricing_strategy(CGAL::QP_BLAND);
  return !CGAL::solve_linear_program(qp, CGAL::Gmpzf(), options).is_infeasible();
}

}  // namespace

TEST(LpCertificate, ProvesSmallSystemsEitherWay) {
  // x + y >= 2 and x + y <= 1 with free x, y: the certificate must make the reduced costs of
  // both free columns exactly zero.
  LinearProgram lp(2);
  lp.add_row(Eigen::Vector2d(1, 1), 2, inf);
  lp.add_row(Eigen::Vector2d(1, 1), -inf, 1);
  EXPECT_TRUE(sets::prove_infeasible(lp));
  EXPECT_EQ(sets::certified_is_empty(lp), BoolInterval::yes);
  // y = (1, -1) (positive on a lower side, negative on an upper side) proves it; y = (1, 0)
  // does not (x + y >= 2 alone is feasible).
  EXPECT_TRUE(sets::verify_infeasibility_certificate(lp.rows(), lower_bounds(lp), upper_bounds(lp),
                                                     Eigen::Vector2d(1, -1)));
  EXPECT_FALSE(sets::verify_infeasibility_certificate(lp.rows(), lower_bounds(lp), upper_bounds(lp),
                                                      Eigen::Vector2d(1, 0)));
  // Multipliers off by rounding noise are repaired exactly.
  EXPECT_TRUE(sets::verify_infeasibility_certificate(lp.rows(), lower_bounds(lp), upper_bounds(lp),
                                                     Eigen::Vector2d(1, -1 - 1e-12)));
  LinearProgram ok(2);
  ok.add_row(Eigen::Vector2d(1, 1), 1, 2);
  ok.add_row(Eigen::Vector2d(1, -1), 0.1, 0.1);  // an equality: a flat set
  EXPECT_FALSE(sets::prove_infeasible(ok));
  EXPECT_EQ(sets::certified_is_empty(ok), BoolInterval::no);
}

TEST(LpCertificate, SnapsAPointOntoItsExactVertex) {
  // 0.1 x1 + 0.2 x2 = 0.3 and x1 = x2 (exact doubles): the rounded point (1, 1) may miss the
  // first equation by rounding, the exact vertex does not.
  LinearProgram lp(2);
  lp.add_row(Eigen::Vector2d(0.1, 0.2), 0.3, 0.3);
  lp.add_row(Eigen::Vector2d(1, -1), 0, 0);
  const Eigen::Vector2d near(1 + 1e-15, 1 - 1e-15);
  EXPECT_TRUE(sets::verify_feasible_point(lp.rows(), lower_bounds(lp), upper_bounds(lp), near));
  // Far from it, the equalities still snap onto the vertex: a proof that the set is not empty.
  EXPECT_TRUE(sets::verify_feasible_point(lp.rows(), lower_bounds(lp), upper_bounds(lp), Eigen::Vector2d(5, -3)));
  // An empty system accepts no point.
  LinearProgram empty(1);
  empty.add_row(Eigen::VectorXd::Constant(1, 1.0), 0, 0);
  empty.add_row(Eigen::VectorXd::Constant(1, 1.0), 1, 1);
  EXPECT_FALSE(sets::verify_feasible_point(empty.rows(), lower_bounds(empty), upper_bounds(empty),
                                           Eigen::VectorXd::Constant(1, 0.0)));
}

// GLPK's glp_exact first replaces every double by a nearby simple fraction (relative tolerance
// about 1e-9) and so decides a different problem. One row, columns fixed at a point, the row's
// range the 1-2 ulp enclosure of the exact activity, column scales 10^-10 .. 10^10: every LP is
// feasible in exact arithmetic. glp_exact calls some of them infeasible; the certified verdict
// never does, and proves every one feasible.
TEST(LpCertificate, GlpExactIsFooledTheCertificateIsNot) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> U(-1, 1);
  std::uniform_int_distribution<int> K(-10, 10);
  int exact_says_infeasible = 0, certified_no = 0;
  for (int problem = 0; problem < 300; ++problem) {
    const int n = 2 + problem % 5;
    LinearProgram lp(n);
    Eigen::VectorXd a(n);
    sets::Interval activity(0.0);
    for (int j = 0; j < n; ++j) {
      const double scale = std::pow(10.0, K(rng));
      const double v = scale * U(rng);
      a[j] = U(rng) / scale * std::pow(10.0, K(rng) / 5);
      lp.set_variable_bounds(j, v, v);
      activity += sets::Interval(a[j]) * sets::Interval(v);
    }
    lp.add_row(a, activity.lower(), activity.upper());
    lp.set_objective(Eigen::VectorXd::Zero(n), sets::Sense::minimize);
    try {
      exact_says_infeasible += lp.solve_exact().status == sets::LpStatus::infeasible;
    } catch (const sets::NumericalError&) {
    }
    const BoolInterval v = sets::certified_is_empty(lp);
    ASSERT_NE(v, BoolInterval::yes) << "problem " << problem;
    certified_no += v == BoolInterval::no;
  }
  EXPECT_GT(exact_says_infeasible, 0) << "glp_exact no longer rounds its input? Revisit the docs.";
  EXPECT_EQ(certified_no, 300);
  RecordProperty("glp_exact_false_infeasible", exact_says_infeasible);
}

// Random badly scaled, near-degenerate systems, about half of them infeasible: the certified
// verdict never contradicts CGAL's exact solver on the same doubles.
RC_GTEST_PROP(LpCertificate, NeverContradictsTheExactSolver, ()) {
  const int n = *rc::gen::inRange(1, 6);
  const int m = *rc::gen::inRange(1, 3 * n + 3);
  Eigen::MatrixXd A(m, n);
  Eigen::VectorXd lo(m), hi(m);
  for (int i = 0; i < m; ++i) {
    const double scale = std::pow(10.0, *rc::gen::inRange(-8, 9));
    for (int j = 0; j < n; ++j) A(i, j) = scale * (*rc::gen::inRange(-1000, 1001) / 97.0);
    if (i > 0 && *rc::gen::inRange(0, 3) == 0) A.row(i) = A.row(i - 1) * (1 + 1e-9 * *rc::gen::inRange(1, 100));
    const double centre = A.row(i).sum() * (*rc::gen::inRange(-100, 101) / 100.0);
    const double half = std::abs(A.row(i).sum()) * (*rc::gen::inRange(0, 30) / 100.0);
    lo[i] = *rc::gen::inRange(0, 5) == 0 ? -inf : centre - half;
    hi[i] = *rc::gen::inRange(0, 5) == 0 ? inf : centre + half;
  }
  const bool boxed = *rc::gen::arbitrary<bool>();
  const Eigen::VectorXd xlo = Eigen::VectorXd::Constant(n, boxed ? -2.0 : -inf);
  const Eigen::VectorXd xhi = Eigen::VectorXd::Constant(n, boxed ? 2.0 : inf);
  LinearProgram lp(n);
  for (int j = 0; j < n; ++j) lp.set_variable_bounds(j, xlo[j], xhi[j]);
  lp.add_rows(A, lo, hi);
  const BoolInterval v = sets::certified_is_empty(lp);
  const bool feasible = exactly_feasible(A, lo, hi, xlo, xhi);
  RC_TAG(feasible ? "feasible" : "infeasible", v == BoolInterval::unknown ? "unknown" : "decided");
  if (v == BoolInterval::yes) RC_ASSERT(!feasible);
  if (v == BoolInterval::no) RC_ASSERT(feasible);
}
