#pragma once
// Private helpers (not installed): exact rational arithmetic on double data with GMP.
// Every finite double is a rational number; mpq_class(double) converts it exactly.

#include <gmpxx.h>

#include <vector>

#include "sets/numeric/interval.hpp"

namespace sets::detail {

using Rational = mpq_class;

/// Solves the n x n system M x = b (M row-major) exactly; false if M is singular.
bool solve_exact(std::vector<Rational> M, std::vector<Rational> b, int n, std::vector<Rational>& x);

/// The smallest interval of doubles containing q.
Interval enclose(const Rational& q);

}  // namespace sets::detail
