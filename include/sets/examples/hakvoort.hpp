#pragma once
// The example of sets-hinf-bound (Hakvoort & Van den Hof's procedure): an order-4 system with a
// lightly damped resonance, its simulated data, and priors that hold for it (used by the app, its
// benchmark and its tests).

#include <Eigen/Core>

#include <random>
#include <string>

#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "sets/models/orthonormal_basis.hpp"
#include "sets/models/transfer_function.hpp"

namespace sets::hakvoort {

/// G0(z) = 0.05 z^-1 (1 + 0.5 z^-1) / [(1 - 2 r1 cos(w1) z^-1 + r1^2 z^-2)(1 - 2 r2 cos(w2) z^-1 + r2^2 z^-2)]
/// with r1 = 0.97, w1 = 0.6 rad/sample (a lightly damped resonance, damping ratio ~0.05) and
/// r2 = 0.8, w2 = 0.9 rad/sample (a well damped second mode).
TransferFunction system();

struct Data {
  Eigen::VectorXd u, y;
};

/// N samples of G: u uniform in [-1, 1] (so u_bar = 1), started 3000 samples before the record
/// (the initial conditions are real and unknown); noise e filtered by 1/(1 - 0.7 q^-1), Gaussian
/// with standard deviation `noise` or (bounded) uniform with |e| <= noise, so |v| <= noise / 0.3.
/// Draws every u, then every e, from `rng`.
Data simulate(const TransferFunction& G, int N, double noise, bool bounded, std::mt19937_64& rng);

/// Priors that are true for a known G (a simulation may know them): M = 1.2 max_k |g0(k)| / rho^k
/// over the first 200 basis coefficients (beyond, they are rounding noise) unless `given.M` > 0,
/// and the impulse-response envelope M_ic = 1.2 max_s |h0(s)| / rho_ic^s with rho_ic = 0.975
/// unless given (> 0). `note` receives the check of the coefficient prior on G.
HinfPriors priors_for(const TransferFunction& G, const OrthonormalBasis& basis, HinfPriors given, std::string& note);

}  // namespace sets::hakvoort
