// Model files, recordings (columns as numpy arrays) and the simulator.

#include <pybind11/numpy.h>

#include "bindings.hpp"
#include "sets/data/noise_level.hpp"
#include "sets/core/error.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

namespace sets::python {

namespace {

py::array_t<double> column_array(const std::vector<double>& c) { return py::array_t<double>(c.size(), c.data()); }

void bind_model_file(py::module_& m) {
  py::class_<ModelParameter>(m, "ModelParameter", "A parameter of a model file.")
      .def(py::init<>())
      .def_readwrite("name", &ModelParameter::name)
      .def_readwrite("value", &ModelParameter::value)
      .def_readwrite("fixed", &ModelParameter::fixed)
      .def_readwrite("min", &ModelParameter::min, "lower bound (-1e300: none)")
      .def_readwrite("max", &ModelParameter::max, "upper bound (1e300: none)")
      .def("__repr__", [](const ModelParameter& p) {
        return "ModelParameter(" + p.name + " = " + std::to_string(p.value) + (p.fixed ? ", fixed)" : ")");
      });
  py::class_<ModelState>(m, "ModelState")
      .def(py::init<>())
      .def_readwrite("name", &ModelState::name)
      .def_readwrite("initial_value", &ModelState::initial_value)
      .def_readwrite("initial_column", &ModelState::initial_column);
  py::class_<ModelFile>(m, "ModelFile",
                        "A continuous-time model written by an engineer (docs/model-format.md): parameters,\n"
                        "states, signals, derivatives and the recording columns it is compared against.\n"
                        "Named lists (inputs, signals, sampled, derivatives, outputs) are lists of (name, text).")
      .def(py::init<>())
      .def_static("parse", &parse_model, py::arg("text"), py::arg("source") = "<model>",
                  "Parses the JSON text (InputError with line and column, or the bad field).")
      .def_static("load", &load_model_file, py::arg("path"), "Reads a model file.")
      .def("to_json_text", [](const ModelFile& f) { return to_json_text(f); }, "The model file's JSON text.")
      .def("save", [](const ModelFile& f, const std::string& path) { save_model_file(f, path); }, py::arg("path"),
           "Writes the model file (complete or not at all).")
      .def_readwrite("name", &ModelFile::name)
      .def_readwrite("time_column", &ModelFile::time_column)
      .def_readwrite("sample_time", &ModelFile::sample_time)
      .def_readwrite("inputs", &ModelFile::inputs)
      .def_readwrite("parameters", &ModelFile::parameters)
      .def_readwrite("states", &ModelFile::states)
      .def_readwrite("signals", &ModelFile::signals)
      .def_readwrite("sampled", &ModelFile::sampled)
      .def_readwrite("derivatives", &ModelFile::derivatives)
      .def_readwrite("outputs", &ModelFile::outputs)
      .def_readwrite("units", &ModelFile::units, "optional (name, unit) pairs for symbols or columns")
      .def("unit", &ModelFile::unit, py::arg("name"),
           "Unit of a symbol or column ('' when none is given; an output column shares its symbol's unit)")
      .def_readwrite("source", &ModelFile::source)
      .def("parameter", [](const ModelFile& f, const std::string& n) {
             const ModelParameter* p = f.parameter(n);
             if (!p) throw InputError(f.source + ": no parameter \"" + n + "\"");
             return *p;
           },
           py::arg("name"))
      .def("__repr__", [](const ModelFile& f) {
        return "ModelFile(" + f.name + ", " + std::to_string(f.parameters.size()) + " parameters, " +
               std::to_string(f.states.size()) + " states, source=" + f.source + ")";
      })
      .def(py::pickle([](const ModelFile& f) { return py::make_tuple(to_json_text(f), f.source); },
                      [](py::tuple t) { return parse_model(t[0].cast<std::string>(), t[1].cast<std::string>()); }));
}

void bind_recording(py::module_& m) {
  py::class_<Recording>(m, "Recording",
                        "Named columns of equal length, from a CSV (header line of names) or a MATLAB .mat\n"
                        "file. `rec['x']` is a column as a numpy array (a copy).")
      .def(py::init<>())
      .def(py::init([](const py::dict& columns, const std::string& source) {
             Recording r;
             r.source = source;
             for (const auto& [k, v] : columns) r.add(k.cast<std::string>(), v.cast<std::vector<double>>());
             return r;
           }),
           py::arg("columns"), py::arg("source") = "<python>",
           "From a dict name -> 1-D array (InputError if the lengths differ).")
      .def_readonly("source", &Recording::source)
      .def_readonly("names", &Recording::names)
      .def_property_readonly("rows", &Recording::rows)
      .def("has", &Recording::has, py::arg("name"))
      .def("__contains__", &Recording::has)
      .def("column", [](const Recording& r, const std::string& n) { return column_array(r.column(n)); }, py::arg("name"),
           "The column as a numpy array (InputError naming the missing column and the file).")
      .def("__getitem__", [](const Recording& r, const std::string& n) {
        if (!r.has(n)) throw py::key_error(n);
        return column_array(r.column(n));
      })
      .def("add", [](Recording& r, const std::string& n, std::vector<double> v) { r.add(n, std::move(v)); },
           py::arg("name"), py::arg("values"))
      .def("to_dict", [](const Recording& r) {
             py::dict d;
             for (std::size_t i = 0; i < r.names.size(); ++i) d[py::str(r.names[i])] = column_array(r.columns[i]);
             return d;
           },
           "Every column, name -> numpy array.")
      .def("__len__", &Recording::rows)
      .def("__repr__", [](const Recording& r) {
        return "Recording(" + r.source + ", " + std::to_string(r.names.size()) + " columns, " + std::to_string(r.rows()) +
               " rows)";
      })
      .def(py::pickle([](const Recording& r) { return py::make_tuple(r.source, r.names, r.columns); },
                      [](py::tuple t) {
                        Recording r;
                        r.source = t[0].cast<std::string>();
                        r.names = t[1].cast<std::vector<std::string>>();
                        r.columns = t[2].cast<std::vector<std::vector<double>>>();
                        return r;
                      }));
  m.def("read_csv", &read_csv, py::arg("path"), "CSV with a header line (errors name file, line and column).");
  m.def("parse_csv", &parse_csv, py::arg("text"), py::arg("source") = "<text>");
  m.def("read_mat", &read_mat, py::arg("path"), "MATLAB .mat: every real vector of the most common length.");
  m.def("read_recording", &read_recording, py::arg("path"), "By extension: .mat or CSV.");
  m.def("write_csv", &write_csv, py::arg("recording"), py::arg("path"), "Writes a CSV (complete or not at all).");
}

void bind_simulator(py::module_& m) {
  py::class_<SimulationResult>(m, "SimulationResult")
      .def_readonly("names", &SimulationResult::names, "every recorded symbol")
      .def_readonly("values", &SimulationResult::values, "samples x names")
      .def_readonly("outputs", &SimulationResult::outputs, "samples x outputs (model order)")
      .def("series", &SimulationResult::series, py::arg("name"));
  py::class_<Simulator>(m, "Simulator",
                        "Fixed-step RK4 simulation of a model file against a recording (inputs held over a\n"
                        "sample). InputError names an unknown symbol or a missing column.")
      .def(py::init([](const ModelFile& model, const Recording& data, int substeps) {
             return std::make_unique<Simulator>(model, data, SimulationOptions{substeps});
           }),
           py::arg("model"), py::arg("data"), py::arg("substeps") = 10)
      .def_property_readonly("samples", &Simulator::samples)
      .def_property_readonly("time", [](const Simulator& s) { return column_array(s.time()); })
      .def_property_readonly("sample_time", &Simulator::sample_time)
      .def_property_readonly("parameter_values", &Simulator::parameter_values)
      .def_property_readonly("parameter_names", &Simulator::parameter_names)
      .def_property_readonly("free_parameters", &Simulator::free_parameters)
      .def_property_readonly("measured", &Simulator::measured, "samples x outputs, from the recording")
      .def_property_readonly("output_names", &Simulator::output_names)
      .def_property_readonly("output_columns", &Simulator::output_columns)
      .def("simulate", &Simulator::simulate, py::arg("parameters"),
           "Simulates with these parameter values (model order); NumericalError on blow-up.")
      .def("simulate_outputs", [](const Simulator& s, const Eigen::VectorXd& p) -> std::optional<Eigen::MatrixXd> {
             Eigen::MatrixXd out;
             if (!s.simulate_outputs(p, out)) return std::nullopt;
             return out;
           },
           py::arg("parameters"), "Outputs only (samples x outputs), None on blow-up.");
  m.def("check_model", &check_model, py::arg("model"), py::arg("data"),
        "Checks a model against a recording without simulating (raises InputError).");
  py::enum_<NoiseMethod>(m, "NoiseMethod", "How a noise level was obtained, most reliable first.")
      .value("repeats", NoiseMethod::repeats)
      .value("residual_coloured", NoiseMethod::residual_coloured)
      .value("residual_floor", NoiseMethod::residual_floor)
      .value("output_spectrum", NoiseMethod::output_spectrum);
  py::class_<NoiseLevelEstimate>(m, "NoiseLevelEstimate", "An estimate (not a bound) of an output's noise level.")
      .def_readonly("sigma", &NoiseLevelEstimate::sigma, "standard deviation, output units")
      .def_readonly("method", &NoiseLevelEstimate::method)
      .def_readonly("reason", &NoiseLevelEstimate::reason)
      .def_readonly("quantisation_step", &NoiseLevelEstimate::quantisation_step)
      .def_readonly("ar_pole", &NoiseLevelEstimate::ar_pole, "AR(1) pole of the noise when its colour was verified, else 0")
      .def("__repr__", [](const NoiseLevelEstimate& e) {
        return "NoiseLevelEstimate(sigma=" + std::to_string(e.sigma) + ", method=" + noise_method_name(e.method) + ")";
      });
  m.def("estimate_noise",
        [](const Eigen::VectorXd& y, std::optional<Eigen::VectorXd> simulated, std::optional<Eigen::MatrixXd> inputs) {
          py::gil_scoped_release release;
          return estimate_noise(y, simulated.value_or(Eigen::VectorXd()), inputs.value_or(Eigen::MatrixXd()));
        },
        py::arg("y"), py::arg("simulated") = py::none(), py::arg("inputs") = py::none(),
        "Noise level of a recorded output (an estimate): optionally the calibrated model's output for y\n"
        "and the model's exogenous inputs (one column each). Says which method gave it and why.");
  m.def("fit_percent", &fit_percent, py::arg("y"), py::arg("yhat"), "100 (1 - ||y - yhat|| / ||y - mean y||).");
}

}  // namespace

void bind_models_data(py::module_& m) {
  bind_model_file(m);
  bind_recording(m);
  bind_simulator(m);
}

}  // namespace sets::python
