// The paper's experiments, reproduced headless and asserted on the runner's
// summary (Sec. 5: Fig. 10, 12, 14). Each test runs a shipped scene in-process with the
// same cores the RTT components wrap; numbers come from the physics, not from
// scripting. Tolerances are the targets of README.md's experiment table unless stated.
#include <gtest/gtest.h>

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <string>

#include "scene_run.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/runner.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

using test::kScenes;

// The paper's experiments and its controllers' comparisons run the paper's
// programs (`*_paper.yaml`: Eq. 2's force alone, CoP_y at 0; test::loadPaper);
// the shipped programs add the force estimate (tests at the end of the file).
RunResult runScene(const std::string& name, ControllerMode mode = ControllerMode::Proposed, Scene* out = nullptr,
                   bool force_mismatch_watchdog = true, const std::vector<std::string>& overrides = {}) {
  Scene sc = test::loadPaper(name, overrides);
  sc.controller = mode;
  if (!force_mismatch_watchdog) sc.servo.watchdogs.mismatch_window_s = 0.0;
  RunResult res = test::runFull(sc);
  if (out) *out = sc;
  return res;
}

double tEnter(const RunResult& r, const std::string& phase) {
  for (const auto& p : r.phases)
    if (p.name == phase) return p.t_enter;
  return NAN;
}

}  // namespace

// (a) Edge exploration (Sec. 5.2, Fig. 9/10): contact from free motion, phase II
// aligns, the switch to edge control happens on edge detection, phase IV
// slides >= 0.15 m along the bar; alignment < 10 s (paper: ~100 s).
TEST(Experiments, EdgeExploration) {
  const RunResult r = runScene("edge_exploration.yaml");
  const Summary& s = r.summary;
  EXPECT_EQ(s.status, "ok");
  EXPECT_EQ(s.exit_code, 0);
  const double t1 = tEnter(r, "free_motion"), t2 = tEnter(r, "align"), t3 = tEnter(r, "edge_control"),
               t4 = tEnter(r, "explore");
  ASSERT_TRUE(std::isfinite(t2) && std::isfinite(t3) && std::isfinite(t4));
  EXPECT_LT(t1, t2);
  EXPECT_LT(t2, t3);
  EXPECT_LT(t3, t4);
  EXPECT_GT(t2, 0.5) << "contact must come from free motion, not from the start pose";
  // The switch to edge control happened on an edge: the row at t3 sees an edge.
  for (const auto& row : r.rows)
    if (row.t >= t3 - 1e-9) {
      EXPECT_EQ(row.contact, ContactType::Edge);
      break;
    }
  EXPECT_LT(s.alignment_time_s, 10.0);
  EXPECT_GE(s.path_length_m, 0.15);
  // While sliding, the true force stays near the 5 N set point (the taxels'
  // 0.2 N firing threshold hides some of the line load: true > measured).
  EXPECT_NEAR(s.force_true_mean_n, 5.0, 1.0);
  EXPECT_LT(s.force_true_rms_error_n, 1.0);
  // Contact may flicker while the first taxels cross the 0.2 N firing
  // threshold at the onset (counted in contact_lost_count), but it is never
  // lost while sliding, until the bar's end ends the exploration.
  EXPECT_LE(s.contact_lost_count, 3);
  const double t_done = tEnter(r, "done");
  int absent = 0, worst_absent = 0;
  for (const auto& row : r.rows) {
    if (row.t < t4 || (std::isfinite(t_done) && row.t >= t_done - 0.5)) continue;
    absent = row.contact == ContactType::None ? absent + 1 : 0;
    worst_absent = std::max(worst_absent, absent);
  }
  EXPECT_LT(worst_absent, 5) << "servo cycles without contact while sliding";
  // The reconstructed cloud follows the true contact points (Fig. 9f).
  ASSERT_GT(r.contacts.size(), 500u);
  double worst = 0;
  for (const auto& c : r.contacts) {
    if (c.t < t4 + 2.0) continue;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (c.p[k] - c.truth[k]) * (c.p[k] - c.truth[k]);
    worst = std::max(worst, std::sqrt(d2));
  }
  EXPECT_LT(worst, 0.005) << "CoP in {g} within 5 mm of the true pressure centre while sliding";
}

// The same exploration with every 1 kHz command going through FRI packets and
// the bridge: the full headless loop can run through FRI.
TEST(Experiments, EdgeExplorationThroughFri) {
  Scene sc;
  ASSERT_TRUE(loadRun(test::shippedRun("edge_exploration.yaml"), sc).ok());
  sc.through_fri = true;
  sc.fri_file = std::string(TACTILE_SOURCE_DIR) + "/params/sensors/fri.yaml";
  Runner runner;
  const ConfigResult c = runner.configure(sc);
  ASSERT_TRUE(c.ok()) << c.message();
  RunResult r;
  runner.run(r);
  const Summary& s = r.summary;
  EXPECT_EQ(s.status, "ok");
  EXPECT_TRUE(std::isfinite(tEnter(r, "explore")));
  EXPECT_LT(s.alignment_time_s, 10.0);
  EXPECT_GE(s.path_length_m, 0.15);
  // One reply per physics cycle, and the KRC never applied a step above the
  // bridge's rate limit (fri.yaml: 0.15 m/s, 1.0 rad/s at 1 kHz; floats on the wire).
  EXPECT_GT(s.fri_replies, static_cast<long>(0.99 * s.sim_time_s * sc.rates.sim));
  EXPECT_LE(s.fri_max_step_m, 0.15 / sc.rates.sim + 2e-7);
  EXPECT_LE(s.fri_max_step_rad, 1.0 / sc.rates.sim + 2e-6);
  EXPECT_GT(s.fri_max_step_m, 0.0);
}

// (b) Bent bar (Sec. 5.2.1, Fig. 12): with DZMP control the true force stays
// near 5 N while sliding at >= 10 mm/s; without any rotation about x_s/y_s
// (the no_rotation ablation, the paper's Fig. 12 "baseline" curve) it drifts
// far. The Li et al. baseline with its CoP -> rotation rows follows the bar as
// well as the proposed controller here (docs/results.md, "Controllers compared").
TEST(Experiments, BentBarProposedHoldsTheForceNoRotationDrifts) {
  const RunResult p = runScene("bent_bar.yaml", ControllerMode::Proposed);
  // The ablation's drift, watched to the end: its force-mismatch watchdog off.
  const RunResult b = runScene("bent_bar.yaml", ControllerMode::NoRotation, nullptr, false);
  EXPECT_EQ(p.summary.status, "ok");
  EXPECT_GE(p.summary.slide_speed_mps, 0.010);
  EXPECT_GE(p.summary.path_length_m, 0.2);
  // The servo holds the *measured* force (sum of calibrated taxels) at 5 N:
  double measured = 0;
  int n = 0;
  for (const auto& row : p.rows)
    if (row.t > 3.0) {
      measured += row.f.force;
      ++n;
    }
  ASSERT_GT(n, 100);
  EXPECT_NEAR(measured / n, 5.0, 0.25);
  // The true force (the simulated Nano17) stays within the paper's 5 +- 1 N
  // after the transient. It sits above the measured force: taxels below the
  // 0.2 N firing threshold read 0 (with this 5 mm edge radius the bias is
  // ~0.6 N; with a 3 mm radius it is ~1.2 N and the band is missed, README).
  EXPECT_NEAR(p.summary.force_true_mean_n, 5.0, 1.0);
  EXPECT_LE(p.summary.force_true_max_n, 6.0);
  EXPECT_GE(p.summary.force_true_in_band_fraction, 0.99);
  EXPECT_LT(p.summary.force_true_rms_error_n, 1.0);
  // No rotation: far from 5 N (the paper reports up to 50 N for its
  // baseline), much of it on the rigid housing, which the taxels do not see.
  EXPECT_GT(b.summary.force_true_max_n, 30.0);
  EXPECT_GT(b.summary.force_true_rms_error_n, 5.0 * p.summary.force_true_rms_error_n);
  double housing = 0;
  for (const auto& row : b.rows) housing = std::max(housing, row.housing_force);
  EXPECT_GT(housing, 10.0);
  // With the watchdog on (the shipped program), the ablation's run does not end
  // `ok`: the arm's estimated wrench contradicts the tactile force (the rigid
  // housing carries load the taxels do not see) and the servo stops it.
  const RunResult w = runScene("bent_bar.yaml", ControllerMode::NoRotation);
  EXPECT_EQ(w.summary.status, "servo_force_mismatch");
  EXPECT_EQ(w.summary.exit_code, 7);
  EXPECT_LT(w.summary.force_true_max_n, b.summary.force_true_max_n);
}

// (b') The Li et al. (RSS 2013) baseline on the bent bar: its CoP -> rotation
// rows roll the pad onto the rising bar (the edge spans the pad, so CoC_x ~ 0
// and CoP_x ~ DZMP_y): the true force stays in the 5 +- 1 N band like the
// proposed controller's, no ceiling, and it slides the bar.
TEST(Experiments, BentBarLiBaselineFollowsTheBarToo) {
  // The scene starts 10 mm above the bar (1 s of free approach, for the shipped
  // program's wrench tare): 23 s reach the bar's end as 22 s did from 2 mm.
  const std::vector<std::string> to_the_end = {"duration=23"};
  const RunResult b = runScene("bent_bar.yaml", ControllerMode::Baseline, nullptr, true, to_the_end);
  EXPECT_EQ(b.summary.controller, "baseline");
  EXPECT_EQ(b.summary.status, "ok");
  EXPECT_NEAR(b.summary.force_true_mean_n, 5.0, 1.0);
  EXPECT_LT(b.summary.force_true_max_n, 6.5);
  EXPECT_GE(b.summary.force_true_in_band_fraction, 0.95);
  EXPECT_LT(b.summary.force_true_rms_error_n, 1.0);
  EXPECT_GE(b.summary.path_length_m, 0.2);
  double housing = 0;
  for (const auto& row : b.rows) housing = std::max(housing, row.housing_force);
  EXPECT_LT(housing, 1.0);
  // At the end of the bar the edge ends under the pad (a partial edge, CoC_x
  // moves off the centre): the baseline rolls towards the bar's end to centre
  // the CoP (by ~33 deg in the last 2.5 s), the proposed controller keeps the
  // line load level and its pitch within 1.5 deg.
  const RunResult p = runScene("bent_bar.yaml", ControllerMode::Proposed, nullptr, true, to_the_end);
  auto pitchAt = [](const RunResult& r, double t) {
    for (const auto& row : r.rows)
      if (row.t >= t) return row.act_rpy[1] * 180.0 / M_PI;
    return std::nan("");
  };
  const double t_end = b.rows.back().t;
  ASSERT_NEAR(p.rows.back().t, t_end, 1e-9);
  EXPECT_LT(std::fabs(pitchAt(p, t_end) - pitchAt(p, t_end - 2.5)), 1.5);
  EXPECT_GT(std::fabs(pitchAt(b, t_end) - pitchAt(b, t_end - 2.5)), 15.0);
}

// Where the DZMP rows matter (Sec. 2, case 2: a partial edge). The bar ends
// under the pad and rises 5 deg towards its end (partial_edge.yaml, held
// without sliding by hold_edge.yaml). The proposed controller levels the line
// load (DZMP_y = 0): the pad lies on the bar at its 5 deg and the true force
// sits close to the set point. The Li et al. baseline rolls until the CoP is
// at the sensor centre, which on a partial edge is not where the contact's
// centre is: the pad stays tilted against the bar and the load piles up at
// the bar's end (more of it below the taxels' firing threshold): its true
// force error is several times the proposed one's; no_rotation never tilts.
TEST(Experiments, PartialEdgeDzmpBeatsCopRolling) {
  Scene sc;
  const RunResult p = runScene("partial_edge.yaml", ControllerMode::Proposed, &sc);
  const RunResult b = runScene("partial_edge.yaml", ControllerMode::Baseline);
  const RunResult n = runScene("partial_edge.yaml", ControllerMode::NoRotation);
  for (const RunResult* r : {&p, &b, &n}) {
    EXPECT_EQ(r->summary.status, "ok") << r->summary.controller;
    EXPECT_GT(r->summary.force_scored_s, 10.0) << r->summary.controller;
  }
  // The pitch of the sensor at the end against the bar's 5 deg.
  auto pitchDeg = [](const RunResult& r) { return r.rows.back().act_rpy[1] * 180.0 / M_PI; };
  EXPECT_NEAR(std::fabs(pitchDeg(p)), 5.0, 0.3);
  EXPECT_GT(std::fabs(std::fabs(pitchDeg(b)) - 5.0), 0.5);
  EXPECT_LT(std::fabs(pitchDeg(n)), 0.5);
  // On the partial edge the contact's centre is off the sensor centre, and
  // the proposed controller's CoP follows it (DZMP_y ~ 0); the baseline's CoP
  // is at the centre instead.
  const LogRow& lp = p.rows.back();
  const LogRow& lb = b.rows.back();
  EXPECT_GT(std::fabs(lp.f.coc_x), 0.003);
  EXPECT_LT(std::fabs(lp.f.dzmp_y), 0.0005);
  EXPECT_LT(std::fabs(lb.f.cop_x), 0.001);
  EXPECT_GT(std::fabs(lb.f.dzmp_y), 0.001);
  // True force: the proposed controller's RMS error is below 40 % of either
  // constant Jacobian's (measured 0.11 N against 0.62 N and 0.68 N).
  EXPECT_NEAR(p.summary.force_true_mean_n, 5.0, 0.3);
  EXPECT_LT(p.summary.force_true_rms_error_n, 0.4 * b.summary.force_true_rms_error_n);
  EXPECT_LT(p.summary.force_true_rms_error_n, 0.4 * n.summary.force_true_rms_error_n);
  EXPECT_LT(p.summary.force_true_max_n, b.summary.force_true_max_n);
  EXPECT_LT(p.summary.force_true_max_n, n.summary.force_true_max_n);
}

// A bar shorter than the pad (short_bar.yaml): the same ordering, smaller
// margin (measured RMS error 0.25 N proposed, 0.52 N Li et al., 0.55 N
// no_rotation; max 5.35 / 6.24 / 6.04 N).
TEST(Experiments, ShortBarDzmpBeatsCopRolling) {
  const RunResult p = runScene("short_bar.yaml", ControllerMode::Proposed);
  const RunResult b = runScene("short_bar.yaml", ControllerMode::Baseline);
  const RunResult n = runScene("short_bar.yaml", ControllerMode::NoRotation);
  for (const RunResult* r : {&p, &b, &n}) EXPECT_EQ(r->summary.status, "ok") << r->summary.controller;
  EXPECT_LT(p.summary.force_true_rms_error_n, 0.7 * b.summary.force_true_rms_error_n);
  EXPECT_LT(p.summary.force_true_rms_error_n, 0.7 * n.summary.force_true_rms_error_n);
  EXPECT_LT(p.summary.force_true_max_n + 0.3, b.summary.force_true_max_n);
  EXPECT_GE(p.summary.force_true_in_band_fraction, 0.99);
}

// Off-centre load (off_centre_load.yaml): a bar across the whole pad, tilted
// and to the side. With the edge spanning the pad CoC_x ~ 0, so CoP_x ~ DZMP_y
// and the Li et al. baseline levels it as the proposed controller does (their
// true-force means within 0.2 N); without rotation the tilted pad ends on its
// rigid housing (watched with the force-mismatch watchdog off; with it on, the
// servo stops the run: the arm's wrench contradicts the tactile force).
TEST(Experiments, OffCentreLoadNeedsRotationNotDzmp) {
  const RunResult p = runScene("off_centre_load.yaml", ControllerMode::Proposed);
  const RunResult b = runScene("off_centre_load.yaml", ControllerMode::Baseline);
  const RunResult n = runScene("off_centre_load.yaml", ControllerMode::NoRotation, nullptr, false);
  const RunResult w = runScene("off_centre_load.yaml", ControllerMode::NoRotation);
  EXPECT_EQ(w.summary.status, "servo_force_mismatch");
  EXPECT_EQ(w.summary.exit_code, 7);
  EXPECT_EQ(p.summary.status, "ok");
  EXPECT_EQ(b.summary.status, "ok");
  EXPECT_NEAR(p.summary.force_true_mean_n, b.summary.force_true_mean_n, 0.2);
  EXPECT_NEAR(p.summary.force_true_mean_n, 5.0, 1.2);
  EXPECT_GT(n.summary.force_true_mean_n, 15.0);
  double housing = 0;
  for (const auto& row : n.rows) housing = std::max(housing, row.housing_force);
  EXPECT_GT(housing, 5.0);
}

// Edge exploration with the Li et al. baseline: its wy row regulates CoP_x
// where the proposed one regulates DZMP_y, so its features flicker more as
// taxels at the ends of the line cross the firing threshold. The program's
// `aligned` test low-passes its errors (filter_s 0.1 s): both controllers
// align and explore. With the raw samples (filter_s 0, the test as it was
// before the filter), the baseline's flicker breaks every 0.2 s streak and it
// never leaves edge_control within the scene's 60 s, although it holds the edge.
RunResult runEdge(ControllerMode mode, double filter_s) {
  Scene sc = test::loadPaper("edge_exploration.yaml");
  sc.controller = mode;
  for (PhaseParams& ph : sc.servo.phases)
    for (TransitionParams& t : ph.transitions)
      if (t.on == TransitionEvent::Aligned) t.filter_s = filter_s;
  return test::runFull(sc);
}

TEST(Experiments, EdgeExplorationLiBaselineAlignsOnlyWithTheFilteredTest) {
  const RunResult p = runScene("edge_exploration.yaml", ControllerMode::Proposed);
  const RunResult b = runScene("edge_exploration.yaml", ControllerMode::Baseline);
  EXPECT_LT(p.summary.alignment_time_s, 5.0);
  EXPECT_LT(b.summary.alignment_time_s, 5.0);
  EXPECT_GT(b.summary.path_length_m, 0.15);
  // The paper's program (Eq. 2's force alone) meets the scene's criteria but
  // the true-force targets, which only the force estimate meets.
  for (const std::string& c : b.summary.criteria_failed)
    EXPECT_TRUE(c.rfind("force_true_rms_error_n", 0) == 0 || c.rfind("force_true_in_band_fraction", 0) == 0) << c;
  const RunResult raw = runEdge(ControllerMode::Baseline, 0.0);
  EXPECT_TRUE(std::isfinite(tEnter(raw, "edge_control")));
  EXPECT_FALSE(std::isfinite(tEnter(raw, "explore")));
  double edge_rows = 0, n = 0;
  for (const auto& row : raw.rows)
    if (row.t > 10.0) {
      edge_rows += row.contact == ContactType::Edge ? 1.0 : 0.0;
      ++n;
    }
  EXPECT_GT(edge_rows / n, 0.95) << "the baseline holds the edge, it only never passes the raw aligned test";
}

// (c) Co-manipulation (Sec. 5.3, Fig. 14): after the weight moves, the arm
// translates along x until DZMP_y is back within 0.5 mm within 5 s; force
// near 6 N; tray angle bounded.
TEST(Experiments, CoManipulationRebalancesTheTray) {
  const RunResult r = runScene("co_manipulation.yaml");
  const Summary& s = r.summary;
  EXPECT_EQ(s.status, "ok");
  // The tray with pad friction: every step found its equilibrium (the scene's
  // tray is dynamic; next test).
  EXPECT_EQ(s.sim_unconverged_steps, 0);
  EXPECT_EQ(s.sim_unconverged_max_residual, 0.0);
  ASSERT_TRUE(std::isfinite(s.dzmp_recovery_time_s));
  EXPECT_LT(s.dzmp_recovery_time_s, 5.0);
  EXPECT_LT(std::fabs(s.dzmp_final_m), 0.0005);
  EXPECT_GT(s.translation_x_m, 0.01) << "the arm moves along x_s towards the weight";
  EXPECT_NEAR(s.force_true_mean_n, 6.0, 1.0);
  EXPECT_LT(s.tray_angle_max_deg, 5.0);
  // The imbalance was real: DZMP_y rose well above the 0.5 mm band first.
  double peak = 0;
  for (const auto& row : r.rows) peak = std::max(peak, std::fabs(row.f.dzmp_y));
  EXPECT_GT(peak, 0.001);
}

// Why the co-manipulation's tray is dynamic (objects.0.fidelity): with pad
// friction the rolling tray sticks and slips while the weight moves, and a
// quasi-static tray stops some steps at the solver's iteration cap (measured
// 10-70 of 15000, seeds 1-3, residuals up to 0.47 N), which summary.json
// reports; the dynamic tray settles every step.
TEST(Experiments, CoManipulationTrayNeedsItsDynamics) {
  const Summary dyn = test::run(test::loadShipped("co_manipulation.yaml"));
  const Summary qs = test::run(test::loadShipped("co_manipulation.yaml", {"objects.0.fidelity=quasi_static"}));
  EXPECT_EQ(dyn.sim_unconverged_steps, 0);
  EXPECT_GT(qs.sim_unconverged_steps, 0);
  EXPECT_GT(qs.sim_unconverged_max_residual, 0.0);
  EXPECT_TRUE(std::isfinite(qs.sim_unconverged_max_residual));
  EXPECT_EQ(qs.status, "ok");  // isolated steps: the run goes on (100 in a row end it)
}

// A point contact never becomes an edge: the touch-dependent Jacobian keeps beta = 0.
TEST(Experiments, SphereStaysAPointContact) {
  const RunResult r = runScene("sphere_table.yaml");
  EXPECT_EQ(r.summary.status, "ok");
  EXPECT_TRUE(std::isnan(tEnter(r, "edge_control")));
  int point_rows = 0;
  for (const auto& row : r.rows)
    if (row.contact == ContactType::Point) {
      ++point_rows;
      EXPECT_EQ(row.beta, 0);
    }
  EXPECT_GT(point_rows, 1000);
  EXPECT_NEAR(r.summary.force_true_mean_n, 5.0, 1.0);
}

TEST(Runner, DeterministicForASeedAndSeedSensitive) {
  const RunResult a = runScene("co_manipulation.yaml");
  const RunResult b = runScene("co_manipulation.yaml");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    ASSERT_EQ(a.rows[i].f.force, b.rows[i].f.force) << i;
    ASSERT_EQ(a.rows[i].act, b.rows[i].act) << i;
  }
  Scene sc;
  ASSERT_TRUE(loadRun(test::shippedRun("co_manipulation.yaml"), sc).ok());
  sc.seed = 7;
  Runner runner;
  ASSERT_TRUE(runner.configure(sc).ok());
  RunResult c;
  runner.run(c);
  bool differs = false;
  for (std::size_t i = 0; i < std::min(a.rows.size(), c.rows.size()); ++i) differs |= a.rows[i].f.force != c.rows[i].f.force;
  EXPECT_TRUE(differs) << "the sensor noise must follow the seed";
}

TEST(Runner, RatesAndStalenessFollowTable2) {
  Scene sc;
  const RunResult r = runScene("edge_exploration.yaml", ControllerMode::Proposed, &sc);
  // Logged at the servo rate.
  ASSERT_GT(r.rows.size(), 100u);
  EXPECT_NEAR(r.rows[1].t - r.rows[0].t, 1.0 / sc.rates.servo, 1e-9);
  // Features are at most one WTS period plus one extraction period old.
  double worst = 0;
  for (const auto& row : r.rows)
    if (std::isfinite(row.feature_age)) worst = std::max(worst, row.feature_age);
  EXPECT_LE(worst, 1.0 / sc.rates.wts + 1.0 / sc.rates.features + 1e-9);
  EXPECT_GT(worst, 0.0);
}

// ------------------------------------------------------------ bad input

namespace {
std::string writeScene(const std::string& name, const std::string& body) {
  const std::string dir = testing::TempDir();
  const std::string path = dir + name;
  std::ofstream(path) << body;
  return path;
}

// A run of a scene of the test's own with the edge-exploration program.
RunFiles withProgram(const std::string& scene, const std::string& controller = "") {
  return RunFiles{scene, std::string(TACTILE_SOURCE_DIR) + "/params/programs/edge_exploration.yaml", controller};
}
}  // namespace

TEST(SceneErrors, NameTheFileAndTheField) {
  struct Case {
    const char* file;
    std::string body;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"unknown_key.yaml", "name: x\nspeed_of_light: 3\n", "speed_of_light: unknown key"},
      {"zero_rate.yaml", "name: x\nrates: {servo: 0}\n", "rates.servo = 0: must be in (0, rates.sim] Hz"},
      {"servo_above_sim.yaml", "name: x\nrates: {sim: 100, servo: 200}\n", "rates.servo = 200: must be in (0, rates.sim] Hz"},
      {"unknown_object.yaml", "name: x\nobjects: [{type: teapot}]\n", "objects[0].type: 'teapot': must be one of plane, sphere, bar, bent_bar, tray"},
      {"inside.yaml",
       "name: x\ninitial_flange: {xyz: [0.72, 0.0, 0.40], rpy_deg: [180, 0, 180]}\n"
       "objects: [{name: ball, type: sphere, center: [0.72, 0.0, 0.36], radius: 0.03}]\n",
       "ball"},
      {"bad_fidelity.yaml", "name: x\nfidelity: magic\n", "fidelity: 'magic': must be one of quasi_static, dynamics"},
      {"no_name.yaml", "duration: 3\n", "name: required"},
      {"names_program.yaml", "name: x\nprogram: ../programs/edge_exploration.yaml\n",
       "program: a scene does not name its run's program: the experiment registry (experiments.yaml) binds"},
      {"names_controller.yaml", "name: x\ncontroller: baseline\n", "controller: a scene does not name its run's controller"},
  };
  for (const auto& c : cases) {
    const std::string path = writeScene(c.file, c.body);
    Scene sc;
    const ConfigResult r = loadScene(path, sc);
    ASSERT_FALSE(r.ok()) << c.file;
    EXPECT_NE(r.message().find(path), std::string::npos) << r.message();
    EXPECT_NE(r.message().find(c.expect), std::string::npos) << c.file << ": " << r.message();
  }
  Scene sc;
  const std::string plain = writeScene("plain.yaml", "name: x\n");
  for (const char* m : {"proposed", "baseline", "no_rotation"}) {  // the run names any controller
    ASSERT_TRUE(loadRun(withProgram(plain, m), sc).ok()) << m;
    EXPECT_STREQ(toString(sc.controller), m);
  }
  ASSERT_TRUE(loadRun(withProgram(plain), sc).ok());  // none: the program's controller.mode
  EXPECT_EQ(sc.controller, sc.servo.mode);
  const ConfigResult li = loadRun(withProgram(plain, "li"), sc);
  ASSERT_FALSE(li.ok());
  EXPECT_NE(li.message().find("controller 'li' must be proposed"), std::string::npos) << li.message();
  ASSERT_TRUE(loadScene(plain, sc).ok());  // a scene alone: no program, and no run
  EXPECT_TRUE(sc.program_file.empty());
  const ConfigResult no_program = Runner().configure(sc);
  ASSERT_FALSE(no_program.ok());
  EXPECT_NE(no_program.message().find("no phase program"), std::string::npos) << no_program.message();
  const ConfigResult missing = loadScene("/nonexistent/scene.yaml", sc);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("/nonexistent/scene.yaml: cannot open file"), std::string::npos);
}

// Every shipped scene declares its pass criteria (metrics.criteria), and the
// proposed controller with the shipped program meets them; the bent bar's
// no-DZMP baseline does not.
TEST(SceneCriteria, ShippedScenesPassTheirCriteria) {
  for (const char* f : {"edge_exploration.yaml", "bent_bar.yaml", "co_manipulation.yaml", "sphere_table.yaml",
                        "partial_edge.yaml", "short_bar.yaml", "off_centre_load.yaml"}) {
    const Scene sc = test::loadShipped(f);
    EXPECT_GE(sc.metrics.criteria.size(), 1u) << f;
    const RunResult r = test::runFull(sc);
    EXPECT_TRUE(r.summary.criteria_failed.empty()) << f << ": " << r.summary.criteria_failed.front();
  }
  // The no_rotation ablation does not pass (stopped by the force-mismatch watchdog).
  const RunResult b = runScene("bent_bar.yaml", ControllerMode::NoRotation);
  EXPECT_FALSE(b.summary.criteria_failed.empty());
}

TEST(SceneCriteria, BoundsAreInclusiveAndNaNFails) {
  Scene sc;
  sc.metrics.criteria = {{"force_true_mean_n", 4.0, 6.0}, {"alignment_time_s", -1e300, 5.0}, {"path_length_m", 0.15, 1e300}};
  Summary s;
  s.force_true_mean_n = 6.0;
  s.alignment_time_s = 5.0;
  s.path_length_m = 0.15;
  checkCriteria(sc, s);
  EXPECT_TRUE(s.criteria_failed.empty());
  s.force_true_mean_n = 6.0001;
  s.alignment_time_s = std::numeric_limits<double>::quiet_NaN();  // never aligned
  s.path_length_m = 0.1499;
  checkCriteria(sc, s);
  ASSERT_EQ(s.criteria_failed.size(), 3u);
  EXPECT_EQ(s.criteria_failed[0], "force_true_mean_n = 6.0001 > 6");
  EXPECT_EQ(s.criteria_failed[1], "alignment_time_s = nan < -1e+300");
  EXPECT_EQ(s.criteria_failed[2], "path_length_m = 0.1499 < 0.15");
  // Scene errors name the file and the key.
  const std::string path = writeScene("bad_criteria.yaml", "name: x\nmetrics: {criteria: {speed_of_light: {max: 3}}}\n");
  const ConfigResult r = loadScene(path, sc);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("metrics.criteria.speed_of_light: not a summary.json metric"), std::string::npos) << r.message();
}

TEST(SceneOverrides, SetKeysBeforeReadingAndAreCheckedLikeTheFile) {
  const std::string path = writeScene("override.yaml", "name: x\nrates: {servo: 100}\nsensor: {noise_counts: 6}\n");
  Scene sc;
  ASSERT_TRUE(loadScene(path, sc, {"rates.servo=250", "sensor.noise_counts=30", "arm.k_trans=1500"}).ok());
  EXPECT_EQ(sc.rates.servo, 250.0);
  EXPECT_EQ(sc.world.pad.noise_counts, 30.0);
  EXPECT_EQ(sc.world.arm.k_trans, 1500.0);  // a map the file did not have
  const std::string with_list =
      writeScene("override_list.yaml", "name: x\nobjects: [{name: a, type: sphere, center: [0.72, 0, 0.2], radius: 0.01}]\n");
  ASSERT_TRUE(loadScene(with_list, sc, {"objects.0.radius=0.02"}).ok());
  ASSERT_EQ(sc.world.objects.size(), 1u);
  EXPECT_EQ(sc.world.objects[0].radius, 0.02);
  const ConfigResult past_end = loadScene(with_list, sc, {"objects.1.radius=0.02"});
  ASSERT_FALSE(past_end.ok());
  EXPECT_NE(past_end.message().find("1 is neither an index nor the name of an element of a list of 1"), std::string::npos) << past_end.message();
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"rates.servo", "key.path=value"},            // no '='
      {"rates..servo=3", "empty key"},              // empty key
      {"name.first=3", "name is not a map"},        // descends into a scalar
      {"speed_of_light=3", "speed_of_light: unknown key"},  // checked like the file
      {"rates.servo=0", "rates.servo = 0: must be in (0, rates.sim] Hz"},
  };
  for (const auto& b : bad) {
    const ConfigResult r = loadScene(path, sc, {b.first});
    ASSERT_FALSE(r.ok()) << b.first;
    EXPECT_NE(r.message().find(path), std::string::npos) << r.message();
    EXPECT_NE(r.message().find(b.second), std::string::npos) << b.first << ": " << r.message();
  }
}

TEST(Runner, AnUnstableRunStopsWithAStatusAndANonZeroExitCode) {
  // Drive the sensor into a table far beyond the force limits: the world's
  // force ceiling (or the servo's) must stop the run, never hang or go NaN.
  const std::string path = writeScene(
      "crash.yaml",
      "name: crash\nduration: 20\ninitial_flange: {xyz: [0.72, 0.0, 0.40], rpy_deg: [180, 0, 180]}\n"
      "objects: [{name: table, type: plane, point: [0, 0, 0.36], normal: [0, 0, 1]}]\n");
  Scene sc;
  ASSERT_TRUE(loadRun(withProgram(path), sc).ok());
  // A huge feed-forward towards the table in the free-motion phase, and no
  // contact detection (threshold above any taxel force): nothing stops it but safety.
  sc.servo.phases[0].feedforward(2) = 0.05;
  sc.servo.safety.max_trans_speed = 0.1;  // m/s
  sc.features.contact_threshold = 1e6;
  Runner runner;
  ASSERT_TRUE(runner.configure(sc).ok());
  RunResult r;
  runner.run(r);
  EXPECT_NE(r.summary.exit_code, 0);
  EXPECT_NE(r.summary.status, "ok");
  EXPECT_LT(r.summary.sim_time_s, 20.0);
  for (const auto& row : r.rows)
    for (double v : row.act) ASSERT_TRUE(std::isfinite(v));
}

// The force estimate (force_estimator.hpp, the shipped programs): the servo
// regulates the tactile force corrected by the arm's estimated wrench, which
// carries the scenes' error (a tared offset, 0.5 N of noise per axis), so the
// TRUE force sits at 5 N. Targets: RMS error <= 0.4 N and >= 95 % of the
// sliding time within 5 +- 0.5 N (the scenes' force_band_n). The same bar and
// start with the tactile-only program miss both: the load on taxels below the
// 0.2 N firing threshold is missing from what it regulates.
TEST(Experiments, ForceEstimatePutsTheTrueForceOnTarget) {
  const RunResult f = runScene("bent_bar_fused.yaml");
  EXPECT_EQ(f.summary.status, "ok");
  EXPECT_TRUE(f.summary.criteria_failed.empty()) << f.summary.criteria_failed.front();
  EXPECT_LE(f.summary.force_true_rms_error_n, 0.4);
  EXPECT_GE(f.summary.force_true_in_band_fraction, 0.95);
  EXPECT_GE(f.summary.path_length_m, 0.2);
  EXPECT_EQ(f.summary.contact_lost_count, 0);
  Scene sc = test::loadShippedWith("bent_bar_fused.yaml", test::kPrograms + "bent_bar_paper.yaml");
  const Summary t = test::run(sc);
  EXPECT_EQ(t.status, "ok");
  EXPECT_GT(t.force_true_rms_error_n, 0.5);       // measured 0.66 N: the true force ~0.6 N above 5 N
  EXPECT_LT(t.force_true_in_band_fraction, 0.5);  // measured 0.21
  EXPECT_GT(t.force_true_mean_n, 5.4);

  // The edge exploration (pad friction 0.5: stick-slip, a 3 mm edge: more
  // than half of the line load below the threshold) meets both targets on
  // each of seeds 1-5 (measured: RMS 0.19-0.26 N, within 5 +- 0.5 N
  // 0.98-0.99 of the sliding time), against 0.8 N RMS for the tactile-only
  // program.
  for (int seed = 1; seed <= 5; ++seed) {
    const RunResult e = test::runFull(test::loadShipped("edge_exploration.yaml", {"seed=" + std::to_string(seed)}));
    EXPECT_EQ(e.summary.status, "ok") << "seed " << seed;
    EXPECT_TRUE(e.summary.criteria_failed.empty()) << "seed " << seed << ": " << e.summary.criteria_failed.front();
    EXPECT_LE(e.summary.force_true_rms_error_n, 0.4) << "seed " << seed;
    EXPECT_GE(e.summary.force_true_in_band_fraction, 0.95) << "seed " << seed;
    EXPECT_LT(e.summary.alignment_time_s, 5.0) << "seed " << seed;
    EXPECT_GE(e.summary.path_length_m, 0.15) << "seed " << seed;
  }
  Scene se = test::loadShippedWith("edge_exploration.yaml", test::kPrograms + "edge_exploration_paper.yaml");
  const Summary te = test::run(se);
  EXPECT_GT(te.force_true_rms_error_n, 0.6);
  EXPECT_LT(te.force_true_in_band_fraction, 0.5);
}

// The scenes that hold a force on a fixed object meet the same targets (RMS
// error <= 0.4 N, >= 95 % of the scored time within +-0.5 N of the set point)
// on seeds 1-3: the tray (6 N, the force estimate tared in the approach), the
// sphere (the edge program's align phase) and the off-centre load (the hold
// program). Measured: RMS 0.09-0.14 / 0.04-0.06 / 0.07-0.11 N, all 100 % of
// the time within the band. Each against its control, one change away: the
// tray on the tactile force alone (the paper's Eq. 2: 0.3 N of the line load
// below the firing threshold), the sphere and the off-centre load with the
// force row's integral back in the holding phase (ki 2 /s^2: the overshoot
// after the first touch decays with the PI's zero, 0.67 /s).
void setPhaseKi(Scene& sc, const std::string& phase, int axis, double ki) {
  for (auto& ph : sc.servo.phases)
    if (ph.name == phase) {
      ph.ki(axis) = ki;
      return;
    }
  ADD_FAILURE() << "no phase " << phase;
}

TEST(Experiments, HoldingScenesPutTheTrueForceOnTarget) {
  for (const char* name : {"co_manipulation.yaml", "sphere_table.yaml", "off_centre_load.yaml"})
    for (int seed = 1; seed <= 3; ++seed) {
      const Summary s = test::run(test::loadShipped(name, {"seed=" + std::to_string(seed), "metrics.force_band_n=0.5"}));
      EXPECT_EQ(s.status, "ok") << name << " seed " << seed;
      EXPECT_TRUE(s.criteria_failed.empty()) << name << " seed " << seed << ": " << s.criteria_failed.front();
      EXPECT_LE(s.force_true_rms_error_n, 0.4) << name << " seed " << seed;
      EXPECT_GE(s.force_true_in_band_fraction, 0.95) << name << " seed " << seed;
    }
  Scene tray = test::loadShipped("co_manipulation.yaml", {"metrics.force_band_n=0.5"});
  ASSERT_TRUE(tray.servo.force_estimate.fused);
  tray.servo.force_estimate.fused = false;
  const Summary t = test::run(tray);
  EXPECT_EQ(t.status, "ok");
  EXPECT_GT(t.force_true_rms_error_n, 0.4);
  EXPECT_LT(t.force_true_in_band_fraction, 0.9);
  // The integral back: more than 1.5 times the RMS error and at least 3 % more
  // of the time out of the band, on seeds 1 and 2 (measured: sphere 0.24 / 0.22 N
  // against 0.04 / 0.05 N, 92-93 % in the band; off-centre load 0.19 / 0.21 N
  // against 0.10 / 0.09 N, 96 / 92 %, all 100 % without it).
  for (const auto& [name, phase] : {std::pair<const char*, const char*>{"sphere_table.yaml", "align"},
                                    std::pair<const char*, const char*>{"off_centre_load.yaml", "hold"}})
    for (const char* seed : {"seed=1", "seed=2"}) {
      const Scene shipped = test::loadShipped(name, {seed, "metrics.force_band_n=0.5"});
      Scene with_i = shipped;
      setPhaseKi(with_i, phase, 2, 2.0);
      const Summary a = test::run(shipped), b = test::run(with_i);
      EXPECT_GT(b.force_true_rms_error_n, 1.5 * a.force_true_rms_error_n) << name << " " << seed;
      EXPECT_LT(b.force_true_in_band_fraction, a.force_true_in_band_fraction - 0.03) << name << " " << seed;
    }
}

// The force estimate's bound (force_estimate.max_correction_n): every newton
// of correction is a newton less on the taxels, so the image thins out. On the
// edge exploration's 3 mm edge the shipped 4.5 N bound puts the true force on
// target where 2.5 N leaves it high on some seeds; the thinner image costs the
// CoP's position ALONG the edge (against the simulator's true pressure
// centre), not the edge's position ACROSS it, which is what the exploration
// reconstructs (docs/results.md, "The force estimate's bound").
struct ImageErrors {
  double along_mean = NAN;  ///< m: |CoP - true pressure centre| along the ridge, mean
  double line_rms = NAN;    ///< m: the contact line's points' distance to the ridge, RMS
};

ImageErrors imageErrorsWhileSliding(const RunResult& r, const Scene& sc) {
  // The bar's ridge in the horizontal plane (the scene's one straight bar).
  const ObjectParams& bar = sc.world.objects.at(0);
  const double ax = bar.vertices[0][0], ay = bar.vertices[0][1];
  double tx = bar.vertices[1][0] - ax, ty = bar.vertices[1][1] - ay;
  const double len = std::hypot(tx, ty);
  tx /= len;
  ty /= len;
  const double t4 = tEnter(r, "explore");
  ImageErrors e;
  double sum = 0;
  int n = 0;
  for (const auto& c : r.contacts) {
    if (!(c.t >= t4 + 2.0)) continue;
    sum += std::fabs((c.p[0] - c.truth[0]) * tx + (c.p[1] - c.truth[1]) * ty);
    ++n;
  }
  EXPECT_GT(n, 500);
  e.along_mean = n > 0 ? sum / n : NAN;
  double ss = 0;
  int m = 0;
  for (const auto& p : r.edge_points) {
    if (!(p.t >= t4 + 2.0)) continue;
    const double across = -(p.p[0] - ax) * ty + (p.p[1] - ay) * tx;
    ss += across * across;
    ++m;
  }
  EXPECT_GT(m, 20);
  e.line_rms = m > 0 ? std::sqrt(ss / m) : NAN;
  return e;
}

// The edge exploration's image (edge_exploration.yaml; docs/design.md, "The
// edge across the rows"): the shipped program holds the edge at 2 deg to the
// taxel rows. Against the same program with the edge along the rows
// (alpha_z = 0) and the paper's program, and with the force estimate's bound
// narrowed from 4.5 N to 2.5 N.
TEST(ShippedPrograms, EdgeAcrossTheRowsKeepsTheLoadOnTheImage) {
  // Means over seeds 1-3: stick-slip on the 3 mm edge makes single runs scatter.
  struct Mean {
    double rms = 0, along = 0, line = 0;
  };
  auto run3 = [](const Scene& base) {
    Mean m;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      Scene sc = base;
      sc.seed = seed;
      const RunResult r = test::runFull(sc);
      EXPECT_EQ(r.summary.status, "ok") << "seed " << seed;
      EXPECT_LT(r.summary.alignment_time_s, 5.0) << "seed " << seed;
      EXPECT_GE(r.summary.path_length_m, 0.15) << "seed " << seed;
      const ImageErrors e = imageErrorsWhileSliding(r, sc);
      m.rms += r.summary.force_true_rms_error_n / 3.0;
      m.along += e.along_mean / 3.0;
      m.line += e.line_rms / 3.0;
    }
    return m;
  };
  const Scene paper_sc = test::loadShippedWith("edge_exploration.yaml",
                                               test::kPrograms + "edge_exploration_paper.yaml");
  const Scene shipped_sc = test::loadShipped("edge_exploration.yaml");
  EXPECT_DOUBLE_EQ(shipped_sc.servo.force_estimate.max_correction_n, 4.5);
  Scene rows_sc = shipped_sc;  // the edge along the rows
  // Along the rows the contact drops while sliding (below): the load the pad
  // misses is not stationary, which the drift check assumes of the shipped
  // slide; this comparison is of the image.
  rows_sc.servo.watchdogs.drift_max_change_n = 0.0;
  Scene narrow_sc = shipped_sc;
  narrow_sc.servo.force_estimate.max_correction_n = 2.5;
  int tilted = 0;
  for (auto& ph : rows_sc.servo.phases) {
    if (ph.name != "edge_control" && ph.name != "explore") continue;
    EXPECT_DOUBLE_EQ(ph.s_d(5), 0.035) << ph.name;
    ph.s_d(5) = 0.0;
    ++tilted;
  }
  ASSERT_EQ(tilted, 2);
  const Mean paper = run3(paper_sc), rows = run3(rows_sc), narrow = run3(narrow_sc), shipped = run3(shipped_sc);
  for (const auto& m : {std::make_pair("paper", paper), std::make_pair("along the rows", rows),
                        std::make_pair("bound 2.5 N", narrow), std::make_pair("shipped", shipped)})
    std::printf("%-15s true-force RMS %.3f N, CoP along the edge %.2f mm, line across %.2f mm\n", m.first,
                m.second.rms, 1e3 * m.second.along, 1e3 * m.second.line);
  // The true force: the shipped program within a 0.25 N mean RMS error (half
  // the band; measured 0.15 N), the paper's 0.8 N.
  EXPECT_LE(shipped.rms, 0.25);
  EXPECT_LT(shipped.rms, 0.3 * paper.rms);
  // Across the rows the image carries enough of the load that the correction
  // stays under 2.5 N: the bound does not bind (the same RMS to 0.03 N, the
  // seeds' own spread; measured identical runs).
  EXPECT_NEAR(narrow.rms, shipped.rms, 0.03);
  // The image's cost: along the edge the CoP wanders with the part of the
  // tilted line that lies on a row (measured 1.8 mm mean, the paper's
  // 0.7 mm); within 2.5 mm, the contours' own tolerance for the CoP...
  EXPECT_LT(shipped.along, 0.0025);
  // ...while the contact line stays on the ridge: within 0.5 mm RMS across it
  // (half the 1 mm the contours' cloud must meet; measured 0.05 mm paper,
  // 0.30 mm along the rows, 0.15 mm shipped). Along the rows: RMS 0.18 N,
  // the CoP along the edge 1.3 mm, but contact drops while sliding
  // (EdgeExplorationContactDrops).
  EXPECT_LT(paper.line, 0.0005);
  EXPECT_LT(rows.line, 0.0005);
  EXPECT_LT(shipped.line, 0.0005);
}

// The family's force targets on a slide (scripts/sweeps/sweep_family.py):
// ended by the program (`done`), status ok, true-force RMS error <= 0.5 N,
// >= 95 % of the time within 5 +- 0.5 N, no contact loss.
static bool meetsSlideTargets(const RunResult& r) {
  bool done = false;
  for (const auto& p : r.phases) done = done || p.name == "done";
  return r.summary.status == "ok" && done && r.summary.force_true_rms_error_n <= 0.5 &&
         r.summary.force_true_in_band_fraction >= 0.95 && r.summary.contact_lost_count == 0;
}

// A fixed slide gain, as the sweeps compare it with the law: the speed law
// off and K_P,x of the `explore` phase set to `kp` (1/s).
static void useFixedGain(Scene& sc, double kp) {
  sc.servo.speed_law.phases.clear();
  for (auto& ph : sc.servo.phases)
    if (ph.name == "explore") ph.kp(0) = kp;
}

// The speed law (tactile_servo/speed_law.hpp, bent_bar_speed_law.yaml): the
// bent bar to its end cap with the slide speed chosen from a 0.5 N error
// budget of the true force. Targets, on each of seeds 1-3: a mean slide speed
// of at least 40 mm/s, RMS error <= 0.5 N, >= 95 % of the time within
// 5 +- 0.5 N, no contact loss (measured: 83.4-84.9 mm/s, 0.12-0.17 N,
// 1.0).
// The careful speed law (bent_bar_speed_law_careful.yaml), one program for
// bars it has not seen: a wave in height of A 2 mm over L 90 mm (R 103 mm,
// tighter than the shipped end-cap program follows within the targets) and
// the bent bar's bend to the right. On each of seeds 1-3 it meets the force
// targets to the end of both, and slides the bend at least 1.5 times as fast
// as the wave (measured 14-15 against 30 mm/s). A single fixed slide gain
// cannot do both: 0.8 1/s leaves the force band on the wave, and 0.6 1/s,
// which holds it there (scripts/sweeps/sweep_family.py, the fastest of its
// grid on every seed), slides the bend at most 0.7 times as fast as the law.
// The fixed gains are the careful program with the law off: its force loop
// (no slope feed-forward, the force estimate's 0.08 s; with the shipped law's
// loop a fixed gain holds the wave: docs/design.md, "The speed law").
TEST(Experiments, CarefulSpeedLawAdaptsWhereNoSingleFixedGainDoes) {
  const std::string careful = std::string(TACTILE_SOURCE_DIR) + "/params/programs/bent_bar_speed_law_careful.yaml";
  // kp = 0: the careful law; kp > 0: the same program with the law off and that slide gain.
  auto runBar = [&](const std::string& bar, int seed, double kp) {
    Scene sc = test::loadShippedWith("curved/" + bar + ".yaml", careful, {"seed=" + std::to_string(seed), "duration=60"});
    if (kp > 0.0) useFixedGain(sc, kp);
    return test::runFull(sc);
  };
  const auto met = meetsSlideTargets;
  for (int seed = 1; seed <= 3; ++seed) {
    const RunResult wave = runBar("wavy_a2mm_l90mm", seed, 0.0);
    const RunResult bend = runBar("bend_right", seed, 0.0);
    EXPECT_TRUE(met(wave)) << seed << ": " << wave.summary.status << ", in band "
                           << wave.summary.force_true_in_band_fraction;
    EXPECT_TRUE(met(bend)) << seed << ": " << bend.summary.status << ", in band "
                           << bend.summary.force_true_in_band_fraction;
    EXPECT_GE(bend.summary.slide_speed_mps, 1.5 * wave.summary.slide_speed_mps) << seed;
    EXPECT_FALSE(met(runBar("wavy_a2mm_l90mm", seed, 0.8))) << seed;
    const RunResult slow = runBar("bend_right", seed, 0.6);
    EXPECT_TRUE(met(slow)) << seed;
    EXPECT_LE(slow.summary.slide_speed_mps, 0.7 * bend.summary.slide_speed_mps) << seed;
  }
}

// The slope feed-forward (slope_feedforward.hpp) with the speed law as
// shipped (bent_bar_speed_law.yaml) on a wave in height it has not seen
// (A 1.5 mm, L 70 mm, R 83 mm): on each of seeds 1-3 the law meets the force
// targets with it (ended by its end rule; the family's sweep finds that end
// within 10 mm of the wave's) (measured: 98-100 % within 5 +- 0.5 N,
// 65-82 mm/s) and misses them without it (77-83 %, 52-59 mm/s).
TEST(Experiments, SlopeFeedforwardLetsTheSpeedLawHoldTheForceOnAWave) {
  const std::string program = std::string(TACTILE_SOURCE_DIR) + "/params/programs/bent_bar_speed_law.yaml";
  for (int seed = 1; seed <= 3; ++seed) {
    RunResult r[2];
    for (int ff = 0; ff < 2; ++ff) {
      Scene sc = test::loadShippedWith("curved/wavy_a1.5mm_l70mm.yaml", program, {"seed=" + std::to_string(seed), "duration=60"});
      ASSERT_EQ(sc.servo.slope_feedforward.phases.size(), 1u);  // shipped on
      if (!ff) sc.servo.slope_feedforward.phases.clear();
      r[ff] = test::runFull(sc);
    }
    EXPECT_TRUE(meetsSlideTargets(r[1])) << seed << ": " << r[1].summary.status << ", RMS "
                                         << r[1].summary.force_true_rms_error_n << " N, in band "
                                         << r[1].summary.force_true_in_band_fraction;
    EXPECT_LT(r[0].summary.force_true_in_band_fraction, 0.95) << seed;
    EXPECT_GT(r[1].summary.slide_speed_mps, r[0].summary.slide_speed_mps) << seed;
  }
}

// The end rule's check (bent_bar_speed_law.yaml, end_check; docs/design.md,
// "The end rule's check"). The wave A 3 mm, L 70 mm (R 41 mm): a crest
// shrinks the image to a point as the bar's end cap does. On each of seeds
// 1-3 the run enters the check at a crest, returns to explore (the image an
// edge again, seed 3; every taxel silent as the pad's housing takes the
// load, seeds 1 and 2) and is stopped by name, surface_too_curved, before
// the true force reaches 7 N (measured 6.36-6.43 N, 228 mm before the end);
// without the return on a contact loss seeds 1 and 2 end ok at that crest,
// and with the check cut to one cycle (the end rule alone) every seed does.
// The bend downwards ends with the wrist 0.6-0.7 deg from its limit: the
// check's joint_margin (5 deg) ends the run at once, ok; without that
// transition the check's roll reaches the joint limit. At the shipped bent
// bar's end cap the image stays a point and the check ends the run, ok,
// within the force targets.
TEST(Experiments, TheEndRulesCheckTellsATightCrestFromTheBarsEnd) {
  const std::string program = std::string(TACTILE_SOURCE_DIR) + "/params/programs/bent_bar_speed_law.yaml";
  enum Variant { kShipped, kEndRuleAlone, kNoJointMargin, kNoLossReturn };
  auto run = [&](const std::string& scene, int seed, Variant v) {
    Scene sc = test::loadShippedWith(scene, program, {"seed=" + std::to_string(seed), "duration=60"});
    PhaseParams& check = sc.servo.phases.back();
    EXPECT_EQ(check.name, "end_check");
    if (v == kEndRuleAlone) {
      check.transitions.resize(1);
      check.transitions[0].on = TransitionEvent::Timeout;
      check.transitions[0].timeout_s = 1e-6;
    } else if (v == kNoJointMargin) {
      check.transitions.erase(check.transitions.begin());
    } else if (v == kNoLossReturn) {
      const std::size_t n = check.transitions.size();
      check.transitions.erase(std::remove_if(check.transitions.begin(), check.transitions.end(),
                                             [](const TransitionParams& t) { return t.on == TransitionEvent::ContactLost; }),
                              check.transitions.end());
      EXPECT_EQ(check.transitions.size(), n - 1);
    }
    return test::runFull(sc);
  };
  auto visits = [](const RunResult& r, const std::string& a, const std::string& b) {  // b entered right after a
    for (std::size_t i = 1; i < r.phases.size(); ++i)
      if (r.phases[i - 1].name == a && r.phases[i].name == b) return true;
    return false;
  };
  auto maxTrueForce = [](const RunResult& r) {
    double m = 0.0;
    for (const LogRow& row : r.rows) m = std::max(m, row.force_true);
    return m;
  };
  const double kFiveDeg = 5.0 * kPi / 180.0;
  int crest_read_as_end = 0;  // without the return on a contact loss
  for (int seed = 1; seed <= 3; ++seed) {
    const RunResult crest = run("curved/wavy_a3mm_l70mm.yaml", seed, kShipped);
    EXPECT_EQ(crest.summary.status, "servo_surface_too_curved") << seed;
    EXPECT_TRUE(visits(crest, "end_check", "explore")) << seed;
    EXPECT_LT(maxTrueForce(crest), 7.0) << seed;  // the bound for the named stop
    const RunResult alone = run("curved/wavy_a3mm_l70mm.yaml", seed, kEndRuleAlone);
    EXPECT_EQ(alone.summary.status, "ok") << seed;  // the crest read as the bar's end
    crest_read_as_end += run("curved/wavy_a3mm_l70mm.yaml", seed, kNoLossReturn).summary.status == "ok" ? 1 : 0;

    const RunResult down = run("curved/bend_down.yaml", seed, kShipped);
    EXPECT_TRUE(meetsSlideTargets(down)) << seed << ": " << down.summary.status;
    ASSERT_TRUE(visits(down, "end_check", "done")) << seed;
    double entered = -1.0, margin = 0.0;
    for (const auto& p : down.phases)
      if (p.name == "end_check") entered = p.t_enter;
    for (const LogRow& row : down.rows)
      if (row.t <= entered + 1e-9) margin = row.joint_margin;
    EXPECT_LT(margin, kFiveDeg) << seed;
    EXPECT_GT(margin, 0.0) << seed;
    EXPECT_NE(run("curved/bend_down.yaml", seed, kNoJointMargin).summary.status, "ok") << seed;

    const RunResult bar = run("bent_bar_speed_law.yaml", seed, kShipped);
    EXPECT_TRUE(meetsSlideTargets(bar)) << seed << ": " << bar.summary.status;
    EXPECT_TRUE(visits(bar, "end_check", "done")) << seed;
    EXPECT_FALSE(visits(bar, "end_check", "explore")) << seed;
  }
  EXPECT_GE(crest_read_as_end, 1);
}

// The wrench's excess against the tactile force (speed_law.excess_against:
// tactile) on the wave A 3 mm over L 120 mm (R 122 mm), where the pad starts
// to bridge each trough: the taxels carry half of the wrench, then two spots
// at the pad's ends read as one long edge. On each of seeds 1-3 the law as
// shipped meets the force targets with no contact loss (measured 99.3-99.6 %
// within 5 +- 0.5 N at 50-62 mm/s); against f_hat (which follows the wrench
// within 0.02 s; 3 N to stop, no dead band at any extent) it misses them on
// seeds 2 and 3 (91 and 97 % within the band, a contact loss each, at
// 97-110 mm/s), and the fixed gain at the ceiling (4.8 1/s) misses them on
// every seed (90-91 %).
TEST(Experiments, SpeedLawSlowsWhereThePadStartsToBridgeATrough) {
  int met_against_estimate = 0, met_fixed = 0;
  for (int seed = 1; seed <= 3; ++seed) {
    auto runWith = [&](int variant) {
      Scene sc = test::loadShippedWith("curved/wavy_a3mm_l120mm.yaml", test::kPrograms + "bent_bar_speed_law.yaml",
                                   {
                                    "seed=" + std::to_string(seed), "duration=60"});
      EXPECT_TRUE(sc.servo.speed_law.excess_against_tactile);
      if (variant == 1) {  // the excess against f_hat
        sc.servo.speed_law.excess_against_tactile = false;
        sc.servo.speed_law.law.excess_deadband_n = 0.0;
        sc.servo.speed_law.law.excess_deadband_per_m = 0.0;
        sc.servo.speed_law.law.excess_ref_n = 3.0;
      } else if (variant == 2) {
        useFixedGain(sc, 4.8);  // the fixed gain at the ceiling
      }
      return test::runFull(sc);
    };
    const RunResult law = runWith(0);
    EXPECT_TRUE(meetsSlideTargets(law)) << seed << ": " << law.summary.status << ", in band "
                                        << law.summary.force_true_in_band_fraction << ", losses "
                                        << law.summary.contact_lost_count;
    met_against_estimate += meetsSlideTargets(runWith(1)) ? 1 : 0;
    met_fixed += meetsSlideTargets(runWith(2)) ? 1 : 0;
  }
  EXPECT_LT(met_against_estimate, 3);
  EXPECT_LT(met_fixed, 3);
}

// The excess dead band of a short image (speed_law.excess_deadband_per_m)
// where a bar bends down, convex under the pad: the image spans 28-33 mm and
// the taxels miss 2.2-2.8 N of the 5 N. On the bend down and the bend to the
// right and down, the law as shipped meets the targets on each of seeds 1-3
// and is, over them, at least as fast as the fastest fixed gain (4.8 1/s at
// the ceiling, which meets them too): measured 70.1 against 66.3 mm/s and
// 69.2 against 67.1 mm/s. With the dead band fixed at 1.8 N it slowed there
// to under 0.95 times the fixed gain (measured 0.93 and 0.93).
TEST(Experiments, SpeedLawKeepsTheFixedGainsPaceWhereABarBendsDown) {
  const std::string program = std::string(TACTILE_SOURCE_DIR) + "/params/programs/bent_bar_speed_law.yaml";
  for (const std::string bar : {"bend_down", "bend_right_down"}) {
    double speed[3] = {0.0, 0.0, 0.0};  // the law, the fixed gain, the law with a fixed dead band
    for (int seed = 1; seed <= 3; ++seed) {
      for (int v = 0; v < 3; ++v) {
        Scene sc = test::loadShippedWith("curved/" + bar + ".yaml", program, {"seed=" + std::to_string(seed), "duration=60"});
        ASSERT_DOUBLE_EQ(sc.servo.speed_law.law.excess_deadband_per_m, 40.0);
        if (v == 1) useFixedGain(sc, 4.8);
        if (v == 2) sc.servo.speed_law.law.excess_deadband_per_m = 0.0;
        const RunResult r = test::runFull(sc);
        if (v < 2) {
          EXPECT_TRUE(meetsSlideTargets(r)) << bar << " " << seed << " " << v << ": " << r.summary.status
                                            << ", in band " << r.summary.force_true_in_band_fraction;
        }
        speed[v] += r.summary.slide_speed_mps / 3.0;
      }
    }
    EXPECT_GE(speed[0], speed[1]) << bar;
    EXPECT_LT(speed[2], 0.95 * speed[1]) << bar;
  }
}

// At its ceiling (0.12 m/s, the CoP_x pull 4.8 1/s) the law slides the
// shipped bent bar at least 1.1 times as fast as any fixed gain that meets
// the targets on every seed (its program with the law off): measured
// 83.4-84.9 mm/s against 4.8 1/s's 67.6 and 4 1/s's 64.3 mm/s (seeds 1-3).
TEST(Experiments, SpeedLawSlidesTheBentBarWithinItsBudget) {
  double law_speed = 0.0;
  const double gains[2] = {4.8, 4.0};
  double fixed_speed[2] = {0.0, 0.0};
  bool fixed_met[2] = {true, true};
  for (int seed = 1; seed <= 3; ++seed) {
    Scene sc = test::loadShipped("bent_bar_speed_law.yaml", {"seed=" + std::to_string(seed)});
    ASSERT_DOUBLE_EQ(sc.servo.speed_law.law.v_max, 0.12);
    const Summary s = test::run(sc);
    EXPECT_EQ(s.status, "ok") << seed;
    EXPECT_TRUE(s.criteria_failed.empty()) << seed << ": " << s.criteria_failed.front();
    EXPECT_GE(s.slide_speed_mps, 0.040) << seed;
    EXPECT_LE(s.force_true_rms_error_n, 0.5) << seed;
    EXPECT_GE(s.force_true_in_band_fraction, 0.95) << seed;
    EXPECT_EQ(s.contact_lost_count, 0) << seed;
    law_speed += s.slide_speed_mps / 3.0;
    for (int k = 0; k < 2; ++k) {
      Scene fx = test::loadShipped("bent_bar_speed_law.yaml", {"seed=" + std::to_string(seed)});
      useFixedGain(fx, gains[k]);
      const RunResult r = test::runFull(fx);
      fixed_met[k] = fixed_met[k] && meetsSlideTargets(r);
      fixed_speed[k] += r.summary.slide_speed_mps / 3.0;
    }
  }
  EXPECT_TRUE(fixed_met[0] || fixed_met[1]);  // the comparison is not empty
  for (int k = 0; k < 2; ++k) {
    if (fixed_met[k]) {
      EXPECT_GE(law_speed, 1.1 * fixed_speed[k]) << gains[k];
    }
  }
}

