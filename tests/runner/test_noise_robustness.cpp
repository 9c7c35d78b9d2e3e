// Robustness to sensor noise (the features' noise-free reconstruction,
// core/features extractor.hpp): with 5x the simulated sensor noise
// (sensor.noise_counts = 30, 1 sigma) the true force stays within 5 +- 1 N
// for >= 95 % of the sliding time on the bent bar and the edge exploration,
// exactly as `tactile_sim run SCENE --set sensor.noise_counts=30` runs them.
// The same run without the estimate (features.censor_tau = 0) is asserted
// to miss the target on the edge exploration with the paper's program
// (Eq. 2's force alone): the cause this test guards.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_run.hpp"
#include "tactile_sim_runner/runner.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {


Summary runNoisy(const std::string& scene, double noise_counts, bool estimate, bool paper = false) {
  const std::vector<std::string> noise = {"sensor.noise_counts=" + std::to_string(noise_counts)};
  Scene sc = paper ? test::loadPaper(scene, noise) : test::loadShipped(scene, noise);
  EXPECT_EQ(sc.world.pad.noise_counts, noise_counts);
  EXPECT_EQ(sc.calibration.noise_counts, noise_counts) << "the reader's noise figure follows the sensor's";
  if (!estimate) sc.features.censor_tau = 0.0;
  return test::run(sc);
}

}  // namespace

TEST(NoiseRobustness, FiveTimesTheNoiseKeepsTheTrueForceInBandOnBentBar) {
  const Summary s = runNoisy("bent_bar.yaml", 30.0, true);
  EXPECT_EQ(s.status, "ok");
  EXPECT_GE(s.force_true_in_band_fraction, 0.95);
}

TEST(NoiseRobustness, FiveTimesTheNoiseKeepsTheTrueForceInBandOnEdgeExploration) {
  const Summary s = runNoisy("edge_exploration.yaml", 30.0, true);
  EXPECT_EQ(s.status, "ok");
  EXPECT_GE(s.force_true_in_band_fraction, 0.95);
  EXPECT_LT(s.alignment_time_s, 10.0);
}

TEST(NoiseRobustness, WithoutTheEstimateTheNoisePushesTheTrueForceOut) {
  // The noise switches taxels near the 0.2 N firing threshold off; the
  // measured force drops, and the paper's program (Eq. 2's force alone)
  // presses harder: true force ~6.2 N. (The shipped program's wrench
  // correction takes part of that up as well.)
  const Summary s = runNoisy("edge_exploration.yaml", 30.0, false, true);
  EXPECT_LT(s.force_true_in_band_fraction, 0.95);
  EXPECT_GT(s.force_true_mean_n, 5.6);
}
