// The diagnostic variants of Cerone–Regruto's PUIs (regressor boxes that leave out some of the
// measurement errors): `both` is the method itself, and leaving errors out can only shrink the
// regressor boxes, hence the feasible set and its PUIs, while the output strips keep Delta eta.

#include <gtest/gtest.h>

#include <optional>

#include <iostream>
#include <random>
#include <string>

#include "sets/examples/cerone_regruto.hpp"
#include "sets/methods/lpv_pui/lpv_pui.hpp"
#include "sets/methods/lpv_pui/unreliable_lpv_pui.hpp"

namespace {

using sets::RegressorErrors;

// The PUI box a lies inside the PUI box b, up to the LPs' tolerance relative to b's widths.
void expect_inside(const sets::IntervalVector& a, const sets::IntervalVector& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  for (Eigen::Index j = 0; j < a.size(); ++j) {
    const double tol = 1e-7 * (b[j].upper() - b[j].lower());
    EXPECT_GE(a[j].lower(), b[j].lower() - tol) << what << ", parameter " << j;
    EXPECT_LE(a[j].upper(), b[j].upper() + tol) << what << ", parameter " << j;
  }
}

double total_width(const sets::IntervalVector& box) {
  double w = 0;
  for (Eigen::Index j = 0; j < box.size(); ++j) w += box[j].upper() - box[j].lower();
  return w;
}

}  // namespace

TEST(UnreliableLpvPui, LeavingErrorsOutOnlyShrinksTheRegressorBoxesAndThePuis) {
  std::mt19937_64 rng(11);
  const double delta = 5e-3;
  const auto e = sets::cerone_regruto::simulate(150, true, delta, rng);
  const auto model = sets::cerone_regruto::structure();

  const auto method = sets::lpv_pui(model, e.data);
  const auto both = sets::unreliable_lpv_pui(model, e.data, RegressorErrors::both);
  ASSERT_FALSE(method.pui.empty());
  for (Eigen::Index j = 0; j < method.pui.box.size(); ++j) {  // `both` is the method itself
    EXPECT_EQ(both.pui.box[j].lower(), method.pui.box[j].lower());
    EXPECT_EQ(both.pui.box[j].upper(), method.pui.box[j].upper());
  }

  int empty = 0;
  std::optional<sets::PuiResult> scheduling;
  for (RegressorErrors which : {RegressorErrors::scheduling, RegressorErrors::output, RegressorErrors::none}) {
    const std::string name = sets::to_string(which);
    const auto r = sets::unreliable_lpv_pui(model, e.data, which);
    ASSERT_EQ(r.regression.Phi.rows(), method.regression.Phi.rows()) << name;
    for (Eigen::Index row = 0; row < r.regression.Phi.rows(); ++row) {
      // The output strips keep the full Delta eta ...
      EXPECT_NEAR(r.regression.Y[row].upper() - r.regression.Y[row].lower(), 2 * delta, 1e-12) << name;
      // ... and each regressor box lies in the method's.
      for (Eigen::Index j = 0; j < r.regression.Phi.cols(); ++j) {
        EXPECT_GE(r.regression.Phi(row, j).lower(), method.regression.Phi(row, j).lower()) << name;
        EXPECT_LE(r.regression.Phi(row, j).upper(), method.regression.Phi(row, j).upper()) << name;
      }
    }
    // A smaller set may be empty: without the errors the data can falsify the model (which is
    // why these variants are not guaranteed). Otherwise it lies in the method's answer and, with
    // errors on both signals, is really narrower.
    if (r.pui.empty()) {
      ++empty;
      continue;
    }
    expect_inside(r.pui.box, method.pui.box, name);
    EXPECT_LT(total_width(r.pui.box), total_width(method.pui.box)) << name;
    if (which == RegressorErrors::scheduling) scheduling = r.pui;
    if (which == RegressorErrors::none && scheduling) expect_inside(r.pui.box, scheduling->box, "none in scheduling");
  }
  EXPECT_LT(empty, 3);  // at least one variant is checked against the method's box
  std::cout << "    " << empty << " of 3 variants found the data inconsistent\n";
}

TEST(UnreliableLpvPui, NamesOfTheVariants) {
  EXPECT_STREQ(sets::to_string(RegressorErrors::both), "both");
  EXPECT_STREQ(sets::to_string(RegressorErrors::scheduling), "scheduling");
  EXPECT_STREQ(sets::to_string(RegressorErrors::output), "output");
  EXPECT_STREQ(sets::to_string(RegressorErrors::none), "none");
}
