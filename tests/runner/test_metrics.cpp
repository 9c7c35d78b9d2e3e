// The run's summary metrics (core/sim/runner/src/metrics.cpp, computeSummary): the
// whole slide beside the scored window, on synthetic logs whose figures are
// known exactly; the criteria that name either; the fault's time.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>

#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/runner.hpp"
#include "tactile_sim_runner/scene.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

// Sums of a few hundred steps of 1 mm or 10 ms in double: exact to ~1e-13;
// the figures below are asserted to 1e-9 (m, s, m/s, N).
constexpr double kSumTol = 1e-9;
constexpr double kRow = 0.01;            // s: the servo's period (100 Hz)
constexpr double kSpeed = 0.1;           // m/s: the true contact's speed while it slides
constexpr double kSetPoint = 5.0;        // N
constexpr double kOutOfBand = 7.0;       // N: 2 N off the set point, outside the 0.5 N band

// A program of four phases: approach (no contact needed: not scored), explore
// (the scored phase), end_check (a detour out of it) and done (terminal).
Scene slideScene() {
  Scene sc;
  for (const char* n : {"approach", "explore", "end_check", "done"}) {
    PhaseParams p;
    p.name = n;
    p.requires_contact = std::string(n) != "approach";
    p.terminal = std::string(n) == "done";
    sc.servo.phases.push_back(p);
  }
  sc.metrics.force_phases = {"explore"};
  sc.metrics.transient_s = 2.0;
  sc.metrics.force_band_n = 0.5;
  return sc;
}

struct Segment {
  int phase;
  double until_s;   // the segment's rows: t from the previous segment's end to until_s (excluded)
  double force_n;   // the true force in it
};

// Rows every 10 ms from t = 0. Outside `approach` the pad touches the bar and
// its true contact point slides at kSpeed along x from the first contact row.
RunResult logOf(const Scene& sc, std::initializer_list<Segment> segments, const std::string& status = "ok") {
  RunResult out;
  for (const auto& p : sc.servo.phases) out.phase_names.push_back(p.name);
  int k = 0;
  double x = 0.0;
  bool touched = false;
  for (const Segment& seg : segments) {
    for (; kRow * k < seg.until_s - 1e-9; ++k) {
      LogRow r;
      r.t = kRow * k;
      r.phase = seg.phase;
      r.sd_force = kSetPoint;
      r.force_true = seg.force_n;
      r.true_in_contact = seg.phase != 0;
      if (r.true_in_contact) {
        if (touched) x += kSpeed * kRow;
        touched = true;
      }
      r.true_contact = {x, 0.0, 0.0};
      out.rows.push_back(r);
    }
  }
  out.phases = phaseEntries(sc, out.rows);
  out.summary.status = status;
  out.summary.sim_time_s = out.rows.empty() ? 0.0 : out.rows.back().t;
  computeSummary(sc, out);
  return out;
}

}  // namespace

// 1 s of approach, then 5 s of explore whose first 0.5 s is off the set point
// (the touch's transient), then done. The slide is explore's 500 rows
// (t = 1.00 ... 5.99 s): 499 steps of 1 mm in 4.99 s; the true force 7 N in 50
// rows and 5 N in 450. The scored window starts 2 s into explore: 300 rows
// (t = 3.00 ... 5.99 s), 299 steps of 1 mm in 2.99 s, all at 5 N.
TEST(Metrics, TheWholeSlideAndTheScoredWindowOfOneSlide) {
  const Scene sc = slideScene();
  const Summary s = logOf(sc, {{0, 1.0, 0.0}, {1, 1.5, kOutOfBand}, {1, 6.0, kSetPoint}, {3, 6.5, kSetPoint}}).summary;
  // The whole slide, transients included.
  EXPECT_NEAR(s.slide_path_m, 0.499, kSumTol);
  EXPECT_NEAR(s.slide_duration_s, 4.99, kSumTol);
  EXPECT_NEAR(s.slide_mean_speed_mps, kSpeed, kSumTol);
  EXPECT_NEAR(s.slide_force_true_mean_n, (50 * kOutOfBand + 450 * kSetPoint) / 500.0, kSumTol);
  EXPECT_DOUBLE_EQ(s.slide_force_true_max_n, kOutOfBand);
  EXPECT_NEAR(s.slide_force_true_rms_error_n, std::sqrt(50 * 4.0 / 500.0), kSumTol);
  EXPECT_NEAR(s.slide_force_true_in_band_fraction, 450.0 / 500.0, kSumTol);
  // The scored window: after explore's 2 s transient.
  EXPECT_NEAR(s.path_length_m, 0.299, kSumTol);
  EXPECT_NEAR(s.scored_duration_s, 2.99, kSumTol);
  EXPECT_NEAR(s.slide_speed_mps, kSpeed, kSumTol);
  EXPECT_NEAR(s.force_scored_s, 3.0, kSumTol);  // each row counts the 10 ms since the log's previous row
  EXPECT_DOUBLE_EQ(s.force_true_mean_n, kSetPoint);
  EXPECT_DOUBLE_EQ(s.force_true_rms_error_n, 0.0);
  EXPECT_DOUBLE_EQ(s.force_true_in_band_fraction, 1.0);
  EXPECT_TRUE(std::isnan(s.fault_time_s)) << "an ok run has no fault";
}

// A detour (end_check and back to explore within the transient) belongs to
// the slide as it belongs to the scored window; the final check, from which
// the run goes to done, belongs to neither. Explore 1-2.5 s, a 0.1 s check at
// 7 N, explore 2.6-4 s, the final check 4-4.3 s, done: the slide is t = 1.00
// ... 3.99 s (300 rows, 299 steps, 10 rows at 7 N); the scored window t = 3.00
// ... 3.99 s (the detour's return starts no new transient).
TEST(Metrics, ADetourBelongsToTheSlideTheFinalCheckDoesNot) {
  const Scene sc = slideScene();
  const Summary s = logOf(sc, {{0, 1.0, 0.0},
                               {1, 2.5, kSetPoint},
                               {2, 2.6, kOutOfBand},
                               {1, 4.0, kSetPoint},
                               {2, 4.3, kOutOfBand},
                               {3, 4.5, kSetPoint}})
                        .summary;
  EXPECT_NEAR(s.slide_path_m, 0.299, kSumTol);
  EXPECT_NEAR(s.slide_duration_s, 2.99, kSumTol);
  EXPECT_NEAR(s.slide_mean_speed_mps, kSpeed, kSumTol);
  EXPECT_NEAR(s.slide_force_true_in_band_fraction, 290.0 / 300.0, kSumTol);
  EXPECT_NEAR(s.path_length_m, 0.099, kSumTol);
  EXPECT_NEAR(s.scored_duration_s, 0.99, kSumTol);
  EXPECT_DOUBLE_EQ(s.force_true_in_band_fraction, 1.0);
}

// The pad slides 0.499 m and the scored window sees 0.299 m of it: a
// criterion "slid at least 0.45 m along the bar" names the whole slide
// (slide_path_m) and holds; the scored window's path (path_length_m, also
// scored_path_m) does not reach it. Each key summaryMetric knows is a
// criterion a scene may name, with the same value as summary.json's.
TEST(Metrics, ACriterionMayNameTheWholeSlideOrTheScoredWindow) {
  const Scene base = slideScene();
  RunResult out = logOf(base, {{0, 1.0, 0.0}, {1, 6.0, kSetPoint}, {3, 6.5, kSetPoint}});
  const double inf = std::numeric_limits<double>::infinity();
  Scene sc = base;
  sc.metrics.criteria = {{"slide_path_m", 0.45, inf}, {"slide_mean_speed_mps", 0.099, 0.101},
                         {"slide_duration_s", 4.98, 5.0}, {"slide_force_true_in_band_fraction", 1.0, inf},
                         {"scored_path_m", 0.29, 0.30}, {"scored_mean_speed_mps", 0.099, 0.101}};
  checkCriteria(sc, out.summary);
  EXPECT_TRUE(out.summary.criteria_failed.empty())
      << (out.summary.criteria_failed.empty() ? "" : out.summary.criteria_failed.front());
  sc.metrics.criteria = {{"path_length_m", 0.45, inf}, {"scored_path_m", 0.45, inf}};
  checkCriteria(sc, out.summary);
  ASSERT_EQ(out.summary.criteria_failed.size(), 2u);
  EXPECT_EQ(out.summary.criteria_failed[0], "path_length_m = 0.299 < 0.45");
  EXPECT_EQ(out.summary.criteria_failed[1], "scored_path_m = 0.299 < 0.45");
  // summary.json carries both windows under these names.
  const std::string js = summaryJson(sc, out);
  for (const char* key : {"\"slide_path_m\": 0.499", "\"slide_duration_s\": 4.99", "\"slide_mean_speed_mps\": 0.1",
                          "\"scored_path_m\": 0.299", "\"path_length_m\": 0.299", "\"scored_duration_s\": 2.99",
                          "\"slide_force_true_in_band_fraction\": 1", "\"fault_time_s\": null"})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in\n" << js;
}

// A run that a servo watchdog ended: the summary names the fault (status) and
// the time of the first cycle with it; the simulator's fatal status, the end.
TEST(Metrics, TheFaultTimeIsTheFirstCycleWithTheFatalStatus) {
  const Scene sc = slideScene();
  RunResult out;
  for (const auto& p : sc.servo.phases) out.phase_names.push_back(p.name);
  for (int k = 0; k < 300; ++k) {
    LogRow r;
    r.t = kRow * k;
    r.phase = 1;
    r.servo = k >= 250 ? ServoStatus::SurfaceTooCurved : ServoStatus::Ok;
    out.rows.push_back(r);
  }
  out.phases = phaseEntries(sc, out.rows);
  out.summary.status = "servo_surface_too_curved";
  out.summary.sim_time_s = 2.995;
  computeSummary(sc, out);
  EXPECT_NEAR(out.summary.fault_time_s, 2.5, kSumTol);
  out.summary.status = "sim_joint_limit";
  computeSummary(sc, out);
  EXPECT_DOUBLE_EQ(out.summary.fault_time_s, 2.995);
}
