// The paper's experiments with the physics and timing effects on at
// realistic levels (Coulomb friction mu 0.5 at the pad, FRI delay 2 ms, KRC
// cycle 2 ms; sim/lwr/README.md "Physics and timing effects"): every shipped
// scene keeps the criteria of test_experiments.cpp, and the effects do reach
// the runner (the co-manipulation's stick-slip tilts the tray further).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene_run.hpp"
#include "tactile_sim/runner.hpp"

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
  // The pad sticks to the tray's bar: the tray tilts further before the pad
  // slips (measured 3.4 deg against 1.25 deg frictionless). The recovery time
  // (DZMP_y low-passed 0.1 s) is about the same (1.41 s against 1.47 s).
  const Summary off = runScene("co_manipulation.yaml", {"effects={}"});
  EXPECT_GT(s.tray_angle_max_deg, off.tray_angle_max_deg + 1.0);
}

TEST(ExperimentsWithPhysicsEffects, SphereTable) {
  const Summary s = runScene("sphere_table.yaml", kEffects);
  EXPECT_EQ(s.status, "ok");
  EXPECT_NEAR(s.force_true_mean_n, 5.0, 1.0);
}

// The realistic delays on top of each scene as shipped (pad friction where it
// ships): the WTS frame's serial transfer (15.7 ms: 181 bytes at 115200 Bd),
// the KRC's 2 ms cycle and a 2 ms FRI delay. Every hold and paper scene but the
// co-manipulation passes its own criteria (metrics.criteria) for seeds 1 and 2,
// and the edge aligns within 5 s. The co-manipulation with friction and the
// WTS delay is not covered here: it fails its criteria for some seeds (README,
// "Simulated effects": stick-slip of the pad on the tray's bar).
TEST(ExperimentsWithRealisticDelays, ShippedScenesPassTheirCriteria) {
  const std::vector<std::string> delays = {"effects.wts_transfer_delay_s=0.0157", "effects.krc_cycle_s=0.002",
                                           "effects.fri_delay_s=0.002"};
  for (const char* name : {"edge_exploration.yaml", "bent_bar.yaml", "sphere_table.yaml", "partial_edge.yaml",
                           "short_bar.yaml", "off_centre_load.yaml"}) {
    for (int seed = 1; seed <= 2; ++seed) {
      Scene sc = test::loadShipped(name, delays);
      EXPECT_DOUBLE_EQ(sc.sensor_effects.wts_transfer_delay_s, 0.0157);
      sc.seed = static_cast<uint64_t>(seed);
      const Summary s = test::run(sc);
      EXPECT_EQ(s.status, "ok") << name << " seed " << seed;
      EXPECT_TRUE(s.criteria_failed.empty())
          << name << " seed " << seed << ": " << (s.criteria_failed.empty() ? "" : s.criteria_failed[0]);
      if (std::string(name) == "edge_exploration.yaml") {
        EXPECT_LT(s.alignment_time_s, 5.0) << "seed " << seed;
      }
    }
  }
}
