#pragma once
// How a sampled input behaves between its samples — a property of the data, as MATLAB's
// `InterSample`: held (`zoh`, the default), linear (`foh`) or band-limited (`bl`: a cubic spline
// through the samples, Boost.Math's cardinal cubic B-spline). The simulator's RK4 stages read each
// input at fractions of the sample interval through `IntersampleInput`. See docs/model-format.md.

#include <optional>
#include <string>
#include <vector>

#include "sets/models/model_file.hpp"

namespace sets {

enum class Intersample { zoh, foh, bl };

/// "zoh", "foh" or "bl".
const char* intersample_name(Intersample mode);
/// Parses "zoh", "foh" or "bl"; InputError naming `where` (a field or a flag) otherwise.
Intersample parse_intersample(const std::string& text, const std::string& where);

/// The mode of input `symbol` as the model file declares it (zoh when it does not).
Intersample declared_intersample(const ModelFile& model, const std::string& symbol);
/// The model with every input's mode written out: `all` for every input when given, otherwise
/// the file's declaration or zoh. The diagnosis starts from this, so that the augmented model
/// file records the assumption its fits were made under.
ModelFile with_intersample(const ModelFile& model, std::optional<Intersample> all = std::nullopt);
/// The same model with every input in `inputs` switched to `mode` (the others unchanged).
ModelFile with_intersample(const ModelFile& model, const std::vector<std::string>& inputs, Intersample mode);

/// Inputs whose intersample behaviour can change a simulation: those read by the continuous part
/// of the model (derivatives or signals). An input read only by `sampled` expressions is seen at
/// the sample instants, where every mode gives the sample itself.
std::vector<std::string> inputs_between_samples(const ModelFile& model);

/// Values of one sampled input inside every sample interval:
///   at(k, j) = u(t_k + j/(2m) (t_{k+1} - t_k)),  j = 0 .. 2m,
/// for m RK4 substeps (the stages of substep s are at j = 2s, 2s+1, 2s+2). Fractions are of the
/// sample index, so an irregular time column is read as one sample per interval.
///   zoh: u_k at every stage (the hold lasts until t_{k+1}; the last stage is its left limit).
///   foh: (1 - f) u_k + f u_{k+1}.
///   bl:  the cubic spline through (k, u_k), precomputed for the 2m - 1 interior fractions. Edges:
///        the end slopes are the five-point one-sided differences of the first and last samples
///        (exact for cubics); records of fewer than 5 samples are linear.
/// After the last sample every mode holds u_{N-1}.
class IntersampleInput {
 public:
  IntersampleInput(const std::vector<double>& samples, Intersample mode, int substeps);

  double at(std::size_t k, int j) const {
    if (j == 0 || mode_ == Intersample::zoh || k + 1 >= u_.size()) return u_[k];
    if (j == 2 * m_) return u_[k + 1];
    if (mode_ == Intersample::foh) {
      const double f = static_cast<double>(j) / (2 * m_);
      return (1 - f) * u_[k] + f * u_[k + 1];
    }
    return interior_[k * static_cast<std::size_t>(2 * m_ - 1) + static_cast<std::size_t>(j - 1)];
  }
  Intersample mode() const { return mode_; }

 private:
  std::vector<double> u_;
  Intersample mode_;
  int m_;
  std::vector<double> interior_;  // bl: sample-major, 2m - 1 fractions per interval
};

/// The whole sequence u(t_k + fraction (t_{k+1} - t_k)), fraction in [0, 1] (e.g. the band-limited
/// mid-interval values for fraction 1/2).
std::vector<double> input_between_samples(const std::vector<double>& samples, Intersample mode, double fraction);

/// Share of the power of u (mean removed) above 0.375 x the sampling frequency (Welch spectrum):
/// an input whose share is below 1e-3 is band-limited well inside Nyquist, so that a smooth
/// interpolation between its samples is meaningful. 1 for a constant input (no power at all).
double power_share_above(const std::vector<double>& samples, double fraction_of_fs = 0.375);

}  // namespace sets
