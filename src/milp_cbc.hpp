#pragma once
// Private (not installed): the CBC backend of LinearProgram::solve_milp. CBC is confined to
// milp_cbc.cpp; linear_program.cpp hands over the stored model.

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "sets/linear_program.hpp"
#include "sets/safe_bound.hpp"

namespace sets::detail {

struct MilpModel {
  const LpRows& rows;
  const Eigen::VectorXd& col_lo;
  const Eigen::VectorXd& col_hi;
  const Eigen::VectorXd& c;
  Sense sense;
  const std::vector<char>& integer;  // 1 for integer columns
};

/// Branch and cut with COIN-OR CBC (through CbcMain1, i.e. with CBC's default cuts and heuristics),
/// single-threaded, wall-clock time limit. Same status/gap conventions as the GLPK backend.
MilpSolution solve_milp_cbc(const MilpModel& model, const MilpOptions& options,
                            const std::optional<Eigen::VectorXd>& start);

}  // namespace sets::detail
