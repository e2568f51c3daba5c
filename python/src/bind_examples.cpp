// The papers' example systems and the synthetic plants (sets.examples).

#include <random>

#include "bindings.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"

namespace sets::python {

void bind_examples(py::module_& parent) {
  py::module_ m = parent.def_submodule("examples", "The papers' example systems and the synthetic plants.");
  py::class_<SyntheticPlant>(m, "SyntheticPlant",
                             "A plant simulated with one catalogue effect (or none) and the nominal model file\n"
                             "that leaves it out (the diagnosis suite).")
      .def_readonly("name", &SyntheticPlant::name)
      .def_readonly("true_effect", &SyntheticPlant::true_effect)
      .def_readonly("nominal", &SyntheticPlant::nominal)
      .def_readonly("truth", &SyntheticPlant::truth)
      .def_readonly("estimation", &SyntheticPlant::estimation)
      .def_readonly("validation", &SyntheticPlant::validation)
      .def_readonly("true_values", &SyntheticPlant::true_values);
  m.def("synthetic_plant_names", &synthetic_plant_names);
  m.def("synthetic_plant", &synthetic_plant, py::arg("name"), release_gil(),
        "Generates one plant (deterministic); InputError for an unknown name.");
  m.def("farah_system", &farah_example_system, "Farah et al., Section V: the printed A, B, C with D = 0.");
  m.def("hakvoort_system", &hinf_example_system, "The order-4 example system of sets-hinf-bound.");
  m.def("farah_data",
        [](int samples, double snr_db, std::uint64_t seed) {
          // The data of one run of sets-ss-uncertainty's Monte Carlo study, drawn exactly as the app
          // draws them (the app seeds run k with seed * 1000003 + k).
          const StateSpaceModel sys = farah_example_system();
          std::mt19937_64 rng(seed);
          std::bernoulli_distribution coin(0.5);
          std::normal_distribution<double> gauss(0.0, 1.0);
          Eigen::MatrixXd u(samples, 2);
          for (int t = 0; t < samples; ++t)
            for (int k = 0; k < 2; ++k) u(t, k) = coin(rng) ? 1.0 : -1.0;
          Eigen::MatrixXd y = simulate(sys, u);
          for (Eigen::Index j = 0; j < y.cols(); ++j) {
            const double var = (y.col(j).array() - y.col(j).mean()).square().mean();
            const double sigma = std::sqrt(var / std::pow(10.0, snr_db / 10.0));
            for (int t = 0; t < samples; ++t) y(t, j) += sigma * gauss(rng);
          }
          return std::make_pair(u, y);
        },
        py::arg("samples"), py::arg("snr_db"), py::arg("seed"),
        "Farah et al., Section V: a random binary input (samples x 2) and the noisy output (samples x 2)\n"
        "at snr_db per channel, from std::mt19937_64(seed) as sets-ss-uncertainty draws them.");
}

}  // namespace sets::python
