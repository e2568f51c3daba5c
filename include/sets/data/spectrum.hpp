#pragma once
// Welch's averaged periodogram of a sampled signal, in cycles per sample (fs = 1), so that every
// rule built on it is free of the sample time and of the signal's units.

#include <Eigen/Core>

namespace sets {

struct WelchSpectrum {
  Eigen::VectorXd frequency;  // cycles/sample, (0, 1/2]; the DC bin is left out
  Eigen::VectorXd density;    // one-sided power density: the mean square of x is its integral over (0, 1/2]
  int segment = 0;            // samples per segment
  int segments = 0;           // segments averaged (about 2 x segments degrees of freedom)
};

/// Hann-windowed segments of 2^round(log2(max(64, N/8))) samples (at most N), half-overlapping,
/// each with its mean removed (scipy.signal.welch's defaults with that segment): about 15
/// segments, 30 degrees of freedom. `segment` > 0 imposes the segment length.
WelchSpectrum welch_spectrum(const Eigen::Ref<const Eigen::VectorXd>& x, int segment = 0);

}  // namespace sets
