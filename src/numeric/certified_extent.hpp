#pragma once
// Certified extent of a convex set given as an LP (internal: pui(), support() of a feasible
// parameter set, and outer_box()/support() of an H-polytope share it).
//
// Phase 1 solves min and max of every coordinate in floating point. Phase 2 bounds the variables
// by a box X slightly larger than those extents (intersected with the set's own variable bounds)
// so that Neumaier–Shcherbina bounds are finite. The set C is convex, so if every certified
// coordinate bound over C ∩ X lies strictly inside the artificial faces of X, then C ⊂ X (a
// point of C outside X would put a point of C on an artificial face), and every safe bound over
// C ∩ X — coordinates and any further direction — holds for C itself. X is tried with growing
// margins; if none certifies, the answer is the set's own variable bounds (often infinite),
// marked uncertified, and the floating-point extent is kept apart as an estimate.

#include <Eigen/Core>

#include <functional>
#include <vector>

#include "sets/numeric/linear_program.hpp"

namespace sets::detail {

enum class ExtentStatus { feasible, empty, unknown };

struct Extent {
  ExtentStatus status = ExtentStatus::unknown;
  Eigen::VectorXd float_lo, float_hi;         // phase-1 floating-point extremes (+-inf: unbounded)
  Eigen::VectorXd lo, hi;  // safe: certified, or the set's own variable bounds; else float_lo/hi
  Eigen::MatrixXd lower_points, upper_points;  // column l: a point attaining lo[l] / hi[l] (LP tolerance)
  std::vector<double> maxima;                 // bound on max d^T x per direction (see below)
  bool certified = false;
  int lps = 0;
};

/// Solves the LP's current objective over the whole set and counts the LPs it used. With row
/// generation it may add rows (the LP then holds a relaxation of the set, which keeps every
/// safe bound valid).
using SolveOverSet = std::function<LpSolution(int& lps)>;

/// `lp` holds the set: its rows and the set's own variable bounds (it is left with X as bounds).
/// `maxima[k]` is a rigorous upper bound on max directions[k]^T x when `safe` (+inf if the
/// direction is unbounded or nothing could be certified), the floating-point maximum otherwise.
/// `empty` only with an infeasibility certificate verified in exact arithmetic
/// (lp_certificate.hpp); an infeasible floating-point LP without one is `unknown`.
Extent certified_extent(LinearProgram& lp, const SolveOverSet& solve,
                        const std::vector<Eigen::VectorXd>& directions, bool safe);

}  // namespace sets::detail
