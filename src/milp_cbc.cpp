#include "milp_cbc.hpp"

#include <coin/Cbc_C_Interface.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "sets/error.hpp"

namespace sets::detail {

namespace {

// CBC marks infinite bounds with COIN_DBL_MAX.
double coin(double v) {
  constexpr double big = std::numeric_limits<double>::max();
  return std::isinf(v) ? (v > 0 ? big : -big) : v;
}

struct ModelDeleter {
  void operator()(Cbc_Model* m) const { Cbc_deleteModel(m); }
};

}  // namespace

MilpSolution solve_milp_cbc(const MilpModel& model, const MilpOptions& options,
                            const std::optional<Eigen::VectorXd>& start) {
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(model.col_lo.size());
  const int m = static_cast<int>(model.rows.entries.size());

  // Rows are stored sparse by row; CBC loads compressed columns.
  std::vector<int> count(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& row : model.rows.entries)
    for (const auto& e : row) ++count[static_cast<std::size_t>(e.first) + 1];
  std::vector<CoinBigIndex> col_start(static_cast<std::size_t>(n) + 1, 0);
  for (int j = 0; j < n; ++j) col_start[j + 1] = col_start[j] + count[j + 1];
  std::vector<int> index(static_cast<std::size_t>(col_start[n]));
  std::vector<double> value(index.size());
  std::vector<CoinBigIndex> next(col_start.begin(), col_start.end() - 1);
  for (int i = 0; i < m; ++i)
    for (const auto& [j, a] : model.rows.entries[i]) {
      index[next[j]] = i;
      value[next[j]++] = a;
    }
  std::vector<double> col_lo(n), col_hi(n), row_lo(m), row_hi(m);
  for (int j = 0; j < n; ++j) {
    col_lo[j] = coin(model.col_lo[j]);
    col_hi[j] = coin(model.col_hi[j]);
  }
  for (int i = 0; i < m; ++i) {
    row_lo[i] = coin(model.rows.lo[i]);
    row_hi[i] = coin(model.rows.hi[i]);
  }

  std::unique_ptr<Cbc_Model, ModelDeleter> cbc(Cbc_newModel());
  Cbc_loadProblem(cbc.get(), n, m, col_start.data(), index.data(), value.data(), col_lo.data(), col_hi.data(),
                  model.c.data(), row_lo.data(), row_hi.data());
  Cbc_setObjSense(cbc.get(), model.sense == Sense::minimize ? 1 : -1);
  for (int j = 0; j < n; ++j)
    if (model.integer[j]) Cbc_setInteger(cbc.get(), j);
  if (start) {
    // CBC fixes the integer columns at these values and recomputes the continuous ones by LP.
    std::vector<int> idx;
    std::vector<double> val;
    for (int j = 0; j < n; ++j)
      if (model.integer[j]) {
        idx.push_back(j);
        val.push_back(std::round((*start)[j]));
      }
    Cbc_setMIPStartI(cbc.get(), static_cast<int>(idx.size()), idx.data(), val.data());
  }
  Cbc_setLogLevel(cbc.get(), options.verbose ? 1 : 0);
  Cbc_setParameter(cbc.get(), "timeMode", "elapsed");  // the limit is wall clock, as with GLPK
  Cbc_setParameter(cbc.get(), "threads", "0");
  Cbc_setMaximumSeconds(cbc.get(), std::max(0.01, options.time_limit_s));
  Cbc_setAllowableFractionGap(cbc.get(), options.relative_gap);
  Cbc_solve(cbc.get());

  MilpSolution out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (Cbc_isAbandoned(cbc.get()))
    throw NumericalError("MILP solver failed (CBC abandoned the search: numerical difficulties)");
  if (Cbc_isContinuousUnbounded(cbc.get()))
    throw NumericalError("MILP relaxation has no optimal solution (unbounded)");
  const double* x = Cbc_bestSolution(cbc.get());
  if (Cbc_isProvenInfeasible(cbc.get()) && x == nullptr) {
    out.status = MilpStatus::infeasible;
    return out;
  }
  out.best_bound = Cbc_getBestPossibleObjValue(cbc.get());
  if (x == nullptr) {
    out.status = MilpStatus::no_solution;
    return out;
  }
  out.status = Cbc_isProvenOptimal(cbc.get()) ? MilpStatus::optimal : MilpStatus::feasible;
  out.objective = Cbc_getObjValue(cbc.get());
  out.x = Eigen::Map<const Eigen::VectorXd>(x, n);
  // CBC stops at the allowable gap and calls that optimal; report its bound as is, like GLPK.
  if (out.status == MilpStatus::optimal && std::abs(out.best_bound) >= 1e50) out.best_bound = out.objective;
  out.gap = std::abs(out.objective - out.best_bound) / std::max(1.0, std::abs(out.objective));
  return out;
}

}  // namespace sets::detail
