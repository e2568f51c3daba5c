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

// The catalogue's candidates on the fixed suite's Coulomb plant, generated on its nominal as a
// first round generates them; Coulomb friction's place and the richer laws there.
struct FrictionLaws {
  test::StageRun s{synthetic_plant("coulomb_friction"), false, 600};
  std::vector<Candidate> all = generate_candidates(s.model, s.fast->simulate(values_of(s.model)), s.estimation);
  const Candidate* coulomb = find("coulomb_friction");
  const Candidate* stribeck = coulomb ? find("stribeck_friction", coulomb->equation) : nullptr;
  const Candidate* asymmetric = coulomb ? find("asymmetric_friction", coulomb->equation) : nullptr;

  const Candidate* find(const std::string& effect, const std::string& equation = "") const {
    for (const auto& c : all)
      if (c.parts.empty() && c.effect == effect && (equation.empty() || c.equation == equation)) return &c;
    return nullptr;
  }
  // Coulomb friction calibrated (by hand) away from its screening start.
  Trial coulomb_optimum() const {
    Trial t;
    t.cand = *coulomb;
    t.model = coulomb->model;
    t.ok = true;
    for (std::size_t k = 0; k < coulomb->parameters.size(); ++k)
      t.model.parameter(coulomb->parameters[k])->value = 1.7 * coulomb->scales[k];
    return t;
  }
  // The largest output difference between `law` at `p` and `special` at its optimum, relative.
  double mismatch(const Candidate& law, const Eigen::VectorXd& p, const Trial& special) const {
    const Simulator at_special(special.model, s.estimation, {s.options.screening_substeps});
    const Eigen::MatrixXd y_special = at_special.simulate(values_of(special.model)).outputs;
    const Eigen::MatrixXd y = Simulator(law.model, s.estimation, {s.options.screening_substeps}).simulate(p).outputs;
    if (y.rows() != y_special.rows() || y.cols() != y_special.cols()) return INFINITY;
    return (y - y_special).cwiseAbs().maxCoeff() / (1 + y_special.cwiseAbs().maxCoeff());
  }
};

}  // namespace

TEST(SpecialCases, StribeckNestsCoulombAtItsOwnPlaceOnly) {
  const FrictionLaws f;
  ASSERT_NE(f.coulomb, nullptr);
  ASSERT_NE(f.stribeck, nullptr);
  Fixed fixed;
  EXPECT_TRUE(nests(*f.stribeck, *f.coulomb, &fixed));
  ASSERT_FALSE(fixed.empty());  // Stribeck's extra term is fixed on the way to Coulomb
  for (const auto& [name, value] : fixed) {
    EXPECT_NE(std::find(f.stribeck->parameters.begin(), f.stribeck->parameters.end(), name), f.stribeck->parameters.end())
        << name;
    EXPECT_TRUE(std::isfinite(value)) << name;
  }
  EXPECT_FALSE(nests(*f.coulomb, *f.stribeck));  // not the other way round
  EXPECT_FALSE(nests(*f.coulomb, *f.coulomb));   // a law is not strictly richer than itself
  for (const auto& c : f.all)
    if (c.parts.empty() && c.effect == "coulomb_friction" && c.equation != f.coulomb->equation) {
      EXPECT_FALSE(nests(*f.stribeck, c)) << "Coulomb in " << c.equation;
    }
}

// At each start built from the special case's optimum, the richer law *is* the special case: the
// same simulated outputs, so its calibration from there cannot end worse than the special case.
TEST(SpecialCases, RicherLawStartedAtItsSpecialCasesOptimumSimulatesAsTheSpecialCase) {
  const FrictionLaws f;
  ASSERT_NE(f.stribeck, nullptr);
  const Trial special = f.coulomb_optimum();
  const std::vector<Eigen::VectorXd> starts = starts_at_special_case(*f.stribeck, special);
  ASSERT_FALSE(starts.empty());
  for (const auto& p : starts) EXPECT_LE(f.mismatch(*f.stribeck, p, special), 1e-9);
  // A law of another place has no start at this special case.
  for (const auto& c : f.all)
    if (c.parts.empty() && c.effect == "stribeck_friction" && c.equation != f.coulomb->equation) {
      EXPECT_TRUE(starts_at_special_case(c, special).empty()) << c.equation;
    }
}

// Asymmetric friction reaches Coulomb by an equality (Fc_pos = Fc_neg = Fc, the catalogue's
// SpecialCase::equal) besides dFv = 0: started there it is Coulomb's optimum itself. Without the
// equality it had no start at Coulomb's optimum at all (a richer law that could end below it).
TEST(SpecialCases, AsymmetricFrictionStartedAtCoulombsOptimumSimulatesAsCoulomb) {
  const FrictionLaws f;
  ASSERT_NE(f.asymmetric, nullptr);
  EXPECT_TRUE(nests(*f.asymmetric, *f.coulomb));
  const Trial special = f.coulomb_optimum();
  const std::vector<Eigen::VectorXd> starts = starts_at_special_case(*f.asymmetric, special);
  ASSERT_EQ(starts.size(), 1u);  // no nonlinear parameter: one start
  EXPECT_LE(f.mismatch(*f.asymmetric, starts[0], special), 1e-9);
}
