// The jump search (src/methods/tv_bound/jump_search.cpp), best-first branch and bound over jump
// patterns that solves (14): the same optimum as GLPK's MILP on small problems, a certified lower
// bound below it, grid restrictions kept, incumbents improved by dropping jumps.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "sets/methods/tv_bound/tv_bound.hpp"
#include "support/tv_fixtures.hpp"

using sets::testing::milp_options;
using sets::testing::small_data;

TEST(TvBound, JumpSearchAndGlpkMilpFindTheSameOptimum) {
  // Two solvers of (14), both run to a proven optimum on small problems with two steps: their
  // objectives agree, the jump search's certified lower bound lies below GLPK's optimum, and its
  // trajectory keeps the noise bound and the box.
  std::mt19937 rng(23);
  const int N = 14;
  for (int run = 0; run < 4; ++run) {
    Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
    const int a = std::uniform_int_distribution<int>(2, N - 3)(rng), b = std::uniform_int_distribution<int>(2, N - 3)(rng);
    pi.block(a, 1, N - a, 1).setConstant(0.6);
    pi.block(b, 2, N - b, 1).setConstant(-0.4);
    const auto data = small_data(pi, 0.01, 300 + run, 4);
    const auto lin = sets::linf_bound(data);
    auto o = milp_options(lin.epsilon, 50000);
    o.start = lin.pi;
    const auto jump = sets::sparse_bound(data, o);
    o.solver = sets::SparseSolver::glpk_big_m;
    const auto glpk = sets::sparse_bound(data, o);
    ASSERT_TRUE(jump.status == sets::MilpStatus::optimal) << "run " << run;
    ASSERT_TRUE(glpk.status == sets::MilpStatus::optimal) << "run " << run;
    const double tol = 2e-4 * (1 + std::abs(glpk.objective));
    EXPECT_NEAR(jump.objective, glpk.objective, tol) << "run " << run;
    EXPECT_LE(jump.best_bound, glpk.objective + tol) << "run " << run;
    EXPECT_LE(data.ball().norms(sets::stack_samples(jump.residual))[0], o.epsilon[0] * (1 + 1e-6) + 1e-9);
    EXPECT_LE(jump.pi.cwiseAbs().maxCoeff(), 1.0 + 1e-9);
  }
}

TEST(TvBound, OffGridWarmStartIsNeverTheIncumbent) {
  // Regression: with grid > 1 the jump search accepted a warm start with a jump off the grid as
  // its incumbent, so it returned a point outside the quantized problem (and pruned with its
  // value). The fine optimum below jumps at sample 7 (off the grid of 3) and is cheaper than any
  // on-grid trajectory; given as the start, it must be rejected and the coarse optimum found.
  const int N = 18;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(7, 1, N - 7, 1).setConstant(0.5);
  const auto data = small_data(pi, 0.01, 41, 4);
  const auto lin = sets::linf_bound(data);
  auto o = milp_options(lin.epsilon, 50000);
  const auto fine = sets::sparse_bound(data, o);
  bool off_grid = false;
  for (const auto& c : fine.changes) off_grid = off_grid || c.sample % 3 != 0;
  ASSERT_TRUE(off_grid) << "the fixture must have an off-grid optimum for this test to mean anything";
  o.grid = 3;
  o.epsilon *= 1 + 1e-4;  // the start then keeps the noise bound with room to spare
  const auto cold = sets::sparse_bound(data, o);
  ASSERT_TRUE(cold.status == sets::MilpStatus::optimal);
  ASSERT_GT(cold.objective, fine.objective + 1e-3) << "the grid must cost something here";
  for (auto solver : {sets::SparseSolver::jump_search, sets::SparseSolver::glpk_big_m}) {
    o.solver = solver;
    o.start = fine.pi;
    const auto warm = sets::sparse_bound(data, o);
    ASSERT_TRUE(warm.status == sets::MilpStatus::optimal);
    for (const auto& c : warm.changes) EXPECT_EQ(c.sample % 3, 0) << "jump at " << c.sample;
    EXPECT_NEAR(warm.objective, cold.objective, 2e-4 * (1 + cold.objective));
    EXPECT_LE(warm.best_bound, cold.objective + 2e-4 * (1 + cold.objective));
  }
}

TEST(TvBound, JumpSearchDropsARemovableJumpOfTheStart) {
  // The local search on an incumbent: a warm start that is the optimum plus a short pulse in pi1
  // (two needless jumps) is improved by dropping jumps, one warm-started LP per try. With an LP
  // budget of 3 (drop the pulse's first jump, its second, then fail to drop the step) the tree
  // itself is never searched, so only the local search can remove the pulse.
  const int N = 18;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(7, 1, N - 7, 1).setConstant(0.5);
  const auto data = small_data(pi, 0.01, 41, 4);
  auto o = milp_options(sets::linf_bound(data).epsilon, 50000);
  const auto opt = sets::sparse_bound(data, o);
  ASSERT_TRUE(opt.status == sets::MilpStatus::optimal);
  Eigen::MatrixXd start = opt.pi;
  start.block(3, 0, 2, 1).array() += 5e-3;  // jumps up at 3, down at 5
  o.epsilon *= 1.2;                          // room for the pulse
  ASSERT_TRUE(data.ball().contains(sets::stack_samples(data.y) - data.regression.upsilon -
                                       data.regression.xi * sets::stack_samples(start),
                                   o.epsilon))
      << "the pulse must keep the noise bound for the start to be offered";
  o.start = start;
  o.milp.node_limit = 3;
  const auto r = sets::sparse_bound(data, o);
  EXPECT_LE(r.changes.size(), opt.changes.size());
  for (const auto& c : r.changes) EXPECT_NE(c.parameter, 0) << "the pulse's jump at " << c.sample << " stayed";
  EXPECT_LE(r.objective, opt.objective + 5e-3 + 1e-6);  // opt (feasible here) plus at most the pulse's peak
}

TEST(TvBound, CoarseGridStartKeepsTheOptimumAndTheBound) {
  // The coarse-grid start and the reweighted-l1 incumbents only supply upper bounds: with and
  // without the coarse start the search proves the same optimum, and each certified lower bound
  // lies below the other run's objective. N = 64 so that the 8x coarser grid has 8 positions.
  const int N = 64;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(21, 1, N - 21, 1).setConstant(0.6);
  pi.block(43, 2, N - 43, 1).setConstant(-0.4);
  const auto data = small_data(pi, 0.01, 77, 8);
  const auto lin = sets::linf_bound(data);
  auto o = milp_options(lin.epsilon, 200000);
  o.start = lin.pi;
  const auto with = sets::sparse_bound(data, o);
  o.coarse_start = false;
  const auto without = sets::sparse_bound(data, o);
  ASSERT_TRUE(with.status == sets::MilpStatus::optimal);
  ASSERT_TRUE(without.status == sets::MilpStatus::optimal);
  const double tol = 2e-4 * (1 + std::abs(without.objective));
  EXPECT_NEAR(with.objective, without.objective, tol);
  EXPECT_LE(with.best_bound, without.objective + tol);
  EXPECT_LE(without.best_bound, with.objective + tol);
  EXPECT_LE(data.ball().norms(sets::stack_samples(with.residual))[0], o.epsilon[0] * (1 + 1e-6) + 1e-9);
  RecordProperty("lps", std::to_string(with.nodes) + " with, " + std::to_string(without.nodes) + " without");
  std::printf("LPs: %ld with the coarse start, %ld without; objective %.4f, %zu jumps\n", with.nodes, without.nodes,
              with.objective, with.changes.size());
}
