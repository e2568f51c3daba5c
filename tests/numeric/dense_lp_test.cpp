// The dense simplex against GLPK on the same LPs: same verdicts and optima, multipliers whose
// Neumaier–Shcherbina bound is as tight as GLPK's, warm starts over changing objectives, rows
// and bounds, and the degenerate cases (empty, unbounded, duplicate, zero and equality rows).

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "sets/core/error.hpp"
#include "sets/numeric/dense_lp.hpp"
#include "sets/numeric/linear_program.hpp"

namespace {

using sets::DenseLp;
using sets::inf;
using sets::LinearProgram;
using sets::LpSolution;
using sets::LpStatus;
using sets::Sense;

// The same LP in both solvers.
struct TwinLp {
  explicit TwinLp(int n) : dense(n), glpk(n) {}
  void add_row(const Eigen::VectorXd& a, double lo, double hi) {
    dense.add_row(a, lo, hi);
    glpk.add_row(a, lo, hi);
  }
  void set_bounds(int j, double lo, double hi) {
    dense.set_variable_bounds(j, lo, hi);
    glpk.set_variable_bounds(j, lo, hi);
  }
  void set_objective(const Eigen::VectorXd& c, Sense s) {
    dense.set_objective(c, s);
    glpk.set_objective(c, s);
  }
  DenseLp dense;
  LinearProgram glpk;
};

double tol(double v) { return 1e-7 * (1 + std::abs(v)); }

// Dense and GLPK agree on the current objective: when the dense solver answers optimal, GLPK's
// optimum is the same and the safe bound from the dense multipliers is valid; with every column
// boxed (`boxed`, as in the certification phase of PUIs) it is as tight as GLPK's own. (A free
// column certifies only if its reduced cost comes out exactly 0 in interval arithmetic, which
// depends on how the multipliers were rounded.)
void expect_agree(TwinLp& lp, bool boxed, bool& dense_answered) {
  const std::optional<LpSolution> d = lp.dense.solve();
  const LpSolution g = lp.glpk.solve();
  dense_answered = d.has_value();
  if (!d) return;
  RC_LOG() << "dense " << to_string(d->status) << " " << d->objective << ", glpk " << to_string(g.status) << " "
           << g.objective << ", objective " << lp.glpk.objective().transpose()
           << (lp.glpk.sense() == Sense::minimize ? " min\n" : " max\n");
  for (int i = 0; i < lp.glpk.num_rows(); ++i) {
    for (const auto& [j, a] : lp.glpk.row(i)) RC_LOG() << a << "*x" << j << " ";
    RC_LOG() << " in [" << lp.glpk.row_lower(i) << ", " << lp.glpk.row_upper(i) << "]\n";
  }
  for (int j = 0; j < lp.glpk.num_variables(); ++j)
    RC_LOG() << "x" << j << " in [" << lp.glpk.variable_lower(j) << ", " << lp.glpk.variable_upper(j) << "]\n";
  RC_ASSERT(d->status == g.status);
  if (g.status != LpStatus::optimal) return;
  RC_ASSERT(std::abs(d->objective - g.objective) <= tol(g.objective));
  RC_ASSERT(d->row_dual.size() == lp.glpk.num_rows());
  const double bd = lp.glpk.safe_bound(*d), bg = lp.glpk.safe_bound(g);
  if (boxed) {
    RC_ASSERT(std::isfinite(bd));
    RC_ASSERT(std::isfinite(bg));
    RC_ASSERT(std::abs(bd - bg) <= tol(g.objective));
  }
  // A valid bound: never beyond the optimum by more than rounding of the optimum itself.
  if (g.sense == Sense::minimize)
    RC_ASSERT(bd <= g.objective + tol(g.objective));
  else
    RC_ASSERT(bd >= g.objective - tol(g.objective));
}

rc::Gen<double> gen_coef() {
  return rc::gen::map(rc::gen::inRange(-1000, 1001), [](int k) { return k / 97.0; });
}

}  // namespace

// Random LPs around a known feasible point x0 (so never empty), with one-sided, two-sided,
// duplicate and zero rows and free, boxed and half-bounded columns; 2n coordinate
// objectives and a random one, each warm-started from the previous basis, then rows added
// and the bounds changed (as PUIs do): the dense simplex agrees with GLPK every time.
RC_GTEST_PROP(DenseLp, AgreesWithGlpkOnRandomLpsThroughWarmStarts, ()) {
  const int n = *rc::gen::inRange(1, 9), m = *rc::gen::inRange(0, 40);
  Eigen::VectorXd x0(n);
  for (int j = 0; j < n; ++j) x0[j] = *gen_coef();
  TwinLp lp(n);
  const auto add_random_row = [&] {
    Eigen::VectorXd a(n);
    for (int j = 0; j < n; ++j) a[j] = *rc::gen::inRange(0, 4) == 0 ? 0.0 : *gen_coef();
    const double v = a.dot(x0);
    // (Equalities are in DuplicateZeroAndEqualityRows: several of them through x0 in
    // floating point are empty or not by rounding alone.)
    const int kind = *rc::gen::inRange(0, 4);
    const double below = std::abs(*gen_coef()) + 1e-3, above = std::abs(*gen_coef()) + 1e-3;
    if (kind == 0) lp.add_row(a, -inf, v + above);
    else if (kind == 1) lp.add_row(a, v - below, inf);
    else lp.add_row(a, v - below, v + above);
  };
  for (int i = 0; i < m; ++i) {
    add_random_row();
    if (*rc::gen::inRange(0, 8) == 0 && i > 0) add_random_row();  // a second random row
  }
  for (int j = 0; j < n; ++j) {
    const int kind = *rc::gen::inRange(0, 4);
    const double w = 1 + std::abs(*gen_coef());
    if (kind == 0) lp.set_bounds(j, x0[j] - w, x0[j] + w);
    else if (kind == 1) lp.set_bounds(j, x0[j] - w, inf);
    else if (kind == 2) lp.set_bounds(j, -inf, x0[j] + w);
  }
  int answered = 0, asked = 0;
  const auto run_all = [&](bool boxed) {
    for (int l = 0; l < n; ++l)
      for (Sense s : {Sense::minimize, Sense::maximize}) {
        Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
        c[l] = 1;
        lp.set_objective(c, s);
        bool a = false;
        expect_agree(lp, boxed, a);
        answered += a;
        ++asked;
      }
    Eigen::VectorXd c(n);
    for (int j = 0; j < n; ++j) c[j] = *gen_coef();
    lp.set_objective(c, *rc::gen::element(Sense::minimize, Sense::maximize));
    bool a = false;
    expect_agree(lp, boxed, a);
    answered += a;
    ++asked;
  };
  run_all(false);
  for (int i = 0; i < 5; ++i) add_random_row();
  for (int j = 0; j < n; ++j) lp.set_bounds(j, x0[j] - 50, x0[j] + 50);
  run_all(true);
  // It may give up (and the caller use GLPK), but not as a habit.
  RC_ASSERT(answered * 4 >= asked * 3);
}

TEST(DenseLp, EmptySetIsNeverReportedOptimal) {
  // x + y >= 2 and x + y <= 1: empty.
  DenseLp lp(2);
  lp.add_row(Eigen::Vector2d(1, 1), 2, inf);
  lp.add_row(Eigen::Vector2d(1, 1), -inf, 1);
  lp.set_objective(Eigen::Vector2d(1, 0), Sense::minimize);
  const auto s = lp.solve();
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->status, LpStatus::infeasible);
}

TEST(DenseLp, BoundsAloneWithoutRows) {
  // No row yet (row generation starts from the box): the optimum is a corner of the bounds, the
  // reduced costs are the costs themselves (no row multipliers).
  DenseLp lp(2);
  lp.set_variable_bounds(0, -1, 2);
  lp.set_variable_bounds(1, 0, 3);
  lp.set_objective(Eigen::Vector2d(1, -2), Sense::minimize);
  const auto s = lp.solve();
  ASSERT_TRUE(s.has_value());
  ASSERT_EQ(s->status, LpStatus::optimal);
  EXPECT_EQ(s->x, Eigen::Vector2d(-1, 3));
  EXPECT_EQ(s->row_dual.size(), 0);
  ASSERT_EQ(s->reduced_cost.size(), 2);
  EXPECT_EQ(s->reduced_cost, Eigen::Vector2d(1, -2));
}

TEST(DenseLp, UnboundedDirectionIsReported) {
  // A strip |x - y| <= 1 is unbounded along (1, 1) and bounded in x - y.
  DenseLp lp(2);
  lp.add_row(Eigen::Vector2d(1, -1), -1, 1);
  lp.set_objective(Eigen::Vector2d(1, 0), Sense::maximize);
  auto s = lp.solve();
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->status, LpStatus::unbounded);
  lp.set_objective(Eigen::Vector2d(1, -1), Sense::maximize);
  s = lp.solve();
  ASSERT_TRUE(s.has_value());
  ASSERT_EQ(s->status, LpStatus::optimal);
  EXPECT_NEAR(s->objective, 1.0, 1e-12);
  EXPECT_NEAR(s->row_dual[0], 1.0, 1e-12);  // c = A^T y
}

TEST(DenseLp, DuplicateZeroAndEqualityRows) {
  DenseLp lp(2);
  LinearProgram ref(2);
  const auto both = [&](Eigen::Vector2d a, double lo, double hi) {
    lp.add_row(a, lo, hi);
    ref.add_row(a, lo, hi);
  };
  both({1, 1}, 0, 2);
  both({1, 1}, 0, 2);     // duplicate
  both({0, 0}, -1, 1);    // zero row, satisfied
  both({1, -1}, 0.5, 0.5);  // equality
  both({1, -1}, 0.5, 0.5);  // duplicate equality
  for (int l = 0; l < 2; ++l)
    for (Sense s : {Sense::minimize, Sense::maximize}) {
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      c[l] = 1;
      lp.set_objective(c, s);
      ref.set_objective(c, s);
      const auto d = lp.solve();
      const LpSolution g = ref.solve();
      ASSERT_TRUE(d.has_value());
      ASSERT_EQ(d->status, LpStatus::optimal);
      EXPECT_NEAR(d->objective, g.objective, 1e-12);
      // x in [0.25, 1.25], y = x - 0.5 in [-0.25, 0.75]: the safe bound is the optimum up to rounding.
      EXPECT_NEAR(ref.safe_bound(*d), g.objective, 1e-12);
    }
  // A zero row that no point satisfies makes the set empty.
  lp.add_row(Eigen::Vector2d(0, 0), 1, 2);
  const auto e = lp.solve();
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->status, LpStatus::infeasible);
}

TEST(DenseLp, BadInputIsAnError) {
  EXPECT_THROW(DenseLp(0), sets::InputError);
  DenseLp lp(2);
  EXPECT_THROW(lp.add_row(Eigen::Vector3d(1, 2, 3), 0, 1), sets::InputError);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, NAN), 0, 1), sets::InputError);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, 1), 2, 1), sets::InputError);
  EXPECT_THROW(lp.set_variable_bounds(2, 0, 1), sets::InputError);
  EXPECT_THROW(lp.set_objective(Eigen::Vector3d(1, 2, 3), Sense::minimize), sets::InputError);
}
