// The loop's shared rules (tactile_sim/loop.hpp): the schedule of Table 2's
// rates, the end rule, and the simulated sensor's response from the one
// calibration file (tactile::sim::TaxelResponse).
#include <gtest/gtest.h>

#include <cmath>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_sim/loop.hpp"
#include "tactile_sim/scene.hpp"
#include "tactile_sim/taxel_response.hpp"

using namespace tactile;
using namespace tactile::sim;

TEST(Schedule, FiresAtTable2RatesInPipelineOrder) {
  Schedule s;
  ASSERT_TRUE(s.configure(Rates{}, 2.0).ok());
  EXPECT_EQ(s.ticks(), 2000);
  EXPECT_EQ(s.periodNs(), 1000000);
  int wts = 0, feat = 0, servo = 0;
  long last_servo = -1;
  for (; !s.finished(); s.advance()) {
    const StageFires f = s.fires();
    if (s.tick() == 0) {
      EXPECT_TRUE(f.wts && f.features && f.servo) << "every stage fires on tick 0";
    }
    wts += f.wts;
    feat += f.features;
    if (f.servo) {
      if (last_servo >= 0) {
        EXPECT_EQ(s.tick() - last_servo, 10) << "100 Hz: every 10th tick";
      }
      last_servo = s.tick();
      ++servo;
    }
  }
  EXPECT_EQ(servo, 200);
  EXPECT_EQ(feat, 400);
  EXPECT_EQ(wts, 280);  // 140 Hz, nearest ticks, no drift
  // Time as RTT's TimeService reads nanoseconds.
  EXPECT_EQ(s.timeOf(1234), static_cast<double>(1234000000LL) / 1e9);
  Schedule bad;
  const ConfigResult r = bad.configure(Rates{1000, 2000, 140, 200}, 1.0);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("rates.servo"), std::string::npos) << r.message();
}

TEST(EndRule, CeilingAtOnceDoneAfterOneSecondFatalSim) {
  EndRule e;
  e.configure(Rates{});
  EXPECT_EQ(e.afterServo(ServoStatus::Ok), EndReason::None);
  EXPECT_EQ(e.afterServo(ServoStatus::ForceCeiling), EndReason::ServoForceCeiling);
  e.reset();
  for (int k = 0; k < 100; ++k) EXPECT_EQ(e.afterServo(ServoStatus::Done), EndReason::None) << k;
  EXPECT_EQ(e.afterServo(ServoStatus::Done), EndReason::DoneHeld);
  EXPECT_EQ(e.afterPhysics(SimStatus::Ok), EndReason::None);
  EXPECT_EQ(e.afterPhysics(SimStatus::ForceCeiling), EndReason::SimFatal);
  Summary s;
  applyEnd(EndReason::SimFatal, SimStatus::ForceCeiling, s);
  EXPECT_EQ(s.status, "sim_force_ceiling");
  EXPECT_EQ(s.exit_code, 3);
  applyEnd(EndReason::ServoForceCeiling, SimStatus::Ok, s);
  EXPECT_EQ(s.status, "servo_force_ceiling");
  EXPECT_EQ(s.exit_code, 4);
}

// The simulated sensor's counts are the inverse of the reader's calibration
// file: calibrated back with the same file they give the forces (noise-free:
// within half a count), saturate at full scale, and read 0 below the firing threshold.
TEST(TaxelResponse, InvertsTheCalibrationFile) {
  Scene sc;
  ASSERT_TRUE(loadScene(TACTILE_SOURCE_DIR "/sim/scenes/edge_exploration.yaml", sc).ok());
  EXPECT_TRUE(sc.world.pad.use_calibration) << "the scene's pad response comes from features_file";
  EXPECT_EQ(sc.calibration.border_coeffs[1], 0.000667) << "wts0614.yaml's border coefficient";
  TaxelResponseParams p;
  p.calibration = sc.calibration;
  p.noise_counts = 0.0;
  p.threshold = 0.2;
  TaxelResponse resp;
  ASSERT_TRUE(resp.configure(p).ok());
  Calibration cal;
  ASSERT_TRUE(cal.configure(sc.calibration).ok());
  TactileFrame forces;
  forces.rows = 6;
  forces.cols = 14;
  for (int i = 0; i < 84; ++i) forces.force[static_cast<std::size_t>(i)] = 0.035 * i;  // 0 .. 2.9 N (centre full scale: 3.01 N)
  forces.force[20] = 1e3;  // beyond full scale
  RawTactileFrame raw;
  tactile::test::AllocationScope scope;
  resp.respond(forces, 1.5, raw);
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(raw.time_s, 1.5);
  TactileFrame back;
  cal.step(raw, back);
  EXPECT_EQ(raw.counts[20], 4095);
  EXPECT_EQ(back.saturated_count, 1);
  for (int i = 0; i < 84; ++i) {
    if (i == 20) continue;
    const double f = forces.force[static_cast<std::size_t>(i)];
    if (f < 0.19) {
      EXPECT_EQ(raw.counts[static_cast<std::size_t>(i)], 0) << i;
      continue;
    }
    if (f < 0.25) continue;  // at the firing threshold: either side after rounding
    const double n = resp.countsFor(i, f);
    const double half_count = 0.5 * (resp.forceFor(i, n + 1.0) - resp.forceFor(i, n));
    EXPECT_NEAR(back.force[static_cast<std::size_t>(i)], f, half_count + 1e-12) << i;
  }
  // A response that cannot be inverted is refused, naming the key.
  p.calibration.coeffs[1] = 0.0;
  const ConfigResult r = resp.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("calibration.coeffs[1]"), std::string::npos) << r.message();
}
