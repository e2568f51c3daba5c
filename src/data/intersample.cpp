#include "sets/data/intersample.hpp"

#include <boost/math/interpolators/cardinal_cubic_b_spline.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <regex>

#include "sets/core/error.hpp"
#include "sets/data/spectrum.hpp"

namespace sets {

const char* intersample_name(Intersample mode) {
  switch (mode) {
    case Intersample::zoh: return "zoh";
    case Intersample::foh: return "foh";
    case Intersample::bl: return "bl";
  }
  return "zoh";
}

Intersample parse_intersample(const std::string& text, const std::string& where) {
  if (text == "zoh") return Intersample::zoh;
  if (text == "foh") return Intersample::foh;
  if (text == "bl") return Intersample::bl;
  throw InputError(where + ": \"" + text + "\" is not an intersample behaviour (zoh: held, foh: linear, bl: band-limited)");
}

Intersample declared_intersample(const ModelFile& model, const std::string& symbol) {
  for (const auto& [input, mode] : model.intersample)
    if (input == symbol) return parse_intersample(mode, model.source + ": intersample." + input);
  return Intersample::zoh;
}

ModelFile with_intersample(const ModelFile& model, std::optional<Intersample> all) {
  ModelFile m = model;
  m.intersample.clear();
  for (const auto& input : model.inputs)
    m.intersample.emplace_back(input.first, intersample_name(all ? *all : declared_intersample(model, input.first)));
  return m;
}

ModelFile with_intersample(const ModelFile& model, const std::vector<std::string>& inputs, Intersample mode) {
  ModelFile m = with_intersample(model);
  for (auto& [input, text] : m.intersample)
    if (std::find(inputs.begin(), inputs.end(), input) != inputs.end()) text = intersample_name(mode);
  return m;
}

std::vector<std::string> inputs_between_samples(const ModelFile& model) {
  // The symbols the continuous part reads: derivatives, and the signals they reach.
  std::vector<std::string> texts;
  for (const auto& d : model.derivatives) texts.push_back(d.second);
  for (const auto& s : model.signals) texts.push_back(s.second);
  std::vector<std::string> out;
  for (const auto& [input, column] : model.inputs) {
    (void)column;
    const std::regex word("(^|[^A-Za-z0-9_])" + input + "([^A-Za-z0-9_]|$)");
    for (const auto& t : texts)
      if (std::regex_search(t, word)) {
        out.push_back(input);
        break;
      }
  }
  return out;
}

namespace {

// The cubic spline through (k, u_k), k = 0 .. N-1 (N >= 5), in sample-index coordinates, its end
// slopes from the five-point one-sided differences (exact for cubics). They are given explicitly
// because Boost 1.74 estimates the right-end slope with the forward formula at u_{N-5}.
boost::math::interpolators::cardinal_cubic_b_spline<double> spline_through(const std::vector<double>& u) {
  const std::size_t n = u.size() - 1;
  const double left = -25.0 / 12 * u[0] + 4 * u[1] - 3 * u[2] + 4.0 / 3 * u[3] - 0.25 * u[4];
  const double right = 25.0 / 12 * u[n] - 4 * u[n - 1] + 3 * u[n - 2] - 4.0 / 3 * u[n - 3] + 0.25 * u[n - 4];
  return boost::math::interpolators::cardinal_cubic_b_spline<double>(u.data(), u.size(), 0.0, 1.0, left, right);
}

}  // namespace

IntersampleInput::IntersampleInput(const std::vector<double>& samples, Intersample mode, int substeps)
    : u_(samples), mode_(mode), m_(substeps) {
  if (substeps < 1) throw InputError("substeps must be >= 1");
  if (u_.empty()) throw InputError("an input needs at least one sample");
  if (mode_ == Intersample::bl && u_.size() < 5) mode_ = Intersample::foh;  // too short for a spline
  if (mode_ != Intersample::bl) return;
  const auto spline = spline_through(u_);
  const std::size_t N = u_.size(), per = static_cast<std::size_t>(2 * m_ - 1);
  interior_.resize(N * per);
  for (std::size_t k = 0; k + 1 < N; ++k)
    for (std::size_t j = 1; j <= per; ++j)
      interior_[k * per + j - 1] = spline(static_cast<double>(k) + static_cast<double>(j) / (2.0 * m_));
  for (std::size_t j = 0; j < per; ++j) interior_[(N - 1) * per + j] = u_.back();
}

std::vector<double> input_between_samples(const std::vector<double>& samples, Intersample mode, double fraction) {
  if (!(fraction >= 0 && fraction <= 1)) throw InputError("the fraction of a sample interval must lie in [0, 1]");
  const std::size_t N = samples.size();
  std::vector<double> out(samples);
  if (mode == Intersample::zoh || fraction == 0 || N < 2) return out;
  if (mode == Intersample::bl && N >= 5) {
    const auto spline = spline_through(samples);
    for (std::size_t k = 0; k + 1 < N; ++k) out[k] = spline(static_cast<double>(k) + fraction);
    return out;
  }
  for (std::size_t k = 0; k + 1 < N; ++k) out[k] = (1 - fraction) * samples[k] + fraction * samples[k + 1];
  return out;
}

double power_share_above(const std::vector<double>& samples, double fraction_of_fs) {
  if (samples.size() < 16) return 1.0;
  const Eigen::Map<const Eigen::VectorXd> u(samples.data(), static_cast<Eigen::Index>(samples.size()));
  const WelchSpectrum s = welch_spectrum(u);
  double total = 0, above = 0;
  for (Eigen::Index k = 0; k < s.density.size(); ++k) {
    total += s.density[k];
    if (s.frequency[k] >= fraction_of_fs) above += s.density[k];
  }
  return total > 0 ? above / total : 1.0;
}

}  // namespace sets
