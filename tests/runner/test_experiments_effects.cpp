// The paper's experiments with the physics and timing effects on at
// realistic levels (Coulomb friction mu 0.5 at the pad, FRI delay 2 ms, KRC
// cycle 2 ms; core/sim/lwr/README.md "Physics and timing effects"): every shipped
// scene keeps the criteria of test_experiments.cpp, and the effects do reach
// the runner (the co-manipulation's pad drags on the tray's bar).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene_run.hpp"
#include "tactile_sim_runner/runner.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

const std::vector<std::string> kEffects = {"effects={friction_mu: 0.5, fri_delay_s: 0.002, krc_cycle_s: 0.002}"};

Summary runScene(const std::string& name, const std::vector<std::string>& overrides) {
  const Scene sc = test::loadShipped(name, overrides);
  if (overrides == kEffects) {
    EXPECT_EQ(sc.world.friction_mu, 0.5);
    EXPECT_EQ(sc.world.fri_delay_s, 0.002);
  }
  return test::run(sc);
}

// Runs `sc` at `seed` and expects status ok with every criterion of the
// scene met (metrics.criteria).
Summary expectCriteriaMet(Scene sc, int seed, const std::string& name) {
  sc.seed = static_cast<uint64_t>(seed);
  const Summary s = test::run(sc);
  EXPECT_EQ(s.status, "ok") << name << " seed " << seed;
  EXPECT_TRUE(s.criteria_failed.empty())
      << name << " seed " << seed << ": " << (s.criteria_failed.empty() ? "" : s.criteria_failed[0]);
  return s;
}

}  // namespace

TEST(ExperimentsWithPhysicsEffects, EdgeExploration) {
  const Summary s = runScene("edge_exploration.yaml", kEffects);
  EXPECT_EQ(s.status, "ok");
  EXPECT_LT(s.alignment_time_s, 10.0);
  EXPECT_GE(s.path_length_m, 0.15);
  EXPECT_NEAR(s.force_true_mean_n, 5.0, 1.0);
  EXPECT_LT(s.force_true_rms_error_n, 1.0);
  EXPECT_LE(s.contact_lost_count, 3);
}

TEST(ExperimentsWithPhysicsEffects, BentBar) {
  const Summary s = runScene("bent_bar.yaml", kEffects);
  EXPECT_EQ(s.status, "ok");
  EXPECT_GE(s.slide_speed_mps, 0.010);
  EXPECT_GE(s.path_length_m, 0.2);
  EXPECT_NEAR(s.force_true_mean_n, 5.0, 1.0);
  EXPECT_LE(s.force_true_max_n, 6.0);
  EXPECT_GE(s.force_true_in_band_fraction, 0.99);
  EXPECT_LT(s.force_true_rms_error_n, 1.0);
}

TEST(ExperimentsWithPhysicsEffects, CoManipulation) {
  const Summary s = runScene("co_manipulation.yaml", kEffects);
  EXPECT_EQ(s.status, "ok");
  ASSERT_TRUE(std::isfinite(s.dzmp_recovery_time_s));
  EXPECT_LT(s.dzmp_recovery_time_s, 5.0);
  EXPECT_LT(std::fabs(s.dzmp_final_m), 0.0005);
  EXPECT_GT(s.translation_x_m, 0.01);
  EXPECT_NEAR(s.force_true_mean_n, 6.0, 1.0);
  EXPECT_LT(s.tray_angle_max_deg, 5.0);
  EXPECT_EQ(s.sim_unconverged_steps, 0);
  // The friction reaches the runner: while the arm slides the pad along the
  // tray's bar to rebalance (5-8 s), the drag mu N (0.5 x ~6.7 N) holds the
  // sensor back from its command by mu N / k_trans (k_trans 1000 N/m):
  // ~3.4 mm (measured 3.75 mm) against 0.09 mm without friction. The tray's
  // tilt and the recovery time stay about the same (1.29 deg and 1.51 s
  // against 1.27 deg and 1.48 s).
  auto maxLagX = [](const RunResult& r) {
    double lag = 0.0;
    for (const auto& row : r.rows)
      if (row.t > 5.0 && row.t < 8.0) lag = std::max(lag, std::fabs(row.cmd[0] - row.act[0]));
    return lag;
  };
  const double mu_n_over_k = 0.5 * 6.0 / 1000.0;  // m, with the 6 N set point
  EXPECT_GT(maxLagX(test::runFull(test::loadShipped("co_manipulation.yaml", kEffects))), 0.8 * mu_n_over_k);
  EXPECT_LT(maxLagX(test::runFull(test::loadShipped("co_manipulation.yaml", {"effects={}"}))), 0.1 * mu_n_over_k);
}

TEST(ExperimentsWithPhysicsEffects, SphereTable) {
  const Summary s = runScene("sphere_table.yaml", kEffects);
  EXPECT_EQ(s.status, "ok");
  EXPECT_NEAR(s.force_true_mean_n, 5.0, 1.0);
}

// The realistic delays on top of each scene as shipped (pad friction where it
// ships): the WTS frame's serial transfer (15.7 ms: 181 bytes at 115200 Bd),
// the KRC's 2 ms cycle and a 2 ms FRI delay. Every hold and paper scene passes
// its own criteria (metrics.criteria) for seeds 1 and 2, and the edge aligns
// within 5 s. (The co-manipulation with friction and the WTS delay once failed
// for some seeds: the quasi-static solve stopped at its iteration cap during
// stick-slip, World::stepQuasiStatic; 20 of 20 seeds pass now.)
TEST(ExperimentsWithRealisticDelays, ShippedScenesPassTheirCriteria) {
  const std::vector<std::string> delays = {"effects.wts_transfer_delay_s=0.0157", "effects.krc_cycle_s=0.002",
                                           "effects.fri_delay_s=0.002"};
  for (const char* name : {"edge_exploration.yaml", "bent_bar.yaml", "sphere_table.yaml", "partial_edge.yaml",
                           "short_bar.yaml", "off_centre_load.yaml", "co_manipulation.yaml"}) {
    for (int seed = 1; seed <= 2; ++seed) {
      const Scene sc = test::loadShipped(name, delays);
      EXPECT_DOUBLE_EQ(sc.sensor_effects.wts_transfer_delay_s, 0.0157);
      const Summary s = expectCriteriaMet(sc, seed, name);
      if (std::string(name) == "edge_exploration.yaml") {
        EXPECT_LT(s.alignment_time_s, 5.0) << "seed " << seed;
      }
    }
  }
}

// Every simulated effect of the hardware at once, at the levels of
// scripts/sweeps/sweep_effects.py (`all`): the delays, pad friction, creep,
// hysteresis, per-taxel gain spread, two dead taxels, calibration error,
// crosstalk, the device's noise level, the arm's wrench error and the dynamic
// tray. Each experiment scene passes its own criteria (metrics.criteria) for
// seeds 1 and 2: the shipped edge-exploration, bent-bar and hold programs
// regulate the force estimate (force_estimator.hpp, bound 2.5 N), which takes
// up the load that the sensor's gain and crosstalk errors hide. The paper's
// tactile-only hold program does not: on the off-centre load its first touch
// at the pad's end loads the rigid housing, and the force-mismatch watchdog
// stops it (seed 2).
TEST(ExperimentsWithEveryEffect, ShippedScenesPassTheirCriteria) {
  const std::string all =
      "effects={wts_transfer_delay_s: 0.0157, krc_cycle_s: 0.002, fri_delay_s: 0.002, friction_mu: 0.5, "
      "creep: {fraction: 0.1, tau_s: 2.0}, hysteresis: 0.05, gain_spread: 0.1, dead_taxels: 2, "
      "calibration_error: 0.05, crosstalk: 0.05, device_noise: true, "
      "wrench_error: {bias_n: [1.0, -1.0, 2.0], noise_n: 0.5}}";
  // The closed contours (the force estimate at 6 N) pass too; the
  // force-mismatch watchdog reads the wrench less its tared zero (before, the
  // estimate's 2 N offset stopped the ring at seed 2 on the tactile force).
  for (const char* name : {"edge_exploration.yaml", "bent_bar.yaml", "sphere_table.yaml", "partial_edge.yaml",
                           "short_bar.yaml", "off_centre_load.yaml", "co_manipulation.yaml", "ring.yaml",
                           "rounded_square.yaml", "s_curve.yaml", "gap_bars.yaml"}) {
    std::vector<std::string> overrides = {all};
    if (std::string(name) == "co_manipulation.yaml") overrides.push_back("objects.0.fidelity=dynamics");
    for (int seed = 1; seed <= 2; ++seed) {
      const Scene sc = test::loadShipped(name, overrides);
      EXPECT_DOUBLE_EQ(sc.sensor_effects.crosstalk, 0.05);
      EXPECT_DOUBLE_EQ(sc.world.friction_mu, 0.5);
      expectCriteriaMet(sc, seed, name);
    }
  }
  Scene paper = test::loadPaper("off_centre_load.yaml", {all});
  ASSERT_FALSE(paper.servo.force_estimate.fused);
  paper.seed = 2;  // stopped at seeds 2-5 of 1-5 (seed 1 passes)
  const Summary p = test::run(paper);
  EXPECT_EQ(p.status, "servo_force_mismatch");
  EXPECT_FALSE(p.criteria_failed.empty());
}
