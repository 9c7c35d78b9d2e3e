// The loop's shared rules (tactile_sim_runner/loop.hpp): the schedule of Table 2's
// rates, the end rule, and the simulated sensor's response from the one
// calibration file (tactile::sim::TaxelResponse).
#include <gtest/gtest.h>

#include <cmath>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"

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
  ASSERT_TRUE(loadScene(TACTILE_SOURCE_DIR "/params/scenes/edge_exploration.yaml", sc).ok());
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

// A world that refuses its steps ends the run with a named status and a
// non-zero exit code (never "ok" with the arm standing still): a refused
// step at once (its time would never advance), refused commands after 0.1 s
// of them without a valid one.
TEST(EndRule, RefusedStepsAndCommandsEndTheRunWithANamedStatus) {
  EndRule e;
  e.configure(Rates{});  // 1 kHz physics
  EXPECT_EQ(e.afterPhysics(SimStatus::StepRejected), EndReason::SimRejected);
  e.reset();
  for (int k = 0; k < 99; ++k) EXPECT_EQ(e.afterPhysics(SimStatus::InvalidCommand), EndReason::None) << k;
  EXPECT_EQ(e.afterPhysics(SimStatus::Ok), EndReason::None);  // a valid command: the count restarts
  for (int k = 0; k < 99; ++k) EXPECT_EQ(e.afterPhysics(SimStatus::InvalidCommand), EndReason::None) << k;
  EXPECT_EQ(e.afterPhysics(SimStatus::InvalidCommand), EndReason::SimRejected);
  EXPECT_EQ(e.afterPhysics(SimStatus::NotConverged), EndReason::None);
  // A quasi-static world without equilibrium for 0.1 s (100 steps at 1 kHz):
  // its state is not the physics any more.
  e.reset();
  for (int k = 0; k < 99; ++k) EXPECT_EQ(e.afterPhysics(SimStatus::NotConverged), EndReason::None) << k;
  EXPECT_EQ(e.afterPhysics(SimStatus::Ok), EndReason::None);  // converged again: the count restarts
  for (int k = 0; k < 99; ++k) EXPECT_EQ(e.afterPhysics(SimStatus::NotConverged), EndReason::None) << k;
  EXPECT_EQ(e.afterPhysics(SimStatus::NotConverged), EndReason::SimFatal);
  EXPECT_EQ(e.unconvergedSteps(), 199);
  Summary s;
  applyEnd(EndReason::SimFatal, SimStatus::NotConverged, s);
  EXPECT_EQ(s.status, "sim_not_converged");
  EXPECT_EQ(s.exit_code, 3);
  applyEnd(EndReason::SimRejected, SimStatus::StepRejected, s);
  EXPECT_EQ(s.status, "sim_step_rejected");
  EXPECT_EQ(s.exit_code, 3);
  applyEnd(EndReason::SimRejected, SimStatus::InvalidCommand, s);
  EXPECT_EQ(s.status, "sim_invalid_command");
  EXPECT_EQ(s.exit_code, 3);
  // The world does refuse such a step (the 2 s physics step).
  Scene sc;
  ASSERT_TRUE(loadScene(TACTILE_SOURCE_DIR "/params/scenes/sphere_table.yaml", sc).ok());
  World w;
  ASSERT_TRUE(w.configure(worldParams(sc)).ok());
  SimState st;
  const double t0 = w.time();
  EXPECT_EQ(w.step(w.state().command_g, 2.0, st), SimStatus::StepRejected);
  EXPECT_EQ(w.time(), t0);
  e.reset();
  EXPECT_EQ(e.afterPhysics(st.status), EndReason::SimRejected);
}

// Rates that make no sense are a configuration error naming the file, the
// key and the valid range: a 2 s physics step would be refused on every cycle.
TEST(SceneEffects, RatesAndEffectsAreValidatedWithFileKeyAndRange) {
  const std::string file = TACTILE_SOURCE_DIR "/params/scenes/edge_exploration.yaml";
  Scene sc;
  ConfigResult r = loadScene(file, sc, {"rates.sim=0.5"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find(file), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("rates.sim"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find(">= 100"), std::string::npos) << r.message();
  ASSERT_TRUE(loadScene(file, sc).ok());
  sc.rates.sim = 50.0;  // a command-line override after loading (tactile_sim --sim-rate)
  sc.rates.servo = sc.rates.wts = sc.rates.features = 50.0;
  EXPECT_FALSE(validateScene(sc).ok());
  for (const char* bad : {"effects.friction_mu=3", "effects.friction_mu=-0.1", "effects.fri_delay_s=2",
                          "effects.krc_cycle_s=-1", "effects.friction_stiffness=0"}) {
    r = loadScene(file, sc, {bad});
    ASSERT_FALSE(r.ok()) << bad;
    const std::string key = std::string(bad).substr(0, std::string(bad).find('='));
    EXPECT_NE(r.message().find(file), std::string::npos) << r.message();
    EXPECT_NE(r.message().find(key), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("must be in"), std::string::npos) << r.message();
  }
  r = loadScene(file, sc, {"effects.fri_delay_s=0.0015"});  // 1.5 physics steps at 1 kHz
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("effects.fri_delay_s"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("whole number of physics steps"), std::string::npos) << r.message();
  r = loadScene(file, sc, {"effects.unknown=1"});
  EXPECT_FALSE(r.ok());
  // Off by default (a scene without an effects: map); set, they reach the
  // world's parameters (runner and RTT arm alike).
  ASSERT_TRUE(loadScene(TACTILE_SOURCE_DIR "/params/scenes/sphere_table.yaml", sc).ok());
  EXPECT_EQ(sc.world.friction_mu, 0.0);
  EXPECT_EQ(sc.world.fri_delay_s, 0.0);
  EXPECT_EQ(sc.world.krc_cycle_s, 0.0);
  ASSERT_TRUE(loadScene(file, sc, {"effects={friction_mu: 0.7, fri_delay_s: 0.002, krc_cycle_s: 0.002}"}).ok());
  const WorldParams wp = worldParams(sc);
  EXPECT_EQ(wp.friction_mu, 0.7);
  EXPECT_EQ(wp.fri_delay_s, 0.002);
  EXPECT_EQ(wp.krc_cycle_s, 0.002);
  EXPECT_EQ(wp.physics_step_s, 1.0 / sc.rates.sim);
}

// --set program.KEY: a key of the run's program (its base merged), by name in
// the phase list; checked as the program file is, the error naming the
// program, the key and its range.
TEST(SceneOverrides, ProgramKeysBySceneAndPhaseName) {
  const RunFiles file{TACTILE_SOURCE_DIR "/params/scenes/bent_bar_speed_law.yaml",
                      TACTILE_SOURCE_DIR "/params/programs/bent_bar_speed_law.yaml", ""};
  Scene plain, sc;
  ASSERT_TRUE(loadRun(file, plain).ok());
  ConfigResult r = loadRun(file, sc, {"program.speed_law.force_budget_n=0.45", "program.phases.explore.kp_per_s.x=2.5",
                                        "program.watchdogs.arm_stall.min_angle_deg=10"});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(sc.servo.speed_law.law.force_budget_n, 0.45);
  EXPECT_NE(plain.servo.speed_law.law.force_budget_n, 0.45);
  EXPECT_NEAR(sc.servo.watchdogs.stall_min_angle, 10.0 * kPi / 180.0, 1e-15);
  int explore = -1;
  for (std::size_t i = 0; i < sc.servo.phases.size(); ++i)
    if (sc.servo.phases[i].name == "explore") explore = static_cast<int>(i);
  ASSERT_GE(explore, 0);
  EXPECT_EQ(sc.servo.phases[static_cast<std::size_t>(explore)].kp(0), 2.5);
  EXPECT_EQ(sc.servo.phases[static_cast<std::size_t>(explore)].kp(2), plain.servo.phases[static_cast<std::size_t>(explore)].kp(2))
      << "the phase's other gains stay";
  EXPECT_EQ(sc.program_file, plain.program_file);

  r = loadRun(file, sc, {"program.speed_law.v_max=2"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("bent_bar_speed_law.yaml: speed_law.v_max = 2: must be in (0, 1] m/s"), std::string::npos)
      << r.message();
  r = loadRun(file, sc, {"program.phases.explorr.kp_per_s.x=2"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("explorr is neither an index nor the name of an element"), std::string::npos)
      << r.message();
  r = loadRun(file, sc, {"program.speed_law.vmax=0.1"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("speed_law.vmax: unknown key"), std::string::npos) << r.message();
  // A scene alone has no program to set a key of.
  r = loadScene(file.scene, sc, {"program.speed_law.v_max=0.05"});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("a scene has no program"), std::string::npos) << r.message();
}

// effects.wrench_error: the arm's estimated wrench = (1 + scale) F + bias +
// drift |p - p_0| + noise, moments exact; the noise a function of (seed, time).
TEST(EstimatedWrench, ErrorModelIsExactAndTheNoiseDependsOnTimeOnly) {
  SimState st;
  st.T_gs = KDL::Frame(KDL::Rotation::RPY(kPi, 0.0, 0.0), KDL::Vector(0.6, 0.1, 0.35));
  st.T_ge = st.T_gs * KDL::Frame(KDL::Vector(0, 0, -0.03));
  st.wrench_s = {0.3, -0.2, -5.0, 0.01, 0.02, 0.0};
  st.time_s = 1.25;
  Wrench exact, w;
  fillEstimatedWrench(st, exact);
  EstimatedWrench model;
  model.configure(WrenchErrorParams{}, 1);
  model.start(st);
  model.fill(st, w);
  EXPECT_EQ(w.w, exact.w);  // no error: the contact wrench itself
  WrenchErrorParams p;
  p.bias_n = {1.0, -1.0, 2.0};
  p.drift_n_per_m = {0.0, 0.5, -3.0};
  p.scale = 0.05;
  model.configure(p, 1);
  SimState start = st;
  start.T_ge.p = st.T_ge.p - KDL::Vector(0.03, 0.04, 0.0);  // 5 cm from the start position
  model.start(start);
  model.fill(st, w);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(w.w[i], 1.05 * exact.w[i] + p.bias_n[i] + p.drift_n_per_m[i] * 0.05, 1e-12) << i;
  for (int i = 3; i < 6; ++i) EXPECT_EQ(w.w[i], exact.w[i]) << i;
  // Noise: the same at the same time whoever asks (runner or RTT arm), zero
  // mean and sigma over many times (4-sigma bounds of the estimates).
  p = WrenchErrorParams{};
  p.noise_n = 0.5;
  model.configure(p, 3);
  model.start(st);
  Wrench a, b;
  model.fill(st, a);
  model.fill(st, b);
  EXPECT_EQ(a.w, b.w);
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    st.time_s = k * 0.001;
    model.fill(st, w);
    const double e = w.w[2] - exact.w[2];
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4.0 * 0.5 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.5, 4.0 * 0.5 / std::sqrt(2.0 * n));
  EstimatedWrench other;
  other.configure(p, 4);  // another seed: other noise
  other.start(st);
  st.time_s = 0.5;
  model.fill(st, a);
  other.fill(st, b);
  EXPECT_NE(a.w[2], b.w[2]);
}

TEST(EstimatedWrench, SceneKeysAreValidatedWithFileKeyAndRange) {
  const std::string file = TACTILE_SOURCE_DIR "/params/scenes/co_manipulation.yaml";
  Scene sc;
  ASSERT_TRUE(loadScene(file, sc, {"effects={friction_mu: 0.5}"}).ok());
  EXPECT_FALSE(sc.wrench_error.any());
  ASSERT_TRUE(loadScene(file, sc, {"effects.wrench_error={bias_n: [1, -1, 2], drift_n_per_m: [0, 0, 1], "
                                   "scale: 0.05, noise_n: 0.5}"})
                  .ok());
  EXPECT_EQ(sc.wrench_error.bias_n[2], 2.0);
  EXPECT_EQ(sc.wrench_error.drift_n_per_m[2], 1.0);
  EXPECT_EQ(sc.wrench_error.scale, 0.05);
  EXPECT_EQ(sc.wrench_error.noise_n, 0.5);
  for (const char* bad : {"effects.wrench_error={bias_n: [0, 0, 25]}", "effects.wrench_error={drift_n_per_m: [0, 200, 0]}",
                          "effects.wrench_error={scale: 0.6}", "effects.wrench_error={noise_n: -1}"}) {
    const ConfigResult r = loadScene(file, sc, {bad});
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.message().find(file), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("effects.wrench_error."), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("must be in"), std::string::npos) << r.message();
  }
  EXPECT_FALSE(loadScene(file, sc, {"effects.wrench_error={bias: [0, 0, 1]}"}).ok());  // unknown key
  EXPECT_FALSE(loadScene(file, sc, {"effects.wrench_error={bias_n: [0, 1]}"}).ok());   // 2 entries
}

// A bar polyline may hold kMaxVertices vertices: a closed 6 cm ring of 64
// segments (chord error 0.07 mm) loads; one vertex more is refused, naming
// the object, the key and the range.
TEST(SceneObjects, AClosedRingOf64SegmentsLoadsOneMoreIsRefused) {
  const std::string file = TACTILE_SOURCE_DIR "/params/scenes/bent_bar.yaml";
  auto ring = [](int n) {
    std::string v = "[";
    for (int k = 0; k <= n; ++k) {
      const double a = -kPi / 2 + 2 * kPi * (k % n) / n;
      v += (k ? ", [" : "[") + std::to_string(0.72 + 0.06 * std::cos(a)) + ", " +
           std::to_string(0.06 + 0.06 * std::sin(a)) + ", 0.368]";
    }
    return "objects=[{name: ring, type: bent_bar, radius: 0.005, vertices: " + v + "]}]";
  };
  Scene sc;
  const ConfigResult ok = loadScene(file, sc, {ring(kMaxVertices - 1)});
  EXPECT_TRUE(ok.ok()) << ok.message();
  const ConfigResult bad = loadScene(file, sc, {ring(kMaxVertices)});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("ring"), std::string::npos) << bad.message();
  EXPECT_NE(bad.message().find("vertices"), std::string::npos) << bad.message();
  EXPECT_NE(bad.message().find("[2, 65]"), std::string::npos) << bad.message();
}

// The force metrics (computeSummary): a detour, the run leaving a scored phase
// and back in it within the transient (the end rule's check returning to
// `explore` at a crest), is scored as the phase it left, and the return starts
// no new transient; a longer absence, and a phase the run does not come back
// from, are not scored, and a return after a longer absence starts a new
// transient. Rows every 10 ms, 5 N in `explore`, 7 N (out of the 5 +- 0.5 N
// band) elsewhere.
TEST(Metrics, ADetourWithinTheTransientIsScoredAsThePhaseItLeft) {
  Scene sc;
  for (const char* n : {"explore", "end_check", "done"}) {
    PhaseParams p;
    p.name = n;
    p.terminal = std::string(n) == "done";
    sc.servo.phases.push_back(p);
  }
  sc.metrics.force_phases = {"explore"};
  sc.metrics.transient_s = 0.5;
  sc.metrics.force_band_n = 0.5;
  // (phase, until t) segments, from t = 0.
  auto run = [&](std::initializer_list<std::pair<int, double>> segments) {
    RunResult out;
    out.phase_names = {"explore", "end_check", "done"};
    int k = 0;
    for (const auto& seg : segments) {
      for (; 0.01 * k < seg.second - 1e-9; ++k) {
        LogRow r;
        r.t = 0.01 * k;
        r.phase = seg.first;
        r.sd_force = 5.0;
        r.force_true = seg.first == 0 ? 5.0 : 7.0;
        r.true_in_contact = true;
        r.true_contact = {0.001 * k, 0.0, 0.0};  // 0.1 m/s
        out.rows.push_back(r);
      }
    }
    out.phases = phaseEntries(sc, out.rows);
    computeSummary(sc, out);
    return out.summary;
  };
  // A 0.1 s check back to explore, then a final one to done: 100 rows of
  // explore after its transient, the 10 of the detour, 90 after it.
  Summary s = run({{0, 1.5}, {1, 1.6}, {0, 2.5}, {1, 2.8}, {2, 3.0}});
  EXPECT_NEAR(s.force_scored_s, 2.0, 1e-9);
  EXPECT_NEAR(s.force_true_in_band_fraction, 190.0 / 200.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.force_true_max_n, 7.0);
  EXPECT_NEAR(s.slide_speed_mps, 0.1, 1e-9);
  // A 0.7 s absence (longer than the transient): not scored, and explore's
  // return waits out a new transient (2.2-2.7 s).
  s = run({{0, 1.5}, {1, 2.2}, {0, 3.0}, {2, 3.2}});
  EXPECT_NEAR(s.force_scored_s, 1.3, 1e-9);
  EXPECT_DOUBLE_EQ(s.force_true_in_band_fraction, 1.0);
  EXPECT_DOUBLE_EQ(s.force_true_max_n, 5.0);
}
