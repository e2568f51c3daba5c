// A fixed-seed slice of the soundness campaign (the full 10 000 problems are
// bench/soundness_campaign_bench.cpp, figures in docs/reliability.md), and PUIs of the same
// problems from 8 threads at once (the TSan preset runs this test).

#include <gtest/gtest.h>

#include <thread>

#include "sets/examples/bounded_error_regression.hpp"
#include "sets/numeric/glpk_environment.hpp"

namespace {

// Seeds 1..250: 50 problems of each kind (seed s has kind (s - 1) mod 5).
constexpr unsigned long kFirstSeed = 1, kLastSeed = 250;

}  // namespace

TEST(SoundnessCampaign, NoFalseEmptyAndTheTruthInsideEveryGuaranteedPui) {
  int consistent = 0, unknown = 0, numerical = 0, guaranteed = 0;
  for (unsigned long seed = kFirstSeed; seed <= kLastSeed; ++seed) {
    const sets::BoundedErrorRegression problem = sets::bounded_error_regression(seed);
    ASSERT_EQ(problem.fps.contains(problem.theta), sets::BoolInterval::yes) << "seed " << seed;
    const sets::SoundnessOutcome o = sets::run_soundness_problem(problem);
    const std::string where = "seed " + std::to_string(seed) + " (" + sets::to_string(o.kind) + ")";
    // The truth is feasible: "the data falsify the model" is always wrong.
    EXPECT_FALSE(o.false_empty()) << where;
    if (o.numerical_error) {
      ++numerical;  // an honest failure (exit 3), never a wrong answer
      continue;
    }
    // Every PUI holds the truth: a guaranteed one by proof, the others because an end that
    // could not be certified is the orthant's own bound (never the floating-point extent).
    EXPECT_TRUE(o.theta_in_box) << where << (o.guaranteed ? " (guaranteed)" : " (not guaranteed)");
    consistent += o.verdict == sets::Falsified::no;
    unknown += o.verdict == sets::Falsified::unknown;
    guaranteed += o.guaranteed;
  }
  const int problems = static_cast<int>(kLastSeed - kFirstSeed + 1);
  // Decisive on most problems: an "unknown" is honest, but a library that answered it always
  // would be useless.
  EXPECT_GE(consistent, problems * 9 / 10) << unknown << " unknown, " << numerical << " numerical errors";
  EXPECT_GE(guaranteed, problems * 9 / 10);
  RecordProperty("certified_consistent", consistent);
  RecordProperty("unknown", unknown);
  RecordProperty("numerical_errors", numerical);
}

TEST(SoundnessCampaign, EightThreadsAtOnceGiveTheSerialAnswers) {
  // GLPK keeps one environment per thread; every pui() builds its own problems. Eight threads
  // run interleaved slices of the campaign; each answer must equal the serial one bit for bit.
  constexpr int threads = 8, per_thread = 6;
  std::vector<sets::BoundedErrorRegression> problems;
  for (unsigned long seed = 1; seed <= threads * per_thread; ++seed) problems.push_back(sets::bounded_error_regression(seed));
  std::vector<sets::PuiResult> serial, parallel(problems.size());
  for (const auto& pr : problems) serial.push_back(sets::pui(pr.fps, pr.options));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      const sets::GlpkThreadEnvironment glpk;
      for (std::size_t k = static_cast<std::size_t>(t); k < problems.size(); k += threads)
        parallel[k] = sets::pui(problems[k].fps, problems[k].options);
    });
  for (auto& th : pool) th.join();
  for (std::size_t k = 0; k < problems.size(); ++k) {
    ASSERT_EQ(parallel[k].consistency.falsified, serial[k].consistency.falsified) << "problem " << k;
    ASSERT_EQ(parallel[k].guaranteed, serial[k].guaranteed) << "problem " << k;
    ASSERT_EQ(parallel[k].box.size(), serial[k].box.size());
    for (Eigen::Index l = 0; l < serial[k].box.size(); ++l) {
      EXPECT_EQ(parallel[k].box[l].lower(), serial[k].box[l].lower()) << "problem " << k;
      EXPECT_EQ(parallel[k].box[l].upper(), serial[k].box[l].upper()) << "problem " << k;
    }
  }
}
