// The scene's `faults:` list (tactile_sim_runner/scene.hpp, tactile_sim_faults/sensor_faults.hpp):
//  * read from the file and from `--set faults=[...]`, every kind's keys;
//  * errors name the file, the key and the valid range;
//  * the estimated wrench's faults (tactile::sim::EstimatedWrench) at known
//    times against the wrench computed here: bias, drift (N/min), the wrong
//    axes (flange, sensor), the wrong sign, a wrong pad mass (fixed in {g}:
//    its component along z_s turns with the flange); no allocation per fill;
//  * the pad's faults reach the runner's sensor path (the phantom press:
//    the reader sees 8 N while nothing touches).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene_run.hpp"
#include "alloc_counter.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/runner.hpp"
#include "tactile_sim_runner/scene.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

const std::string kScenes = std::string(TACTILE_SOURCE_DIR) + "/params/scenes/";

ConfigResult load(const std::string& faults, Scene& sc, const std::string& scene = "edge_exploration.yaml") {
  return loadRun(sim::test::shippedRun(scene), sc, {"faults=" + faults});
}

// A state with the sensor facing down (z_s = -z_g) pressed with 5 N, or turned by `pitch` about y_g.
SimState pressed(double t, double pitch = 0.0) {
  SimState st;
  st.time_s = t;
  st.T_ge = KDL::Frame(KDL::Rotation::RotY(pitch) * KDL::Rotation::RPY(kPi, 0.0, kPi), KDL::Vector(0.72, 0.0, 0.40));
  st.T_gs = st.T_ge * KDL::Frame(KDL::Vector(0.0, 0.0, 0.03));
  st.wrench_s = {0.0, 0.0, -5.0, 0.01, -0.02, 0.0};
  return st;
}

FaultSpec fault(SensorFault k, double start) {
  FaultSpec f;
  f.kind = k;
  f.start_s = start;
  return f;
}

void expectWrench(const Wrench& a, const std::array<double, 6>& b, const char* what) {
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(a.w[i], b[i], 1e-9) << what << " [" << i << "]";
}

}  // namespace

TEST(SceneFaults, EveryKindFromTheSetList) {
  Scene sc;
  const std::string list =
      "[{kind: stuck, start_s: 8, rows: [1, 4], cols: [5, 8], force_n: 8}, {kind: dead, start_s: 9, cols: [0, 4]},"
      " {kind: tare_creep, start_s: 1, counts_per_min: 300}, {kind: calibration, scale: 0.5},"
      " {kind: repeat, start_s: 2, duration_s: 1.5}, {kind: wrench_drift, start_s: 3, drift_n_per_min: [0, 0, 10]},"
      " {kind: wrench_frame, axes: sensor}, {kind: pad_mass, mass_kg: 0.4}]";
  ASSERT_TRUE(load(list, sc).ok()) << load(list, sc).message();
  ASSERT_EQ(sc.faults.size(), 8u);
  const FaultSpec& s = sc.faults[0];
  EXPECT_EQ(s.kind, SensorFault::Stuck);
  EXPECT_EQ(s.start_s, 8.0);
  EXPECT_EQ(s.row0, 1);
  EXPECT_EQ(s.row1, 4);
  EXPECT_EQ(s.col0, 5);
  EXPECT_EQ(s.col1, 8);
  EXPECT_EQ(s.force_n, 8.0);
  EXPECT_LT(s.counts, 0.0);
  EXPECT_EQ(sc.faults[1].col1, 4);
  EXPECT_EQ(sc.faults[1].row1, -1) << "rows: the whole pad";
  EXPECT_EQ(sc.faults[2].counts_per_min, 300.0);
  EXPECT_EQ(sc.faults[3].scale, 0.5);
  EXPECT_EQ(sc.faults[3].start_s, 0.0) << "static: from the start";
  EXPECT_EQ(sc.faults[4].duration_s, 1.5);
  EXPECT_EQ(sc.faults[5].drift_n_per_min[2], 10.0);
  EXPECT_EQ(sc.faults[6].axes, WrenchAxes::Sensor);
  EXPECT_EQ(sc.faults[7].mass_kg, 0.4);
  EXPECT_EQ(responseParams(sc).faults.size(), 8u) << "the sensor's schedule gets the list";
  // One element of a list the scene has: --set faults.0.start_s=...
  Scene ph;
  ASSERT_TRUE(loadRun(sim::test::shippedRun("faults/phantom_contact.yaml"), ph, {"faults.0.start_s=3.5"}).ok());
  ASSERT_EQ(ph.faults.size(), 1u);
  EXPECT_EQ(ph.faults[0].start_s, 3.5);
  EXPECT_EQ(ph.faults[0].force_n, 8.0);
}

TEST(SceneFaults, ErrorsNameTheFileTheKeyAndTheRange) {
  struct Case {
    const char* list;
    const char* text;
  };
  const Case cases[] = {
      {"{kind: stuck}", "faults: must be a list"},
      {"[{kind: wobble}]", "faults[0].kind: 'wobble': must be one of '', stale, disconnect"},
      {"[{start_s: 1}]", "faults[0].kind: required"},
      {"[{kind: nan, start_s: 1}]", "nan is the RTT simulated sensor's `fault` property only"},
      {"[{kind: dead, counts: 3}]", "faults[0].counts: only for 'stuck'"},
      {"[{kind: dead, colour: red}]", "faults[0].colour: unknown key"},
      {"[{kind: dead, rows: [1, 2, 3]}]", "faults[0].rows: must be [first, last]"},
      {"[{kind: dead, rows: [1, 7]}]", "faults[0].rows = [1, 7]: must be [first, last] within [0, 5]"},
      {"[{kind: stale, start_s: 1}]", "faults[0].duration_s = 0: must be in (0, 60] s"},
      {"[{kind: stuck, counts: 100, force_n: 2}]", "faults[0].counts / force_n: give exactly one"},
      {"[{kind: stuck, counts: -3}]", "faults[0].counts: must be >= 0"},
      {"[{kind: calibration, scale: 20}]", "faults[0].scale = 20: must be in [0.1, 10]"},
      {"[{kind: wrench_bias, bias_n: [0, 0]}]", "faults[0].bias_n: must have 3 entries"},
      {"[{kind: wrench_frame, axes: tool}]", "faults[0].axes: 'tool': must be one of flange, sensor"},
      {"[{kind: pad_mass, mass_kg: 9}]", "faults[0].mass_kg = 9: must be in [-5, 5] kg"},
      {"[{kind: tare_creep, start_s: -2}]", "faults[0].start_s = -2: must be >= 0 s"},
  };
  for (const Case& c : cases) {
    Scene sc;
    const ConfigResult r = load(c.list, sc);
    ASSERT_FALSE(r.ok()) << c.list;
    EXPECT_NE(r.message().find(c.text), std::string::npos) << c.list << " -> " << r.message();
    EXPECT_NE(r.message().find("edge_exploration.yaml"), std::string::npos) << "names the file: " << r.message();
  }
}

// Each wrench fault against the wrench computed from the state, before and after its start.
TEST(WrenchFaults, EachFaultAtKnownTimes) {
  EstimatedWrench plain;
  ASSERT_TRUE(plain.configure(WrenchErrorParams{}, 1).ok());
  Wrench w0, w;
  plain.fill(pressed(1.0), w0);
  const SimState st0 = pressed(1.0);
  auto check = [&](const FaultSpec& f, const std::array<double, 6>& after, const char* what) {
    EstimatedWrench e;
    ASSERT_TRUE(e.configure(WrenchErrorParams{}, 1, {f}).ok());
    SimState before = pressed(1.9), later = pressed(12.0);
    e.fill(before, w);
    expectWrench(w, w0.w, what);  // unchanged before start_s = 2
    e.fill(later, w);
    expectWrench(w, after, what);
  };
  const auto& b = w0.w;  // force (0, 0, 5) N on the flange, in {g}
  EXPECT_NEAR(b[2], 5.0, 1e-12);
  FaultSpec bias = fault(SensorFault::WrenchBias, 2.0);
  bias.bias_n = {1.0, -2.0, 3.0};
  check(bias, {b[0] + 1.0, b[1] - 2.0, b[2] + 3.0, b[3], b[4], b[5]}, "bias");
  FaultSpec drift = fault(SensorFault::WrenchDrift, 2.0);
  drift.drift_n_per_min = {0.0, 6.0, -12.0};  // 10 s after its start: +1 N, -2 N
  check(drift, {b[0], b[1] + 1.0, b[2] - 2.0, b[3], b[4], b[5]}, "drift");
  FaultSpec sign = fault(SensorFault::WrenchSign, 2.0);
  check(sign, {-b[0], -b[1], -b[2], -b[3], -b[4], -b[5]}, "sign");
  // Flange axes: the facing-down flange's z_e is -z_g, x_e is -x_g.
  const KDL::Vector fe = st0.T_ge.M.Inverse(KDL::Vector(b[0], b[1], b[2]));
  const KDL::Vector me = st0.T_ge.M.Inverse(KDL::Vector(b[3], b[4], b[5]));
  FaultSpec frame = fault(SensorFault::WrenchFrame, 2.0);
  check(frame, {fe.x(), fe.y(), fe.z(), me.x(), me.y(), me.z()}, "flange axes");
  EXPECT_NEAR(fe.z(), -5.0, 1e-9);
  // A pad 0.5 kg heavier than the load model: -4.9 N along z_g at the pad's
  // centre of mass (15 mm along z_e from the flange: no moment while z_e is vertical).
  FaultSpec mass = fault(SensorFault::PadMass, 2.0);
  mass.mass_kg = 0.5;
  check(mass, {b[0], b[1], b[2] - 0.5 * kGravity, b[3], b[4], b[5]}, "pad mass");
}

// The wrong pad mass is fixed in {g}: turned by 30 deg, its component along
// z_s is cos(30 deg) of it and it has a moment about the flange; the wrench
// the servo projects on z_s changes with the posture.
TEST(WrenchFaults, PadMassTurnsWithTheFlange) {
  FaultSpec mass = fault(SensorFault::PadMass, 0.0);
  mass.mass_kg = 0.5;
  EstimatedWrench e, plain;
  ASSERT_TRUE(e.configure(WrenchErrorParams{}, 1, {mass}).ok());
  ASSERT_TRUE(plain.configure(WrenchErrorParams{}, 1).ok());
  const double pitch = 30.0 * kPi / 180.0;
  const SimState st = pressed(5.0, pitch);
  Wrench w, w0;
  e.fill(st, w);
  plain.fill(st, w0);
  const KDL::Vector df(w.w[0] - w0.w[0], w.w[1] - w0.w[1], w.w[2] - w0.w[2]);
  const double m = 0.5 * kGravity;
  EXPECT_NEAR(df.x(), 0.0, 1e-9);
  EXPECT_NEAR(df.z(), -m, 1e-9) << "fixed in {g}";
  const KDL::Vector zs = st.T_gs.M.UnitZ();
  EXPECT_NEAR(dot(df, zs), m * std::cos(pitch), 1e-9) << "along z_s: cos of the tilt";
  const KDL::Vector lever = 0.5 * (st.T_gs.p - st.T_ge.p);
  const KDL::Vector dm(w.w[3] - w0.w[3], w.w[4] - w0.w[4], w.w[5] - w0.w[5]);
  const KDL::Vector want = lever * KDL::Vector(0.0, 0.0, -m);
  EXPECT_NEAR((dm - want).Norm(), 0.0, 1e-12);
  EXPECT_GT(dm.Norm(), 0.01) << "a moment once z_e is not vertical";
}

// A duration ends the fault; wrench faults combine (bias + drift, then sign).
TEST(WrenchFaults, DurationAndCombination) {
  FaultSpec bias = fault(SensorFault::WrenchBias, 1.0);
  bias.bias_n = {0.0, 0.0, 2.0};
  bias.duration_s = 2.0;
  FaultSpec sign = fault(SensorFault::WrenchSign, 2.0);
  EstimatedWrench e;
  ASSERT_TRUE(e.configure(WrenchErrorParams{}, 1, {bias, sign}).ok());
  Wrench w;
  e.fill(pressed(1.5), w);
  EXPECT_NEAR(w.w[2], 7.0, 1e-9);
  e.fill(pressed(2.5), w);
  EXPECT_NEAR(w.w[2], -7.0, 1e-9) << "the sign applies to the whole reported wrench";
  e.fill(pressed(3.5), w);
  EXPECT_NEAR(w.w[2], -5.0, 1e-9) << "the bias's window has ended";
}

TEST(WrenchFaults, FillDoesNotAllocate) {
  std::vector<FaultSpec> all;
  for (SensorFault k : {SensorFault::WrenchBias, SensorFault::WrenchDrift, SensorFault::WrenchFrame,
                        SensorFault::WrenchSign, SensorFault::PadMass}) {
    FaultSpec f = fault(k, 0.5);
    f.mass_kg = 0.2;
    all.push_back(f);
  }
  WrenchErrorParams p;
  p.noise_n = 0.5;
  EstimatedWrench e;
  ASSERT_TRUE(e.configure(p, 3, all).ok());
  Wrench w;
  SimState st = pressed(0.0);
  tactile::test::AllocationScope scope;
  for (int k = 0; k < 1000; ++k) {
    st.time_s = k * 1e-3;
    e.fill(st, w);
  }
  EXPECT_EQ(scope.count(), 0u);
}

// The phantom press reaches the runner's sensor path: the features see about
// 8 N while the true force is 0 (nothing within reach).
TEST(SceneFaults, PhantomPressReachesTheRunnersSensor) {
  Scene sc;
  ASSERT_TRUE(loadRun(sim::test::shippedRun("faults/phantom_contact.yaml"), sc, {"duration=1.0"}).ok());
  Runner runner;
  ASSERT_TRUE(runner.configure(sc).ok());
  RunResult out;
  runner.run(out);
  ASSERT_FALSE(out.rows.empty());
  int seen = 0;
  for (const LogRow& r : out.rows) {
    EXPECT_EQ(r.force_true, 0.0) << "nothing touches, t " << r.t;
    if (r.f.contact == ContactType::None) continue;
    ++seen;
    EXPECT_NEAR(r.f.force, 8.0, 0.05) << "t " << r.t;
  }
  EXPECT_GT(seen, static_cast<int>(out.rows.size()) - 3) << "from the first frames on";
}

// A stream that re-sends its last frame for 2 s in the slide (new sequence
// numbers and time stamps, the same image): the servo holds once the arm has
// moved 2 mm on the frozen image (safety.frozen_image in the edge
// exploration's program) instead of sliding blind on it, and goes on when the
// frames change again. Without the check the arm slides on for the whole 2 s
// (about 20 mm at the slide's 10 mm/s) and may lose the edge.
TEST(SceneFaults, AFrozenStreamHoldsTheArmUntilTheImageChanges) {
  Scene sc;
  ASSERT_TRUE(load("[{kind: repeat, start_s: 12, duration_s: 2}]", sc).ok());
  Runner runner;
  ASSERT_TRUE(runner.configure(sc).ok());
  RunResult out;
  runner.run(out);
  ASSERT_FALSE(out.rows.empty());
  const LogRow* at_fault = nullptr;
  const LogRow* at_end = nullptr;
  int holding = 0, after = 0;
  for (const LogRow& r : out.rows) {
    if (r.t >= 12.0 && !at_fault) at_fault = &r;
    if (r.t <= 14.0) at_end = &r;
    if (r.t >= 12.3 && r.t < 14.0 && r.servo == ServoStatus::Holding) ++holding;
    if (r.t >= 15.0 && r.servo == ServoStatus::Ok) ++after;
  }
  ASSERT_TRUE(at_fault && at_end);
  const double travel = std::hypot(at_end->act[0] - at_fault->act[0], at_end->act[1] - at_fault->act[1]);
  // 2 mm and 0.1 s (the program's frozen_image) plus the cycles until a new
  // frame shows the repeat and the arm settles: within 4 mm.
  EXPECT_LT(travel, 0.004) << "the arm slid on a frozen image";
  EXPECT_GT(holding, 100) << "held (status Holding) for most of the repeat";
  EXPECT_GT(after, 100) << "the slide goes on once the frames change";
  EXPECT_EQ(out.summary.status, "ok");
}
