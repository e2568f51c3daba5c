// "Do the data falsify the model?" (sets/fps/falsification.hpp): the three-valued verdict on tiny
// hand-made bounded-error systems whose answer is known exactly — strips that miss each other are
// certified to falsify the model (the Farkas certificate is checked in rationals), a gap below the
// LP tolerance is never called consistent, strips that touch in one point are certified
// consistent — and the messages the user reads.

#include "sets/fps/falsification.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "sets/fps/feasible_parameter_set.hpp"
#include "support/messages.hpp"

using sets::ConsistencyVerdict;
using sets::FeasibleParameterSet;
using sets::Falsified;
using sets::test::contains;

namespace {

// Scalar model y = theta + e, |e| <= delta, one strip per (y, delta).
FeasibleParameterSet scalar(const std::vector<std::pair<double, double>>& samples) {
  FeasibleParameterSet fps(1);
  for (const auto& [y, delta] : samples) fps.add_strip(Eigen::VectorXd::Ones(1), y, delta);
  return fps;
}

bool has_sample(const sets::Falsification& f, int s) {
  return std::find(f.samples.begin(), f.samples.end(), s) != f.samples.end();
}

}  // namespace

TEST(Falsification, StripsThatMissEachOtherAreCertifiedToFalsify) {
  // theta in [0.5, 1.5] and theta in [1.5 + 1e-3, 2.5 + 1e-3]: empty.
  const auto fps = scalar({{1.0, 0.5}, {2.001, 0.5}});
  const ConsistencyVerdict v = sets::check_consistency(fps);
  EXPECT_EQ(v.falsified, Falsified::yes) << v.message();
  EXPECT_TRUE(v.certified_falsified());
  EXPECT_FALSE(v.certified_consistent());
  EXPECT_TRUE(has_sample(v.conflict, 0));
  EXPECT_TRUE(has_sample(v.conflict, 1));
  ASSERT_EQ(v.conflict.samples.size(), v.conflict.violation.size());
  for (double e : v.conflict.violation) EXPECT_NEAR(e, 5e-4, 1e-9);  // the best compromise splits the gap
  EXPECT_TRUE(contains(v.message(), "the data falsify the model")) << v.message();
  EXPECT_TRUE(contains(v.message(), "certified in exact arithmetic")) << v.message();
  // pui() reports the same verdict and an empty box.
  const sets::PuiResult r = sets::pui(fps);
  EXPECT_EQ(r.consistency.falsified, Falsified::yes);
  EXPECT_TRUE(r.empty());
}

TEST(Falsification, AGapBelowTheLpToleranceIsNeverCalledConsistent) {
  // Gaps of 2^-40 .. 1e-7 are within the floating-point LP's tolerance: the LP finds a "point",
  // which then fails the exact check. The answer may be yes or unknown, never no.
  for (double gap : {std::ldexp(1.0, -40), 1e-9, 1e-7}) {
    const ConsistencyVerdict v = sets::check_consistency(scalar({{1.0, 0.5}, {2.0 + gap, 0.5}}));
    EXPECT_NE(v.falsified, Falsified::no) << gap << ": " << v.message();
    EXPECT_FALSE(v.certified_consistent()) << gap;
    if (v.falsified == Falsified::unknown) {
      EXPECT_FALSE(v.reason.empty()) << gap;
    }
  }
}

TEST(Falsification, StripsThatTouchInOnePointAreCertifiedConsistent) {
  // theta in [0.5, 1.5] and theta in [1.5, 2.5]: the single point 1.5 satisfies both exactly.
  const auto fps = scalar({{1.0, 0.5}, {2.0, 0.5}});
  const ConsistencyVerdict v = sets::check_consistency(fps);
  EXPECT_EQ(v.falsified, Falsified::no) << v.message();
  EXPECT_TRUE(v.certified_consistent());
  EXPECT_TRUE(v.conflict.samples.empty());
  EXPECT_TRUE(contains(v.message(), "consistent")) << v.message();
  const sets::PuiResult r = sets::pui(fps);
  ASSERT_FALSE(r.empty());
  EXPECT_LE(r.box[0].lower(), 1.5);
  EXPECT_GE(r.box[0].upper(), 1.5);
}

TEST(Falsification, ThreeStripsWithoutACommonPointNameAConflictThatIsItselfInfeasible) {
  // theta1 + theta2 within 1e-3 of 0, theta1 within 1e-3 of 1, theta2 within 1e-3 of 1: the three
  // cannot hold together (1 + 1 != 0), any two can. A fourth, harmless sample is not in conflict.
  FeasibleParameterSet fps(2);
  fps.add_strip(Eigen::Vector2d(1, 1), 0.0, 1e-3);
  fps.add_strip(Eigen::Vector2d(1, 0), 1.0, 1e-3);
  fps.add_strip(Eigen::Vector2d(0, 1), 1.0, 1e-3);
  fps.add_strip(Eigen::Vector2d(1, -1), 0.0, 10.0);
  const ConsistencyVerdict v = sets::check_consistency(fps);
  ASSERT_EQ(v.falsified, Falsified::yes) << v.message();
  for (int s : {0, 1, 2}) EXPECT_TRUE(has_sample(v.conflict, s)) << v.message();
  EXPECT_FALSE(has_sample(v.conflict, 3)) << v.message();
  // Any two of the three are consistent.
  for (int drop : {0, 1, 2}) {
    FeasibleParameterSet two(2);
    const Eigen::Vector2d phi[3] = {{1, 1}, {1, 0}, {0, 1}};
    const double y[3] = {0.0, 1.0, 1.0};
    for (int s = 0; s < 3; ++s)
      if (s != drop) two.add_strip(phi[s], y[s], 1e-3);
    EXPECT_EQ(sets::check_consistency(two).falsified, Falsified::no) << "without sample " << drop;
  }
}

TEST(Falsification, MessagesAndNamesOfTheVerdict) {
  EXPECT_STREQ(sets::to_string(Falsified::no), "no");
  EXPECT_STREQ(sets::to_string(Falsified::yes), "yes");
  EXPECT_STREQ(sets::to_string(Falsified::unknown), "unknown");
  std::ostringstream os;
  os << Falsified::unknown << ' ' << Falsified::yes;
  EXPECT_EQ(os.str(), "unknown yes");

  sets::Falsification f;
  EXPECT_EQ(f.message(), "the data falsify the model: no parameter value satisfies all samples");
  f.samples = {3, 7};
  f.violation = {0.25, 1.5};
  EXPECT_TRUE(contains(f.message(), " 3: 0.25 7: 1.5")) << f.message();

  ConsistencyVerdict u;  // undecided by default: never reported as falsified
  EXPECT_EQ(u.falsified, Falsified::unknown);
  EXPECT_FALSE(u.certified_falsified());
  EXPECT_FALSE(u.certified_consistent());
  EXPECT_EQ(u.message(), "whether the data falsify the model could not be decided");
  u.reason = "no certificate";
  EXPECT_EQ(u.message(), "whether the data falsify the model could not be decided: no certificate");
  EXPECT_FALSE(contains(u.message(), "the data falsify the model:"));
}
