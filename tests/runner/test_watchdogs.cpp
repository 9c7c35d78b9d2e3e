// Nothing passes silently: runs where the servo's watchdogs must end the run
// with a named status and a non-zero exit code (never `ok`), each against the
// shipped programs' defaults, and the shipped experiments do not trip them.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_run.hpp"
#include "tactile_sim_runner/runner.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {


Scene load(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return test::loadShipped(name, overrides);
}

Summary run(const Scene& sc) { return test::run(sc); }

}  // namespace

// A pad 10x softer than the calibration assumes (`--set sensor.modulus=5e6`):
// the rigid housing carries the load and no taxel fires; the arm's estimated
// wrench carries a load the taxels do not see: servo_unseen_load, exit 10.
TEST(Watchdogs, SoftPadEndsWithUnseenLoad) {
  for (const char* scene : {"edge_exploration.yaml", "bent_bar.yaml"}) {
    Scene sc = load(scene, {"sensor.modulus=5e6"});
    const Summary s = run(sc);
    EXPECT_EQ(s.status, "servo_unseen_load") << scene;
    EXPECT_EQ(s.exit_code, 10) << scene;
    // With the check off the same run goes on (the failure it catches).
    Scene off = sc;
    off.servo.watchdogs.unseen_window_s = 0.0;
    off.duration = 3.0;
    EXPECT_NE(run(off).status, "servo_unseen_load") << scene;
  }
}

// An arm that does not follow its commands (impedance 1 N/m, 1 N m/rad with
// dynamics): the free-motion phase commands 10 mm/s and the measured pose
// stays put: servo_arm_stalled, exit 6.
TEST(Watchdogs, ArmThatDoesNotMoveEndsWithArmStalled) {
  Scene sc = load("edge_exploration.yaml", {"fidelity=dynamics", "arm.k_trans=1", "arm.k_rot=1"});
  const Summary s = run(sc);
  EXPECT_EQ(s.status, "servo_arm_stalled");
  EXPECT_EQ(s.exit_code, 6);
  EXPECT_LT(s.sim_time_s, 3.0);
  Scene off = sc;
  off.servo.watchdogs.stall_window_s = 0.0;
  off.duration = 5.0;
  EXPECT_EQ(run(off).status, "ok");  // without the watchdog: `ok`, the arm never having moved
}

// The closed-contour program's wider stall test (2 s, 10 mm: the first touch
// below the firing threshold and pad friction at the start of the slide lead
// the arm by several mm) still catches an arm that does not move, within 4 s.
TEST(Watchdogs, ClosedContourProgramStillCatchesAFrozenArm) {
  Scene sc = load("ring.yaml", {"fidelity=dynamics", "arm.k_trans=1", "arm.k_rot=1"});
  EXPECT_DOUBLE_EQ(sc.servo.watchdogs.stall_window_s, 2.0);
  EXPECT_DOUBLE_EQ(sc.servo.watchdogs.stall_min_distance, 0.01);
  const Summary s = run(sc);
  EXPECT_EQ(s.status, "servo_arm_stalled");
  EXPECT_EQ(s.exit_code, 6);
  EXPECT_LT(s.sim_time_s, 4.0);
}

// A phase that never ends: the edge-exploration program with its free-motion
// phase limited to 1 s, started far above the bar: servo_phase_timeout, exit 5.
TEST(Watchdogs, PhaseThatNeverEndsEndsWithPhaseTimeout) {
  Scene sc = load("edge_exploration.yaml");
  sc.servo.phases[static_cast<std::size_t>(0)].max_duration_s = 1.0;
  ASSERT_EQ(sc.servo.phases[0].name, "free_motion");
  const Summary s = run(sc);
  EXPECT_EQ(s.status, "servo_phase_timeout");
  EXPECT_EQ(s.exit_code, 5);
  EXPECT_NEAR(s.sim_time_s, 1.0, 0.05);
  Scene off = sc;
  off.servo.phases[0].max_duration_s = 0.0;
  off.duration = 2.0;
  EXPECT_EQ(run(off).status, "ok");
}

// The shipped program's default (phase_defaults.max_duration_s: 30 s): an
// edge that is never aligned (the `aligned` tolerance on alpha_z made
// unreachable) leaves edge_control running forever; the run says so after
// 30 s instead of `ok` after 60 s of nothing.
TEST(Watchdogs, EdgeExplorationThatNeverAlignsEndsWithPhaseTimeoutNotOk) {
  Scene sc = load("edge_exploration.yaml");
  bool found = false;
  for (auto& ph : sc.servo.phases)
    if (ph.name == "edge_control")
      for (auto& tr : ph.transitions)
        if (tr.on == TransitionEvent::Aligned) {
          tr.tolerance[kTolAlphaZ] = 1e-12;  // with the edge on one taxel row alpha_z can read exactly 0,
          tr.tolerance[kTolDzmpY] = 1e-12;   // so DZMP_y's tolerance too
          found = true;
        }
  ASSERT_TRUE(found);
  const Summary s = run(sc);
  EXPECT_EQ(s.status, "servo_phase_timeout");
  EXPECT_EQ(s.exit_code, 5);
  EXPECT_GT(s.sim_time_s, 30.0);
  EXPECT_LT(s.sim_time_s, 40.0);
}
