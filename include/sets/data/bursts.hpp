#pragma once
// Bursts in a signal's fast part: how much of the energy of its first few differences lies in
// samples far outside their Gaussian body. Measurement noise (white, coloured by any linear filter,
// or quantised) has none: a linear filter of Gaussian noise is Gaussian, and quantisation error is
// bounded. Model error that switches (a hysteresis or backlash reversal, a missed step, an absolute
// value's kink) puts its fast part into a few samples at each event: bursts. A spectrum cannot tell
// the two apart (the bursts' power spreads over every frequency and can mimic coloured noise), the
// clipped RMS can. Scale-free: ratios of RMS values of the same signal.

#include <Eigen/Core>

namespace sets {

/// RMS / clipped RMS of a signal's differences above which its fast part is not noise: the
/// bursts hold as much energy as the Gaussian body (noise gives 1 to about 1/sqrt(2N)).
constexpr double kBurstRatioLimit = 1.4142135623730951;

/// RMS after discarding |x| > 3.5 rms, iterated (the spikes that steps make in differences); unlike
/// a median it works on lattice-valued data. 0.996: RMS of a Gaussian truncated at 3.5 sigma, so
/// that Gaussian data give their RMS.
double clipped_rms(const Eigen::Ref<const Eigen::VectorXd>& x);

/// The largest, over the differences of order 1..max_order, of RMS / clipped RMS. 1 for Gaussian
/// or bounded data (to about 1/sqrt(2N)); sqrt(2) when the bursts hold as much energy as the
/// body. 1 for signals too short or constant.
double burst_ratio(const Eigen::Ref<const Eigen::VectorXd>& x, int max_order = 3);

}  // namespace sets
