// Model files, recordings, simulation, and the diagnosis (synthetic plants and EMPS).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "sets/diagnosis/diagnosis.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/core/error.hpp"
#include "sets/models/model_file.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/shared_data.hpp"

using namespace sets;

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "<no exception>";
}

const char* kDecay = R"json({"name": "decay", "sample_time": 0.1, "inputs": {"u": "u"},
  "parameters": {"a": 2.0}, "states": {"x": 1.0},
  "sampled": {"us": "u + 0*prev(x, 1)", "lag": "prev(x, 2)"},
  "derivatives": {"x": "-a*x + us"}, "outputs": {"x": "y", "lag": "y"}})json";

Recording columns(int n, double u) {
  Recording r;
  r.source = "test";
  r.add("u", std::vector<double>(static_cast<std::size_t>(n), u));
  r.add("y", std::vector<double>(static_cast<std::size_t>(n), 0.0));
  return r;
}

}  // namespace

TEST(ModelFile, MalformedJsonNamesLineAndColumn) {
  const std::string text = "{\n  \"name\": \"x\",\n  \"time\" \"t\"\n}";
  const auto msg = message_of([&] { parse_model(text, "m.json"); });
  EXPECT_NE(msg.find("m.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3, column 10"), std::string::npos) << msg;  // start of the offending token
}

TEST(ModelFile, RoundTripKeepsEverything) {
  const ModelFile m = parse_model(kDecay, "decay");
  const ModelFile back = parse_model(to_json_text(m), "back");
  EXPECT_EQ(back.sampled, m.sampled);
  EXPECT_EQ(back.derivatives, m.derivatives);
  EXPECT_EQ(back.outputs, m.outputs);
  ASSERT_EQ(back.parameters.size(), 1u);
  EXPECT_EQ(back.parameters[0].value, 2.0);
  ASSERT_TRUE(back.sample_time.has_value());
}

TEST(ModelFile, UnknownSymbolIsNamed) {
  ModelFile m = parse_model(kDecay, "decay.json");
  *m.derivative("x") = "-a*x + us*gain";
  const auto msg = message_of([&] { Simulator s(m, columns(10, 0)); });
  EXPECT_NE(msg.find("unknown symbol \"gain\""), std::string::npos) << msg;
  EXPECT_NE(msg.find("derivatives.x"), std::string::npos) << msg;
}

TEST(Recording, MissingColumnIsNamed) {
  ModelFile m = parse_model(kDecay, "decay.json");
  m.inputs = {{"u", "force"}};
  const auto msg = message_of([&] { Simulator s(m, columns(10, 0)); });
  EXPECT_NE(msg.find("missing column \"force\""), std::string::npos) << msg;
}

TEST(Recording, NanRowIsNamed) {
  const auto msg = message_of([] { parse_csv("t,y\n0,1\n0.1,2\n0.2,nan\n", "r.csv"); });
  EXPECT_NE(msg.find("r.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find("data row 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"y\""), std::string::npos) << msg;
}

TEST(Recording, BadNumberNamesLineAndColumn) {
  const auto msg = message_of([] { parse_csv("t,y\n0,1\n0.1,2x\n", "r.csv"); });
  EXPECT_NE(msg.find("line 3, column 2"), std::string::npos) << msg;
}

TEST(Simulation, TimeMustIncrease) {
  ModelFile m = parse_model(kDecay, "decay.json");
  m.sample_time.reset();
  m.time_column = "t";
  Recording r = parse_csv("t,u,y\n0,0,0\n0.1,0,0\n0.1,0,0\n0.3,0,0\n", "r.csv");
  const auto msg = message_of([&] { Simulator s(m, r); });
  EXPECT_NE(msg.find("does not increase at data row 3"), std::string::npos) << msg;
}

TEST(Simulation, BlowUpNamesTheTime) {
  ModelFile m = parse_model(R"json({"sample_time": 0.1, "states": {"x": 1.0},
    "derivatives": {"x": "x*x"}, "outputs": {"x": "y"}})json", "blow.json");
  Simulator s(m, columns(30, 0));
  const auto msg = message_of([&] { s.simulate(s.parameter_values()); });
  // x' = x^2, x(0) = 1 escapes at t = 1.
  EXPECT_NE(msg.find("blew up at t = "), std::string::npos) << msg;
  const double t = std::stod(msg.substr(msg.find("t = ") + 4));
  EXPECT_NEAR(t, 1.0, 0.05);
}

TEST(Simulation, Rk4MatchesExponentialAndPrevHoldsPastSamples) {
  const ModelFile m = parse_model(kDecay, "decay.json");
  Simulator s(m, columns(21, 0.0));
  const auto r = s.simulate(s.parameter_values());
  const Eigen::VectorXd x = r.series("x"), lag = r.series("lag");
  for (int k = 0; k <= 20; ++k) EXPECT_NEAR(x[k], std::exp(-2.0 * 0.1 * k), 1e-9);
  EXPECT_DOUBLE_EQ(lag[0], x[0]);  // no earlier sample: the first one
  EXPECT_DOUBLE_EQ(lag[1], x[0]);
  for (int k = 2; k <= 20; ++k) EXPECT_DOUBLE_EQ(lag[k], x[k - 2]);
}

TEST(Simulation, SampledInputIsHeldOverTheSample) {
  // x' = us with us held: x grows by us*Ts per sample exactly.
  const ModelFile m = parse_model(R"json({"sample_time": 0.5, "inputs": {"u": "u"}, "states": {"x": 0.0},
    "sampled": {"us": "u"}, "derivatives": {"x": "us"}, "outputs": {"x": "y"}})json", "hold.json");
  Recording r;
  r.add("u", {1, 3, -2, 0});
  r.add("y", {0, 0, 0, 0});
  Simulator s(m, r);
  const Eigen::VectorXd x = s.simulate(s.parameter_values()).series("x");
  EXPECT_NEAR(x[1], 0.5, 1e-12);
  EXPECT_NEAR(x[2], 2.0, 1e-12);
  EXPECT_NEAR(x[3], 1.0, 1e-12);
}

TEST(Diagnosis, SyntheticCoulombPlantIsNamedAndCleanPlantGetsNothing) {
  {
    const SyntheticPlant p = synthetic_plant("coulomb_friction");
    const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
    ASSERT_FALSE(d.effects.empty());
    EXPECT_EQ(d.effects.front().name, "coulomb_friction");
    ASSERT_EQ(d.effects.front().parameters.size(), 1u);
    const auto& fc = d.effects.front().parameters.front();
    EXPECT_NEAR(fc.estimate, 0.3, 0.03);  // the plant's true value
    EXPECT_LE(fc.lo, 0.3);
    EXPECT_GE(fc.hi, 0.3);
    EXPECT_GT(d.fit_augmented_validation[0], d.fit_nominal_validation[0] + 5);
  }
  {
    const SyntheticPlant p = synthetic_plant("clean_axis");
    const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
    EXPECT_TRUE(d.effects.empty()) << d.effects.front().name;
    EXPECT_TRUE(d.nothing_missing);
    EXPECT_NE(diagnosis_text(d).find("No physics is missing"), std::string::npos);
  }
}

// Nested laws: Coulomb friction is Stribeck friction with Fs = 0, so the sparser Coulomb law wins
// unless the Stribeck law passes every rule against it and its bounded-error interval of Fs
// excludes 0. On the suite's Stribeck plant (Fs = 0.35 against Fc = 0.15) the data exclude it; on
// EMPS (EmpsNamesCoulombFrictionAndOffset) asymmetric friction does not get past Coulomb + offset.
TEST(Diagnosis, RicherLawNamedOnlyWhenTheDataExcludeItsSpecialCase) {
  const SyntheticPlant p = synthetic_plant("stribeck_friction");
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects.front().name, "stribeck_friction") << d.effects.front().evidence;
  EXPECT_NE(d.effects.front().evidence.find("coulomb_friction, its special case"), std::string::npos)
      << d.effects.front().evidence;
  for (const auto& ep : d.effects.front().parameters) {
    if (ep.role == "Fs") {
      EXPECT_GT(ep.lo, 0.0);
    }
  }
}

// A plant whose stiffness steps from 4 to 7 at t = 23.7 s, diagnosed from the constant-parameter
// model: the time-varying estimates must name k and a window holding the step.
TEST(Diagnosis, VaryingParameterNamesTheSteppingParameterAndWhen) {
  const char* nominal = R"({"name": "axis", "time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.2, "k": 3.5, "c": 1.0}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})";
  ModelFile truth = parse_model(nominal);
  *truth.derivative("v") = "(u - (4 + 3*(t >= 23.7))*x - 0.8*v)/1.0";
  const int n = 4000;
  const double Ts = 0.01;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> level(-2, 2), hold(0.5, 3.0);
  std::vector<double> t(n), u(n);
  double next = 0, value = 0;
  for (int k = 0; k < n; ++k) {
    t[static_cast<std::size_t>(k)] = k * Ts;
    if (k * Ts >= next) value = level(rng), next = k * Ts + hold(rng);
    u[static_cast<std::size_t>(k)] = value;
  }
  Recording r;
  r.add("t", t);
  r.add("u", u);
  r.add("x_meas", std::vector<double>(n, 0.0));
  Simulator sim(truth, r);
  const Eigen::VectorXd x = sim.simulate(sim.parameter_values()).outputs.col(0);
  const double sd = std::sqrt((x.array() - x.mean()).square().mean());
  std::normal_distribution<double> noise(0.0, 0.01 * sd);
  std::vector<double> meas(n);
  for (int k = 0; k < n; ++k) meas[static_cast<std::size_t>(k)] = x[k] + noise(rng);
  r.add("x_meas", meas);

  DiagnosisOptions opt;
  opt.max_effects = 0;  // only the mismatch location is tested here
  const Diagnosis d = diagnose(parse_model(nominal), r, nullptr, opt);
  ASSERT_EQ(d.varying.size(), 3u);
  const VaryingParameter& v = d.varying.front();
  std::ostringstream trace;  // the estimates, shown when an expectation fails
  for (const auto& p : d.varying) {
    trace << p.name << " (" << p.method << ", explained " << p.explained << ", squared " << p.explained_squared << "):";
    for (const auto& s : p.trajectory) trace << " " << s.value;
    trace << "; when:";
    for (const auto& w : p.when) trace << " [" << w.first << ", " << w.second << "]";
    trace << "\n";
  }
  if (std::getenv("SETS_VERBOSE")) std::cout << trace.str();
  SCOPED_TRACE(trace.str());
  EXPECT_EQ(v.name, "k");
  ASSERT_FALSE(v.when.empty());
  EXPECT_LE(v.when.front().first, 23.7);
  EXPECT_GE(v.when.front().second, 23.7);
  // The estimated trajectory is lower before the step than after it.
  ASSERT_FALSE(v.trajectory.empty());
  EXPECT_LT(v.trajectory.front().value, v.trajectory.back().value);
  EXPECT_GT(v.explained, d.varying[1].explained);
}

// Equation-error PUIs of the Coulomb plant's force balance, measured at values a little off the
// truth (as an estimate would be): every true parameter must lie in its interval, and the
// parameters that enter nonlinearly or through prev() are refused with a reason.
TEST(EquationError, PuiContainsTheTrueParametersOfTheCoulombPlant) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  ModelFile m = p.nominal;
  *m.derivative("v") = "(K*u - k*x - c*v - Fc*sign(v))/m";
  ModelParameter fc;
  fc.name = "Fc";
  m.parameters.push_back(fc);
  const std::vector<std::pair<std::string, double>> truth{{"m", 1.0}, {"k", 4.0}, {"c", 0.8}, {"Fc", 0.3}};
  const std::vector<double> off{1.03, 3.9, 0.84, 0.28};
  for (std::size_t i = 0; i < truth.size(); ++i) m.parameter(truth[i].first)->value = off[i];
  const EquationErrorResult r = equation_error_pui(m, p.estimation, "v");
  ASSERT_TRUE(r.built) << r.note;
  EXPECT_EQ(r.order, 2);
  ASSERT_EQ(r.parameters.size(), 4u);
  EXPECT_EQ(r.parameters.front(), "m");  // the inertia: m * v' is affine in k, c, Fc
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    double tv = 0;
    for (const auto& [n, v] : truth)
      if (n == r.parameters[i]) tv = v;
    EXPECT_LE(r.box[static_cast<Eigen::Index>(i)].lower(), tv) << r.parameters[i];
    EXPECT_GE(r.box[static_cast<Eigen::Index>(i)].upper(), tv) << r.parameters[i];
  }
  ModelFile nonlinear = m;
  *nonlinear.derivative("v") = "(K*u - k*x - c*v - Fc*sign(v)*exp(-(v/m)^2))/m";
  EXPECT_FALSE(equation_error_pui(nonlinear, p.estimation, "v").built);
  ModelFile delayed = m;
  *delayed.derivative("v") = "(K*prev(u, 3) - k*x - c*v)/m";
  const EquationErrorResult rd = equation_error_pui(delayed, p.estimation, "v");
  EXPECT_FALSE(rd.built);
  EXPECT_NE(rd.note.find("prev"), std::string::npos) << rd.note;
}

TEST(Diagnosis, EmpsNamesCoulombFrictionAndOffset) {
  const auto model = test::shared_data("emps/nominal.json");
  const auto est = test::shared_data("emps/estimation.csv");
  const auto val = test::shared_data("emps/validation.csv");
  if (model.empty() || est.empty() || val.empty()) GTEST_SKIP() << "emps data not found under ../shared/data";
  const Recording e = read_csv(est.string()), v = read_csv(val.string());
  const Diagnosis d = diagnose(load_model_file(model.string()), e, &v);
  ASSERT_GE(d.effects.size(), 2u);
  EXPECT_EQ(d.effects[0].name, "coulomb_friction");
  EXPECT_EQ(d.effects[1].name, "constant_offset");
  const auto& fc = d.effects[0].parameters.at(0);
  const auto& off = d.effects[1].parameters.at(0);
  EXPECT_NEAR(fc.estimate, 20.4, 1.5);
  EXPECT_NEAR(off.estimate, -3.2, 0.5);
  EXPECT_LE(fc.lo, 20.4);
  EXPECT_GE(fc.hi, 20.4);
  EXPECT_LE(off.lo, -3.2);
  EXPECT_GE(off.hi, -3.2);
  EXPECT_GE(d.fit_augmented_validation.at(1), 90.0);  // u
  // The equation-error PUIs exist for both and are much narrower than the output-error ones
  // (+-40 N before they were built).
  EXPECT_TRUE(fc.has_ee);
  EXPECT_TRUE(off.has_ee);
  EXPECT_LT(fc.hi - fc.lo, 25.0);
  EXPECT_LT(off.hi - off.lo, 15.0);
}

TEST(Recording, MatFileHasTheSameRecordAsTheCsv) {
  const auto mat = test::shared_data("emps/DATA_EMPS.mat");
  const auto csv = test::shared_data("emps/estimation.csv");
  if (mat.empty() || csv.empty()) GTEST_SKIP() << "emps data not found under ../shared/data";
  const Recording m = read_mat(mat.string()), c = read_csv(csv.string());
  ASSERT_EQ(m.rows(), c.rows());
  const auto& vir = m.column("vir");
  const auto& u = c.column("u");
  for (int k = 0; k < m.rows(); k += 997) EXPECT_NEAR(vir[static_cast<std::size_t>(k)], u[static_cast<std::size_t>(k)], 1e-9);
}

TEST(App, BadInputExitsNonZeroAndWritesNothing) {
  const std::filesystem::path app = std::filesystem::path(SETS_BINARY_DIR) / "apps/sets-diagnose/sets-diagnose";
  if (!std::filesystem::exists(app)) GTEST_SKIP() << "sets-diagnose not built";
  const auto dir = std::filesystem::temp_directory_path() / "sets_diagnose_app_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.json") << "{\"states\": {\"x\": 1.0},\n \"derivatives\": {\"x\": \"-x\"}, }";
  std::ofstream(dir / "data.csv") << "t,y\n0,1\n0.1,0.9\n";
  const std::string cmd = app.string() + " --quiet --model " + (dir / "bad.json").string() + " --data " +
                          (dir / "data.csv").string() + " --json " + (dir / "out.json").string() + " --report " +
                          (dir / "rep").string() + " 2>" + (dir / "err.txt").string();
  const int rc = std::system(cmd.c_str());
  EXPECT_NE(rc, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "out.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "rep"));
  std::ifstream err(dir / "err.txt");
  const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("line 2"), std::string::npos) << text;
  std::filesystem::remove_all(dir);
}
