#include "sets/numeric/linear_program.hpp"

#include <glpk.h>

#include <chrono>
#include <algorithm>
#include <climits>
#include <cmath>
#include <sstream>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/glpk_error.hpp"
#include "sets/numeric/safe_bound.hpp"

namespace sets {

namespace {

// Magnitudes GLPK is given: beyond these its scaling and pivoting lose every digit (products
// of two entries overflow or underflow). Real data stay far inside; anything outside is an
// input error, named, instead of a silent wrong answer.
constexpr double kMaxMagnitude = 1e150, kMinMagnitude = 1e-150;

std::string show(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

int glpk_bound_type(double lo, double hi) {
  if (std::isinf(lo) && std::isinf(hi)) return GLP_FR;
  if (std::isinf(hi)) return GLP_LO;
  if (std::isinf(lo)) return GLP_UP;
  if (lo == hi) return GLP_FX;
  return GLP_DB;
}

// `what` names the bound or coefficient in the error: a string, or a function that makes one
// (built only when there is an error: add_row is called once per LP row).
std::string name(const std::string& what) { return what; }
template <class F>
std::string name(const F& what) {
  return what();
}

template <class What>
void check_bounds(double lo, double hi, const What& what) {
  if (std::isnan(lo) || std::isnan(hi) || lo > hi || lo == inf || hi == -inf)
    throw InputError(name(what) + ": invalid bounds [" + show(lo) + ", " + show(hi) + "]");
  for (double b : {lo, hi})
    if (std::isfinite(b) && std::abs(b) > kMaxMagnitude)
      throw InputError(name(what) + ": bound " + show(b) + " is beyond +-1e150 (use an infinite bound instead)");
}

template <class What>
void check_coefficient(double a, const What& what) {
  if (!std::isfinite(a)) throw InputError(name(what) + " is not finite");
  if (a != 0 && (std::abs(a) > kMaxMagnitude || std::abs(a) < kMinMagnitude))
    throw InputError(name(what) + " = " + show(a) + " is outside the magnitudes the LP solver handles (1e-150..1e150)");
}

// GLPK's limits are ints: clamp instead of overflowing.
int iteration_limit(int m, int n) {
  const long long lim = 10000LL + 50LL * (static_cast<long long>(m) + n);
  return static_cast<int>(std::min<long long>(lim, INT_MAX / 2));
}

int milliseconds(double seconds, const char* what) {
  if (std::isnan(seconds) || seconds <= 0)
    throw InputError(std::string(what) + ": the time limit must be a positive number of seconds, not " + show(seconds));
  if (seconds * 1000 >= static_cast<double>(INT_MAX)) return INT_MAX;
  return std::max(1, static_cast<int>(seconds * 1000));
}

void set_glpk_col_bounds(glp_prob* lp, int j, double lo, double hi) {
  glp_set_col_bnds(lp, j + 1, glpk_bound_type(lo, hi), std::isinf(lo) ? 0.0 : lo, std::isinf(hi) ? 0.0 : hi);
}
void set_glpk_row_bounds(glp_prob* lp, int i, double lo, double hi) {
  glp_set_row_bnds(lp, i + 1, glpk_bound_type(lo, hi), std::isinf(lo) ? 0.0 : lo, std::isinf(hi) ? 0.0 : hi);
}

}  // namespace

// The problem's data live here (the certificates and safe bounds work on them, exactly as
// given); GLPK holds a copy. After a GLPK internal error the thread's GLPK environment is freed
// (glpk_error.hpp) and the copy is rebuilt from this one on next use.
struct LinearProgram::Impl {
  glp_prob* lp = nullptr;
  unsigned long generation = 0;  // glpk_environment_generation() when `lp` was created
  LpRows rows;
  Eigen::VectorXd col_lo, col_hi, c;
  Eigen::VectorXd col_max;    // largest |a_ij| of each column (for the objective's factor)
  double obj_factor = 1;      // GLPK holds obj_factor * c (a power of 2, so exact)
  std::vector<char> integer;
  Sense sense = Sense::minimize;
  bool has_integer = false;
  bool scaled = false;  // GLPK holds scale factors (only inside a recovering solve())
  // Rows reach GLPK only when GLPK is next used (prob()): callers that solve elsewhere (the
  // dense simplex of pui()) and keep this object for its rows and safe bounds pay nothing for
  // GLPK's copy (it was a fifth of a Cerone-Regruto PUI).
  int loaded_rows = 0;

  Impl() { create(); }
  ~Impl() {
    if (!lp || generation != glpk_environment_generation()) return;  // freed with its environment
    try {
      glp_prob* p = lp;
      call_glpk("LinearProgram", [p] { glp_delete_prob(p); });
    } catch (const NumericalError&) {
    }
  }
  int n() const { return static_cast<int>(col_lo.size()); }
  int m() const { return static_cast<int>(rows.entries.size()); }

  void create() {
    glp_prob* p = nullptr;
    call_glpk("LinearProgram", [&p] {
      glp_term_out(GLP_OFF);
      p = glp_create_prob();
    });
    lp = p;
    generation = glpk_environment_generation();
    scaled = false;
    loaded_rows = 0;
  }

  /// GLPK's problem with its columns (rows may be pending), rebuilt (cold) if an internal
  /// error freed it: enough to change columns and the objective.
  glp_prob* columns() {
    if (generation == glpk_environment_generation()) return lp;
    create();
    if (n() > 0) {
      glp_prob* p = lp;
      const int count = n();
      call_glpk("LinearProgram", [p, count] { glp_add_cols(p, count); });
      for (int j = 0; j < n(); ++j) load_col(j);
    }
    return lp;
  }
  /// GLPK's problem with every row loaded.
  glp_prob* prob() {
    columns();
    for (; loaded_rows < m(); ++loaded_rows) load_row(loaded_rows);
    return lp;
  }

  void load_col(int j) {
    glp_prob* p = lp;
    const double lo = col_lo[j], hi = col_hi[j], cj = c[j] * obj_factor;
    const bool is_int = integer[static_cast<std::size_t>(j)];
    const int dir = sense == Sense::minimize ? GLP_MIN : GLP_MAX;
    call_glpk("LinearProgram", [=] {
      set_glpk_col_bounds(p, j, lo, hi);
      glp_set_obj_coef(p, j + 1, cj);
      glp_set_col_kind(p, j + 1, is_int ? GLP_IV : GLP_CV);
      glp_set_obj_dir(p, dir);
    });
  }

  // Row i of the stored data appended to GLPK's problem (which holds rows 0 .. i-1).
  void load_row(int i) {
    const auto& entries = rows.entries[static_cast<std::size_t>(i)];
    std::vector<int> ind(1);
    std::vector<double> val(1);
    for (const auto& [j, a] : entries) {
      ind.push_back(j + 1);
      val.push_back(a);
    }
    glp_prob* p = lp;
    const double lo = rows.lo[static_cast<std::size_t>(i)], hi = rows.hi[static_cast<std::size_t>(i)];
    const int len = static_cast<int>(ind.size()) - 1;
    const int* pind = ind.data();
    const double* pval = val.data();
    call_glpk("LinearProgram::add_row", [=] {
      glp_add_rows(p, 1);
      glp_set_mat_row(p, i + 1, len, pind, pval);
      set_glpk_row_bounds(p, i, lo, hi);
    });
  }

  void push_row(std::vector<std::pair<int, double>> entries, double lo, double hi) {
    const auto what = [this] { return "LinearProgram row " + std::to_string(m()); };  // only for errors
    check_bounds(lo, hi, what);
    for (const auto& [j, a] : entries) {
      if (j < 0 || j >= n()) throw InputError(what() + ": column " + std::to_string(j) + " out of range");
      const int col = j;
      check_coefficient(a, [&] { return what() + ": coefficient of column " + std::to_string(col); });
    }
    for (const auto& [j, a] : entries) col_max[j] = std::max(col_max[j], std::abs(a));
    rows.entries.push_back(std::move(entries));
    rows.lo.push_back(lo);
    rows.hi.push_back(hi);
  }

  // The power of 2 that brings the objective to the size of the matrix columns it weighs:
  // GLPK's tolerances on reduced costs and duals are absolute, and the objective +-x_j of a
  // column with entries ~1e9 has duals ~1e-9, all "zero" to GLPK, which then stops at any
  // vertex (seen: PUI intervals of width 0 on badly scaled regressions). A positive factor
  // changes no optimum; the duals and the objective value are divided by it again (exactly).
  // Only ever > 1, judged by the largest cost: a weighted objective whose big weights already
  // give duals of size 1 is left alone (shrinking it would push its small costs under the
  // tolerance instead).
  double wanted_obj_factor() const {
    double r = 0;
    for (int j = 0; j < n(); ++j)
      if (c[j] != 0 && col_max[j] > 0) r = std::max(r, std::abs(c[j]) / col_max[j]);
    if (!(r > 0)) return 1;
    return std::ldexp(1.0, std::clamp(-std::ilogb(r), 0, 200));
  }

  void set_obj_factor(double f) {
    if (f == obj_factor) return;
    obj_factor = f;
    glp_prob* p = lp;
    const double* pc = c.data();
    const int count = n();
    call_glpk("LinearProgram::solve", [=] {
      for (int j = 0; j < count; ++j) glp_set_obj_coef(p, j + 1, pc[j] * f);
    });
  }

  // GLPK's own scaling (geometric mean, then equilibration, factors rounded to powers of 2 so
  // that scaling is exact), as a recovery step only. GLPK keeps the unscaled data and reports
  // unscaled values; the stored copy here, on which certificates are checked, is never scaled.
  // Not the default: column scaling multiplies the objective by the column factors, so on a
  // badly scaled problem the objective +-x_j of a PUI can fall below GLPK's reduced-cost
  // tolerance and any feasible vertex is reported optimal (seen: a PUI interval of width 0).
  void scale(bool on) {
    if (on == scaled) return;
    glp_prob* p = lp;
    call_glpk("LinearProgram::solve", [p, on] {
      if (on)
        glp_scale_prob(p, GLP_SF_GM | GLP_SF_EQ | GLP_SF_2N);
      else
        glp_unscale_prob(p);
    });
    scaled = on;
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
  check_bounds(lo, hi, std::string("LinearProgram::add_variables"));
  glp_prob* p = impl_->columns();
  const int first = impl_->n();
  call_glpk("LinearProgram::add_variables", [p, count] { glp_add_cols(p, count); });
  impl_->col_lo.conservativeResize(first + count);
  impl_->col_hi.conservativeResize(first + count);
  impl_->c.conservativeResize(first + count);
  impl_->col_max.conservativeResize(first + count);
  impl_->integer.resize(static_cast<std::size_t>(first + count), 0);
  for (int j = first; j < first + count; ++j) {
    impl_->c[j] = 0;
    impl_->col_max[j] = 0;
    impl_->col_lo[j] = lo;
    impl_->col_hi[j] = hi;
    impl_->load_col(j);
  }
  return first;
}

void LinearProgram::set_variable_bounds(int j, double lo, double hi) {
  if (j < 0 || j >= impl_->n()) throw InputError("LinearProgram: variable index out of range");
  check_bounds(lo, hi, "LinearProgram variable " + std::to_string(j));
  glp_prob* p = impl_->columns();
  impl_->col_lo[j] = lo;
  impl_->col_hi[j] = hi;
  call_glpk("LinearProgram::set_variable_bounds", [=] { set_glpk_col_bounds(p, j, lo, hi); });
}
double LinearProgram::variable_lower(int j) const { return impl_->col_lo[j]; }
double LinearProgram::variable_upper(int j) const { return impl_->col_hi[j]; }

void LinearProgram::set_integer(int j, bool integer) {
  if (j < 0 || j >= impl_->n()) throw InputError("LinearProgram: variable index out of range");
  glp_prob* p = impl_->columns();
  impl_->integer[static_cast<std::size_t>(j)] = integer;
  call_glpk("LinearProgram::set_integer", [=] { glp_set_col_kind(p, j + 1, integer ? GLP_IV : GLP_CV); });
  if (integer) impl_->has_integer = true;
}

int LinearProgram::add_row(const Eigen::Ref<const Eigen::VectorXd>& a, double lo, double hi) {
  if (a.size() != impl_->n())
    throw InputError("LinearProgram::add_row: " + std::to_string(a.size()) + " coefficients for " +
                     std::to_string(impl_->n()) + " variables");
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

int LinearProgram::add_rows(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& lo,
                            const Eigen::Ref<const Eigen::VectorXd>& hi) {
  if (A.rows() != lo.size() || A.rows() != hi.size())
    throw InputError("LinearProgram::add_rows: row bounds do not match the matrix");
  const int first = impl_->m();
  for (Eigen::Index i = 0; i < A.rows(); ++i) add_row(A.row(i).transpose(), lo[i], hi[i]);
  return first;
}

int LinearProgram::add_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A,
                            const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi) {
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
  glp_prob* p = impl_->prob();
  impl_->rows.lo[static_cast<std::size_t>(i)] = lo;
  impl_->rows.hi[static_cast<std::size_t>(i)] = hi;
  call_glpk("LinearProgram::set_row_bounds", [=] { set_glpk_row_bounds(p, i, lo, hi); });
}
double LinearProgram::row_lower(int i) const { return impl_->rows.lo.at(static_cast<std::size_t>(i)); }
double LinearProgram::row_upper(int i) const { return impl_->rows.hi.at(static_cast<std::size_t>(i)); }
const LpRows& LinearProgram::rows() const { return impl_->rows; }
const std::vector<std::pair<int, double>>& LinearProgram::row(int i) const {
  return impl_->rows.entries.at(static_cast<std::size_t>(i));
}

void LinearProgram::set_objective(const Eigen::Ref<const Eigen::VectorXd>& c, Sense sense) {
  if (c.size() != impl_->n()) throw InputError("LinearProgram::set_objective: wrong dimension");
  for (Eigen::Index j = 0; j < c.size(); ++j)
    check_coefficient(c[j], "LinearProgram::set_objective: cost of column " + std::to_string(j));
  glp_prob* p = impl_->columns();
  impl_->c = c;
  impl_->sense = sense;
  const double* pc = impl_->c.data();
  const int n = impl_->n();
  const double f = impl_->obj_factor;
  const int dir = sense == Sense::minimize ? GLP_MIN : GLP_MAX;
  call_glpk("LinearProgram::set_objective", [=] {
    for (int j = 0; j < n; ++j) glp_set_obj_coef(p, j + 1, pc[j] * f);
    glp_set_obj_dir(p, dir);
  });
}

void LinearProgram::set_objective_coordinate(int j, Sense sense) {
  if (j < 0 || j >= impl_->n()) throw InputError("LinearProgram: variable index out of range");
  Eigen::VectorXd c = Eigen::VectorXd::Zero(impl_->n());
  c[j] = 1;
  set_objective(c, sense);
}
const Eigen::VectorXd& LinearProgram::objective() const { return impl_->c; }
Sense LinearProgram::sense() const { return impl_->sense; }

void LinearProgram::reset_basis() {
  glp_prob* p = impl_->prob();
  call_glpk("LinearProgram::reset_basis", [p] { glp_std_basis(p); });
}

// ---------------------------------------------------------------- bases

LpBasis LinearProgram::basis() const {
  LpBasis b;
  b.rows.resize(static_cast<std::size_t>(impl_->m()));
  b.cols.resize(static_cast<std::size_t>(impl_->n()));
  if (impl_->generation != glpk_environment_generation()) {  // lost with its environment: slack basis
    std::fill(b.rows.begin(), b.rows.end(), static_cast<unsigned char>(GLP_BS));
    for (int j = 0; j < impl_->n(); ++j)
      b.cols[static_cast<std::size_t>(j)] = static_cast<unsigned char>(std::isfinite(impl_->col_lo[j]) ? GLP_NL
                                                                       : std::isfinite(impl_->col_hi[j]) ? GLP_NU
                                                                                                         : GLP_NF);
    return b;
  }
  glp_prob* p = impl_->prob();
  unsigned char* rs = b.rows.data();
  unsigned char* cs = b.cols.data();
  const int m = impl_->m(), n = impl_->n();
  call_glpk("LinearProgram::basis", [=] {
    for (int i = 0; i < m; ++i) rs[i] = static_cast<unsigned char>(glp_get_row_stat(p, i + 1));
    for (int j = 0; j < n; ++j) cs[j] = static_cast<unsigned char>(glp_get_col_stat(p, j + 1));
  });
  return b;
}

void LinearProgram::set_basis(const LpBasis& b) {
  if (b.rows.size() != static_cast<std::size_t>(impl_->m()) || b.cols.size() != static_cast<std::size_t>(impl_->n()))
    throw InputError("LinearProgram::set_basis: the basis is for another problem size");
  for (const auto* v : {&b.rows, &b.cols})
    for (unsigned char s : *v)
      if (s < GLP_BS || s > GLP_NS) throw InputError("LinearProgram::set_basis: invalid status " + std::to_string(s));
  glp_prob* p = impl_->prob();
  const unsigned char* rs = b.rows.data();
  const unsigned char* cs = b.cols.data();
  const int m = impl_->m(), n = impl_->n();
  // GLPK's setters replace a non-basic status the current bounds do not allow by the one they do.
  call_glpk("LinearProgram::set_basis", [=] {
    for (int i = 0; i < m; ++i) glp_set_row_stat(p, i + 1, rs[i]);
    for (int j = 0; j < n; ++j) glp_set_col_stat(p, j + 1, cs[j]);
  });
}

// ---------------------------------------------------------------- solving

namespace {

struct SimplexRun {
  int rc = 0, status = 0, prim = 0, dual = 0;
};

bool cut_off(const SimplexRun& r) { return r.rc == GLP_EOBJUL || r.rc == GLP_EOBJLL; }

bool decided(const SimplexRun& r) {
  if (cut_off(r)) return true;
  if (r.rc != 0) return false;
  return r.status == GLP_OPT || r.status == GLP_NOFEAS || r.prim == GLP_NOFEAS || r.status == GLP_UNBND ||
         (r.prim == GLP_FEAS && r.dual == GLP_NOFEAS);
}

// GLPK's primal, reduced costs and row duals after a solve, in the problem's own objective scale
// (GLPK holds f * c); returns GLPK's iteration count.
int read_solution(glp_prob* lp, int n, int m, double f, const char* where, LpSolution& s) {
  s.x.resize(n);
  s.reduced_cost.resize(n);
  s.row_dual.resize(m);
  double* x = s.x.data();
  double* d = s.reduced_cost.data();
  double* y = s.row_dual.data();
  double objective = 0;
  int iterations = 0;
  double* pobj = &objective;
  int* pit = &iterations;
  call_glpk(where, [=] {
    *pobj = glp_get_obj_val(lp);
    *pit = glp_get_it_cnt(lp);
    for (int j = 0; j < n; ++j) {
      x[j] = glp_get_col_prim(lp, j + 1);
      d[j] = glp_get_col_dual(lp, j + 1);
    }
    for (int i = 0; i < m; ++i) y[i] = glp_get_row_dual(lp, i + 1);
  });
  s.objective = objective / f;
  s.row_dual /= f;
  s.reduced_cost /= f;
  return iterations;
}

}  // namespace

// Recovery, in order, until GLPK gives a verdict: (1) dual simplex from the last basis on the
// data as given (then the primal, which can prove unboundedness); (2) scaled (exact power-of-2
// factors), primal from an advanced basis; (3) scaled, dual from the slack basis with the
// textbook ratio test and no bound shifting (a different pivoting path out of cycling); (4)
// GLPK's exact simplex from the slack basis, as a search aid only (it rounds the data; an
// infeasible verdict is checked by lp_certificate.hpp before it is used as a proof, and an
// optimum is used only through safe_bound). Then NumericalError. The scale factors are removed
// again at the end, so every solve starts on the data as given.
LpSolution LinearProgram::solve() { return solve(LpSolveOptions{}); }

LpSolution LinearProgram::solve(const LpSolveOptions& options) {
  if (impl_->n() == 0) throw InputError("LinearProgram::solve: no variables");
  if (options.cutoff && std::isnan(*options.cutoff)) throw InputError("LinearProgram::solve: the cutoff is NaN");
  glp_prob* lp = impl_->prob();
  struct Unscale {  // the next solve starts unscaled, whatever happens here
    Impl* impl;
    ~Unscale() {
      try {
        if (impl->generation == glpk_environment_generation()) impl->scale(false);
      } catch (const NumericalError&) {
      }
    }
  } unscale_at_exit{impl_.get()};
  impl_->set_obj_factor(impl_->wanted_obj_factor());
  const double f = impl_->obj_factor;
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.it_lim = iteration_limit(impl_->m(), impl_->n());
  if (options.long_step) parm.r_test = GLP_RT_FLIP;
  if (options.cutoff) {  // only the dual simplex uses it; a stop there is status cutoff
    if (impl_->sense == Sense::minimize)
      parm.obj_ul = *options.cutoff * f;
    else
      parm.obj_ll = *options.cutoff * f;
  }
  std::string codes;
  SimplexRun run;
  const auto simplex = [&](int method, int start) {
    parm.meth = method;
    glp_smcp* pp = &parm;
    SimplexRun* r = &run;
    call_glpk("LinearProgram::solve", [=] {
      if (start == 1) glp_adv_basis(lp, 0);
      if (start == 2) glp_std_basis(lp);
      if (start == 3) glp_std_basis(lp);
      r->rc = start == 3 ? glp_exact(lp, pp) : glp_simplex(lp, pp);
      r->status = glp_get_status(lp);
      r->prim = glp_get_prim_stat(lp);
      r->dual = glp_get_dual_stat(lp);
    });
    codes += (codes.empty() ? "" : ", ") + std::to_string(run.rc);
    return decided(run);
  };
  bool ok = simplex(GLP_DUALP, 0);
  if (!ok && run.rc == 0) ok = simplex(GLP_PRIMAL, 0);  // the dual simplex cannot prove unboundedness
  if (!ok) {
    impl_->scale(true);
    ok = simplex(GLP_PRIMAL, 1);
  }
  if (!ok) {
    parm.r_test = GLP_RT_STD;
    parm.shift = GLP_OFF;
    ok = simplex(GLP_DUALP, 2);
    if (!ok && run.rc == 0) ok = simplex(GLP_PRIMAL, 0);
  }
  if (!ok) ok = simplex(GLP_PRIMAL, 3);
  if (!ok)
    throw NumericalError("LP solver failed (GLPK return codes " + codes + "; status " + std::to_string(run.status) +
                         ") on a problem with " + std::to_string(impl_->m()) + " rows and " +
                         std::to_string(impl_->n()) + " columns, after scaling, three simplex restarts and the "
                         "exact simplex");
  LpSolution s;
  s.sense = impl_->sense;
  if (cut_off(run)) {
    s.status = LpStatus::cutoff;
  } else if (run.status == GLP_OPT) {
    s.status = LpStatus::optimal;
  } else if (run.status == GLP_NOFEAS || run.prim == GLP_NOFEAS) {
    s.status = LpStatus::infeasible;
  } else {
    s.status = LpStatus::unbounded;
  }
  const int n = impl_->n(), m = impl_->m();
  s.iterations = read_solution(lp, n, m, f, "LinearProgram::solve", s);
  if (s.status == LpStatus::optimal && (!std::isfinite(s.objective) || !s.x.allFinite() || !s.row_dual.allFinite()))
    throw NumericalError("LP solver returned a non-finite optimum on a problem with " + std::to_string(m) + " rows and " +
                         std::to_string(n) + " columns");
  return s;
}

LpSolution LinearProgram::solve_exact() {
  if (impl_->n() == 0) throw InputError("LinearProgram::solve_exact: no variables");
  glp_prob* lp = impl_->prob();
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  parm.it_lim = iteration_limit(impl_->m(), impl_->n());  // as in solve(): never cycle forever
  SimplexRun run;
  glp_smcp* pp = &parm;
  SimplexRun* r = &run;
  call_glpk("LinearProgram::solve_exact", [=] {
    r->rc = glp_exact(lp, pp);
    r->status = glp_get_status(lp);
  });
  if (run.rc != 0) throw NumericalError("exact LP solver failed (GLPK glp_exact code " + std::to_string(run.rc) + ")");
  LpSolution s;
  s.sense = impl_->sense;
  switch (run.status) {
    case GLP_OPT: s.status = LpStatus::optimal; break;
    case GLP_NOFEAS: s.status = LpStatus::infeasible; break;
    case GLP_UNBND: s.status = LpStatus::unbounded; break;
    default: throw NumericalError("exact LP solver ended without a verdict");
  }
  s.iterations = read_solution(lp, impl_->n(), impl_->m(), impl_->obj_factor, "LinearProgram::solve_exact", s);
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

MilpSolution LinearProgram::solve_milp(const MilpOptions& options, const std::optional<Eigen::VectorXd>& start) {
  // Every parameter GLPK is given is checked first: GLPK takes ints and doubles as they come
  // (a NaN time limit becomes an undefined int).
  if (start && start->size() != impl_->n())
    throw InputError("LinearProgram::solve_milp: start point has the wrong dimension");
  if (start && !start->allFinite()) throw InputError("LinearProgram::solve_milp: start point is not finite");
  if (options.node_limit < 0) throw InputError("LinearProgram::solve_milp: node_limit must be >= 0");
  if (!(options.relative_gap >= 0) || !std::isfinite(options.relative_gap))
    throw InputError("LinearProgram::solve_milp: relative_gap must be a finite number >= 0, not " +
                     show(options.relative_gap));
  const int limit_ms = milliseconds(options.time_limit_s, "LinearProgram::solve_milp");
  if (impl_->n() == 0) throw InputError("LinearProgram::solve_milp: no variables");
  glp_prob* lp = impl_->prob();
  impl_->set_obj_factor(1);  // the MILP's objective values are reported as they are
  const auto t0 = std::chrono::steady_clock::now();
  // The relaxation first (GLPK's branch-and-cut needs an optimal LP basis).
  glp_smcp sm;
  glp_init_smcp(&sm);
  sm.msg_lev = GLP_MSG_OFF;
  sm.tm_lim = limit_ms;
  sm.it_lim = iteration_limit(impl_->m(), impl_->n());
  SimplexRun relax;
  {
    glp_smcp* psm = &sm;
    SimplexRun* r = &relax;
    call_glpk("LinearProgram::solve_milp", [=] {
      r->rc = glp_simplex(lp, psm);
      if (r->rc != 0 && r->rc != GLP_ETMLIM) {  // one restart from an advanced basis
        glp_adv_basis(lp, 0);
        r->rc = glp_simplex(lp, psm);
      }
      r->status = glp_get_status(lp);
    });
  }
  MilpSolution out;
  if (relax.rc != 0 && relax.rc != GLP_ETMLIM)
    throw NumericalError("MILP relaxation failed (GLPK glp_simplex code " + std::to_string(relax.rc) + ")");
  if (relax.status == GLP_NOFEAS) {
    out.status = MilpStatus::infeasible;
    return out;
  }
  if (relax.status != GLP_OPT)
    throw NumericalError("MILP relaxation has no optimal solution (unbounded or not solved)");
  double relax_obj = 0;
  {
    double* po = &relax_obj;
    call_glpk("LinearProgram::solve_milp", [=] { *po = glp_get_obj_val(lp); });
  }
  Milp_callback_data info{start, relax_obj, options.node_limit};
  glp_iocp parm;
  glp_init_iocp(&parm);
  parm.msg_lev = options.verbose ? GLP_MSG_ON : GLP_MSG_OFF;
  parm.cb_func = milp_callback;
  parm.cb_info = &info;
  parm.mip_gap = options.relative_gap;
  const double elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  parm.tm_lim = limit_ms == INT_MAX ? INT_MAX : std::max(1, static_cast<int>(limit_ms - elapsed_ms));
  parm.gmi_cuts = GLP_ON;
  parm.mir_cuts = GLP_ON;
  parm.fp_heur = GLP_ON;
  int rc = 0, status = 0;
  {
    glp_iocp* pp = &parm;
    int* prc = &rc;
    int* pst = &status;
    call_glpk("LinearProgram::solve_milp", [=] {
      *prc = glp_intopt(lp, pp);
      *pst = glp_mip_status(lp);
    });
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.nodes = info.nodes;
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
  out.x.resize(impl_->n());
  double* x = out.x.data();
  double* po = &out.objective;
  const int n = impl_->n();
  call_glpk("LinearProgram::solve_milp", [=] {
    *po = glp_mip_obj_val(lp);
    for (int j = 0; j < n; ++j) x[j] = glp_mip_col_val(lp, j + 1);
  });
  out.best_bound = out.status == MilpStatus::optimal ? out.objective : info.best_bound;
  out.gap = std::abs(out.objective - out.best_bound) / std::max(1.0, std::abs(out.objective));
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
