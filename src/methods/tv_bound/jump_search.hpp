#pragma once
// Private to src/methods/tv_bound: the branch-and-bound over jump patterns that solves (14)
// (SparseSolver::jump_search). docs/methods/tv-bound.md explains the search and its bounds.

#include "sets/methods/tv_bound/tv_bound.hpp"

namespace sets::detail {

/// Solves (14) with the threshold rows of the single-binary form (the same optimum as the
/// paper's (12)-(13)) by best-first branch and bound over sign-monotone jump patterns. Options
/// are validated by the caller. The returned best_bound is a certified lower bound on the optimum
/// (every LP bound used is a Neumaier-Shcherbina safe bound).
TvBoundResult jump_search(const TvBoundData& data, const SparseBoundOptions& options);

}  // namespace sets::detail
