#pragma once
// Small simulated plants for the diagnosis tests: a truth model file simulated on random steps of
// one input, its outputs measured with white noise, paired with the nominal model that leaves
// something out.

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "sets/data/simulation.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "sets/models/model_file.hpp"

namespace sets::test {

struct StepInput {
  std::string column = "u";
  double lo = -2, hi = 2;          // levels
  double hold_lo = 0.5, hold_hi = 3;  // seconds
};

/// Time column "t", input `in.column`, every output of the truth measured with white noise of
/// `noise` times its standard deviation; a second record (another seed) for validation.
inline SyntheticPlant simulated_plant(const std::string& truth_json, const std::string& nominal_json, int n, double Ts,
                                      const StepInput& in, double noise, unsigned seed) {
  SyntheticPlant p;
  p.truth = parse_model(truth_json, "truth");
  p.nominal = parse_model(nominal_json, "nominal");
  for (int r = 0; r < 2; ++r) {
    std::mt19937 rng(seed + 1000u * static_cast<unsigned>(r));
    std::uniform_real_distribution<double> level(in.lo, in.hi), hold(in.hold_lo, in.hold_hi);
    std::vector<double> t(static_cast<std::size_t>(n)), u(static_cast<std::size_t>(n));
    double next = 0, value = level(rng);
    for (int k = 0; k < n; ++k) {
      t[static_cast<std::size_t>(k)] = k * Ts;
      if (k * Ts >= next) value = level(rng), next = k * Ts + hold(rng);
      u[static_cast<std::size_t>(k)] = value;
    }
    Recording rec;
    rec.source = r ? "validation" : "estimation";
    rec.add("t", t);
    rec.add(in.column, u);
    for (const auto& [sym, col] : p.truth.outputs)
      if (!rec.has(col)) rec.add(col, std::vector<double>(static_cast<std::size_t>(n), 0.0));
    Simulator sim(p.truth, rec, {10});
    const Eigen::MatrixXd y = sim.simulate(sim.parameter_values()).outputs;
    std::normal_distribution<double> e(0, 1);
    for (std::size_t j = 0; j < p.truth.outputs.size(); ++j) {
      const Eigen::VectorXd yj = y.col(static_cast<Eigen::Index>(j));
      const double sd = std::sqrt((yj.array() - yj.mean()).square().mean());
      std::vector<double> m(static_cast<std::size_t>(n));
      for (int k = 0; k < n; ++k) m[static_cast<std::size_t>(k)] = yj[k] + noise * sd * e(rng);
      rec.add(p.truth.outputs[j].second, m);
      if (r == 0) p.noise_sigma.push_back(noise * sd);
    }
    (r ? p.validation : p.estimation) = rec;
  }
  return p;
}

/// The whole diagnosis of a plant against its validation record, on one thread as the suite runs
/// each plant (o.threads is overridden).
inline Diagnosis diagnosed(const SyntheticPlant& p, DiagnosisOptions o = {}) {
  o.threads = 1;
  return diagnose(p.nominal, p.estimation, &p.validation, o);
}

}  // namespace sets::test
