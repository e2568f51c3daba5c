// The nominal calibration starts from several points, so that a local minimum of the output
// error is not blamed on missing physics.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"
#include "sets/data/simulation.hpp"
#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/examples/random_plants.hpp"
#include "sets/models/model_file.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;

namespace {

// x' = v, v' = u - k x - c v (unit mass, known) driven by one sine near the resonance (a poor
// excitation, as in a frequency-response test).
Recording sine_record(const std::string& truth_json, unsigned seed) {
  const int n = 4000;
  const double Ts = 0.02;
  std::mt19937 rng(seed);
  std::vector<double> t(n), u(n);
  for (int k = 0; k < n; ++k) {
    t[static_cast<std::size_t>(k)] = k * Ts;
    u[static_cast<std::size_t>(k)] = std::sin(2.1 * k * Ts + 0.3 * seed);
  }
  Recording r;
  r.add("t", t);
  r.add("u", u);
  r.add("x_meas", std::vector<double>(n, 0.0));
  Simulator truth(parse_model(truth_json), r, {10});
  const Eigen::VectorXd y = truth.simulate(truth.parameter_values()).outputs.col(0);
  std::normal_distribution<double> e(0, 0.01 * std::sqrt((y.array() - y.mean()).square().mean()));
  std::vector<double> m(n);
  for (int k = 0; k < n; ++k) m[static_cast<std::size_t>(k)] = y[k] + e(rng);
  r.add("x_meas", m);
  return r;
}

}  // namespace

TEST(CalibrateNominal, LocalMinimumOfTheNominalIsEscaped) {
  // A lightly damped resonance at 2 rad/s; the file says 4 rad/s (k = 16): from the file's
  // values the output error settles in a local minimum far from the data.
  const std::string truth = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": {"value": 1.0, "fixed": true}, "k": 4.0, "c": 0.05}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})j";
  const std::string nominal = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": {"value": 1.0, "fixed": true}, "k": 16.0, "c": 0.5}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})j";
  const Recording est = sine_record(truth, 3), val = sine_record(truth, 4);
  const ModelFile model = parse_model(nominal);
  {
    Simulator s(model, est, {2});
    const auto single = calibrate(s, s.parameter_values(), s.free_parameters());
    ASSERT_TRUE(single.ok);
    EXPECT_LT(single.fit.at(0), 50) << "the file's values should end in a local minimum for this test to mean anything";
  }
  DiagnosisOptions opt;
  opt.screening_substeps = 2;  // as above: the file's values alone end in the local minimum
  const Diagnosis d = diagnose(model, est, &val, opt);
  EXPECT_GT(d.fit_nominal_estimation.at(0), 97) << d.nominal_note;
  EXPECT_NEAR(d.nominal.parameter("k")->value, 4.0, 0.2);
  // One call from the file's values stops on its budget below 50 %; since 2026-11-24 each start is
  // continued at the screening step until converged, and this one then reaches the data itself
  // (before, the other starts did and the note said "several minima").
  EXPECT_LT(d.nominal_note.find("substeps until converged ("), d.nominal_note.find("the best continued")) << d.nominal_note;
  EXPECT_TRUE(d.effects.empty()) << d.effects.front().name;  // nothing is missing: no invented effect
  EXPECT_FALSE(d.nominal_far);
}

TEST(CalibrateNominal, SaysWhenTheNominalCannotBeBroughtNearTheData) {
  // The data come from a plant with an integrator the nominal (a first-order lag) cannot follow.
  const std::string truth = R"({"time": "t", "inputs": {"u": "u"}, "parameters": {"g": 1.0},
    "states": {"x": 0.0, "y": 0.0}, "derivatives": {"x": "g*u", "y": "x - 0.1*y"}, "outputs": {"y": "y_meas"}})";
  const std::string nominal = R"({"time": "t", "inputs": {"u": "u"}, "parameters": {"a": 1.0, "b": 1.0},
    "states": {"y": 0.0}, "derivatives": {"y": "b*u - a*y"}, "outputs": {"y": "y_meas"}})";
  const SyntheticPlant p = test::simulated_plant(truth, nominal, 2000, 0.05, {"u", -1, 1, 1, 5}, 0.01, 5);
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
  if (d.fit_nominal_estimation.at(0) < 50) {
    EXPECT_TRUE(d.nominal_far);
    EXPECT_NE(d.nominal_note.find("cannot be brought near the data"), std::string::npos) << d.nominal_note;
  }
  EXPECT_FALSE(d.nothing_missing);
}

namespace {

// x' = v, v' = u - k x - c v with a known unit mass: the resonance of the two tests below.
std::string resonance(double k, double c) {
  return R"({"time": "t", "inputs": {"u": "u"}, "parameters": {"m": {"value": 1.0, "fixed": true}, "k": )" +
         std::to_string(k) + R"(, "c": )" + std::to_string(c) + R"(}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})";
}

}  // namespace

TEST(CalibrateNominal, OptimumOfTheCoarseStepThatDivergesAtTheFineStepIsRejected) {
  // A lightly damped resonance sampled at 4.5 samples per period. One RK4 substep per sample
  // damps the oscillation numerically (|R(i w h)| < 1), so the output error calibrated with that
  // step wants a negative damping c, whose fine-step simulation grows without bound (random plant
  // 5000023, two masses, went that way: fits of -1e111 % and a noise "estimate" 5e92 x the truth).
  const SyntheticPlant p = test::simulated_plant(resonance(1.0, 0.01), resonance(1.3, 0.05), 1500, 1.4, {"u", -1, 1, 5, 30}, 0.02, 7);
  DiagnosisOptions opt;
  opt.screening_substeps = 1;
  {
    Simulator coarse(p.nominal, p.estimation, {1}), fine(p.nominal, p.estimation, {opt.final_substeps});
    const CalibrationResult r = calibrate(coarse, coarse.parameter_values(), coarse.free_parameters());
    ASSERT_TRUE(r.ok);
    const CalibrationResult f = evaluate(fine, r.parameters);
    EXPECT_TRUE(!f.ok || f.fit.at(0) < 0) << "the coarse optimum should diverge at the fine step for this test to mean "
                                             "anything (c = " << r.parameters[2] << ")";
  }
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation, opt);
  ASSERT_EQ(d.fit_nominal_estimation.size(), 1u);
  EXPECT_GT(d.fit_nominal_estimation[0], 90) << d.nominal_note;
  EXPECT_NEAR(d.nominal.parameter("c")->value, 0.01, 0.01) << d.nominal_note;
  ASSERT_EQ(d.noise.size(), 1u);
  EXPECT_NEAR(d.noise[0].estimate.sigma / p.noise_sigma[0], 1.0, 0.5);
  EXPECT_NE(d.nominal_note.find("calibrated again"), std::string::npos) << d.nominal_note;
}

TEST(CalibrateNominal, TheNominalIsTheOptimumOfTheFinalStepNotOfTheScreeningStep) {
  // A lightly damped resonance (w = 1 rad/s, zeta = 0.1) sampled at 10 samples per period, noise
  // 0.3 % of the output: one RK4 substep per sample misplaces the mode's frequency by more than
  // the noise resolves, and the parameters calibrated with it absorb that. Evaluated with the
  // final substeps, that optimum leaves a model error of several noise levels (random plant
  // 5 001 765 went that way: a clean plant called unexplained, its noise read 0.39x the truth).
  const SyntheticPlant p = test::simulated_plant(resonance(1.0, 0.2), resonance(1.4, 0.3), 3000, 0.63, {"u", -1, 1, 5, 30}, 0.003, 12);
  DiagnosisOptions opt;
  opt.screening_substeps = 1;
  const Simulator fine(p.nominal, p.estimation, {opt.final_substeps});
  Eigen::VectorXd true_values = fine.parameter_values();
  true_values[1] = 1.0, true_values[2] = 0.2;
  const CalibrationResult at_truth = evaluate(fine, true_values);
  ASSERT_TRUE(at_truth.ok);
  {
    Simulator coarse(p.nominal, p.estimation, {1});
    const CalibrationResult r = calibrate(coarse, coarse.parameter_values(), coarse.free_parameters());
    ASSERT_TRUE(r.ok);
    const CalibrationResult f = evaluate(fine, r.parameters);
    ASSERT_TRUE(f.ok);
    EXPECT_LT(f.fit.at(0), at_truth.fit.at(0) - 0.1) << "the coarse optimum should fit worse than the truth at the fine step "
                                                          "for this test to mean anything";
  }
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation, opt);
  // The least-squares optimum fits the estimation record at least as well as the true values.
  EXPECT_GE(d.fit_nominal_estimation.at(0), at_truth.fit.at(0) - 1e-3) << d.nominal_note;
  EXPECT_NE(d.nominal_note.find("continued at 10 RK4 substeps"), std::string::npos) << d.nominal_note;
  ASSERT_EQ(d.noise.size(), 1u);
  EXPECT_NEAR(d.noise[0].estimate.sigma / p.noise_sigma[0], 1.0, 0.3);
  EXPECT_TRUE(d.effects.empty()) << d.effects.front().name;
  EXPECT_TRUE(d.nothing_missing) << d.verdict;  // the screening step's optimum: "unexplained" (fit 99.50 % against 99.71 %)
}

namespace {

// x' = v, v' = u - k x - c v (unit mass, known), an overdamped truth (c = 8, poles -0.54, -7.46).
const char* damped_truth = R"({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": {"value": 1.0, "fixed": true}, "k": 4.0, "c": 8.0}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})";

}  // namespace

TEST(CalibrateNominal, FileValuesThatBlowUpAreNotAvailableAndTheOtherStartsAreCalibrated) {
  // The engineer wrote the damping with the wrong sign: at the file's values the model grows as
  // e^(7.46 t) and is no longer finite long before the end of the 200 s record, while the
  // structure is right and the equation error of v' estimates k and c from the data.
  const std::string nominal = R"({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": {"value": 1.0, "fixed": true}, "k": 4.0, "c": -8.0}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})";
  const SyntheticPlant p = test::simulated_plant(damped_truth, nominal, 2000, 0.1, {"u", -1, 1, 2, 10}, 0.01, 11);
  {
    Simulator s(p.nominal, p.estimation, {10});
    EXPECT_THROW(s.simulate(s.parameter_values()), NumericalError) << "the file's values should blow up for this test to mean anything";
  }
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
  ASSERT_EQ(d.fit_start_estimation.size(), 1u);
  ASSERT_EQ(d.fit_start_validation.size(), 1u);
  EXPECT_TRUE(std::isnan(d.fit_start_estimation[0]));  // not available
  EXPECT_TRUE(std::isnan(d.fit_start_validation[0]));
  EXPECT_NE(d.fit_start_note.find("blew up at t = "), std::string::npos) << d.fit_start_note;
  EXPECT_EQ(d.nominal_note.rfind("the file's values cannot be simulated", 0), 0u) << d.nominal_note;
  ASSERT_EQ(d.fit_nominal_estimation.size(), 1u);
  EXPECT_GT(d.fit_nominal_estimation[0], 90) << d.nominal_note;
  EXPECT_GT(d.fit_nominal_validation.at(0), 90) << d.nominal_note;
  EXPECT_NEAR(d.nominal.parameter("c")->value, 8.0, 0.8) << d.nominal_note;
  EXPECT_FALSE(d.nominal_far);
  EXPECT_TRUE(d.effects.empty()) << d.effects.front().name;  // the structure is right: nothing invented
}

TEST(CalibrateNominal, EndsWithNumericalErrorWhenNoStartCanBeSimulated) {
  // Every parameter fixed: the file's values are the only start, and they blow up.
  const std::string nominal = R"({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": {"value": 1.0, "fixed": true}, "k": {"value": 4.0, "fixed": true}, "c": {"value": -8.0, "fixed": true}},
    "states": {"x": 0.0, "v": 0.0}, "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})";
  const SyntheticPlant p = test::simulated_plant(damped_truth, nominal, 2000, 0.1, {"u", -1, 1, 2, 10}, 0.01, 11);
  try {
    diagnose(p.nominal, p.estimation, &p.validation);
    ADD_FAILURE() << "expected NumericalError";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be simulated over the record from any start"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("blew up at t = "), std::string::npos) << e.what();
  }
}

namespace {

// x' = a (u - x), x measured.
ModelFile first_order_lag(double a) {
  return parse_model(R"json({"time": "t", "inputs": {"u": "u"}, "parameters": {"a": )json" + std::to_string(a) +
                     R"json(}, "states": {"x": 0.0}, "derivatives": {"x": "a*(u - x)"}, "outputs": {"x": "x_meas"}})json");
}

// 2000 samples at 0.1 s of u = sin(w t), and x_meas = u.
Recording slow_sine_record(double w) {
  const int n = 2000;
  std::vector<double> t(n), u(n);
  for (int k = 0; k < n; ++k) {
    t[static_cast<std::size_t>(k)] = 0.1 * k;
    u[static_cast<std::size_t>(k)] = std::sin(w * 0.1 * k);
  }
  Recording r;
  r.add("t", t);
  r.add("u", u);
  r.add("x_meas", u);
  return r;
}

}  // namespace

TEST(CalibrateNominal, ScreeningStepIsTheCoarsestThatRK4ResolvesNotTheNextRungOfALadder) {
  // x' = a (u - x) with a = 150 /s, sampled at 0.1 s: h a = 15 / substeps, and RK4 is stable on
  // the real axis for h a < 2.79, so 1 - 5 substeps blow up and 6 (h a = 2.5) is the coarsest
  // that simulates; the slow sine input is followed to far better than 0.2 points there. (Random
  // plants 5 002 090 and 5 001 980 went that way at their calibrated values, a mass near 0: finite
  // from 8 and 9 substeps, and a ladder {1, 2, 5} screened every hypothesis at the final 10.)
  const ModelFile model = first_order_lag(150.0);
  const Recording r = slow_sine_record(0.05);
  const int final_substeps = 10;
  const Simulator exact(model, r, {final_substeps});
  const Eigen::VectorXd p = exact.parameter_values();
  for (int sub : {1, 5})
    EXPECT_FALSE(evaluate(Simulator(model, r, {sub}), p).ok) << sub << " substeps should blow up for this test to mean anything";
  EXPECT_TRUE(evaluate(Simulator(model, r, {6}), p).ok);
  EXPECT_EQ(diagnosis_stage::screening_substeps(model, r, exact, p, final_substeps), 6);  // {1, 2, 5}: the final 10
  // Chosen again after a blow-up at 2 (diagnose's re-choice): the same coarsest step.
  EXPECT_EQ(diagnosis_stage::screening_substeps(model, r, exact, p, final_substeps, 3), 6);
  // Never finer than the final step, and never coarser than asked.
  EXPECT_EQ(diagnosis_stage::screening_substeps(model, r, exact, p, final_substeps, 7), 7);
  EXPECT_EQ(diagnosis_stage::screening_substeps(model, r, exact, p, 4), 4);
}

TEST(CalibrateNominal, AStartStoppedOnItsBudgetIsContinuedAtTheScreeningStepBeforeTheFinalStep) {
  // Random plant 5 002 312: a clean two-mass plant (no effect), coloured noise. The screening
  // calibration from the file's values stops on its evaluation budget at 59.5 %; continued from
  // there at the final step (main 164a1ae) it went to a coupling stiffness ab = 226 (the truth
  // 4.46) with a negative damping cs = -0.044, 83.6 %, and Coulomb friction was named (98.1 % on
  // validation). Continued at the screening step first, it reaches the truth's basin.
  const SyntheticPlant p = random_plant(5002312);
  ASSERT_TRUE(p.effects.empty());
  const Diagnosis d = test::diagnosed(p);
  ASSERT_EQ(d.fit_nominal_estimation.size(), 1u);
  EXPECT_LT(d.nominal_note.find("substeps until converged ("), d.nominal_note.find("the best continued")) << d.nominal_note;
  EXPECT_GT(d.fit_nominal_estimation[0], 99.5) << d.nominal_note;
  EXPECT_NEAR(d.nominal.parameter("ab")->value, p.truth.parameter("ab")->value, 0.2 * p.truth.parameter("ab")->value);
  EXPECT_GT(d.nominal.parameter("cs")->value, 0);
  EXPECT_TRUE(d.effects.empty()) << d.verdict;
  EXPECT_TRUE(d.nothing_missing) << d.verdict;
  // Near the data and within the noise from its first starts: no random starts (they cost simulations).
  EXPECT_EQ(d.nominal_note.find("random start"), std::string::npos) << d.nominal_note;
}

TEST(CalibrateNominal, ARealEffectIsStillNamedWhenTheStartsAreContinued) {
  // Random plant 800 001: viscous friction missing from a two-mass nominal. Its starts stop on
  // their budget at the screening step and are continued there (the note says so); the nominal
  // still cannot fit what the missing friction does, and the friction is named.
  const SyntheticPlant p = random_plant(800001);
  ASSERT_EQ(p.effects.size(), 1u);
  const Diagnosis d = test::diagnosed(p);
  EXPECT_LT(d.nominal_note.find("substeps until converged ("), d.nominal_note.find("the best continued")) << d.nominal_note;
  ASSERT_EQ(d.effects.size(), 1u) << d.verdict;
  EXPECT_EQ(d.effects[0].name, p.effects[0].name) << d.verdict;
  // Not within the noise, so random starts were tried for a stall; none fits markedly better.
  EXPECT_NE(d.nominal_note.find("not within the noise: "), std::string::npos) << d.nominal_note;
  EXPECT_NE(d.nominal_note.find("the first starts' best is kept"), std::string::npos) << d.nominal_note;
}

TEST(CalibrateNominal, AScreeningStepThatGrowsTheCalibratedModeWithoutOverflowIsChosenAgain) {
  // x' = a (u - x) sampled at 0.1 s, one RK4 substep: the file's a = 15 (h a = 1.5) is resolved;
  // a calibrated a = 28.5 (h a = 2.85, just outside RK4's interval 2.79) grows by |R(h a)| = 1.10
  // per sample, to about 1e84 over the record: finite, so "ok", yet no model to search around.
  const ModelFile model = first_order_lag(15.0);
  const Recording r = slow_sine_record(0.5);
  const Simulator fast(model, r, {1});
  Eigen::VectorXd calibrated = fast.parameter_values();
  calibrated[0] = 28.5;
  const auto at = evaluate(fast, calibrated);
  ASSERT_TRUE(at.ok) << "the growth must stay finite for this test to mean anything";  // the old test: !ok
  EXPECT_GT(at.cost, 1e10);
  EXPECT_TRUE(diagnosis_stage::blows_up_at(fast, calibrated, model));
  calibrated[0] = 16.0;  // resolved at that step: no new choice
  EXPECT_FALSE(diagnosis_stage::blows_up_at(fast, calibrated, model));
}

TEST(CalibrateNominal, BacklashBehindAScreeningStepThatGrowsTheCalibratedModeIsExplained) {
  // Random plant 5 003 617 (two masses, a backlash at the motor torque, PRBS): the nominal calibrated
  // at the final step (stiffness 0.41 -> 0.73) fits its data, but at the screening step chosen at
  // the file's values (1 substep) its misfit is 1e88, finite; every hypothesis was judged against
  // that and the answer was "unexplained". Chosen again (2 substeps), a law at the drive removes
  // 63 % of the misfit (backlash, dead zone and input saturation tie on a two-level drive).
  // (Seed 5 003 617: held out in the fifteenth session, development since.)
  const SyntheticPlant p = random_plant(5003617);
  ASSERT_EQ(p.effects.size(), 1u);
  DiagnosisOptions o;
  o.max_effects = 1;
  const Diagnosis d = test::diagnosed(p, o);
  ASSERT_EQ(d.effects.size(), 1u) << d.verdict;
  EXPECT_EQ(d.effects[0].equation, p.effects[0].where) << d.effects[0].name;
}

TEST(CalibrateNominal, ANominalThatStaysFarFromTheDataIsCalibratedFromMoreStarts) {
  // Random plant 5 008 712: a clean two-mass plant whose states are not measured (no equation-error
  // start). From the file's values and from the record's head the output error stalls at -207 %;
  // main c570ea6 then credited the stall to a Bouc-Wen law (a coupling stiffness 14x the truth's).
  // From the file's values times random factors, one start reaches the data.
  const SyntheticPlant p = random_plant(5008712);
  ASSERT_TRUE(p.effects.empty());
  const Diagnosis d = test::diagnosed(p);
  ASSERT_EQ(d.fit_nominal_estimation.size(), 1u);
  const auto more = d.nominal_note.find("far from the data: ");
  ASSERT_NE(more, std::string::npos) << d.nominal_note;
  // The first starts were far: every fit before the random ones is below 50 %.
  const std::string first = d.nominal_note.substr(0, more);
  int fits_read = 0;
  for (auto at = first.find("fit "); at != std::string::npos; at = first.find("fit ", at + 1), ++fits_read)
    EXPECT_LT(std::stod(first.substr(at + 4)), 50) << first;
  EXPECT_GE(fits_read, 2) << first;
  EXPECT_GT(d.fit_nominal_estimation[0], 99) << d.nominal_note;
  EXPECT_FALSE(d.nominal_far);
  EXPECT_TRUE(d.effects.empty()) << d.verdict;
  EXPECT_TRUE(d.nothing_missing) << d.verdict;
}


TEST(CalibrateNominal, ARandomStartThatStaysFarFromTheDataIsNotTaken) {
  // Random plant 5 008 447: the nominal leaves out the plant's only damping (viscous friction,
  // and a hysteresis), so no start can bring it near the data. A random start fits better (24.7 %
  // against 10.4 %) with the stiffness 2x the truth's; from there the search named three wrong
  // effects. Physics is missing, not a stall: the first starts' optimum is kept.
  const SyntheticPlant p = random_plant(5008447);
  ASSERT_EQ(p.effects.size(), 2u);
  const Diagnosis d = test::diagnosed(p);
  EXPECT_NE(d.nominal_note.find("random start"), std::string::npos) << d.nominal_note;
  EXPECT_NE(d.nominal_note.find("the first starts' best is kept"), std::string::npos) << d.nominal_note;
  EXPECT_TRUE(d.nominal_far);
  bool viscous = false;
  for (const auto& e : d.effects) viscous = viscous || e.name == "viscous_friction";
  EXPECT_TRUE(viscous) << d.verdict;
}

TEST(CalibrateNominal, ANominalThatStallsNearTheDataIsCalibratedFromMoreStarts) {
  // Random plant 5 008 857: a clean two-mass plant. From the file's values (0.58 - 1.40x the
  // truth's) and from the record's head the calibration ends at 99.2 % with a coupling damping 16x
  // the truth's: near the data, not within the noise. Main 1c1986b named viscous friction
  // (99.8 %, as the truth's values fit). A random start removes far more than an effect must.
  const SyntheticPlant p = random_plant(5008857);
  ASSERT_TRUE(p.effects.empty());
  const Diagnosis d = test::diagnosed(p);
  ASSERT_EQ(d.fit_nominal_estimation.size(), 1u);
  const auto more = d.nominal_note.find("not within the noise: ");
  ASSERT_NE(more, std::string::npos) << d.nominal_note;
  EXPECT_EQ(d.nominal_note.find("far from the data: "), std::string::npos) << d.nominal_note;
  EXPECT_NE(d.nominal_note.find("their best is taken", more), std::string::npos) << d.nominal_note;
  EXPECT_GT(d.fit_nominal_estimation[0], 99.5) << d.nominal_note;
  EXPECT_TRUE(d.effects.empty()) << d.verdict;
  EXPECT_TRUE(d.nothing_missing) << d.verdict;
}
