#include "sets/data/noise_level.hpp"

#include <unsupported/Eigen/FFT>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numeric>
#include <sstream>

#include "sets/data/bursts.hpp"
#include "sets/data/spectrum.hpp"

namespace sets {

const char* noise_method_name(NoiseMethod m) {
  switch (m) {
    case NoiseMethod::repeats: return "repeats";
    case NoiseMethod::residual_coloured: return "residual (coloured)";
    case NoiseMethod::residual_floor: return "residual (white floor)";
    case NoiseMethod::output_spectrum: return "output spectrum";
  }
  return "?";
}

namespace {

using Eigen::Index;
using Eigen::VectorXd;

std::string num(double x, int precision = 3) {
  std::ostringstream o;
  o.precision(precision);
  o << x;
  return o.str();
}

// numpy's median (the mean of the two middle values for an even count).
double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const std::size_t n = v.size(), h = n / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(h), v.end());
  if (n % 2) return v[h];
  const double hi = v[h];
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<long>(h)));
}

// ---- spectrum of the noise

// AR(1) density c / (1 + a^2 - 2 a cos 2 pi f) fitted to P over a band of octaves that starts as
// the top half and grows one octave at a time while every octave of the band keeps mean(P / S)
// within [1/1.5, 1.5] (1.5 is ~4 standard errors of a 30-dof Welch average over >= 4 bins). Signal
// and model error add to the noise's density, never take from it: once the shape holds over two
// octaves (a constrained), an octave above it by more than 1.5 is left out as theirs and the band
// looks further down; one below it ends the band, and the one that rejoins it below a gap must
// match the shape found above the gap. The noise variance is extrapolated under what
// was left out: c / (2 (1 - a^2)). The density is largest at the lowest frequencies (a >= 0), so
// the octave that ends the band must not lie below the shape in `upper`, a density the noise's
// cannot exceed (the raw residual's), in any octave from there down: there the noise would hold
// more than the residual does, and the shape above it is model error's, not the noise's (`below`).
// `contiguous`, `ended_above` and `lowest_unbent` describe the band's unbroken top part for the
// short-band rule of from_spectrum.
struct ArBand {
  double sigma = 0, a = 0, f_lo = 0.25;  // f_lo: lower edge of the lowest octave in the band
  int octaves = 1;                       // octaves in the band
  int skipped = 0;                       // octaves above f_lo left out as signal or model error
  bool below = false;                    // the band ended on an octave of `upper` below the shape
  int contiguous = 1;                    // octaves from the top before the first one left out
  bool ended_above = false;              // that top part ended on an octave above the shape
  bool lowest_unbent = false;            // its lowest octave matched the shape fitted without it
};

ArBand ar_band(const VectorXd& f, const VectorXd& P, const VectorXd& upper) {
  constexpr double a_max = 0.9, accept = 1.5;
  const Index nb = f.size();
  const VectorXd cw = (2 * M_PI * f).array().cos();
  auto shape = [&](double a, Index k) { return 1 + a * a - 2 * a * cw[k]; };
  // c(a) = mean(P D_a) over the band; a on a grid of 0.01 minimising the log-misfit.
  auto fit = [&](const std::vector<char>& band, double& a_best, double& c_best) {
    double best = 1e300;
    for (int g = 0; g <= 90; ++g) {
      const double a = a_max * g / 90.0;
      double c = 0;
      long n = 0;
      for (Index k = 0; k < nb; ++k)
        if (band[static_cast<std::size_t>(k)]) c += P[k] * shape(a, k), ++n;
      c /= static_cast<double>(std::max<long>(1, n));
      double mis = 0;
      for (Index k = 0; k < nb; ++k)
        if (band[static_cast<std::size_t>(k)]) {
          const double l = std::log(P[k] * shape(a, k) / c);
          mis += l * l;
        }
      mis /= static_cast<double>(std::max<long>(1, n));
      if (mis < best) best = mis, a_best = a, c_best = c;
    }
  };
  // Octave [lo, 2 lo) (the top one [1/4, 1/2] closed): its bins and its mean(P / S) under (a, c).
  auto in_octave = [&](double lo, Index k) { return f[k] >= lo && (lo >= 0.25 || f[k] < 2 * lo); };
  auto octave_ratio_of = [&](const VectorXd& D, double lo, double a, double c) {
    double sum = 0;
    long n = 0;
    for (Index k = 0; k < nb; ++k)
      if (in_octave(lo, k)) sum += D[k] * shape(a, k) / c, ++n;
    return n > 0 ? sum / static_cast<double>(n) : 1.0;
  };
  auto octave_ratio = [&](double lo, double a, double c) { return octave_ratio_of(P, lo, a, c); };
  // Every octave of `upper` from lo down (those of >= 4 bins, at least two) below the shape: one
  // octave of 4 Welch bins is only ~2 standard errors from 1/1.5 and white noise's own residual
  // falls there by chance (random plants 900 009, 900 013, the truth's residual); two cannot.
  auto below_to_the_end = [&](double lo, double a, double c) {
    int octaves_below = 0;
    for (double o = lo;; o /= 2) {
      long bins = 0;
      for (Index k = 0; k < nb; ++k) bins += in_octave(o, k) ? 1 : 0;
      if (bins < 4) break;
      if (octave_ratio_of(upper, o, a, c) >= 1 / accept) return false;
      ++octaves_below;
    }
    return octaves_below >= 2;
  };
  ArBand r;
  std::vector<char> band(static_cast<std::size_t>(nb));
  for (Index k = 0; k < nb; ++k) band[static_cast<std::size_t>(k)] = f[k] >= r.f_lo;
  std::vector<double> octaves{0.25};  // lower edges of the octaves in the band
  bool after_gap = false;             // the octave above the one tried was left out
  double c = 0;
  fit(band, r.a, c);
  for (double nf = r.f_lo / 2;; nf /= 2) {
    std::vector<char> grown = band;
    long added = 0;
    for (Index k = 0; k < nb; ++k)
      if (in_octave(nf, k)) grown[static_cast<std::size_t>(k)] = 1, ++added;
    if (added < 4) break;
    double a2 = 0, c2 = 0;
    fit(grown, a2, c2);
    bool holds = true;
    for (double lo : octaves) holds = holds && std::abs(std::log(octave_ratio(lo, a2, c2))) <= std::log(accept);
    holds = holds && std::abs(std::log(octave_ratio(nf, a2, c2))) <= std::log(accept);
    // The octave just below a gap must match the shape found above it, not bend it: a refit can
    // swing a far enough to meet model error further down.
    holds = holds && (!after_gap || std::abs(std::log(octave_ratio(nf, r.a, c))) <= std::log(accept));
    if (holds) {
      if (r.skipped == 0) r.lowest_unbent = std::abs(std::log(octave_ratio(nf, r.a, c))) <= std::log(accept);
      band = grown, octaves.push_back(nf), r.f_lo = nf, r.a = a2, c = c2, after_gap = false;
      continue;
    }
    if (octaves.size() < 2) break;
    if (r.skipped == 0) r.contiguous = static_cast<int>(octaves.size());
    if (octave_ratio(nf, r.a, c) <= accept) {
      r.below = below_to_the_end(nf, r.a, c);
      break;
    }
    r.ended_above = r.ended_above || r.skipped == 0;
    ++r.skipped, after_gap = true;
  }
  if (r.skipped == 0) r.contiguous = static_cast<int>(octaves.size());
  r.octaves = static_cast<int>(octaves.size());
  r.sigma = std::sqrt(c / (2 * (1 - r.a * r.a)));
  return r;
}

// Colour is believed only when the AR(1) shape holds from f = 1/32 to 1/2: by then it has risen
// above its Nyquist value by 3.4x (a = 0.3) to 81x (a = 0.9), so a is well constrained. With
// octaves left out between, it must still hold on as many (4) as without: model error decaying
// towards Nyquist can mimic the shape over the top two octaves and one more further down.
constexpr double colour_gate = 1.0 / 32;
constexpr int colour_octaves = 4;

// Or when the shape holds unbroken over the top three octaves (to 1/16, where it has risen 3x at
// a = 0.3 and 25x at a = 0.9) and the band ends on an octave ABOVE it: model error only adds, so
// an octave holding more than the shape is the model's, and the noise under it is the shape's
// (random plant 5 004 769: AR(1) noise, a = 0.75, under the low-frequency error a named Stribeck
// law leaves from 1/32 down; the white floor read 0.36x). The lowest of the three must match the
// shape fitted on the two above it: model error rising into it otherwise bends the refit towards
// a = 0.9 and the extrapolation multiplies it (synthetic: white noise read 1.2x, a = 0.3 noise 3.2x).
constexpr int short_band_octaves = 3;
bool colour_verified(const ArBand& ar) {
  const bool long_band = ar.f_lo <= colour_gate && ar.octaves >= colour_octaves;
  const bool short_band = ar.contiguous >= short_band_octaves && ar.ended_above && ar.lowest_unbent;
  return (long_band || short_band) && !ar.below;
}

struct SpectralReading {
  double sigma = 0, ar_pole = 0;
  bool coloured = false;
  std::string reason;
};

// The noise in one or more signals that all carry it (y itself, or the raw and the projected
// residual): per-bin minimum of their Welch densities, then the AR(1) extrapolation if its shape
// is verified, else the lower of the white floor of the top 1/8 band and the difference plateau.
// `bursts`: the first signal's fast part has bursts (sets/data/bursts.hpp), which noise does not
// make; their power spreads over every frequency and can take the AR(1) shape (random plant
// 5 004 294: a switching model error read as a = 0.9 noise 7.5x the truth), so the shape is not
// believed and the clipped differences, which drop the bursts, can read the noise.
// `quantiser` (q / sqrt(12) of a quantised output, else 0): a busy quantiser's error is white with
// that RMS, and any AR(1) noise under it (a <= 0.9) puts at least (1 - a) / (1 + a) of its own white
// density into the top band, and dithers the quantiser once it matters (RMS above q / 2). So when the
// top band's white floor is no more than the quantiser's, the data hold no noise beyond the
// quantisation: a shape read lower down is model error's, or the quantisation error of a slow signal
// (which is coloured and bounded by q / 2), and the level read is the quantiser's, not the shape
// extrapolated (random plants 5 004 919, 5 005 025: a position loop and a thermal node with quantised
// outputs, the final model's low-frequency error read as AR(1) noise 2.95x and 2.18x the truth). The
// pole stays: a slow signal's quantisation error is coloured, and the residual tests whiten by it
// (without it four clean plants of 5 004 900 - 5 005 199 lost "no physics is missing").
SpectralReading from_spectrum(const std::vector<VectorXd>& signals, bool bursts = false, double quantiser = 0) {
  WelchSpectrum s = welch_spectrum(signals.front());
  const VectorXd first = s.density;  // what the noise's density cannot exceed (y, or the raw residual)
  for (std::size_t i = 1; i < signals.size(); ++i) s.density = s.density.cwiseMin(welch_spectrum(signals[i]).density);
  SpectralReading out;
  std::vector<double> top;  // 0.98: median / mean of a 30-dof chi-square
  for (Index k = 0; k < s.frequency.size(); ++k)
    if (s.frequency[k] >= 0.5 * (1 - 1.0 / 8)) top.push_back(s.density[k]);
  const double floor = std::sqrt(0.5 * median(top) / 0.98);
  const bool quantiser_only = quantiser > 0 && floor <= quantiser;
  const ArBand ar = ar_band(s.frequency, s.density, first);
  if (colour_verified(ar) && !bursts) {
    out.sigma = ar.sigma;
    out.ar_pole = ar.a;
    out.coloured = true;
    out.reason = "AR(1) a = " + num(ar.a, 2) + " fits the spectrum from f = " + num(ar.f_lo, 3) + " to 0.5 cycles/sample";
    if (quantiser_only) {  // the residual's colour stays, for whitening; its level is the quantiser's
      out.sigma = quantiser;
      out.reason += ", but the top band holds no more than the quantiser's white error: its RMS q/sqrt(12), not the shape extrapolated";
      return out;
    }
    if (ar.f_lo > colour_gate)
      out.reason += " (three octaves; the " + std::to_string(ar.skipped) + " below hold more than the shape: signal or model error)";
    else if (ar.skipped > 0)
      out.reason += " (" + std::to_string(ar.skipped) + " octave(s) between left out: more power than the shape, signal or model error)";
    return out;
  }
  double plateau = 1e300;
  int order = 0;
  for (const auto& x : signals) {
    const DifferencePlateau p = difference_plateau(x);
    if (p.sigma < plateau) plateau = p.sigma, order = p.order;
  }
  const std::string held = bursts ? " (bursts in the fast part: no AR(1) shape believed)"
                           : ar.below ? " (AR(1) shape held down to f = " + num(ar.f_lo, 3) + ", the residual below it further down: not the noise's shape)"
                           : ar.skipped == 0 ? " (AR(1) shape held only above f = " + num(ar.f_lo, 3) + ")"
                                           : " (AR(1) shape held on " + std::to_string(ar.octaves) + " octaves down to f = " + num(ar.f_lo, 3) +
                                                 ", " + std::to_string(ar.skipped) + " left out between: fewer than " + std::to_string(colour_octaves) + ")";
  if (floor <= plateau) {
    out.sigma = floor;
    out.reason = "white floor of the top 1/8 band" + held;
  } else {
    out.sigma = plateau;
    out.reason = "plateau of the " + std::to_string(order) + "-th difference" + held;
  }
  return out;
}

// ---- the calibrated model's residual

// r minus its least-squares fit by two-sided FIRs (lags -3 .. L-1) of each regressor (standardised)
// and a constant, over the rows where every lag exists; returns the projected residual and the
// number of fitted parameters. The normal equations are accumulated in blocks of rows (the
// regressor matrix of a long record would not fit in memory) and solved by a symmetric
// eigen-decomposition that drops directions below 1e-12 of the largest (lags of a smooth signal
// are nearly collinear).
VectorXd project_residual(const VectorXd& r, const std::vector<VectorXd>& regressors, int L, int& parameters) {
  const Index N = r.size(), lags = L + 3;
  std::vector<VectorXd> z;
  for (const auto& c : regressors) {
    const double mean = c.mean();
    const double sd = std::sqrt((c.array() - mean).square().mean());
    if (!(sd > 0)) continue;  // a constant regressor carries nothing
    z.push_back((c.array() - mean) / sd);
  }
  const Index p = 1 + static_cast<Index>(z.size()) * lags;
  parameters = static_cast<int>(p);
  const Index first = L, last = N - 3;  // rows [first, last)
  constexpr Index block = 1024;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(p, p);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> X(block, p);
  auto fill_row = [&](Index t, Index i) {
    X(i, 0) = 1;
    for (std::size_t c = 0; c < z.size(); ++c)
      for (Index l = -3; l < L; ++l) X(i, 1 + static_cast<Index>(c) * lags + (l + 3)) = z[c][t - l];
  };
  VectorXd h = VectorXd::Zero(p);
  for (Index t0 = first; t0 < last; t0 += block) {
    const Index b = std::min(block, last - t0);
    for (Index i = 0; i < b; ++i) fill_row(t0 + i, i);
    G.selfadjointView<Eigen::Lower>().rankUpdate(X.topRows(b).transpose());
    h += X.topRows(b).transpose() * r.segment(t0, b);
  }
  G = G.selfadjointView<Eigen::Lower>();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G);
  const VectorXd& lambda = eig.eigenvalues();
  const double cut = 1e-12 * lambda.cwiseAbs().maxCoeff();
  VectorXd coeff = eig.eigenvectors().transpose() * h;
  for (Index k = 0; k < p; ++k) coeff[k] = lambda[k] > cut ? coeff[k] / lambda[k] : 0.0;
  const VectorXd beta = eig.eigenvectors() * coeff;
  VectorXd e(last - first);
  for (Index t0 = first; t0 < last; t0 += block) {
    const Index b = std::min(block, last - t0);
    for (Index i = 0; i < b; ++i) fill_row(t0 + i, i);
    e.segment(t0 - first, b) = r.segment(t0, b) - X.topRows(b) * beta;
  }
  return e;
}

// The calibrated model's residual r = y - simulated: raw (the rows the projection keeps), projected
// off the FIRs of project_residual, and the projected residual's RMS with the fitted parameters'
// degrees of freedom removed. The noise is independent of the inputs, so E[upper^2] >= sigma^2:
// an upper bound in expectation (noise plus what the model leaves unexplained).
struct ResidualReading {
  VectorXd raw, projected;
  int parameters = 0;
  double upper = 0;
};

ResidualReading read_residual(const VectorXd& r, const VectorXd& simulated, const Eigen::Ref<const Eigen::MatrixXd>& inputs) {
  const Index N = r.size();
  const int L = static_cast<int>(std::min<Index>(64, std::max<Index>(8, N / 200)));
  const VectorXd s = simulated.array() - simulated.mean();
  std::vector<VectorXd> regressors{simulated, s.array().square(), s.array().cube()};
  for (Index j = 0; inputs.rows() == N && j < inputs.cols(); ++j) regressors.emplace_back(inputs.col(j));
  ResidualReading out;
  out.projected = project_residual(r, regressors, L, out.parameters);
  out.raw = r.segment(L, N - 3 - L);
  const double dof = static_cast<double>(out.projected.size() - out.parameters);
  out.upper = dof > 0 ? std::sqrt(out.projected.squaredNorm() / dof) : std::sqrt(out.raw.squaredNorm() / static_cast<double>(out.raw.size()));
  return out;
}

}  // namespace

double lattice_step(const Eigen::Ref<const Eigen::VectorXd>& y) {
  double smallest = std::numeric_limits<double>::infinity();
  long steps = 0;
  for (Index k = 1; k < y.size(); ++k) {
    const double d = std::abs(y[k] - y[k - 1]);
    if (d > 0) smallest = std::min(smallest, d), ++steps;
  }
  if (steps == 0) return 0;
  auto on_lattice = [&](double q) {
    for (Index k = 0; k < y.size(); ++k) {
      const double z = (y[k] - y[0]) / q;
      if (std::abs(z - std::round(z)) >= 1e-3) return false;
    }
    return true;
  };
  // The smallest step itself on a busy output (>= 10 steps), whatever its number of levels.
  if (steps >= 10 && on_lattice(smallest)) return smallest;
  // Otherwise the smallest step or a fraction of it (an output that crosses several levels between
  // samples, 5 006 649; or one that sits on a level for long stretches and steps rarely,
  // 5 007 815, whose residual was then read as noise at 1e-14 of the truth): only with >= 5
  // distinct values, so that values that fall on one of these 64 lattices to 1e-3 by chance
  // (probability <= 64 (2e-3)^(5 - 2), about 5e-7) are not taken for a quantiser.
  std::vector<double> sorted(y.data(), y.data() + y.size());
  std::sort(sorted.begin(), sorted.end());
  if (std::unique(sorted.begin(), sorted.end()) - sorted.begin() < 5) return 0;
  for (int divisor = 1; divisor <= 64; ++divisor)
    if (on_lattice(smallest / divisor)) return smallest / divisor;
  return 0;
}

DifferencePlateau difference_plateau(const Eigen::Ref<const Eigen::VectorXd>& x) {
  static const double central_binomial[] = {2, 6, 20, 70, 252, 924, 3432, 12870};  // C(2m, m)
  std::vector<double> s;
  VectorXd d = x;
  for (int m = 1; m <= 8 && d.size() > 1; ++m) {
    d = (d.tail(d.size() - 1) - d.head(d.size() - 1)).eval();
    s.push_back(clipped_rms(d) / std::sqrt(central_binomial[m - 1]));
  }
  if (s.empty()) return {};
  // For white noise sigma_{m+1} / sigma_m = 1; each further order multiplies a signal's share by
  // about sin(pi f) < 1, so a fall of more than 10 % means signal still dominates sigma_m.
  std::size_t pick = s.size() - 1;
  for (std::size_t i = 0; i + 1 < s.size(); ++i)
    if (s[i + 1] > 0.9 * s[i]) {
      pick = i;
      break;
    }
  return {s[pick], static_cast<int>(pick) + 1};
}

InputRepeats detect_repeats(const Eigen::Ref<const Eigen::MatrixXd>& inputs) {
  InputRepeats none;
  const Index N = inputs.rows();
  // Standardised non-constant inputs; a window matches when all of them repeat together.
  std::vector<VectorXd> x;
  for (Index j = 0; j < inputs.cols(); ++j) {
    const VectorXd c = inputs.col(j).array() - inputs.col(j).mean();
    const double sd = std::sqrt(c.squaredNorm() / static_cast<double>(std::max<Index>(1, N)));
    if (sd > 0) x.push_back(c / sd);
  }
  if (x.empty() || N < 64) return none;
  // Autocorrelation (FFT, zero-padded), summed over the inputs and normalised.
  Index nfft = 1;
  while (nfft < 2 * N) nfft *= 2;
  Eigen::FFT<double> fft;
  std::vector<double> ac(static_cast<std::size_t>(N), 0.0);
  {
    std::vector<double> pad(static_cast<std::size_t>(nfft));
    std::vector<std::complex<double>> F;
    std::vector<double> back;
    for (const auto& c : x) {
      std::fill(pad.begin(), pad.end(), 0.0);
      for (Index i = 0; i < N; ++i) pad[static_cast<std::size_t>(i)] = c[i];
      fft.fwd(F, pad);
      for (auto& v : F) v = std::norm(v);
      fft.inv(back, F);
      for (Index i = 0; i < N; ++i) ac[static_cast<std::size_t>(i)] += back[static_cast<std::size_t>(i)];
    }
  }
  const double ac0 = ac[0];
  if (!(ac0 > 0)) return none;
  for (auto& v : ac) v /= ac0;
  Index Lc = -1;  // correlation length: first lag below 0.5
  for (Index i = 0; i < N; ++i)
    if (ac[static_cast<std::size_t>(i)] < 0.5) {
      Lc = i;
      break;
    }
  if (Lc < 0) return none;
  // >= ~16 independent input values per window: a binary input matches by chance with ~2^-16.
  const Index W = std::max<Index>(32, 32 * Lc);
  const Index lo = std::max<Index>(2 * Lc, 8), hi = N - 8 * W;
  if (hi - lo < 3) return none;
  std::vector<std::pair<double, Index>> peaks;
  for (Index i = lo + 1; i + 1 < hi; ++i) {
    const double v = ac[static_cast<std::size_t>(i)];
    if (v > ac[static_cast<std::size_t>(i - 1)] && v >= ac[static_cast<std::size_t>(i + 1)]) peaks.emplace_back(v, i);
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  if (peaks.size() > 5) peaks.resize(5);
  double mean_energy = 0;
  for (const auto& c : x) mean_energy += c.squaredNorm();
  mean_energy /= static_cast<double>(N);
  InputRepeats best;
  for (const auto& [value, P] : peaks) {
    (void)value;
    const Index M = N - P;  // pairs (n, n + P)
    // Prefix sums of (a - b)^2, a^2, b^2 over all inputs, a = x[n + P], b = x[n].
    std::vector<double> d2(static_cast<std::size_t>(M + 1), 0.0), ea(d2), eb(d2);
    for (Index n = 0; n < M; ++n) {
      double dd = 0, aa = 0, bb = 0;
      for (const auto& c : x) {
        const double a = c[n + P], b = c[n];
        dd += (a - b) * (a - b), aa += a * a, bb += b * b;
      }
      const auto u = static_cast<std::size_t>(n);
      d2[u + 1] = d2[u] + dd, ea[u + 1] = ea[u] + aa, eb[u + 1] = eb[u] + bb;
    }
    std::vector<int> cover(static_cast<std::size_t>(M + 1), 0);  // difference array of the mask
    for (Index n = 0; n + W <= M; ++n) {
      const auto a = static_cast<std::size_t>(n), b = static_cast<std::size_t>(n + W);
      const double wd = d2[b] - d2[a], wa = ea[b] - ea[a], wb = eb[b] - eb[a];
      const double floor = 0.1 * static_cast<double>(W) * mean_energy;
      if (1 - wd / (wa + wb + 1e-300) > 0.99 && wa > floor && wb > floor) ++cover[a], --cover[b];
    }
    InputRepeats r;
    r.lag = static_cast<int>(P);
    r.mask.assign(static_cast<std::size_t>(M), 0);
    int run = 0;
    for (Index n = 0; n < M; ++n) {
      run += cover[static_cast<std::size_t>(n)];
      if (run > 0) r.mask[static_cast<std::size_t>(n)] = 1, ++r.matched;
    }
    if (r.matched >= 2 * W && r.matched > best.matched) best = std::move(r);
  }
  return best;
}

double sigma_from_repeats(const Eigen::Ref<const Eigen::VectorXd>& y, const InputRepeats& rep) {
  const Index P = rep.lag, M = static_cast<Index>(rep.mask.size());
  std::vector<Index> idx;
  for (Index n = 0; n < M; ++n)
    if (rep.mask[static_cast<std::size_t>(n)]) idx.push_back(n);
  if (idx.empty()) return 0;
  auto d = [&](Index n) { return (y[n + P] - y[n]) / std::sqrt(2.0); };
  double mean = 0;
  for (Index n : idx) mean += d(n);
  mean /= static_cast<double>(idx.size());
  // Runs of consecutive matched samples, cut into blocks of max(16, shortest run / 8).
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // [begin, end) into idx
  for (std::size_t i = 0; i < idx.size();) {
    std::size_t j = i + 1;
    while (j < idx.size() && idx[j] == idx[j - 1] + 1) ++j;
    runs.emplace_back(i, j);
    i = j;
  }
  std::size_t shortest = idx.size();
  for (const auto& [a, b] : runs) shortest = std::min(shortest, b - a);
  const std::size_t block = std::max<std::size_t>(16, shortest / 8);
  std::vector<double> ms;
  for (const auto& [a, b] : runs) {
    const std::size_t len = b - a, pieces = std::max<std::size_t>(1, len / block);
    // numpy.array_split: the first len % pieces pieces hold one sample more.
    std::size_t start = a;
    for (std::size_t k = 0; k < pieces; ++k) {
      const std::size_t size = len / pieces + (k < len % pieces ? 1 : 0);
      double s = 0;
      for (std::size_t i = start; i < start + size; ++i) s += (d(idx[i]) - mean) * (d(idx[i]) - mean);
      ms.push_back(s / static_cast<double>(size));
      start += size;
    }
  }
  // Blocks above 4 x the median block hold the plant's transient after the input starts repeating.
  const double med = median(ms);
  double sum = 0;
  long kept = 0;
  for (double v : ms)
    if (v <= 4 * med) sum += v, ++kept;
  return std::sqrt(sum / static_cast<double>(std::max<long>(1, kept)));
}

namespace {

// The share of the inputs' repeat difference x(n + P) - x(n) over the matched samples that their
// centred derivative explains (R^2 of a one-column least squares, summed over the inputs). A near
// repeat is a phase drift, whose difference is the derivative times the drift (near 1); an exact
// repeat's difference is the inputs' own noise (near 0).
double drift_share(const Eigen::Ref<const Eigen::MatrixXd>& inputs, const InputRepeats& rep) {
  double dd = 0, dg = 0;
  const Index M = static_cast<Index>(rep.mask.size());
  for (Index j = 0; j < inputs.cols(); ++j) {
    double a = 0, b = 0, c = 0;
    for (Index n = 1; n + 1 < M; ++n) {
      if (!rep.mask[static_cast<std::size_t>(n)]) continue;
      const double d = inputs(n + rep.lag, j) - inputs(n, j), g = 0.5 * (inputs(n + 1, j) - inputs(n - 1, j));
      a += d * d, b += d * g, c += g * g;
    }
    dd += a, dg += (c > 0 ? b * b / c : 0);
  }
  return dd > 0 ? dg / dd : 0;
}

}  // namespace

NoiseLevelEstimate estimate_noise(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& simulated,
                                  const Eigen::Ref<const Eigen::MatrixXd>& inputs) {
  NoiseLevelEstimate out;
  const Index N = y.size();
  const bool have_model = simulated.size() == N && N > 0;
  const bool have_inputs = inputs.rows() == N && inputs.cols() > 0;
  out.quantisation_step = lattice_step(y);
  const double q = out.quantisation_step;
  const double quantiser = q / std::sqrt(12.0);  // the quantisation error's RMS once levels are crossed
  // Quantisation repeats with the signal, so a quantised output's repeat difference is not its noise.
  if (have_inputs && q == 0) {
    const InputRepeats rep = detect_repeats(inputs);
    if (rep.matched > 0) {
      const std::string found = "the inputs repeat with a lag of " + std::to_string(rep.lag) + " samples over " +
                                std::to_string(rep.matched) + " samples";
      // An input that only nearly repeats (a sine whose period is no whole number of samples)
      // leaves the signal's change over the lag in the repeat difference, and the input's own
      // repeat difference is then its derivative times the phase short: the residual is read
      // instead. Capping such repeats at the model's projected residual RMS read the model error
      // as noise (random plant 700 069: 10x the truth, a strong Stribeck law then failing the
      // noise rule).
      if (drift_share(inputs, rep) > 0.5) {
        out.reason = found + ", but their difference is a phase drift (explained by their derivative), not noise; ";
      } else {
        out.sigma = sigma_from_repeats(y, rep);
        out.method = NoiseMethod::repeats;
        out.reason = found;
        // The residual's repeat difference drops the part of y's change over the lag that the
        // model simulates (its response to the inputs' own non-repeat); it and y's are each the
        // noise plus something independent of it, and the lower is kept.
        if (have_model) {
          const double of_residual = sigma_from_repeats(y - simulated, rep);
          if (of_residual < out.sigma) {
            out.sigma = of_residual;
            out.reason += " (read on the model's residual, which drops the signal's change over the lag)";
          }
        }
        return out;
      }
    }
  }
  const VectorXd r = have_model ? VectorXd(y - simulated) : VectorXd(y);
  if (N < 64) {  // too short for a spectrum
    const DifferencePlateau p = difference_plateau(r);
    out.sigma = p.sigma;
    out.method = have_model ? NoiseMethod::residual_floor : NoiseMethod::output_spectrum;
    out.reason += "plateau of the " + std::to_string(p.order) + "-th difference (" + std::to_string(N) + " samples: too few for a spectrum)";
  } else if (have_model) {
    const ResidualReading rr = read_residual(r, simulated, inputs);
    const double dof = static_cast<double>(rr.projected.size() - rr.parameters);
    const bool bursts = burst_ratio(rr.raw) > kBurstRatioLimit;
    const SpectralReading sp = dof > rr.parameters ? from_spectrum({rr.raw, rr.projected}, bursts, quantiser)
                                                   : from_spectrum({rr.raw}, bursts, quantiser);
    out.sigma = sp.sigma;
    out.method = sp.coloured ? NoiseMethod::residual_coloured : NoiseMethod::residual_floor;
    out.ar_pole = sp.ar_pole;
    out.reason += "residual of the model: " + sp.reason;
    if (out.sigma > rr.upper) {
      out.sigma = rr.upper;
      out.reason += "; capped by the projected residual's RMS";
    }
  } else {
    const SpectralReading sp = from_spectrum({r}, false, quantiser);
    out.sigma = sp.sigma;
    out.method = NoiseMethod::output_spectrum;
    out.ar_pole = sp.ar_pole;
    out.reason += "spectrum of the output: " + sp.reason;
  }
  if (out.sigma < quantiser) {
    out.sigma = quantiser;
    out.reason += "; raised to the quantisation floor q/sqrt(12), q = " + num(q);
  }
  return out;
}

std::size_t most_reliable(const std::vector<NoiseLevelEstimate>& estimates) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < estimates.size(); ++i)
    if (static_cast<int>(estimates[i].method) < static_cast<int>(estimates[best].method)) best = i;
  return best;
}

}  // namespace sets
