// The Monte Carlo study of Farah et al., Section V: independent of the thread count, its figures
// are those of the single runs, and the guaranteed set holds the truth when its assumption holds.

#include <gtest/gtest.h>

#include "sets/core/error.hpp"
#include "sets/examples/farah_study.hpp"

namespace {

void expect_same_counts(const sets::farah::FailureCount& a, const sets::farah::FailureCount& b, const char* what) {
  EXPECT_EQ(a.outside, b.outside) << what;
  EXPECT_EQ(a.undecided, b.undecided) << what;
  EXPECT_EQ(a.runs, b.runs) << what;
}

void expect_same_study(const sets::farah::StudyResult& one, const sets::farah::StudyResult& other) {
  EXPECT_EQ(one.mean, other.mean);
  EXPECT_EQ(one.std_dev, other.std_dev);
  EXPECT_EQ(one.mean_ell, other.mean_ell);
  EXPECT_EQ(one.ellipsoid_box_halfwidth, other.ellipsoid_box_halfwidth);
  EXPECT_EQ(one.estimate_pui_halfwidth, other.estimate_pui_halfwidth);
  EXPECT_EQ(one.mean_state_radius, other.mean_state_radius);
  expect_same_counts(one.ellipsoid, other.ellipsoid, "ellipsoid");
  expect_same_counts(one.estimate_fps, other.estimate_fps, "estimate FPS");
  expect_same_counts(one.estimate_fps_pui, other.estimate_fps_pui, "estimate FPS PUI");
  expect_same_counts(one.guaranteed, other.guaranteed, "guaranteed");
  EXPECT_EQ(one.runs_meeting_assumption, other.runs_meeting_assumption);
  ASSERT_EQ(one.pairs.size(), other.pairs.size());
  for (std::size_t k = 0; k < one.pairs.size(); ++k) {
    expect_same_counts(one.pairs[k].projection, other.pairs[k].projection, "projection");
    expect_same_counts(one.pairs[k].slice, other.pairs[k].slice, "slice");
  }
}

// Every figure bit for bit (the timing aside): runs depend only on their index and the sums
// follow the run order, so neither the thread count nor the scheduling may show.
TEST(FarahStudy, ThreadCountDoesNotChangeTheResult) {
  sets::farah::StudyOptions o;
  o.runs = 9;
  o.fps_pui_runs = 4;  // run-index dependent work
  o.threads = 1;
  const auto one = sets::farah::study(o);
  EXPECT_EQ(one.estimate_fps_pui.runs, 4);
  for (const int threads : {2, 3}) {
    o.threads = threads;
    const auto other = sets::farah::study(o);
    expect_same_study(one, other);
    // The busiest worker's CPU time is part of the process' CPU time.
    EXPECT_GT(other.busiest_thread_cpu_seconds, 0.0);
    EXPECT_LE(other.busiest_thread_cpu_seconds, other.cpu_seconds + 1e-3);
  }
}

// Table I and the ellipsoid's failure count are those of the runs made one by one with
// run_generator, farah::simulate and ss_uncertainty.
TEST(FarahStudy, AgreesWithSingleRuns) {
  sets::farah::StudyOptions o;
  o.runs = 4;
  o.seed = 17;
  o.guaranteed = false;
  o.fps_pui_runs = 0;
  o.threads = 2;
  const auto r = sets::farah::study(o);
  const auto sys = sets::farah::system();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(r.truth.size());
  int outside = 0;
  for (int k = 0; k < o.runs; ++k) {
    auto rng = sets::farah::run_generator(o.seed, k);
    const auto d = sets::farah::simulate(sys, o.samples, o.snr_db, rng);
    sets::SsUncertaintyOptions so;
    so.identification.order = 3;
    so.identification.past = o.past;
    so.identification.rows = r.rows;
    so.estimate_fps_pui = false;
    const auto run = sets::ss_uncertainty(d.u, d.y, so);
    sum += run.estimate_level_set.theta;
    outside += sets::contains(run.estimate_level_set.ellipsoid, r.truth) == sets::BoolInterval::no;
  }
  const Eigen::VectorXd mean = sum / o.runs;
  EXPECT_LE((r.mean - mean).cwiseAbs().maxCoeff(), 1e-12 * mean.cwiseAbs().maxCoeff());
  EXPECT_EQ(r.ellipsoid.outside, outside);
  EXPECT_EQ(r.ellipsoid.runs, o.runs);
  EXPECT_GT(r.std_dev.minCoeff(), 0.0);
  // The true parameters are those of the printed system in the rows' canonical form.
  const sets::CanonicalStructure structure(r.rows, 2, 2, false);
  EXPECT_EQ(r.truth, structure.to_parameters(sets::canonical_form(sys, r.rows)));
  ASSERT_EQ(r.pairs.size(), static_cast<std::size_t>(r.truth.size() * (r.truth.size() - 1) / 2));
  EXPECT_EQ(r.names[r.pairs[0].i], "-a0");
  EXPECT_EQ(r.names[r.pairs[0].j], "-a1");
}

// Under bounded (uniform) noise the guaranteed set's assumption holds in every run, and then the
// set holds the true parameters in every run, its PUIs too.
TEST(FarahStudy, GuaranteedSetHoldsTheTruthUnderBoundedNoise) {
  sets::farah::StudyOptions o;
  o.runs = 24;
  o.seed = 3;
  o.noise = sets::farah::Noise::uniform;
  o.fps_pui_runs = 0;
  o.guaranteed_pui_runs = 2;
  o.threads = 2;
  const auto r = sets::farah::study(o);
  EXPECT_EQ(r.runs_meeting_assumption, o.runs);
  EXPECT_EQ(r.contradicted_runs, 0);
  EXPECT_EQ(r.guaranteed.outside, 0);
  EXPECT_EQ(r.guaranteed.runs, o.runs);
  EXPECT_EQ(r.guaranteed_pui.runs, 2);
  EXPECT_EQ(r.guaranteed_pui.outside, 0);
  EXPECT_GT(r.guaranteed_pui_halfwidth.minCoeff(), 0.0);
  EXPECT_GT(r.mean_state_radius.minCoeff(), 0.0);
}

TEST(FarahStudy, OptionsItCannotUseNameTheField) {
  sets::farah::StudyOptions o;
  o.past = 2;
  try {
    sets::farah::study(o);
    ADD_FAILURE() << "no InputError";
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("past"), std::string::npos) << e.what();
  }
  o.past = 20;
  o.runs = 0;
  EXPECT_THROW(sets::farah::study(o), sets::InputError);
}

}  // namespace
