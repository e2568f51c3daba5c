#include "sets/data/spectrum.hpp"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "sets/core/error.hpp"

namespace sets {

WelchSpectrum welch_spectrum(const Eigen::Ref<const Eigen::VectorXd>& x, int segment) {
  const Eigen::Index N = x.size();
  if (N < 4) throw InputError("a spectrum needs at least 4 samples");
  Eigen::Index n = segment;
  if (n <= 0) n = static_cast<Eigen::Index>(std::lround(std::exp2(std::round(std::log2(std::max(64.0, N / 8.0))))));
  n = std::min(n, N);
  const Eigen::Index step = std::max<Eigen::Index>(1, n / 2);
  const Eigen::Index count = (N - n) / step + 1;
  // Periodic Hann window, density scaling 1 / sum(w^2) (fs = 1).
  std::vector<double> w(static_cast<std::size_t>(n));
  double w2 = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    w[static_cast<std::size_t>(i)] = 0.5 - 0.5 * std::cos(2 * M_PI * static_cast<double>(i) / static_cast<double>(n));
    w2 += w[static_cast<std::size_t>(i)] * w[static_cast<std::size_t>(i)];
  }
  const Eigen::Index bins = n / 2;  // 1 .. n/2 (DC left out)
  Eigen::VectorXd P = Eigen::VectorXd::Zero(bins);
  Eigen::FFT<double> fft;
  std::vector<double> seg(static_cast<std::size_t>(n));
  std::vector<std::complex<double>> spec;
  for (Eigen::Index s = 0; s < count; ++s) {
    const auto part = x.segment(s * step, n);
    const double mean = part.mean();
    for (Eigen::Index i = 0; i < n; ++i) seg[static_cast<std::size_t>(i)] = (part[i] - mean) * w[static_cast<std::size_t>(i)];
    fft.fwd(spec, seg);
    for (Eigen::Index k = 1; k <= bins; ++k) {
      // One-sided: every bin doubled except Nyquist (even n).
      const double two = (n % 2 == 0 && k == bins) ? 1.0 : 2.0;
      P[k - 1] += two * std::norm(spec[static_cast<std::size_t>(k)]) / w2;
    }
  }
  WelchSpectrum r;
  r.density = P / static_cast<double>(count);
  r.frequency.resize(bins);
  for (Eigen::Index k = 1; k <= bins; ++k) r.frequency[k - 1] = static_cast<double>(k) / static_cast<double>(n);
  r.segment = static_cast<int>(n);
  r.segments = static_cast<int>(count);
  return r;
}

}  // namespace sets
