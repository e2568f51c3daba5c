// Tests of src/diagnosis/special_cases.cpp: which hypothesis nests which, and the starts a richer
// law is refined from at its special case's optimum.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "diagnosis/hypothesis_search.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

namespace {

// The catalogue's candidates on the plant's nominal, generated as a first round generates them.
std::vector<Candidate> candidates_on(const test::StageRun& s) {
  return generate_candidates(s.model, s.fast->simulate(values_of(s.model)), s.estimation);
}

const Candidate* find(const std::vector<Candidate>& cs, const std::string& effect, const std::string& equation = "") {
  for (const auto& c : cs)
    if (c.parts.empty() && c.effect == effect && (equation.empty() || c.equation == equation)) return &c;
  return nullptr;
}

}  // namespace

TEST(SpecialCases, StribeckNestsCoulombAtItsOwnPlaceOnly) {
  const test::StageRun s(synthetic_plant("coulomb_friction"), false, 600);
  const std::vector<Candidate> cs = candidates_on(s);
  const Candidate* coulomb = find(cs, "coulomb_friction");
  ASSERT_NE(coulomb, nullptr);
  const Candidate* stribeck = find(cs, "stribeck_friction", coulomb->equation);
  ASSERT_NE(stribeck, nullptr);
  Fixed fixed;
  EXPECT_TRUE(nests(*stribeck, *coulomb, &fixed));
  ASSERT_FALSE(fixed.empty());  // Stribeck's extra term is fixed on the way to Coulomb
  for (const auto& [name, value] : fixed) {
    EXPECT_NE(std::find(stribeck->parameters.begin(), stribeck->parameters.end(), name), stribeck->parameters.end()) << name;
    EXPECT_TRUE(std::isfinite(value)) << name;
  }
  EXPECT_FALSE(nests(*coulomb, *stribeck));  // not the other way round
  EXPECT_FALSE(nests(*coulomb, *coulomb));   // a law is not strictly richer than itself
  for (const auto& c : cs)
    if (c.parts.empty() && c.effect == "coulomb_friction" && c.equation != coulomb->equation)
      EXPECT_FALSE(nests(*stribeck, c)) << "Coulomb in " << c.equation;
}

// At each start built from the special case's optimum, the richer law *is* the special case: the
// same simulated outputs, so its calibration from there cannot end worse than the special case.
TEST(SpecialCases, RicherLawStartedAtItsSpecialCasesOptimumSimulatesAsTheSpecialCase) {
  const test::StageRun s(synthetic_plant("coulomb_friction"), false, 600);
  const std::vector<Candidate> cs = candidates_on(s);
  const Candidate* coulomb = find(cs, "coulomb_friction");
  ASSERT_NE(coulomb, nullptr);
  const Candidate* stribeck = find(cs, "stribeck_friction", coulomb->equation);
  ASSERT_NE(stribeck, nullptr);
  Trial special;
  special.cand = *coulomb;
  special.model = coulomb->model;
  special.ok = true;
  for (std::size_t k = 0; k < coulomb->parameters.size(); ++k)  // an optimum away from the start
    special.model.parameter(coulomb->parameters[k])->value = 1.7 * coulomb->scales[k];
  const Simulator at_special(special.model, s.estimation, {s.options.screening_substeps});
  const Eigen::MatrixXd y_special = at_special.simulate(values_of(special.model)).outputs;
  const std::vector<Eigen::VectorXd> starts = starts_at_special_case(*stribeck, special);
  ASSERT_FALSE(starts.empty());
  const Simulator richer(stribeck->model, s.estimation, {s.options.screening_substeps});
  for (const auto& p : starts) {
    const Eigen::MatrixXd y = richer.simulate(p).outputs;
    ASSERT_EQ(y.rows(), y_special.rows());
    EXPECT_LE((y - y_special).cwiseAbs().maxCoeff(), 1e-9 * (1 + y_special.cwiseAbs().maxCoeff()));
  }
  // A law of another place has no start at this special case.
  for (const auto& c : cs)
    if (c.parts.empty() && c.effect == "stribeck_friction" && c.equation != coulomb->equation)
      EXPECT_TRUE(starts_at_special_case(c, special).empty()) << c.equation;
}

// Asymmetric friction reaches Coulomb by an equality (Fc_pos = Fc_neg = Fc, the catalogue's
// SpecialCase::equal) besides dFv = 0: started there it is Coulomb's optimum itself. Without the
// equality it had no start at Coulomb's optimum at all (a richer law that could end below it).
TEST(SpecialCases, AsymmetricFrictionStartedAtCoulombsOptimumSimulatesAsCoulomb) {
  const test::StageRun s(synthetic_plant("coulomb_friction"), false, 600);
  const std::vector<Candidate> cs = candidates_on(s);
  const Candidate* coulomb = find(cs, "coulomb_friction");
  ASSERT_NE(coulomb, nullptr);
  const Candidate* asymmetric = find(cs, "asymmetric_friction", coulomb->equation);
  ASSERT_NE(asymmetric, nullptr);
  EXPECT_TRUE(nests(*asymmetric, *coulomb));
  Trial special;
  special.cand = *coulomb;
  special.model = coulomb->model;
  special.ok = true;
  special.model.parameter(coulomb->parameters[0])->value = 1.7 * coulomb->scales[0];
  const Simulator at_special(special.model, s.estimation, {s.options.screening_substeps});
  const Eigen::MatrixXd y_special = at_special.simulate(values_of(special.model)).outputs;
  const std::vector<Eigen::VectorXd> starts = starts_at_special_case(*asymmetric, special);
  ASSERT_EQ(starts.size(), 1u);  // no nonlinear parameter: one start
  const Simulator richer(asymmetric->model, s.estimation, {s.options.screening_substeps});
  const Eigen::MatrixXd y = richer.simulate(starts[0]).outputs;
  EXPECT_LE((y - y_special).cwiseAbs().maxCoeff(), 1e-9 * (1 + y_special.cwiseAbs().maxCoeff()));
}
