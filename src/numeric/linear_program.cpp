#include "sets/numeric/linear_program.hpp"

#include <glpk.h>

#include <chrono>
#include <cmath>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/safe_bound.hpp"

namespace sets {

namespace {

int glpk_bound_type(double lo, double hi) {
  if (std::isinf(lo) && std::isinf(hi)) return GLP_FR;
  if (std::isinf(hi)) return GLP_LO;
  if (std::isinf(lo)) return GLP_UP;
  if (lo == hi) return GLP_FX;
  return GLP_DB;
}

void check_bounds(double lo, double hi, const std::string& what) {
  if (std::isnan(lo) || std::isnan(hi) || lo > hi || lo == inf || hi == -inf)
    throw InputError(what + ": invalid bounds [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "]");
}

}  // namespace

struct LinearProgram::Impl {
  glp_prob* lp = nullptr;
  LpRows rows;
  Eigen::VectorXd col_lo, col_hi, c;
  Sense sense = Sense::minimize;
  bool has_integer = false;
  std::optional<Eigen::VectorXd> heuristic_start;
  // Best bound seen by the MILP callback.
  double tree_bound = 0;
  bool tree_bound_valid = false;

  Impl() {
    glp_term_out(GLP_OFF);
    lp = glp_create_prob();
  }
  ~Impl() {
    if (lp) glp_delete_prob(lp);
  }
  int n() const { return static_cast<int>(col_lo.size()); }
  int m() const { return static_cast<int>(rows.entries.size()); }

  void push_row(std::vector<std::pair<int, double>> entries, double lo, double hi) {
    check_bounds(lo, hi, "LinearProgram row " + std::to_string(m()));
    std::vector<int> ind(1);
    std::vector<double> val(1);
    for (const auto& [j, a] : entries) {
      if (j < 0 || j >= n())
        throw InputError("LinearProgram row " + std::to_string(m()) + ": column " +
                         std::to_string(j) + " out of range");
      if (!std::isfinite(a))
        throw InputError("LinearProgram row " + std::to_string(m()) + ": coefficient of column " +
                         std::to_string(j) + " is not finite");
      ind.push_back(j + 1);
      val.push_back(a);
    }
    const int i = glp_add_rows(lp, 1);
    glp_set_mat_row(lp, i, static_cast<int>(ind.size()) - 1, ind.data(), val.data());
    glp_set_row_bnds(lp, i, glpk_bound_type(lo, hi), std::isinf(lo) ? 0.0 : lo,
                     std::isinf(hi) ? 0.0 : hi);
    rows.entries.push_back(std::move(entries));
    rows.lo.push_back(lo);
    rows.hi.push_back(hi);
  }
};

LinearProgram::LinearProgram(int num_variables) : impl_(std::make_unique<Impl>()) {
  if (num_variables < 0) throw InputError("LinearProgram: negative number of variables");
  if (num_variables > 0) add_variables(num_variables);
}
LinearProgram::~LinearProgram() = default;
LinearProgram::LinearProgram(LinearProgram&&) noexcept = default;
LinearProgram& LinearProgram::operator=(LinearProgram&&) noexcept = default;

int LinearProgram::num_variables() const { return impl_->n(); }
int LinearProgram::num_rows() const { return impl_->m(); }

int LinearProgram::add_variables(int count, double lo, double hi) {
  if (count <= 0) throw InputError("LinearProgram::add_variables: count must be positive");
  check_bounds(lo, hi, "LinearProgram::add_variables");
  const int first = impl_->n();
  glp_add_cols(impl_->lp, count);
  impl_->col_lo.conservativeResize(first + count);
  impl_->col_hi.conservativeResize(first + count);
  impl_->c.conservativeResize(first + count);
  for (int j = first; j < first + count; ++j) {
    impl_->c[j] = 0;
    impl_->col_lo[j] = lo;
    impl_->col_hi[j] = hi;
    glp_set_col_bnds(impl_->lp, j + 1, glpk_bound_type(lo, hi), std::isinf(lo) ? 0.0 : lo,
                     std::isinf(hi) ? 0.0 : hi);
  }
  return first;
}

void LinearProgram::set_variable_bounds(int j, double lo, double hi) {
  if (j < 0 || j >= impl_->n()) throw InputError("LinearProgram: variable index out of range");
  check_bounds(lo, hi, "LinearProgram variable " + std::to_string(j));
  impl_->col_lo[j] = lo;
  impl_->col_hi[j] = hi;
  glp_set_col_bnds(impl_->lp, j + 1, glpk_bound_type(lo, hi), std::isinf(lo) ? 0.0 : lo,
                   std::isinf(hi) ? 0.0 : hi);
}
double LinearProgram::variable_lower(int j) const { return impl_->col_lo[j]; }
double LinearProgram::variable_upper(int j) const { return impl_->col_hi[j]; }

void LinearProgram::set_integer(int j, bool integer) {
  if (j < 0 || j >= impl_->n()) throw InputError("LinearProgram: variable index out of range");
  glp_set_col_kind(impl_->lp, j + 1, integer ? GLP_IV : GLP_CV);
  if (integer) impl_->has_integer = true;
}

int LinearProgram::add_row(const Eigen::Ref<const Eigen::VectorXd>& a, double lo, double hi) {
  if (a.size() != impl_->n())
    throw InputError("LinearProgram::add_row: " + std::to_string(a.size()) +
                     " coefficients for " + std::to_string(impl_->n()) + " variables");
  std::vector<std::pair<int, double>> entries;
  for (Eigen::Index j = 0; j < a.size(); ++j)
    if (a[j] != 0 || std::isnan(a[j])) entries.emplace_back(static_cast<int>(j), a[j]);
  impl_->push_row(std::move(entries), lo, hi);
  return impl_->m() - 1;
}

int LinearProgram::add_row(const std::vector<std::pair<int, double>>& entries, double lo, double hi) {
  impl_->push_row(entries, lo, hi);
  return impl_->m() - 1;
}

int LinearProgram::add_rows(const Eigen::Ref<const Eigen::MatrixXd>& A,
                            const Eigen::Ref<const Eigen::VectorXd>& lo,
                            const Eigen::Ref<const Eigen::VectorXd>& hi) {
  if (A.rows() != lo.size() || A.rows() != hi.size())
    throw InputError("LinearProgram::add_rows: row bounds do not match the matrix");
  const int first = impl_->m();
  for (Eigen::Index i = 0; i < A.rows(); ++i) add_row(A.row(i).transpose(), lo[i], hi[i]);
  return first;
}

int LinearProgram::add_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A,
                            const Eigen::Ref<const Eigen::VectorXd>& lo,
                            const Eigen::Ref<const Eigen::VectorXd>& hi) {
  if (A.rows() != lo.size() || A.rows() != hi.size() || A.cols() != impl_->n())
    throw InputError("LinearProgram::add_rows: dimensions do not match");
  const int first = impl_->m();
  for (Eigen::Index i = 0; i < A.outerSize(); ++i) {
    std::vector<std::pair<int, double>> entries;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(A, i); it; ++it)
      entries.emplace_back(static_cast<int>(it.col()), it.value());
    impl_->push_row(std::move(entries), lo[i], hi[i]);
  }
  return first;
}

void LinearProgram::set_row_bounds(int i, double lo, double hi) {
  if (i < 0 || i >= impl_->m()) throw InputError("LinearProgram: row index out of range");
  check_bounds(lo, hi, "LinearProgram row " + std::to_string(i));
  impl_->rows.lo[static_cast<std::size_t>(i)] = lo;
  impl_->rows.hi[static_cast<std::size_t>(i)] = hi;
  glp_set_row_bnds(impl_->lp, i + 1, glpk_bound_type(lo, hi), std::isinf(lo) ? 0.0 : lo,
                   std::isinf(hi) ? 0.0 : hi);
}
double LinearProgram::row_lower(int i) const { return impl_->rows.lo.at(static_cast<std::size_t>(i)); }
double LinearProgram::row_upper(int i) const { return impl_->rows.hi.at(static_cast<std::size_t>(i)); }
const std::vector<std::pair<int, double>>& LinearProgram::row(int i) const {
  return impl_->rows.entries.at(static_cast<std::size_t>(i));
}

void LinearProgram::set_objective(const Eigen::Ref<const Eigen::VectorXd>& c, Sense sense) {
  if (c.size() != impl_->n()) throw InputError("LinearProgram::set_objective: wrong dimension");
  for (Eigen::Index j = 0; j < c.size(); ++j) {
    if (!std::isfinite(c[j])) throw InputError("LinearProgram::set_objective: non-finite cost");
    glp_set_obj_coef(impl_->lp, static_cast<int>(j) + 1, c[j]);
  }
  impl_->c = c;
  impl_->sense = sense;
  glp_set_obj_dir(impl_->lp, sense == Sense::minimize ? GLP_MIN : GLP_MAX);
}

void LinearProgram::set_objective_coordinate(int j, Sense sense) {
  if (j < 0 || j >= impl_->n()) throw InputError("LinearProgram: variable index out of range");
  Eigen::VectorXd c = Eigen::VectorXd::Zero(impl_->n());
  c[j] = 1;
  set_objective(c, sense);
}
const Eigen::VectorXd& LinearProgram::objective() const { return impl_->c; }
Sense LinearProgram::sense() const { return impl_->sense; }

void LinearProgram::reset_basis() { glp_std_basis(impl_->lp); }

LpBasis LinearProgram::basis() const {
  LpBasis b;
  b.rows.resize(static_cast<std::size_t>(impl_->m()));
  b.cols.resize(static_cast<std::size_t>(impl_->n()));
  for (int i = 0; i < impl_->m(); ++i) b.rows[static_cast<std::size_t>(i)] = static_cast<unsigned char>(glp_get_row_stat(impl_->lp, i + 1));
  for (int j = 0; j < impl_->n(); ++j) b.cols[static_cast<std::size_t>(j)] = static_cast<unsigned char>(glp_get_col_stat(impl_->lp, j + 1));
  return b;
}

void LinearProgram::set_basis(const LpBasis& b) {
  if (b.rows.size() != static_cast<std::size_t>(impl_->m()) || b.cols.size() != static_cast<std::size_t>(impl_->n()))
    throw InputError("LinearProgram::set_basis: the basis is for another problem size");
  // GLPK's setters replace a non-basic status the current bounds do not allow by the one they do.
  for (int i = 0; i < impl_->m(); ++i) glp_set_row_stat(impl_->lp, i + 1, b.rows[static_cast<std::size_t>(i)]);
  for (int j = 0; j < impl_->n(); ++j) glp_set_col_stat(impl_->lp, j + 1, b.cols[static_cast<std::size_t>(j)]);
}

LpSolution LinearProgram::solve() { return solve(LpSolveOptions{}); }

LpSolution LinearProgram::solve(const LpSolveOptions& options) {
  glp_prob* lp = impl_->lp;
  if (impl_->n() == 0) throw InputError("LinearProgram::solve: no variables");
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.meth = GLP_DUALP;  // dual simplex suits re-solves after objective or bound changes
  if (options.long_step) parm.r_test = GLP_RT_FLIP;
  if (options.cutoff) {
    if (std::isnan(*options.cutoff)) throw InputError("LinearProgram::solve: the cutoff is NaN");
    if (impl_->sense == Sense::minimize) parm.obj_ul = *options.cutoff;
    else parm.obj_ll = *options.cutoff;
  }
  // GLPK can cycle on degenerate, badly scaled problems (seen in the safe-bound property test):
  // a healthy solve needs a few times (rows + columns) iterations, so cap it far above that.
  parm.it_lim = 10000 + 50 * (impl_->m() + impl_->n());
  int rc = glp_simplex(lp, &parm);
  if (rc == GLP_EBADB || rc == GLP_ESING || rc == GLP_ECOND || rc == GLP_EFAIL || rc == GLP_EITLIM) {
    // Recover once from a bad or ill-conditioned basis or from cycling: scale, rebuild the
    // basis, primal simplex.
    glp_scale_prob(lp, GLP_SF_AUTO);
    glp_adv_basis(lp, 0);
    parm.meth = GLP_PRIMAL;
    rc = glp_simplex(lp, &parm);
  }
  if (rc == 0 && glp_get_status(lp) != GLP_OPT && glp_get_status(lp) != GLP_NOFEAS &&
      glp_get_status(lp) != GLP_UNBND) {
    // The dual simplex stops without a verdict when the problem is unbounded (it cannot prove
    // that); the primal simplex from the current basis can.
    parm.meth = GLP_PRIMAL;
    rc = glp_simplex(lp, &parm);
  }
  const bool cut = options.cutoff && (rc == GLP_EOBJUL || rc == GLP_EOBJLL);
  if (rc != 0 && !cut)
    throw NumericalError("LP solver failed (GLPK glp_simplex code " + std::to_string(rc) +
                         ") on a problem with " + std::to_string(impl_->m()) + " rows and " +
                         std::to_string(impl_->n()) + " columns");
  LpSolution s;
  s.sense = impl_->sense;
  const int status = glp_get_status(lp);
  const int prim = glp_get_prim_stat(lp);
  const int dual = glp_get_dual_stat(lp);
  if (cut) {
    s.status = LpStatus::cutoff;
  } else if (status == GLP_OPT) {
    s.status = LpStatus::optimal;
  } else if (status == GLP_NOFEAS || prim == GLP_NOFEAS) {
    s.status = LpStatus::infeasible;
  } else if (status == GLP_UNBND || (prim == GLP_FEAS && dual == GLP_NOFEAS)) {
    s.status = LpStatus::unbounded;
  } else {
    throw NumericalError("LP solver ended without a verdict (GLPK status " +
                         std::to_string(status) + ")");
  }
  s.objective = glp_get_obj_val(lp);
  s.iterations = glp_get_it_cnt(lp);
  s.x.resize(impl_->n());
  s.reduced_cost.resize(impl_->n());
  for (int j = 0; j < impl_->n(); ++j) {
    s.x[j] = glp_get_col_prim(lp, j + 1);
    s.reduced_cost[j] = glp_get_col_dual(lp, j + 1);
  }
  s.row_dual.resize(impl_->m());
  for (int i = 0; i < impl_->m(); ++i) s.row_dual[i] = glp_get_row_dual(lp, i + 1);
  if (s.status == LpStatus::optimal && !std::isfinite(s.objective))
    throw NumericalError("LP solver returned a non-finite optimum");
  return s;
}

LpSolution LinearProgram::solve_exact() {
  glp_prob* lp = impl_->lp;
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.it_lim = 10000 + 50 * (impl_->m() + impl_->n());  // as in solve(): never cycle forever
  const int rc = glp_exact(lp, &parm);
  if (rc != 0)
    throw NumericalError("exact LP solver failed (GLPK glp_exact code " + std::to_string(rc) + ")");
  LpSolution s;
  s.sense = impl_->sense;
  switch (glp_get_status(lp)) {
    case GLP_OPT: s.status = LpStatus::optimal; break;
    case GLP_NOFEAS: s.status = LpStatus::infeasible; break;
    case GLP_UNBND: s.status = LpStatus::unbounded; break;
    default: throw NumericalError("exact LP solver ended without a verdict");
  }
  s.objective = glp_get_obj_val(lp);
  s.x.resize(impl_->n());
  s.reduced_cost.resize(impl_->n());
  for (int j = 0; j < impl_->n(); ++j) {
    s.x[j] = glp_get_col_prim(lp, j + 1);
    s.reduced_cost[j] = glp_get_col_dual(lp, j + 1);
  }
  s.row_dual.resize(impl_->m());
  for (int i = 0; i < impl_->m(); ++i) s.row_dual[i] = glp_get_row_dual(lp, i + 1);
  return s;
}

double LinearProgram::safe_bound(const LpSolution& solution) const {
  if (solution.status != LpStatus::optimal && solution.status != LpStatus::cutoff)
    return impl_->sense == Sense::minimize ? -inf : inf;
  if (solution.row_dual.size() != impl_->m())
    throw InputError("LinearProgram::safe_bound: solution does not belong to this problem");
  return impl_->sense == Sense::minimize
             ? safe_lower_bound(impl_->c, impl_->rows, impl_->col_lo, impl_->col_hi, solution.row_dual)
             : safe_upper_bound(impl_->c, impl_->rows, impl_->col_lo, impl_->col_hi, solution.row_dual);
}

namespace {

struct Milp_callback_data {
  std::optional<Eigen::VectorXd> start;  // heuristic solution offered at the root
  double best_bound = 0;                 // bound of the best open node, tracked as the tree moves
  long node_limit = 0;                   // 0 = none
  long nodes = 0;                        // largest node count seen
};

void milp_callback(glp_tree* tree, void* info) {
  auto* data = static_cast<Milp_callback_data*>(info);
  int active = 0, current = 0, total = 0;
  glp_ios_tree_size(tree, &active, &current, &total);
  data->nodes = std::max(data->nodes, static_cast<long>(total));
  if (data->node_limit > 0) {
    if (total > data->node_limit) {
      glp_ios_terminate(tree);
      return;
    }
  }
  switch (glp_ios_reason(tree)) {
    case GLP_IHEUR:
      if (data->start.has_value() && glp_ios_curr_node(tree) == 1) {
        const Eigen::VectorXd& x0 = *data->start;
        std::vector<double> x(static_cast<std::size_t>(x0.size()) + 1, 0.0);
        for (Eigen::Index j = 0; j < x0.size(); ++j) x[static_cast<std::size_t>(j) + 1] = x0[j];
        glp_ios_heur_sol(tree, x.data());
      }
      break;
    case GLP_ISELECT:
    case GLP_IBINGO:
    case GLP_IPREPRO: {
      const int best = glp_ios_best_node(tree);
      if (best != 0) data->best_bound = glp_ios_node_bound(tree, best);
      break;
    }
    default:
      break;
  }
}

}  // namespace

MilpSolution LinearProgram::solve_milp(const MilpOptions& options,
                                       const std::optional<Eigen::VectorXd>& start) {
  glp_prob* lp = impl_->lp;
  if (start && start->size() != impl_->n())
    throw InputError("LinearProgram::solve_milp: start point has the wrong dimension");
  const auto t0 = std::chrono::steady_clock::now();
  // The relaxation first (GLPK's branch-and-cut needs an optimal LP basis).
  glp_smcp sm;
  glp_init_smcp(&sm);
  sm.msg_lev = GLP_MSG_OFF;
  sm.tm_lim = static_cast<int>(std::min(options.time_limit_s, 2e6) * 1000);
  int rc = glp_simplex(lp, &sm);
  MilpSolution out;
  if (rc != 0 && rc != GLP_ETMLIM)
    throw NumericalError("MILP relaxation failed (GLPK glp_simplex code " + std::to_string(rc) + ")");
  if (glp_get_status(lp) == GLP_NOFEAS) {
    out.status = MilpStatus::infeasible;
    return out;
  }
  if (glp_get_status(lp) != GLP_OPT)
    throw NumericalError("MILP relaxation has no optimal solution (unbounded or not solved)");
  if (options.node_limit < 0) throw InputError("LinearProgram::solve_milp: node_limit must be >= 0");
  Milp_callback_data info{start, glp_get_obj_val(lp), options.node_limit};
  glp_iocp parm;
  glp_init_iocp(&parm);
  parm.msg_lev = options.verbose ? GLP_MSG_ON : GLP_MSG_OFF;
  parm.cb_func = milp_callback;
  parm.cb_info = &info;
  parm.mip_gap = options.relative_gap;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  parm.tm_lim = static_cast<int>(std::max(1.0, (options.time_limit_s - elapsed) * 1000));
  parm.gmi_cuts = GLP_ON;
  parm.mir_cuts = GLP_ON;
  parm.fp_heur = GLP_ON;
  rc = glp_intopt(lp, &parm);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.nodes = info.nodes;
  const int status = glp_mip_status(lp);
  if (rc != 0 && rc != GLP_ETMLIM && rc != GLP_EMIPGAP && rc != GLP_ESTOP)
    throw NumericalError("MILP solver failed (GLPK glp_intopt code " + std::to_string(rc) + ")");
  if (status == GLP_NOFEAS) {
    out.status = MilpStatus::infeasible;
    return out;
  }
  if (status != GLP_OPT && status != GLP_FEAS) {
    out.status = MilpStatus::no_solution;
    out.best_bound = info.best_bound;
    return out;
  }
  out.status = (status == GLP_OPT && rc == 0) ? MilpStatus::optimal : MilpStatus::feasible;
  out.objective = glp_mip_obj_val(lp);
  out.best_bound = out.status == MilpStatus::optimal ? out.objective : info.best_bound;
  out.gap = std::abs(out.objective - out.best_bound) / std::max(1.0, std::abs(out.objective));
  out.x.resize(impl_->n());
  for (int j = 0; j < impl_->n(); ++j) out.x[j] = glp_mip_col_val(lp, j + 1);
  return out;
}

const char* to_string(LpStatus s) {
  switch (s) {
    case LpStatus::optimal: return "optimal";
    case LpStatus::infeasible: return "infeasible";
    case LpStatus::cutoff: return "stopped at the objective cutoff";
    default: return "unbounded";
  }
}
const char* to_string(MilpStatus s) {
  switch (s) {
    case MilpStatus::optimal: return "optimal";
    case MilpStatus::feasible: return "feasible (limit reached)";
    case MilpStatus::infeasible: return "infeasible";
    default: return "no solution found";
  }
}

}  // namespace sets
