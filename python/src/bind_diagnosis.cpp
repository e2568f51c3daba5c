// The discrepancy diagnosis. Python's sets.diagnose() (sets/__init__.py) wraps _diagnose into a
// dict with the structure of the JSON of sets-diagnose, plus the signals for plots.

#include <pybind11/functional.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/diagnosis/report_html.hpp"

namespace sets::python {

void bind_diagnosis(py::module_& m) {
  py::class_<DiagnosisOptions> o(m, "DiagnosisOptions", "Options of diagnose() (see docs/methods/diagnosis.md).");
  with_keywords(o);
  o.def_readwrite("screening_substeps", &DiagnosisOptions::screening_substeps)
      .def_readwrite("final_substeps", &DiagnosisOptions::final_substeps)
      .def_readwrite("max_effects", &DiagnosisOptions::max_effects)
      .def_readwrite("min_cost_reduction", &DiagnosisOptions::min_cost_reduction)
      .def_readwrite("sparsity_tolerance", &DiagnosisOptions::sparsity_tolerance)
      .def_readwrite("noise_floor_factor", &DiagnosisOptions::noise_floor_factor)
      .def_readwrite("threads", &DiagnosisOptions::threads)
      .def_readwrite("varying_segments", &DiagnosisOptions::varying_segments)
      .def_readwrite("progress", &DiagnosisOptions::progress, "callable(str), one line per stage (optional)");
  py::class_<Diagnosis>(m, "DiagnosisData", "The C++ diagnosis (use sets.diagnose(), which returns a dict).")
      .def("json_text", &diagnosis_json, py::arg("augmented_path") = "", "The JSON of sets-diagnose.")
      .def("text", &diagnosis_text, "The terminal report.")
      .def("html",
           [](const Diagnosis& d, const std::vector<std::pair<std::string, std::string>>& figures,
              const std::string& augmented_path) {
             std::vector<ReportFigure> f;
             for (const auto& [file, caption] : figures) f.push_back({file, caption});
             return diagnosis_html(d, f, augmented_path);
           },
           py::arg("figures"), py::arg("augmented_path") = "augmented_model.json",
           "The report page of sets-diagnose --report; figures: (file, caption) pairs.")
      .def_readonly("outputs", &Diagnosis::outputs)
      .def_readonly("nominal", &Diagnosis::nominal)
      .def_readonly("augmented", &Diagnosis::augmented)
      .def_readonly("has_validation", &Diagnosis::has_validation)
      .def_readonly("error_bound", &Diagnosis::error_bound)
      .def_readonly("time_estimation", &Diagnosis::time_estimation)
      .def_readonly("time_validation", &Diagnosis::time_validation)
      .def_readonly("measured_estimation", &Diagnosis::measured_estimation)
      .def_readonly("nominal_estimation", &Diagnosis::nominal_estimation)
      .def_readonly("augmented_estimation", &Diagnosis::augmented_estimation)
      .def_readonly("measured_validation", &Diagnosis::measured_validation)
      .def_readonly("nominal_validation", &Diagnosis::nominal_validation)
      .def_readonly("augmented_validation", &Diagnosis::augmented_validation)
      .def_readonly("signature_variable", &Diagnosis::signature_variable)
      .def_readonly("signature_x", &Diagnosis::signature_x)
      .def_readonly("signature_residual", &Diagnosis::signature_residual)
      .def_readonly("signature_output", &Diagnosis::signature_output);
  m.def("_diagnose",
        [](const ModelFile& model, const Recording& estimation, std::optional<Recording> validation,
           const DiagnosisOptions& options) {
          py::gil_scoped_release release;
          return diagnose(model, estimation, validation ? &*validation : nullptr, options);
        },
        py::arg("model"), py::arg("data"), py::arg("validation") = py::none(), py::arg("options") = DiagnosisOptions{});
}

}  // namespace sets::python
