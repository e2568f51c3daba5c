// The locate stage of the diagnosis (src/diagnosis/locate.cpp) on the Coulomb-friction plant: the
// error bound is 3 x the noise estimate, the mismatch windows lie inside the record, the residual is
// concentrated in its top operating region, the frequency band lies below Nyquist, and the
// signature is the residual of the worst-fitting output.

#include <gtest/gtest.h>

#include "sets/examples/random_plants.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

TEST(Locate, OutputNormsAreTheSpreadAboutTheMeanAndOneForAConstant) {
  Eigen::MatrixXd Y(4, 2);
  Y << 1, 5, 3, 5, 1, 5, 3, 5;
  const std::vector<double> n = output_norms(Y);
  ASSERT_EQ(n.size(), 2u);
  EXPECT_DOUBLE_EQ(n[0], 2.0);  // sqrt(4 * 1^2)
  EXPECT_EQ(n[1], 1.0);
}

TEST(Locate, CoulombPlantMismatchIsPlacedInsideTheRecordAndBelowNyquist) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  test::StageRun s(p, true, 2000);
  s.options.varying_segments = 10;
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  locate_mismatch(s.c(), nominal, noise, s.d);
  const Diagnosis& d = s.d;
  ASSERT_EQ(d.error_bound.size(), 1u);
  EXPECT_DOUBLE_EQ(d.error_bound[0], 3 * noise.sigma[0]);
  const double t0 = s.exact->time().front(), t1 = s.exact->time().back();
  ASSERT_FALSE(d.windows.empty()) << "friction leaves a mismatch far above the noise";
  for (const auto& w : d.windows) {
    EXPECT_EQ(w.output, "x_meas");
    EXPECT_GE(w.start, t0);
    EXPECT_LE(w.end, t1);
    EXPECT_LT(w.start, w.end);
    EXPECT_GT(w.rms, 0.0);
  }
  ASSERT_FALSE(d.regions.empty());
  EXPECT_GT(d.regions[0].residual_share, d.regions[0].sample_share) << d.regions[0].description;
  for (const auto& r : d.regions) {
    EXPECT_GE(r.sample_share, 0.0);
    EXPECT_LE(r.residual_share, 1.0);
  }
  const double nyquist = 0.5 / s.exact->sample_time();
  for (const auto& b : d.bands) {
    EXPECT_LE(0.0, b.lo_hz);
    EXPECT_LE(b.lo_hz, b.peak_hz);
    EXPECT_LE(b.peak_hz, b.hi_hz);
    EXPECT_LE(b.hi_hz, nyquist * (1 + 1e-12));
  }
  EXPECT_EQ(d.signature_output, "x_meas");
  ASSERT_EQ(d.signature_residual.size(), s.exact->samples());
  EXPECT_NEAR(d.signature_residual[10], s.exact->measured()(10, 0) - nominal.simulation.outputs(10, 0), 1e-12);
  EXPECT_EQ(d.varying.size(), nominal.free.size());
}

// A mismatch window of fewer samples than free parameters (here one sample at the record's start,
// where the moving RMS has seen only that sample) has no FPS to test: it is reported, not
// falsified, and the stage does not throw. (Random plant 5 001 816, a clean plant of the ninth
// session's held-out run, failed there with "FeasibleParameterSet: 1 samples for 3 parameters".)
TEST(Locate, AWindowWithFewerSamplesThanParametersIsNotFalsifiedAndDoesNotThrow) {
  test::StageRun s(random_plant(5001816));
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  ASSERT_NO_THROW(locate_mismatch(s.c(), nominal, noise, s.d));
  bool short_window = false;
  for (const auto& w : s.d.windows) {
    const double samples = (w.end - w.start) / s.exact->sample_time() + 1;
    if (samples < static_cast<double>(nominal.free.size())) {
      short_window = true;
      EXPECT_FALSE(w.falsified);
    }
  }
  EXPECT_TRUE(short_window) << "the plant no longer has the short window this test is about";
}
