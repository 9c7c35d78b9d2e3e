// The KRC's own start sequence and its interruptions, in-process: the edge
// exploration through the FRI bridge (bytes on the wire, tactile::fri::
// KrcModel as the KRC) with the KRC following a KRL script (the scene key
// `krc`, tactile::fri::KrcScript):
//   friOpen -> friStart 1 s later (monitor mode first, as KRL starts it);
//   friStop -> friStart in the middle of the slide;
//   a drop of the link quality to BAD and back;
//   the drives off and on.
// Each run must: hold the arm still while it cannot be commanded (the servo
// waits: waiting_for_robot); follow within 1 s of command mode; never let the
// KRC apply two consecutive commands further apart than the bridge's limited
// step (max_lin_speed x 1 ms); and end as the run that started in command
// mode does (the scene's criteria, the same phases, the true force on target).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene_run.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/params_io.hpp"
#include "tactile_sim_runner/runner.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

struct Case {
  const char* name;
  RunResult run;
  Scene scene;
};

Scene sceneWith(const std::string& krc, double extra_s, bool through_fri = true) {
  Scene sc = test::loadShipped("edge_exploration.yaml");
  sc.through_fri = through_fri;
  sc.krc = krc;
  sc.duration += extra_s;  // the time the arm cannot be commanded is added to the run
  return sc;
}

double tEnter(const RunResult& r, const std::string& phase) {
  for (const auto& p : r.phases)
    if (p.name == phase) return p.t_enter;
  return NAN;
}

double dist3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

const LogRow* rowAt(const RunResult& r, double t) {
  for (const LogRow& row : r.rows)
    if (row.t >= t - 1e-9) return &row;
  return nullptr;
}

// The reference: command mode from the start (the default "0:friOpen,0.005:friStart").
const RunResult& reference() {
  static const RunResult r = test::runFull(sceneWith("", 0.0));
  return r;
}

// The KRC's applied command steps stay within one limited step (1 ms at the
// bridge's max_lin_speed; 2e-7 m: the wire's float positions).
double bridgeStep() {
  fri::BridgeParams bp;  // the scene's fri_file, or the bridge's defaults (as the runner)
  fri::UdpParams up;
  const Scene sc = sceneWith("", 0.0);
  if (!sc.fri_file.empty()) {
    EXPECT_TRUE(fri::loadBridgeParamsFile(sc.fri_file, bp, up).ok());
  }
  return bp.max_lin_speed * 0.001 + 2e-7;
}

// While the arm cannot be commanded over [t0, t1): every servo row after the
// first reports waiting_for_robot and the sensor stays where it was (0.05 mm:
// the impedance settling of a held arm); within 1 s of t1 it moves again.
void expectHeldThenFollows(const RunResult& r, double t0, double t1, const std::string& what) {
  const LogRow* at0 = rowAt(r, t0 + 0.02);
  ASSERT_NE(at0, nullptr) << what;
  int waiting = 0;
  double drift = 0.0;
  for (const LogRow& row : r.rows) {
    if (row.t < t0 + 0.02 || row.t >= t1) continue;
    waiting += row.servo == ServoStatus::WaitingForRobot;
    drift = std::max(drift, dist3(row.act, at0->act));
  }
  const int rows = static_cast<int>(std::lround((t1 - t0 - 0.02) * 100.0));
  EXPECT_GE(waiting, rows - 1) << what << ": the servo did not wait";
  EXPECT_LT(drift, 5e-5) << what << ": the arm moved while it could not be commanded";
  const LogRow* at1 = rowAt(r, t1);
  ASSERT_NE(at1, nullptr) << what;
  double moved = 0.0;
  for (const LogRow& row : r.rows)
    if (row.t >= t1 && row.t <= t1 + 1.0) moved = std::max(moved, dist3(row.act, at1->act));
  EXPECT_GT(moved, 5e-4) << what << ": the arm did not follow within 1 s of command mode";
  for (const LogRow& row : r.rows) {
    if (row.t > t1 + 0.05 && row.t < t1 + 1.0) {
      EXPECT_NE(row.servo, ServoStatus::WaitingForRobot) << what << " at " << row.t;
    }
  }
}

// The same result as the reference run: ok, the scene's criteria met, the same
// phases in the same order, the true force on target as well (0.1 N: one
// seed's spread between runs of the same scene shifted in time), the same
// exploration (the bar's end reached: path within 5 %).
void expectSameResult(const RunResult& r, const std::string& what) {
  const RunResult& ref = reference();
  EXPECT_EQ(r.summary.status, ref.summary.status) << what;
  EXPECT_EQ(r.summary.exit_code, 0) << what;
  EXPECT_TRUE(r.summary.criteria_failed.empty()) << what << ": " << (r.summary.criteria_failed.empty() ? "" : r.summary.criteria_failed[0]);
  ASSERT_EQ(r.phases.size(), ref.phases.size()) << what;
  for (std::size_t i = 0; i < r.phases.size(); ++i) EXPECT_EQ(r.phases[i].name, ref.phases[i].name) << what;
  EXPECT_NEAR(r.summary.force_true_rms_error_n, ref.summary.force_true_rms_error_n, 0.1) << what;
  EXPECT_NEAR(r.summary.path_length_m, ref.summary.path_length_m, 0.05 * ref.summary.path_length_m) << what;
  EXPECT_LE(r.summary.fri_max_step_m, bridgeStep()) << what << ": the KRC saw a step larger than one limited step";
}

}  // namespace

TEST(KrcSequences, ReferenceStartsInCommandMode) {
  const RunResult& r = reference();
  EXPECT_EQ(r.summary.status, "ok");
  EXPECT_TRUE(r.summary.criteria_failed.empty());
  EXPECT_GT(r.summary.fri_replies, 0);
  EXPECT_LE(r.summary.fri_max_step_m, bridgeStep());
}

TEST(KrcSequences, FriOpenThenFriStartOneSecondLater) {
  const RunResult r = test::runFull(sceneWith("0:friOpen,1.0:friStart", 1.0));
  expectHeldThenFollows(r, 0.0, 1.0, "friOpen -> friStart");
  expectSameResult(r, "friOpen -> friStart");
  // The phases start 1 s later than in the reference, to within a servo cycle or two.
  EXPECT_NEAR(tEnter(r, "align") - tEnter(reference(), "align"), 1.0, 0.03);
}

TEST(KrcSequences, FriStopAndFriStartInTheMiddleOfTheSlide) {
  const double t_explore = tEnter(reference(), "explore");
  ASSERT_TRUE(std::isfinite(t_explore));
  const double t0 = t_explore + 2.0, t1 = t0 + 0.5;
  const std::string krc = "0:friOpen,0.005:friStart," + std::to_string(t0) + ":friStop," + std::to_string(t1) + ":friStart";
  const RunResult r = test::runFull(sceneWith(krc, 0.5));
  ASSERT_EQ(rowAt(r, t0)->phase, rowAt(reference(), t0)->phase) << "the stop must fall in the slide";
  expectHeldThenFollows(r, t0, t1, "friStop -> friStart");
  expectSameResult(r, "friStop -> friStart");
}

TEST(KrcSequences, AQualityDropToBadAndBack) {
  const double t0 = tEnter(reference(), "explore") + 1.0, t1 = t0 + 0.3;
  const std::string krc =
      "0:friOpen,0.005:friStart," + std::to_string(t0) + ":quality=BAD," + std::to_string(t1) + ":quality=PERFECT";
  const RunResult r = test::runFull(sceneWith(krc, 0.3));
  // At BAD the KRC keeps its last set point (it applies no command): the arm
  // settles on it, a few tenths of a mm, then holds; the servo waits.
  int waiting = 0;
  for (const LogRow& row : r.rows) waiting += row.t >= t0 + 0.02 && row.t < t1 && row.servo == ServoStatus::WaitingForRobot;
  EXPECT_GE(waiting, 26);
  double moved = 0.0;
  const LogRow* at1 = rowAt(r, t1);
  for (const LogRow& row : r.rows)
    if (row.t >= t1 && row.t <= t1 + 1.0) moved = std::max(moved, dist3(row.act, at1->act));
  EXPECT_GT(moved, 5e-4) << "the arm did not follow within 1 s of the quality's return";
  expectSameResult(r, "quality BAD -> PERFECT");
}

TEST(KrcSequences, TheDrivesOffAndOn) {
  const double t0 = tEnter(reference(), "explore") + 1.5, t1 = t0 + 0.4;
  const std::string krc = "0:friOpen,0.005:friStart," + std::to_string(t0) + ":power=off," + std::to_string(t1) + ":power=on";
  const RunResult r = test::runFull(sceneWith(krc, 0.4));
  expectHeldThenFollows(r, t0, t1, "drives off -> on");
  expectSameResult(r, "drives off -> on");
}

TEST(KrcSequences, WithoutFriTheSimulatedArmFollowsTheSameScript) {
  // The simulated arm component's path (no bytes on the wire): the same rule.
  const RunResult r = test::runFull(sceneWith("0:friOpen,1.0:friStart", 1.0, false));
  expectHeldThenFollows(r, 0.0, 1.0, "friOpen -> friStart (no FRI)");
  EXPECT_EQ(r.summary.status, "ok");
  EXPECT_TRUE(r.summary.criteria_failed.empty());
}

TEST(KrcSequences, AScriptThatNeverStartsHoldsForTheWholeRun) {
  Scene sc = sceneWith("0:friOpen", 0.0);
  sc.duration = 3.0;
  const RunResult r = test::runFull(sc);
  ASSERT_FALSE(r.rows.empty());
  for (const LogRow& row : r.rows) {
    if (row.t < 0.02) continue;
    EXPECT_EQ(row.servo, ServoStatus::WaitingForRobot) << row.t;
    EXPECT_LT(dist3(row.act, r.rows.front().act), 5e-5) << row.t;
  }
  EXPECT_EQ(r.phases.size(), 1u) << "the program advanced";
}

TEST(KrcSequences, ABadScriptIsAClearError) {
  for (const char* bad : {"1:friStart", "0:friOpen,1:friBegin", "0:friOpen,2:friStart,1:friStop", "0:friOpen,x:friStart",
                          "0:friOpen,1:quality=GOOD"}) {
    Scene sc = sceneWith(bad, 0.0);
    Runner runner;
    const ConfigResult c = runner.configure(sc);
    EXPECT_FALSE(c.ok()) << bad;
    EXPECT_NE(c.message().find("krc"), std::string::npos) << c.message();
  }
  Scene sc;
  const ConfigResult c = loadScene(test::kScenes + "edge_exploration.yaml", sc, {"krc=\"0:friOpen,1:friBegin\""});
  EXPECT_FALSE(c.ok());
  EXPECT_NE(c.message().find("edge_exploration.yaml: krc"), std::string::npos) << c.message();
  EXPECT_NE(c.message().find("friBegin"), std::string::npos) << c.message();
  EXPECT_NE(c.message().find("friOpen | friStart"), std::string::npos) << c.message();
}
