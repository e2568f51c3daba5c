// The papers' example systems and data generators (include/sets/examples) and the synthetic
// plants of the diagnosis suite, as sets.examples.

#include <random>

#include "bindings.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/cerone_regruto.hpp"
#include "sets/examples/crane.hpp"
#include "sets/examples/farah.hpp"
#include "sets/examples/hakvoort.hpp"
#include "sets/examples/synthetic_plants.hpp"

namespace sets::python {

namespace {

// The generators draw from a std::mt19937_64; Python passes its seed (the apps seed run k of a
// study with seed * 1000003 + k).
void bind_farah(py::module_& m) {
  m.def("farah_system", &farah::system, "Farah et al., Section V: the printed A, B, C with D = 0.");
  m.def("farah_data",
        [](int samples, double snr_db, std::uint64_t seed, const std::string& noise) {
          if (noise != "gaussian" && noise != "uniform")
            throw InputError("farah_data: noise must be \"gaussian\" or \"uniform\", not \"" + noise + "\"");
          std::mt19937_64 rng(seed);
          farah::Data d;
          {
            py::gil_scoped_release release;
            d = farah::simulate(farah::system(), samples, snr_db, rng,
                                noise == "uniform" ? farah::Noise::uniform : farah::Noise::gaussian);
          }
          return std::make_pair(d.u, d.y);
        },
        py::arg("samples"), py::arg("snr_db"), py::arg("seed"), py::arg("noise") = "gaussian",
        "Farah et al., Section V: (u, y), a random binary input (samples x 2) and the noisy output\n"
        "(samples x 2) at snr_db per channel (Gaussian, or uniform of the same variance), from\n"
        "std::mt19937_64(seed) as sets-ss-uncertainty draws them.");
}

void bind_hakvoort(py::module_& m) {
  m.def("hakvoort_system", &hakvoort::system, "The order-4 example system of sets-hinf-bound.");
  m.def("hakvoort_data",
        [](int samples, double noise, bool bounded, std::uint64_t seed) {
          std::mt19937_64 rng(seed);
          const hakvoort::Data d = hakvoort::simulate(hakvoort::system(), samples, noise, bounded, rng);
          return std::make_pair(d.u, d.y);
        },
        py::arg("samples"), py::arg("noise"), py::arg("bounded") = false, py::arg("seed") = 1,
        "(u, y) of the order-4 system: u uniform in [-1, 1], coloured noise of level `noise`\n"
        "(Gaussian, or uniform with |e| <= noise when bounded), from std::mt19937_64(seed).");
  m.def("hakvoort_priors",
        [](const RationalModel& G, const OrthonormalBasis& basis, HinfPriors given) {
          std::string note;
          HinfPriors p = hakvoort::priors_for(G, basis, given, note);
          return std::make_pair(p, note);
        },
        py::arg("system"), py::arg("basis"), py::arg("given") = HinfPriors{},
        "Priors true for a known system (M and M_ic unless given > 0) and the check of the coefficient prior.");
}

void bind_cerone_regruto(py::module_& m) {
  m.def("cerone_regruto_structure", &cerone_regruto::structure,
        "Section IV's LPV system: a1 = a11 l; a2 = a21 + a22 l^2; b1 = b11; b2 = b21 l + b22 l^2.");
  m.def("cerone_regruto_theta", &cerone_regruto::true_theta, "Its true parameters, in the structure's order.");
  py::class_<cerone_regruto::Experiment>(m, "CeroneRegrutoExperiment", "The simulated experiment of Section IV.")
      .def_readonly("data", &cerone_regruto::Experiment::data, "what the method sees")
      .def_readonly("w", &cerone_regruto::Experiment::w, "noise-free output")
      .def_readonly("eta", &cerone_regruto::Experiment::eta)
      .def_readonly("lam", &cerone_regruto::Experiment::lambda)
      .def_readonly("eps", &cerone_regruto::Experiment::eps);
  m.def("cerone_regruto_experiment",
        [](int N, bool uniform_lambda, double delta, std::uint64_t seed) {
          std::mt19937_64 rng(seed);
          return cerone_regruto::simulate(N, uniform_lambda, delta, rng);
        },
        py::arg("N"), py::arg("uniform_lambda"), py::arg("delta"), py::arg("seed"),
        "N regressions of Section IV with errors uniform in [-delta, delta], from std::mt19937_64(seed).");
}

void bind_crane(py::module_& m) {
  m.def("crane_model", &crane::model, py::arg("lambda0") = 3.3, py::arg("kappa0") = 0.25, py::arg("b0") = 2.0,
        "Salehpour–Johansson's overhead crane (15) as model (1), h = 0.05 s.");
  m.def("crane_input", &crane::input, py::arg("kind"), py::arg("N"), py::arg("seed") = 1,
        "N samples of \"square\", \"prbs\" or \"multisine\" (|u| <= 1).");
  m.def("crane_window", &crane::window, "The paper's window norm: 36 samples, 1/35.");
  m.def("crane_noise", &crane::noise, py::arg("N"), py::arg("level"), py::arg("window"), py::arg("seed"),
        "White Gaussian output noise (N + 1 samples) scaled to the window norm `level`.");
}

}  // namespace

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
  bind_farah(m);
  bind_hakvoort(m);
  bind_cerone_regruto(m);
  bind_crane(m);
}

}  // namespace sets::python
