#pragma once
// Feasible parameter set (FPS) of bounded-error, linear-in-parameter data.
//
// Sample t says: there are a regressor phi in the box Phi_t and an output e in Y_t with
// phi^T theta = e. For an exact regressor this is the strip |y_t - phi_t^T theta| <= Delta_t.
// With interval regressors (errors in variables) the set is not convex, but inside one orthant
// of theta (fixed signs s) it is the polyhedron
//   sum_j lo_j(s) theta_j <= sup Y_t   and   sum_j hi_j(s) theta_j >= inf Y_t,
// where lo_j(s)/hi_j(s) pick the end of Phi_tj that minimises/maximises phi_j theta_j. Those
// coefficients are the exact interval ends, so the orthant polyhedra describe the FPS exactly
// (Cerone–Regruto eqs. 37–39 are this with Phi_t = centre ± radius).

#include <Eigen/Core>

#include <string>
#include <vector>

#include "sets/core/bool_interval.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/fps/falsification.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

/// Signs of theta in one orthant: +1 means theta_j >= 0, -1 means theta_j <= 0, 0 means theta_j
/// free (pui() uses 0 for a parameter whose regressors are all points: its sign does not matter).
using Orthant = std::vector<int>;

class FeasibleParameterSet {
 public:
  explicit FeasibleParameterSet(int dimension);

  /// Bounded-error data with exact regressors: rows of Phi, outputs y, error bounds delta >= 0.
  static FeasibleParameterSet from_data(const Eigen::Ref<const Eigen::MatrixXd>& Phi,
                                        const Eigen::Ref<const Eigen::VectorXd>& y,
                                        const Eigen::Ref<const Eigen::VectorXd>& delta);
  /// Errors in variables: interval regressors and interval outputs (already including the bound).
  static FeasibleParameterSet from_interval_data(const IntervalMatrix& Phi, const IntervalVector& Y);

  /// |y - phi^T theta| <= delta. The strip's ends are rounded outward.
  void add_strip(const Eigen::Ref<const Eigen::VectorXd>& phi, double y, double delta);
  /// phi in Phi, phi^T theta in Y.
  void add_strip(const IntervalVector& Phi, const Interval& Y);

  int dimension() const { return p_; }
  int size() const { return static_cast<int>(n_); }
  bool has_interval_regressors() const { return eiv_; }
  /// The samples' regressors (size() x dimension()) and outputs: views of the first size() rows
  /// of the storage, which add_strip grows geometrically (amortised O(p) per strip).
  Eigen::Ref<const IntervalMatrix> regressors() const { return Phi_.topRows(n_); }
  Eigen::Ref<const IntervalVector> outputs() const { return Y_.head(n_); }

  /// Is theta in the set? `unknown` only when rounding cannot decide.
  BoolInterval contains(const Eigen::Ref<const Eigen::VectorXd>& theta) const;
  /// Least squares on the central regressors and outputs (no guarantee; a starting point).
  Eigen::VectorXd least_squares() const;
  /// The exact H-polytope of the set inside one orthant (sign constraints included). Its
  /// coefficients are doubles taken from the interval ends, so it contains the true set.
  HPolytope orthant_polytope(const Orthant& orthant) const;

 private:
  int p_;
  bool eiv_ = false;
  Eigen::Index n_ = 0;  // samples; the rows of Phi_ and Y_ beyond n_ are spare capacity
  IntervalMatrix Phi_;  // capacity x p
  IntervalVector Y_;    // capacity
};

enum class OrthantSelection {
  remark2,  // least-squares sign orthant, extended when a bound lands on 0 (Cerone–Regruto); with
            // `safe`, every other orthant is then searched too unless a box proven from p
            // samples misses it (the set need not be connected): same PUIs as `all`
            // (up to LP tolerance), fewer LPs when the set is far from the faces
  all       // every one of the 2^p orthants (only for interval regressors)
};

/// Which solver finds the LP optima of pui()/support(). Both give floating-point multipliers
/// only; every reported end is the same Neumaier–Shcherbina bound computed from them.
enum class PuiLpSolver {
  dense,  // numeric/dense_lp.hpp, warm-started across the 2p objectives; GLPK where it gives up
  glpk    // every LP in GLPK (the reference; for comparisons and tests)
};

struct PuiOptions {
  OrthantSelection orthants = OrthantSelection::remark2;
  bool safe = true;           // certify every end with a Neumaier–Shcherbina safe bound
  double zero_tolerance = 1e-9;  // relative: a floating-point end this close to 0 also extends the
                                 // search (with `safe`, a certified end that reaches 0 always does)
  /// Constraint generation: start each orthant LP from a spread subset of the samples and add
  /// the violated ones until none is (same PUIs, much faster for N >> p). Off: every sample.
  bool working_set = true;
  bool warm_start = true;     // re-solve from the previous basis (false: cold start, for benchmarks)
  PuiLpSolver solver = PuiLpSolver::dense;
};

/// feasible: the LPs found points (see OrthantReport::witness for a proof); empty: certified
/// by an exact infeasibility certificate; unknown: the LP said infeasible (or failed) and no
/// certificate could be verified — never counted as empty.
enum class OrthantStatus { feasible, empty, unknown };

struct OrthantReport {
  Orthant signs;             // empty vector: the whole space (exact regressors)
  OrthantStatus status = OrthantStatus::unknown;
  IntervalVector box;        // outer bound of the set inside this orthant (the orthant itself when unknown)
  bool witness = false;      // a point of this orthant was proven to satisfy every sample
};

struct PuiResult {
  IntervalVector box;             // the PUIs [theta_min, theta_max]; size 0 when certified empty
  /// The floating-point LP extents (an estimate: may miss the set by the LP's tolerances, e.g.
  /// on badly scaled data). With `safe`, `box` never falls back to it: an end that cannot be
  /// certified is the orthant's own bound there (0 or +-inf).
  IntervalVector unreliable_box;
  Eigen::VectorXd central;        // centre of the box (eqs. 41–42)
  ConsistencyVerdict consistency; // do the data falsify the model? (yes/no only when certified)
  /// Every orthant's extent certified by safe bounds. With `safe` the box is an outer bound
  /// either way; false means some ends fell back to the orthant's own bounds (0 or +-inf).
  bool guaranteed = false;
  std::vector<OrthantReport> orthants;
  Eigen::MatrixXd lower_points;   // column l: a feasible point attaining theta_l^min (LP tolerance)
  Eigen::MatrixXd upper_points;   // column l: a feasible point attaining theta_l^max
  int lp_solves = 0;
  int lp_fallbacks = 0;           // of those, the dense solver gave up on (GLPK solved them; GLPK
                                  // also re-decides every infeasible or unbounded verdict)

  /// True only when the data are *certified* to falsify the model (consistency.falsified ==
  /// yes). `unknown` is not empty: the box is then still an outer bound (infinite where nothing
  /// could be said) and the caller reports that consistency was not certified.
  bool empty() const { return consistency.certified_falsified(); }
};

/// Parameter uncertainty intervals: a box that contains the FPS (the part reached by the chosen
/// orthants). With `safe`, each finite end is a rigorous bound; see docs/architecture.md.
PuiResult pui(const FeasibleParameterSet& fps, const PuiOptions& options = {});

/// Upper bounds on the support function max { d^T theta : theta in the FPS } for each direction
/// d (a minimum is minus the maximum over -d). One working-set LP per orthant answers all
/// directions, warm-started, adding violated samples until none is; with `safe` every value is
/// a Neumaier–Shcherbina bound over the artificial box that certifies the PUIs (see
/// docs/architecture.md), so it holds for the whole set. +inf: unbounded or not certified.
/// Interval regressors: the maximum over the orthants that pui() visits with the same options.
struct FpsSupport {
  std::vector<double> maxima;      // one per direction; -inf when certified empty
  IntervalVector box;              // the PUIs found on the way
  ConsistencyVerdict consistency;  // as PuiResult::consistency
  bool guaranteed = false;         // every finite value certified by a safe bound
  int lp_solves = 0;

  /// True only when the data are *certified* to falsify the model (see PuiResult::empty).
  bool empty() const { return consistency.certified_falsified(); }
};
FpsSupport support(const FeasibleParameterSet& fps, const std::vector<Eigen::VectorXd>& directions,
                   const PuiOptions& options = {});

/// Do the data falsify the model? The verdict of pui() without the bounds (for callers that
/// need only this answer, e.g. diagnosis windows).
ConsistencyVerdict check_consistency(const FeasibleParameterSet& fps, const PuiOptions& options = {});

/// The samples whose constraints conflict (support of the minimax-violation fit, in floating
/// point: a report, not a proof), or an empty list if the fit violates none.
Falsification find_conflict(const FeasibleParameterSet& fps);

std::vector<Orthant> all_orthants(int p);
const char* to_string(OrthantStatus s);

}  // namespace sets
