// Real-time factor of the simulator: simulated seconds per wall second
// (counter "rtf"), for quasi-static vs dynamics and for the physics
// sub-sampling K = 1/2/4 (and the image sub-sampling of the acquisition), in
// one run. Scene: the sensor slides at 10 mm/s along a bar with a rounded
// edge, pressed with ~5 N (the edge-exploration workload), WTS acquisition
// at 140 Hz.
//
// BM_SensorEffects: frames per CPU second of the simulated WTS electronics
// (TaxelResponse::acquire + deliver) on the bar's contact image, each sensor
// effect alone at its realistic level and all together, against all off in
// the same run; BM_SimSensor: the same effects in the arm + sensor loop
// (World::acquireForces + TaxelResponse, as the runner), rtf.
//
//   bench_sim --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>

#include "tactile_sim_lwr/taxel_response.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "sim_scenes.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {
using simtest::downPose;
constexpr double kBarTop = 0.043;

WorldParams barScene(Fidelity f, int k_phys, int k_img, bool dyn_every_step = false) {
  WorldParams p;
  if (dyn_every_step) {  // M and C evaluated every step (no cache)
    p.arm.dyn_refresh_q = 0.0;
    p.arm.dyn_refresh_qd = 0.0;
  }
  p.fidelity = f;
  p.pad.physics_subsamples = k_phys;
  p.pad.subsamples = k_img;
  ObjectParams bar;
  bar.name = "bar";
  bar.type = ObjectType::Bar;
  bar.radius = 0.003;
  // Slightly inclined (1 cm over 0.6 m) so that the load is non-uniform.
  bar.vertices = {{0.3, 0.0005, kBarTop - 0.003 - 0.005}, {0.9, 0.0005, kBarTop - 0.003 + 0.005}};
  p.objects = {bar};
  p.use_initial_flange_pose = true;
  p.initial_flange_pose = downPose(0.58, 0.0, kBarTop + 0.02 + 0.0005);
  return p;
}

// One benchmark iteration = one simulated second: sim steps at sim_rate, the
// command updated at the 100 Hz servo rate (Table 2), acquisitions at 140 Hz.
void runSecond(World& w, double sim_rate, double& t, SimState& s, RawTactileFrame& raw, SensorTruth& truth, double& next_acq) {
  const double dt = 1.0 / sim_rate;
  const int n = static_cast<int>(std::lround(sim_rate));
  for (int i = 0; i < n; ++i) {
    t += dt;
    const double ts = std::floor(t * 100.0 + 1e-9) / 100.0;  // servo sample time
    const double ph = std::fmod(ts, 20.0);
    const double x = 0.58 + 0.01 * (ph < 10.0 ? ph : 20.0 - ph);  // 10 mm/s back and forth over 0.1 m
    w.step(downPose(x, 0.0, kBarTop + 0.02 - 0.005), dt, s);
    if (t >= next_acq) {
      w.acquire(raw, truth);
      next_acq += 1.0 / 140.0;
    }
  }
}

void BM_Sim(benchmark::State& state) {
  const Fidelity f = state.range(0) == 0 ? Fidelity::QuasiStatic : Fidelity::Dynamics;
  const double sim_rate = static_cast<double>(state.range(1));
  const int k_phys = static_cast<int>(state.range(2));
  const int k_img = static_cast<int>(state.range(3));
  const bool every = state.range(4) != 0;
  World w;
  if (!w.configure(barScene(f, k_phys, k_img, every)).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  SimState s;
  RawTactileFrame raw;
  SensorTruth truth;
  double t = 0.0, next_acq = 0.0;
  runSecond(w, sim_rate, t, s, raw, truth, next_acq);  // settle into contact
  double sim_s = 0.0;
  for (auto _ : state) {
    runSecond(w, sim_rate, t, s, raw, truth, next_acq);
    sim_s += 1.0;
    double f_now = s.normal_force;
    benchmark::DoNotOptimize(f_now);
  }
  state.counters["rtf"] = benchmark::Counter(sim_s, benchmark::Counter::kIsRate);
  state.counters["MC_evals/s"] = static_cast<double>(w.arm().dynEvaluations()) / (sim_s + 1.0);
  char label[96];
  std::snprintf(label, sizeof label, "%s F=%.2fN status=%s", toString(f), s.normal_force, toString(s.status));
  state.SetLabel(label);
}
// Args: fidelity (0 quasi-static, 1 dynamics), sim rate (Hz), physics K, image K,
// MCevery (1: dynamics evaluates M and C every step, the reference for the cache).
BENCHMARK(BM_Sim)
    ->ArgNames({"dyn", "rate", "Kphys", "Kimg", "MCevery"})
    ->Args({0, 100, 2, 4, 0})
    ->Args({0, 1000, 2, 4, 0})
    ->Args({0, 1000, 1, 4, 0})
    ->Args({0, 1000, 4, 4, 0})
    ->Args({0, 1000, 2, 1, 0})
    ->Args({0, 1000, 2, 2, 0})
    ->Args({1, 1000, 1, 4, 0})
    ->Args({1, 1000, 1, 4, 1})
    ->Args({1, 1000, 2, 4, 0})
    ->Args({1, 1000, 2, 4, 1})
    ->Args({1, 1000, 4, 4, 0})
    ->Args({1, 1000, 1, 1, 0})
    ->Args({1, 1000, 2, 1, 0})
    ->Args({1, 1000, 2, 8, 0})
    ->Unit(benchmark::kMillisecond);

// The physics and timing effects (WorldParams), on vs off in the same run:
// effect 0 off, 1 friction mu 0.5, 2 FRI delay 2 ms, 3 KRC cycle 2 ms,
// 4 all three. The ratio rtf(on) / rtf(off) is the effect's cost.
void BM_Effects(benchmark::State& state) {
  const Fidelity f = state.range(0) == 0 ? Fidelity::QuasiStatic : Fidelity::Dynamics;
  const int e = static_cast<int>(state.range(1));
  WorldParams p = barScene(f, 2, 4);
  if (e == 1 || e == 4) p.friction_mu = 0.5;
  if (e == 2 || e == 4) p.fri_delay_s = 0.002;
  if (e == 3 || e == 4) p.krc_cycle_s = 0.002;
  World w;
  if (!w.configure(p).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  SimState s;
  RawTactileFrame raw;
  SensorTruth truth;
  double t = 0.0, next_acq = 0.0;
  runSecond(w, 1000.0, t, s, raw, truth, next_acq);
  double sim_s = 0.0;
  for (auto _ : state) {
    runSecond(w, 1000.0, t, s, raw, truth, next_acq);
    sim_s += 1.0;
    double f_now = s.normal_force;
    benchmark::DoNotOptimize(f_now);
  }
  state.counters["rtf"] = benchmark::Counter(sim_s, benchmark::Counter::kIsRate);
  char label[96];
  std::snprintf(label, sizeof label, "%s F=%.2fN fx=%.2fN status=%s", toString(f), s.normal_force, s.wrench_s[0],
                toString(s.status));
  state.SetLabel(label);
}
BENCHMARK(BM_Effects)
    ->ArgNames({"dyn", "effect"})
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({0, 2})
    ->Args({0, 3})
    ->Args({0, 4})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Args({1, 3})
    ->Args({1, 4})
    ->Unit(benchmark::kMillisecond);

// Single calls, for the cost breakdown.
void BM_Step(benchmark::State& state) {
  const Fidelity f = state.range(0) == 0 ? Fidelity::QuasiStatic : Fidelity::Dynamics;
  World w;
  if (!w.configure(barScene(f, static_cast<int>(state.range(1)), 4, state.range(2) != 0)).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  SimState s;
  double t = 0.0;
  for (int i = 0; i < 500; ++i) w.step(downPose(0.58, 0.0, kBarTop + 0.02 - 0.005), 0.001, s);
  for (auto _ : state) {
    t += 0.001;
    const double ph = std::fmod(t, 20.0);
    w.step(downPose(0.58 + 0.01 * (ph < 10.0 ? ph : 20.0 - ph), 0.0, kBarTop + 0.02 - 0.005), 0.001, s);
    double f_now = s.normal_force;
    benchmark::DoNotOptimize(f_now);
  }
}
BENCHMARK(BM_Step)
    ->ArgNames({"dyn", "Kphys", "MCevery"})
    ->Args({0, 1, 0})
    ->Args({0, 2, 0})
    ->Args({0, 4, 0})
    ->Args({1, 1, 0})
    ->Args({1, 2, 0})
    ->Args({1, 2, 1})
    ->Args({1, 4, 0})
    ->Unit(benchmark::kMicrosecond);

// One acquisition: full contact integral (PadSensor::acquire at the world's
// placement; repeat = 0) or the reuse path World::acquire takes when nothing
// moved since the previous frame (repeat = 1).
void BM_Acquire(benchmark::State& state) {
  const WorldParams p = barScene(Fidelity::QuasiStatic, 2, static_cast<int>(state.range(0)));
  World w;
  if (!w.configure(p).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  SimState s;
  for (int i = 0; i < 10; ++i) w.step(downPose(0.58, 0.0, kBarTop + 0.02 - 0.005), 0.01, s);
  PadSensor pad;
  ObjectSet objects;
  PadParams pp = w.pad().params();
  if (!pad.configure(pp).ok() || !objects.configure(p.objects).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  const double hx = 0.5 * pp.housing_size_x + 1e-4, hy = 0.5 * pp.housing_size_y + 1e-4;
  objects.setRegion(-hx, hx, -hy, hy);
  objects.pose(s.T_gs, TrayPose{});
  RawTactileFrame raw;
  SensorTruth truth;
  const bool repeat = state.range(1) != 0;
  double t = 0.0;
  for (auto _ : state) {
    t += 1.0 / 140.0;
    if (repeat)
      w.acquire(raw, truth);
    else
      pad.acquire(objects, s.T_gs, t, raw, truth);
    benchmark::DoNotOptimize(raw.counts[40]);
  }
  char label[64];
  std::snprintf(label, sizeof label, "F=%.2fN", truth.layer.force);
  state.SetLabel(label);
}
BENCHMARK(BM_Acquire)->ArgNames({"Kimg", "repeat"})->Args({1, 0})->Args({4, 0})->Args({8, 0})->Args({4, 1})->Unit(benchmark::kMicrosecond);

// The sensor effects at the levels of core/sim/lwr/README.md ("Sensor effects").
const char* const kEffectNames[] = {"off", "delay", "gain", "dead", "calib", "crosstalk", "creep", "hysteresis",
                                    "device_noise", "all"};
SensorEffects effectsFor(int which) {
  SensorEffects e;
  const bool all = which == 9;
  if (which == 1 || all) e.wts_transfer_delay_s = 0.0157;
  if (which == 2 || all) e.gain_spread = 0.1;
  if (which == 3 || all) e.dead_taxels = 2;
  if (which == 4 || all) e.calibration_error = 0.05;
  if (which == 5 || all) e.crosstalk = 0.05;
  if (which == 6 || all) e.creep_fraction = 0.1, e.creep_tau_s = 2.0;
  if (which == 7 || all) e.hysteresis = 0.05;
  if (which == 8 || all) e.device_noise = true;
  e.max_frame_rate_hz = 140.0;
  return e;
}

bool configureResponse(const World& w, int which, TaxelResponse& r) {
  TaxelResponseParams rp;
  rp.calibration = w.calibration();
  rp.noise_counts = 6.0;
  rp.effects = effectsFor(which);
  return r.configure(rp).ok();
}

// One iteration = one frame: acquire at 140 Hz and deliver (the reader's poll).
void BM_SensorEffects(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  World w;
  if (!w.configure(barScene(Fidelity::QuasiStatic, 2, 4)).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  SimState s;
  for (int i = 0; i < 10; ++i) w.step(downPose(0.58, 0.0, kBarTop + 0.02 - 0.005), 0.01, s);
  TactileFrame forces;
  SensorTruth truth;
  w.acquireForces(forces, truth);
  TaxelResponse r;
  if (!configureResponse(w, which, r)) {
    state.SkipWithError("response configure failed");
    return;
  }
  RawTactileFrame raw;
  double t = 0.0;
  long delivered = 0;
  for (auto _ : state) {
    t += 1.0 / 140.0;
    if (r.acquire(forces, t, raw)) ++delivered;
    if (r.deliver(t, raw)) ++delivered;
    benchmark::DoNotOptimize(raw.counts[40]);
  }
  state.SetItemsProcessed(state.iterations());  // frames per CPU second
  state.SetLabel(kEffectNames[which]);
  benchmark::DoNotOptimize(delivered);
}
BENCHMARK(BM_SensorEffects)->ArgName("effect")->DenseRange(0, 9)->Unit(benchmark::kNanosecond);

// The arm + sensor loop of the runner at 1 kHz, quasi-static, K 2/4: rtf with each effect.
void BM_SimSensor(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  World w;
  if (!w.configure(barScene(Fidelity::QuasiStatic, 2, 4)).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  TaxelResponse r;
  if (!configureResponse(w, which, r)) {
    state.SkipWithError("response configure failed");
    return;
  }
  SimState s;
  TactileFrame forces;
  SensorTruth truth;
  RawTactileFrame raw;
  double t = 0.0, next_acq = 0.0;
  const double dt = 1e-3;
  for (auto _ : state) {
    for (int i = 0; i < 1000; ++i) {
      t += dt;
      const double ts = std::floor(t * 100.0 + 1e-9) / 100.0;
      const double ph = std::fmod(ts, 20.0);
      const double x = 0.58 + 0.01 * (ph < 10.0 ? ph : 20.0 - ph);
      w.step(downPose(x, 0.0, kBarTop + 0.02 - 0.005), dt, s);
      if (t >= next_acq) {
        w.acquireForces(forces, truth);
        r.acquire(forces, t, raw);
        next_acq += 1.0 / 140.0;
      }
      if (r.delayed()) r.deliver(t, raw);
    }
    benchmark::DoNotOptimize(raw.counts[40]);
  }
  state.counters["rtf"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(kEffectNames[which]);
}
BENCHMARK(BM_SimSensor)->ArgName("effect")->Arg(0)->Arg(9)->Arg(5)->Arg(8)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
