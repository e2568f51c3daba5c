// The LP/MILP layer: statuses, warm starts, and safe bounds checked against CGAL's exact LP solver.

#include <gtest/gtest.h>

#include <random>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <cmath>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"

namespace {

using sets::inf;
using sets::LinearProgram;
using sets::LpStatus;
using sets::Sense;

struct ExactLp {
  bool feasible = false;
  bool bounded = false;
  CGAL::Quotient<CGAL::Gmpzf> value;
};

// The exact optimum of the same LP (with the same double data) from CGAL's QP solver.
ExactLp exact_optimum(const Eigen::MatrixXd& A, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                      const Eigen::VectorXd& xlo, const Eigen::VectorXd& xhi, const Eigen::VectorXd& c,
                      Sense sense) {
  const int n = static_cast<int>(A.cols());
  CGAL::Quadratic_program<double> qp(CGAL::SMALLER, false, 0, false, 0);
  int row = 0;
  for (int i = 0; i < A.rows(); ++i) {
    for (int side = 0; side < 2; ++side) {
      const double b = side == 0 ? hi[i] : lo[i];
      if (std::isinf(b)) continue;
      for (int j = 0; j < n; ++j) qp.set_a(j, row, side == 0 ? A(i, j) : -A(i, j));
      qp.set_b(row, side == 0 ? b : -b);
      ++row;
    }
  }
  for (int j = 0; j < n; ++j) {
    qp.set_l(j, std::isfinite(xlo[j]), std::isfinite(xlo[j]) ? xlo[j] : 0.0);
    qp.set_u(j, std::isfinite(xhi[j]), std::isfinite(xhi[j]) ? xhi[j] : 0.0);
    qp.set_c(j, sense == Sense::minimize ? c[j] : -c[j]);
  }
  // Bland's rule: the reference solver must terminate on the degenerate, nearly parallel rows
  // this property generates (the default pricing ran for minutes on seed 4438, max_success=500).
  CGAL::Quadratic_program_options options;
  options.set_pricing_strategy(CGAL::QP_BLAND);
  const auto s = CGAL::solve_linear_program(qp, CGAL::Gmpzf(), options);
  ExactLp out;
  out.feasible = !s.is_infeasible();
  out.bounded = !s.is_unbounded();
  if (out.feasible && out.bounded) out.value = s.objective_value();
  if (sense == Sense::maximize) out.value = -out.value;
  return out;
}

bool leq(double a, const CGAL::Quotient<CGAL::Gmpzf>& b) { return CGAL::Quotient<CGAL::Gmpzf>(a) <= b; }
bool geq(double a, const CGAL::Quotient<CGAL::Gmpzf>& b) { return CGAL::Quotient<CGAL::Gmpzf>(a) >= b; }

}  // namespace

TEST(LinearProgram, SolvesSmallProblemAndWarmStarts) {
  // max x + y  s.t.  x + 2y <= 4, 3x + y <= 6, x, y >= 0  -> optimum 2.8 at (1.6, 1.2)
  // Finite variable bounds: the safe bound needs them wherever a reduced cost is not exactly 0.
  LinearProgram lp(2);
  lp.set_variable_bounds(0, 0, 10);
  lp.set_variable_bounds(1, 0, 10);
  lp.add_row(Eigen::Vector2d(1, 2), -inf, 4);
  lp.add_row(Eigen::Vector2d(3, 1), -inf, 6);
  lp.set_objective(Eigen::Vector2d(1, 1), Sense::maximize);
  auto s = lp.solve();
  ASSERT_EQ(s.status, LpStatus::optimal);
  EXPECT_NEAR(s.objective, 2.8, 1e-12);
  const double ub = lp.safe_bound(s);
  EXPECT_GE(ub, 2.8);
  EXPECT_LE(ub, 2.8 + 1e-12);
  lp.set_objective_coordinate(0, Sense::maximize);
  s = lp.solve();
  EXPECT_NEAR(s.objective, 2.0, 1e-12);
  lp.set_objective_coordinate(0, Sense::minimize);
  s = lp.solve();
  EXPECT_NEAR(s.objective, 0.0, 1e-12);
}

TEST(LinearProgram, BasisRestoresAnEarlierOptimumAndCutoffStopsEarly) {
  // min sum x_i  s.t.  x_i + x_{i+1} >= 1 (a chain), 0 <= x <= 1: optimum n/2 for even n.
  const int n = 40;
  LinearProgram lp(n);
  for (int i = 0; i < n; ++i) lp.set_variable_bounds(i, 0, 1);
  for (int i = 0; i + 1 < n; ++i) lp.add_row(std::vector<std::pair<int, double>>{{i, 1.0}, {i + 1, 1.0}}, 1, inf);
  lp.set_objective(Eigen::VectorXd::Ones(n), Sense::minimize);
  const auto first = lp.solve();
  ASSERT_EQ(first.status, LpStatus::optimal);
  const sets::LpBasis optimal = lp.basis();
  ASSERT_EQ(optimal.rows.size(), static_cast<std::size_t>(n - 1));
  ASSERT_EQ(optimal.cols.size(), static_cast<std::size_t>(n));
  // Change the problem, solve it, restore the first basis: the original re-solves in 0 iterations.
  lp.set_variable_bounds(0, 1, 1);
  lp.set_variable_bounds(n - 1, 1, 1);
  const auto changed = lp.solve();
  ASSERT_EQ(changed.status, LpStatus::optimal);
  lp.set_variable_bounds(0, 0, 1);
  lp.set_variable_bounds(n - 1, 0, 1);
  lp.set_basis(optimal);
  const auto again = lp.solve();
  ASSERT_EQ(again.status, LpStatus::optimal);
  EXPECT_EQ(again.iterations, changed.iterations);  // GLPK's count is cumulative: no new iteration
  EXPECT_NEAR(again.objective, first.objective, 1e-12);
  // From a cold start, a cutoff far below the optimum stops the dual simplex early, and the safe
  // bound of the point reached still bounds the optimum from below.
  lp.reset_basis();
  sets::LpSolveOptions cut;
  cut.cutoff = 1.0;
  const auto stopped = lp.solve(cut);
  if (stopped.status == LpStatus::cutoff) {
    const double b = lp.safe_bound(stopped);
    EXPECT_GT(b, 1.0 - 1e-9);
    EXPECT_LE(b, first.objective + 1e-9);
  } else {
    EXPECT_EQ(stopped.status, LpStatus::optimal);
  }
  cut.cutoff = first.objective + 1;  // above the optimum: solved to the end
  lp.reset_basis();
  EXPECT_EQ(lp.solve(cut).status, LpStatus::optimal);
  sets::LpBasis wrong;
  wrong.rows.resize(3);
  EXPECT_THROW(lp.set_basis(wrong), sets::InputError);
}

TEST(LinearProgram, ReportsInfeasibleAndUnbounded) {
  LinearProgram lp(1);
  lp.add_row(Eigen::VectorXd::Constant(1, 1.0), 2, inf);
  lp.set_objective_coordinate(0, Sense::maximize);
  EXPECT_EQ(lp.solve().status, LpStatus::unbounded);
  EXPECT_EQ(lp.safe_bound(lp.solve()), inf);
  lp.add_row(Eigen::VectorXd::Constant(1, 1.0), -inf, 1);
  EXPECT_EQ(lp.solve().status, LpStatus::infeasible);
  EXPECT_EQ(lp.solve_exact().status, LpStatus::infeasible);
}

TEST(LinearProgram, RejectsBadInput) {
  LinearProgram lp(2);
  EXPECT_THROW(lp.add_row(Eigen::Vector3d(1, 2, 3), 0, 1), sets::InputError);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, NAN), 0, 1), sets::InputError);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, 1), 2, 1), sets::InputError);
  EXPECT_THROW(lp.set_variable_bounds(5, 0, 1), sets::InputError);
}

// Random LPs built to mislead floating point: rows scaled by 10^-6..10^6, pairs of nearly
// parallel rows (near-degenerate vertices), a bounded box. The safe bound must enclose the
// exact optimum (CGAL, exact arithmetic on the same doubles) every time.
RC_GTEST_PROP(SafeBound, EnclosesExactOptimumOfIllConditionedLps, ()) {
  const int n = *rc::gen::inRange(2, 5);
  const int m = *rc::gen::inRange(n, 3 * n);
  Eigen::MatrixXd A(m, n);
  Eigen::VectorXd lo(m), hi(m);
  for (int i = 0; i < m; ++i) {
    const double scale = std::pow(10.0, *rc::gen::inRange(-6, 7));
    for (int j = 0; j < n; ++j) A(i, j) = scale * (*rc::gen::inRange(-1000, 1001) / 97.0);
    if (i > 0 && *rc::gen::inRange(0, 3) == 0) {
      // nearly parallel to the previous row
      A.row(i) = A.row(i - 1) * (1 + 1e-9 * *rc::gen::inRange(1, 100));
    }
    // Keep x = 0 feasible-ish: the row range contains a random point near 0.
    const double centre = A.row(i).sum() * (*rc::gen::inRange(-100, 101) / 1000.0);
    const double half = std::abs(A.row(i).sum()) * (*rc::gen::inRange(1, 100) / 100.0) + 1e-300;
    lo[i] = centre - half;
    hi[i] = *rc::gen::inRange(0, 4) == 0 ? inf : centre + half;
  }
  const Eigen::VectorXd xlo = Eigen::VectorXd::Constant(n, -10.0), xhi = Eigen::VectorXd::Constant(n, 10.0);
  Eigen::VectorXd c(n);
  for (int j = 0; j < n; ++j) c[j] = *rc::gen::inRange(-100, 101) / 7.0;
  const Sense sense = *rc::gen::element(Sense::minimize, Sense::maximize);

  LinearProgram lp(n);
  for (int j = 0; j < n; ++j) lp.set_variable_bounds(j, xlo[j], xhi[j]);
  lp.add_rows(A, lo, hi);
  lp.set_objective(c, sense);
  sets::LpSolution s;
  try {
    s = lp.solve();
  } catch (const sets::NumericalError&) {
    RC_DISCARD("GLPK reported a numerical failure (an error, not a wrong number)");
  }
  const ExactLp exact = exact_optimum(A, lo, hi, xlo, xhi, c, sense);
  RC_PRE(exact.feasible);
  RC_PRE(s.status == LpStatus::optimal);
  const double bound = lp.safe_bound(s);
  RC_TAG(std::isfinite(bound) ? "finite bound" : "no bound certified");
  // How often the plain floating-point optimum lies on the wrong side of the exact one: the
  // reason safe bounds exist.
  const bool float_wrong = sense == Sense::minimize ? !leq(s.objective, exact.value) : !geq(s.objective, exact.value);
  RC_CLASSIFY(float_wrong, "floating-point optimum on the wrong side");
  if (sense == Sense::minimize)
    RC_ASSERT(leq(bound, exact.value));
  else
    RC_ASSERT(geq(bound, exact.value));
}

TEST(Milp, SolvesKnapsackWithGapAndBound) {
  // max 5a + 4b + 3c  s.t.  2a + 3b + c <= 5, 4a + b + 2c <= 11, 3a + 4b + 2c <= 8, binary
  LinearProgram lp(3);
  for (int j = 0; j < 3; ++j) {
    lp.set_variable_bounds(j, 0, 1);
    lp.set_integer(j);
  }
  lp.add_row(Eigen::Vector3d(2, 3, 1), -inf, 5);
  lp.add_row(Eigen::Vector3d(4, 1, 2), -inf, 11);
  lp.add_row(Eigen::Vector3d(3, 4, 2), -inf, 8);
  lp.set_objective(Eigen::Vector3d(5, 4, 3), Sense::maximize);
  const auto s = lp.solve_milp({.time_limit_s = 10});
  ASSERT_EQ(s.status, sets::MilpStatus::optimal);
  EXPECT_NEAR(s.objective, 9.0, 1e-9);  // a = b = 1
  EXPECT_NEAR(s.gap, 0.0, 1e-9);
}

TEST(Milp, NodeLimitStopsDeterministically) {
  // A seeded 0-1 knapsack with two constraints that GLPK cannot close at the root. With a node
  // limit the run stops with the same incumbent every time, whatever the machine's speed.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> w(20, 60);
  const int n = 40;
  LinearProgram lp(n);
  Eigen::VectorXd c(n), a1(n), a2(n);
  for (int j = 0; j < n; ++j) {
    lp.set_variable_bounds(j, 0, 1);
    lp.set_integer(j);
    a1[j] = w(rng);
    a2[j] = w(rng);
    c[j] = a1[j] + a2[j] + w(rng) % 7;
  }
  lp.add_row(a1, -inf, 0.5 * a1.sum() + 0.5);
  lp.add_row(a2, -inf, 0.5 * a2.sum() + 0.5);
  lp.set_objective(c, Sense::maximize);
  const auto full = lp.solve_milp({.time_limit_s = 120});
  ASSERT_EQ(full.status, sets::MilpStatus::optimal);
  ASSERT_GT(full.nodes, 20) << "the instance closes too early to test a node limit";
  const long limit = full.nodes / 4;
  const auto cut1 = lp.solve_milp({.time_limit_s = 120, .node_limit = limit});
  const auto cut2 = lp.solve_milp({.time_limit_s = 120, .node_limit = limit});
  EXPECT_NE(cut1.status, sets::MilpStatus::optimal);
  EXPECT_LE(cut1.nodes, limit + 2);  // GLPK creates children in pairs
  EXPECT_EQ(cut1.status, cut2.status);
  EXPECT_EQ(cut1.objective, cut2.objective);
  EXPECT_EQ(cut1.nodes, cut2.nodes);
  if (cut1.status == sets::MilpStatus::feasible) {
    EXPECT_LE(cut1.objective, full.objective + 1e-9);  // an incumbent, never better than the optimum
    EXPECT_GE(cut1.best_bound, full.objective - 1e-6);  // and the tree's bound still holds
  }
  EXPECT_THROW(lp.solve_milp({.node_limit = -1}), sets::InputError);
}

// The LP on which GLPK's dual simplex cycled forever (safe-bound property above, RC_PARAMS
// "seed=12636605580891481652", case 99: near-parallel rows 1-2 scaled by 1e5, rows 6-7 by 1e-5).
// It hung CI until solve() capped the simplex iterations; now the cap trips (10 577 iterations)
// and the recovery solves it. Pinned with its exact doubles: the solve must return (optimal, or a
// NumericalError), and an optimal answer must still give a safe bound on the exact optimum.
TEST(LinearProgram, DegenerateLpThatOnceCycledReturns) {
  Eigen::MatrixXd A(7, 4);
  A << 0x1.14dc49e59bb62p+19, -0x1.e7c7224f2cddbp+19, -0x1.4c3b8be054742p+17, 0x1.17e17c0a8e83fp+19,
      0x1.14dc49fcd53edp+19, -0x1.e7c7227817d0ep+19, -0x1.4c3b8bfc33183p+17, 0x1.17e17c2208e8ep+19,
      -0x1.66ed869912797p-5, 0x1.3d8baa47930e1p-4, -0x1.2e580afa9db7ap-5, 0x1.862cf8b743ab2p-6,
      -0x1.a941fab8be054p+9, -0x1.0b02a3a0fd5c6p+9, -0x1.920fd5c5f02a4p+8, 0x1.d06ed8699127ap+9,
      0x1.6ae2f8151d07ep+6, -0x1.e1a6449e59bb6p+2, -0x1.354741fab8bep+6, -0x1.bd5c5f02a3a1p+4,
      0x1.70c0b977de00fp-18, -0x1.b27a5e9ba4126p-19, -0x1.9f1b3b68ad0ffp-18, 0x1.2da4daf5064acp-18,
      0x1.b53ed159c75bep-18, 0x1.09ab074d3b8f5p-18, 0x1.d67432436ecddp-20, 0x1.785cf502bf0bp-19;
  Eigen::VectorXd lo(7), hi(7), c(4);
  lo << -0x1.941fab8be0554p+11, -0x1.b834c8b8b894ap+13, 0x1.23df25c599af2p-11, -0x1.9eb6a1847c91ap+9,
      -0x1.c5ee79d30748cp+3, -0x1.f9ee80a00a39ep-22, -0x1.886339f8f496dp-18;
  hi << 0x1.bf6c34c893cc2p+12, 0x1.2612797f98aedp+14, inf, 0x1.878dfcd53ecfep+9, 0x1.773b391c9bd12p+3,
      0x1.afa7c09c42a4p-22, 0x1.a9accbb92e312p-19;
  c << -0x1.b6db6db6db6dbp-2, -0x1.4924924924925p+1, 0x1p+3, -0x1.a924924924925p+3;
  const Eigen::VectorXd xlo = Eigen::VectorXd::Constant(4, -10.0), xhi = Eigen::VectorXd::Constant(4, 10.0);
  // The same calls in the same order as the property (GLPK's path depends on them).
  LinearProgram lp(4);
  for (int j = 0; j < 4; ++j) lp.set_variable_bounds(j, xlo[j], xhi[j]);
  lp.add_rows(A, lo, hi);
  lp.set_objective(c, Sense::minimize);
  sets::LpSolution s;
  try {
    s = lp.solve();
  } catch (const sets::NumericalError&) {
    SUCCEED() << "reported as a numerical failure: acceptable, it returned";
    return;
  }
  ASSERT_EQ(s.status, LpStatus::optimal);
  const ExactLp exact = exact_optimum(A, lo, hi, xlo, xhi, c, Sense::minimize);
  ASSERT_TRUE(exact.feasible && exact.bounded);
  EXPECT_TRUE(leq(lp.safe_bound(s), exact.value));
}
