#pragma once
// An estimate of the measurement noise level of one recorded output that does not mistake signal
// for noise, whether the signal is sampled fast or coarsely, and whether the noise is white,
// coloured or a quantisation. It says which method gave it and why. Every rule is scale-free:
// ratios of powers, fractions of the band and counts of samples; neither units nor the sample
// time enter. The design study and its validation are in docs/methods/noise-level.md.
//
// It is an estimate, not a bound: nothing here is guaranteed.

#include <Eigen/Core>

#include <string>
#include <vector>

namespace sets {

/// How the noise level was obtained, most reliable first.
enum class NoiseMethod {
  repeats,            // the exogenous inputs repeat: the output's difference over the lag is noise
  residual_coloured,  // residual of the calibrated model; AR(1) noise shape verified from 1/32 (or 1/16, model error below) to 1/2 cycles/sample
  residual_floor,     // residual of the calibrated model; its white floor (a lower bound for coloured noise)
  output_spectrum,    // no model: the output's own spectrum (white floor or difference plateau)
};
const char* noise_method_name(NoiseMethod m);

struct NoiseLevelEstimate {
  double sigma = 0;                 // estimated standard deviation of the noise, output units
  NoiseMethod method = NoiseMethod::output_spectrum;
  std::string reason;               // what was found, in one line
  double quantisation_step = 0;     // the output's lattice step q when it is quantised (0: not)
  /// The AR(1) pole a of the noise when its colour was verified from 1/32 (or 1/16) to 1/2 cycles/sample
  /// (method residual_coloured, or output_spectrum read as coloured); 0 otherwise (white, or not
  /// known: repeats and the white floor say nothing of the colour). Read above the signal's band.
  double ar_pole = 0;
};

/// The noise level of `y`. Optional evidence (pass empty objects when absent):
///   simulated  the calibrated model's output for y (same length);
///   inputs     the model's EXOGENOUS inputs, one column each (a closed loop's reference, never
///              a controller output: the noise must be independent of them).
/// Rule (docs/methods/noise-level.md): a quantised y (every value on a lattice of step q) is never
/// judged by repeats; repeated stretches of the inputs give the noise directly (with a model: the
/// lower of y's and the residual's repeat difference), unless the inputs only nearly repeat (their
/// repeat difference is mostly their derivative: a phase drift, not noise); otherwise the
/// residual y - simulated, projected off short FIRs of the simulated output, its square and
/// cube and the inputs, is read from its Welch spectrum (an AR(1) shape extrapolated when it holds
/// from 1/32 to 1/2 cycles/sample, or unbroken from 1/16 with more power than the shape below it,
/// else the white floor of the top 1/8 band or the plateau of
/// the differences, whichever is lower), capped by the projected residual's RMS; without a model
/// the same reading of y itself. Never below q/sqrt(12); on a quantised y an AR(1) shape is
/// extrapolated only when the top band holds more than the quantiser's white error (white floor >
/// q/sqrt(12)), else the level is q/sqrt(12) and the shape's pole is kept.
NoiseLevelEstimate estimate_noise(const Eigen::Ref<const Eigen::VectorXd>& y,
                                  const Eigen::Ref<const Eigen::VectorXd>& simulated = Eigen::VectorXd(),
                                  const Eigen::Ref<const Eigen::MatrixXd>& inputs = Eigen::MatrixXd());

/// One estimate for one output column recorded several times: the most reliable method wins
/// (the earliest on a tie), because the noise of a channel is a property of the channel.
std::size_t most_reliable(const std::vector<NoiseLevelEstimate>& estimates);

// ---- the parts, exposed for tests and for callers that need one of them

/// The largest q such that every y - y[0] is an integer multiple of q (to 1e-3 q), q being the
/// smallest nonzero |step| or a fraction 1/2 .. 1/64 of it; 0 when there is none or too little
/// evidence (docs/methods/noise-level.md, step 1).
double lattice_step(const Eigen::Ref<const Eigen::VectorXd>& y);

/// A lag P at which the inputs repeat themselves over stretches, and which samples n (n + P < N)
/// lie in matching windows. Empty mask: no repeats.
struct InputRepeats {
  int lag = 0;
  std::vector<char> mask;  // size N - lag
  long matched = 0;        // samples in the mask
};
InputRepeats detect_repeats(const Eigen::Ref<const Eigen::MatrixXd>& inputs);
/// RMS of (y(n + P) - y(n)) / sqrt(2) over the matched samples, blocks holding left-over transients
/// (mean square > 4 x the median block) dropped.
double sigma_from_repeats(const Eigen::Ref<const Eigen::VectorXd>& y, const InputRepeats& repeats);

/// sigma_m = clipped RMS of the m-th difference / sqrt(C(2m, m)), m = 1..8, at the first m whose
/// successor falls by less than 10 % (a white plateau), and that order m (0: fewer than 2 samples).
struct DifferencePlateau {
  double sigma = 0;
  int order = 0;
};
DifferencePlateau difference_plateau(const Eigen::Ref<const Eigen::VectorXd>& x);

}  // namespace sets
