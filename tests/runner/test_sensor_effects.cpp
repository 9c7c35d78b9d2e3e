// The simulated WTS0614's effects (tactile::sim::TaxelResponse, SensorEffects;
// the scene's `effects:` map), each against a computed expectation:
//  * transfer delay: a load step appears in the delivered frames exactly
//    `delay` after the acquisition that first saw it (to the physics tick);
//    in the runner, every frame the servo sees is at least `delay` old;
//  * creep: the step response's time constant, fitted from the calibrated
//    output, equals tau_s;
//  * hysteresis: the loop width of a triangular load equals 2 h x;
//  * crosstalk: the total is conserved and each 4-neighbour gets c of the load;
//  * gain spread / calibration error: the reader's per-taxel ratio to the true
//    force is g_i (n linear) / 1 / (1 + e_i), the seeded draws have the set spread;
//  * dead taxels: the counted or listed taxels read 0;
//  * device noise: the threshold-derived level;
//  * determinism (same seed, same output), no allocation per frame, off == before,
//    range errors naming the file, the key and the range.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include "scene_run.hpp"
#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_sim_runner/runner.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

const std::string kScenes = std::string(TACTILE_SOURCE_DIR) + "/params/scenes/";

// The shipped calibration (wts0614.yaml), noise-free unless set.
TaxelResponseParams fileParams(double noise = 0.0) {
  Scene sc;
  EXPECT_TRUE(loadScene(kScenes + "edge_exploration.yaml", sc).ok());
  TaxelResponseParams p;
  p.calibration = sc.calibration;
  p.noise_counts = noise;
  p.threshold = 0.2;
  p.seed = 7;
  return p;
}

TactileFrame uniform(double f) {
  TactileFrame fr;
  fr.rows = 6;
  fr.cols = 14;
  for (int i = 0; i < 84; ++i) fr.force[static_cast<std::size_t>(i)] = f;
  return fr;
}

// What the reader makes of taxel i (the file's calibration).
double readBack(const TaxelResponse& r, int i, const RawTactileFrame& raw) {
  const uint16_t n = raw.counts[static_cast<std::size_t>(i)];
  return n == 0 ? 0.0 : r.forceFor(i, n);
}

constexpr int kCentre = 2 * 14 + 7;  // an interior taxel (row 2, col 7)

}  // namespace

// Off (the default) is the response without effects, bit for bit, and costs no state.
TEST(SensorEffects, OffIsTheBareResponse) {
  TaxelResponseParams p = fileParams(6.0);
  EXPECT_FALSE(p.effects.any());
  TaxelResponse a, b;
  ASSERT_TRUE(a.configure(p).ok());
  p.effects.max_frame_rate_hz = 140.0;  // not an effect
  ASSERT_TRUE(b.configure(p).ok());
  EXPECT_FALSE(a.delayed());
  RawTactileFrame ra, rb;
  for (int k = 0; k < 50; ++k) {
    TactileFrame f = uniform(0.3 + 0.02 * k);
    ASSERT_TRUE(b.acquire(f, k * 0.007, rb));  // no delay: written at once
    EXPECT_FALSE(b.deliver(k * 0.007, rb));
    a.respond(f, k * 0.007, ra);
    EXPECT_EQ(ra.counts, rb.counts) << k;
  }
}

// The WTS transfer delay, sample-exact: acquisitions at 140 Hz on a 1 kHz
// tick (as the runner's Schedule), the reader polled every tick. The load
// steps at acquisition k0; the first frame with the step is delivered at the
// first tick >= t(k0) + d, carrying t(k0) as its time, and every frame before
// it is the old load.
TEST(SensorEffects, TransferDelayIsSampleExact) {
  for (double d : {0.0157, 0.007, 0.0005, 0.030}) {
    TaxelResponseParams p = fileParams();
    p.effects.wts_transfer_delay_s = d;
    p.effects.max_frame_rate_hz = 140.0;
    TaxelResponse r;
    ASSERT_TRUE(r.configure(p).ok());
    ASSERT_TRUE(r.delayed());
    const double dt = 1e-3;
    const TactileFrame lo = uniform(0.5), hi = uniform(2.0);
    long next_acq = 0;  // acquisition ticks: ceil(k * 1000 / 140)
    int k_acq = 0;
    const int k0 = 20;  // the acquisition that first sees the step
    double t_step = -1.0;
    long tick_seen = -1;
    RawTactileFrame raw;
    tactile::test::AllocationScope scope;
    for (long tick = 0; tick < 400; ++tick) {
      const double t = static_cast<double>(tick) * dt;
      if (tick == next_acq) {
        if (k_acq == k0) t_step = t;
        EXPECT_FALSE(r.acquire(k_acq >= k0 ? hi : lo, t, raw));
        ++k_acq;
        next_acq = static_cast<long>(std::ceil(k_acq * 1000.0 / 140.0 - 1e-9));
      }
      if (r.deliver(t, raw)) {
        EXPECT_GE(t - raw.time_s, d - 1e-9) << "delivered before its transfer ended";
        EXPECT_LT(t - raw.time_s, d + dt - 1e-9) << "delivered a tick late";
        const bool stepped = raw.counts[kCentre] > r.countsFor(kCentre, 1.0);
        if (stepped && tick_seen < 0) {
          tick_seen = tick;
          EXPECT_DOUBLE_EQ(raw.time_s, t_step);
        }
        if (!stepped) {
          EXPECT_LT(tick_seen, 0) << "old load after the step";
        }
      }
    }
    EXPECT_EQ(scope.count(), 0u);
    ASSERT_GT(t_step, 0.0);
    EXPECT_EQ(tick_seen, static_cast<long>(std::ceil((t_step + d) / dt - 1e-6))) << "d = " << d;
    EXPECT_EQ(r.overruns(), 0);
  }
}

// In the runner the servo only ever sees frames at least `delay` old: the
// features' time (the frame's acquisition time) lags the row's time by >= d,
// and by at most d + one acquisition period + one feature period + one tick.
TEST(SensorEffects, TransferDelayInTheRunnerTimeSeries) {
  const double d = 0.0157;
  Scene sc;
  ASSERT_TRUE(loadRun(sim::test::shippedRun("edge_exploration.yaml"), sc,
                        {"duration=4", "effects.wts_transfer_delay_s=" + std::to_string(d)})
                  .ok());
  ASSERT_EQ(sc.sensor_effects.wts_transfer_delay_s, d);
  Runner runner;
  ASSERT_TRUE(runner.configure(sc).ok());
  RunResult res;
  runner.run(res);
  int seen = 0;
  double min_lag = 1e9, max_lag = 0.0;
  for (const auto& row : res.rows) {
    if (!(row.f.time_s > 0.0)) continue;  // no frame extracted yet
    const double lag = row.t - row.f.time_s;
    min_lag = std::min(min_lag, lag);
    max_lag = std::max(max_lag, lag);
    ++seen;
  }
  ASSERT_GT(seen, 100);
  EXPECT_GE(min_lag, d - 1e-9);
  EXPECT_LE(max_lag, d + 1.0 / 140 + 1.0 / 200 + 1e-3 + 1e-9);
  EXPECT_LT(min_lag, d + 1.0 / 140) << "not a whole acquisition period late";
}

// Creep: a load step; the reader's force tends to (1 + a) f with time
// constant tau. Fitted from the output: log(s_inf - s(t)) is linear in t with
// slope -1/tau. Tolerance 1 % (12-bit quantisation of the signal).
TEST(SensorEffects, CreepStepResponseTimeConstant) {
  for (double tau : {0.5, 2.0}) {
    TaxelResponseParams p = fileParams();
    p.effects.creep_fraction = 0.25;
    p.effects.creep_tau_s = tau;
    TaxelResponse r;
    ASSERT_TRUE(r.configure(p).ok());
    const double f = 1.6, dt = 1.0 / 140.0;
    RawTactileFrame raw;
    std::vector<double> ts, ys;
    ts.reserve(2000), ys.reserve(2000);
    tactile::test::AllocationScope scope;
    for (int k = 0; k < static_cast<int>(6.0 * tau / dt); ++k) {
      r.respond(k < 5 ? uniform(0.0) : uniform(f), k * dt, raw);
      if (k >= 5) {
        ts.push_back((k - 5) * dt);
        ys.push_back(readBack(r, kCentre, raw));
      }
    }
    EXPECT_EQ(scope.count(), 0u);
    EXPECT_NEAR(ys.front(), f, 2e-3) << "instantaneous value at the step";
    const double s_inf = (1.0 + 0.25) * f;
    EXPECT_NEAR(ys.back(), s_inf, 0.25 * f * std::exp(-5.9) + 3e-3);
    // Least squares on the first 3 tau (the distance to s_inf >= 5 % of the creep).
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int m = 0;
    for (std::size_t j = 0; j < ts.size() && ts[j] < 3.0 * tau; ++j) {
      const double y = std::log(s_inf - ys[j]);
      sx += ts[j], sy += y, sxx += ts[j] * ts[j], sxy += ts[j] * y, ++m;
    }
    const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
    EXPECT_NEAR(-1.0 / slope, tau, 0.01 * tau) << "measured time constant";
  }
}

// Hysteresis: a triangular load 0 -> F -> 0. Loading reads (1 - h) x, unloading
// (1 + h) x below (1 - h) F / (1 + h): the loop width at x = F / 2 is 2 h (F / 2).
TEST(SensorEffects, HysteresisLoopWidthOfATriangularLoad) {
  const double h = 0.08, F = 2.4;
  TaxelResponseParams p = fileParams();
  p.effects.hysteresis = h;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(p).ok());
  RawTactileFrame raw;
  const int N = 200;  // frames per ramp
  double up_half = NAN, down_half = NAN, top = NAN;
  for (int k = 0; k <= 2 * N; ++k) {
    const double x = F * (k <= N ? double(k) / N : double(2 * N - k) / N);
    r.respond(uniform(x), k * 0.01, raw);
    const double y = readBack(r, kCentre, raw);
    if (k == N / 2) up_half = y;
    if (k == N) top = y;
    if (k == 3 * N / 2) down_half = y;
  }
  const double q = 2e-3;  // quantisation (< 1 count ~ 0.5 mN near 1 N, incl. the cubic)
  EXPECT_NEAR(up_half, (1 - h) * F / 2, q);
  EXPECT_NEAR(top, (1 - h) * F, q) << "the top of the loading path";
  EXPECT_NEAR(down_half, (1 + h) * F / 2, q);
  EXPECT_NEAR(down_half - up_half, 2 * h * F / 2, 2 * q) << "loop width at F/2";
  // Back at zero load: zero.
  r.respond(uniform(0.0), 10.0, raw);
  EXPECT_EQ(raw.counts[kCentre], 0);
}

// Crosstalk: one loaded interior taxel gives c of its load to each of its four
// neighbours and keeps 1 - 4c; a corner keeps 1 - 2c. The total is conserved.
TEST(SensorEffects, CrosstalkSpreadsToTheFourNeighboursConservingTheTotal) {
  const double c = 0.1, F = 2.5;
  TaxelResponseParams p = fileParams();
  p.threshold = 0.0;
  p.effects.crosstalk = c;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(p).ok());
  TactileFrame f = uniform(0.0);
  f.force[kCentre] = F;
  f.force[0] = F;  // corner (0, 0)
  RawTactileFrame raw;
  r.respond(f, 0.0, raw);
  const double q = 1.5e-3;
  EXPECT_NEAR(readBack(r, kCentre, raw), (1 - 4 * c) * F, q);
  for (int nb : {kCentre - 1, kCentre + 1, kCentre - 14, kCentre + 14}) EXPECT_NEAR(readBack(r, nb, raw), c * F, q) << nb;
  EXPECT_NEAR(readBack(r, kCentre - 15, raw), 0.0, q) << "diagonal: nothing";
  EXPECT_NEAR(readBack(r, 0, raw), (1 - 2 * c) * F, q);
  EXPECT_NEAR(readBack(r, 1, raw), c * F, q);
  EXPECT_NEAR(readBack(r, 14, raw), c * F, q);
  double total = 0.0;
  for (int i = 0; i < 84; ++i) total += readBack(r, i, raw);
  EXPECT_NEAR(total, 2 * F, 12 * q);
}

// Gain spread and calibration error: seeded per-taxel draws with the set
// spread; the reader (the file's calibration) gets f / (1 + e_i) through
// counts g_i p^-1(.), so the sim no longer reads back its own input.
TEST(SensorEffects, GainSpreadAndCalibrationErrorAgainstTheDraws) {
  TaxelResponseParams p = fileParams();
  p.effects.gain_spread = 0.1;
  p.effects.calibration_error = 0.05;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(p).ok());
  double sg = 0, sgg = 0, se = 0, see = 0;
  for (int i = 0; i < 84; ++i) {
    sg += r.gain(i), sgg += r.gain(i) * r.gain(i);
    se += r.calibrationError(i), see += r.calibrationError(i) * r.calibrationError(i);
  }
  const double sd_g = std::sqrt(sgg / 84 - (sg / 84) * (sg / 84)), sd_e = std::sqrt(see / 84 - (se / 84) * (se / 84));
  EXPECT_NEAR(sd_g, 0.1, 0.03) << "84 draws: the sample sigma within ~3 standard errors";
  EXPECT_NEAR(sd_e, 0.05, 0.015);
  const double F = 1.2;
  RawTactileFrame raw;
  r.respond(uniform(F), 0.0, raw);
  int differ = 0;
  for (int i = 0; i < 84; ++i) {
    const double n_want = r.gain(i) * r.countsFor(i, F / (1.0 + r.calibrationError(i)));
    EXPECT_NEAR(raw.counts[static_cast<std::size_t>(i)], std::min(4095.0, std::round(n_want)), 0.5) << i;
    if (std::fabs(readBack(r, i, raw) - F) > 0.02) ++differ;
  }
  EXPECT_GT(differ, 42) << "the reader no longer inverts the sensor's response";
  // Gain alone, on counts: in the linear range the reader's ratio is ~g_i.
  TaxelResponseParams pg = fileParams();
  pg.effects.gain_spread = 0.1;
  TaxelResponse g;
  ASSERT_TRUE(g.configure(pg).ok());
  g.respond(uniform(0.6), 0.0, raw);  // ~1500 counts: the cubic term is ~10 % of the linear one
  const double n0 = g.countsFor(kCentre, 0.6);
  EXPECT_NEAR(raw.counts[kCentre], std::round(g.gain(kCentre) * n0), 0.5);
}

// Dead taxels: a seeded count of distinct positions, or a list; they read 0.
TEST(SensorEffects, DeadTaxelsReadZero) {
  TaxelResponseParams p = fileParams(6.0);
  p.effects.dead_taxels = 5;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(p).ok());
  int dead = 0;
  for (int i = 0; i < 84; ++i) dead += r.dead(i);
  EXPECT_EQ(dead, 5);
  RawTactileFrame raw;
  r.respond(uniform(1.0), 0.0, raw);
  for (int i = 0; i < 84; ++i) EXPECT_EQ(raw.counts[static_cast<std::size_t>(i)] == 0, r.dead(i)) << i;
  p.effects.dead_taxels = 0;
  p.effects.dead_list = {{2, 7}, {5, 13}};
  TaxelResponse l;
  ASSERT_TRUE(l.configure(p).ok());
  l.respond(uniform(1.0), 0.0, raw);
  EXPECT_EQ(raw.counts[kCentre], 0);
  EXPECT_EQ(raw.counts[5 * 14 + 13], 0);
  EXPECT_GT(raw.counts[kCentre + 1], 0);
}

// Device noise: threshold counts of the most sensitive taxel / z (App. A's
// 0.2 N threshold on wts0614.yaml's border polynomial: 298.5 counts / 4.68).
TEST(SensorEffects, DeviceNoiseLevel) {
  TaxelResponseParams p = fileParams(6.0);
  p.effects.device_noise = true;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(p).ok());
  double thr_min = 1e9;
  for (int i = 0; i < 84; ++i) thr_min = std::min(thr_min, r.countsFor(i, 0.2));
  EXPECT_NEAR(thr_min, 298.5, 0.5);
  EXPECT_NEAR(r.noiseCounts(), thr_min / kDeviceNoiseZ, 1e-9);
  EXPECT_NEAR(r.noiseCounts(), 63.8, 0.1);
  // The sample sigma of an interior taxel at 1 N.
  const double n0 = r.countsFor(kCentre, 1.0);
  double s = 0, ss = 0;
  const int N = 4000;
  RawTactileFrame raw;
  for (int k = 0; k < N; ++k) {
    r.respond(uniform(1.0), k * 0.007, raw);
    const double e = raw.counts[kCentre] - n0;
    s += e, ss += e * e;
  }
  EXPECT_NEAR(std::sqrt(ss / N - (s / N) * (s / N)), 63.8, 63.8 * 0.05);
}

// All effects on: same seed, same frames; another seed, other frames; no
// allocation per frame (acquire + deliver); reseed() restarts the sequence.
TEST(SensorEffects, DeterministicAndAllocationFree) {
  TaxelResponseParams p = fileParams(6.0);
  SensorEffects& e = p.effects;
  e.wts_transfer_delay_s = 0.0157;
  e.gain_spread = 0.1;
  e.dead_taxels = 3;
  e.calibration_error = 0.05;
  e.crosstalk = 0.05;
  e.creep_fraction = 0.1;
  e.hysteresis = 0.05;
  e.max_frame_rate_hz = 140.0;
  auto run = [&](TaxelResponse& r, std::vector<RawTactileFrame>& out) {
    RawTactileFrame raw;
    for (int tick = 0; tick < 2000; ++tick) {
      const double t = tick * 1e-3;
      if (tick % 7 == 0) r.acquire(uniform(1.0 + 0.8 * std::sin(3.0 * t)), t, raw);
      if (r.deliver(t, raw)) out.push_back(raw);
    }
  };
  TaxelResponse a, b, c;
  ASSERT_TRUE(a.configure(p).ok());
  ASSERT_TRUE(b.configure(p).ok());
  p.seed = 8;
  ASSERT_TRUE(c.configure(p).ok());
  std::vector<RawTactileFrame> fa, fb, fc, fa2;
  fa.reserve(400), fb.reserve(400), fc.reserve(400), fa2.reserve(400);
  {
    tactile::test::AllocationScope scope;
    run(a, fa);
    EXPECT_EQ(scope.count(), 0u);
  }
  run(b, fb);
  run(c, fc);
  a.reseed(7);
  run(a, fa2);
  ASSERT_EQ(fa.size(), fb.size());
  ASSERT_GT(fa.size(), 250u);
  bool other = false;
  for (std::size_t k = 0; k < fa.size(); ++k) {
    EXPECT_EQ(fa[k].counts, fb[k].counts) << k;
    EXPECT_EQ(fa[k].counts, fa2[k].counts) << k;
    EXPECT_EQ(fa[k].time_s, fb[k].time_s);
    if (k < fc.size() && fc[k].counts != fa[k].counts) other = true;
  }
  EXPECT_TRUE(other) << "another seed gives other frames";
}

// Scene keys: parsed into the response's parameters; errors name the file, the key and the range.
TEST(SensorEffects, SceneKeysAndRangeErrors) {
  const std::string f = kScenes + "edge_exploration.yaml";
  Scene sc;
  ASSERT_TRUE(loadScene(f, sc,
                        {"effects.wts_transfer_delay_s=0.0157", "effects.gain_spread=0.1", "effects.dead_taxels=[[1, 2]]",
                         "effects.calibration_error=0.05", "effects.crosstalk=0.05",
                         "effects.creep={fraction: 0.1, tau_s: 2}", "effects.hysteresis=0.05",
                         "effects.device_noise=true"})
                  .ok());
  const TaxelResponseParams rp = responseParams(sc);
  EXPECT_EQ(rp.effects.wts_transfer_delay_s, 0.0157);
  EXPECT_EQ(rp.effects.gain_spread, 0.1);
  ASSERT_EQ(rp.effects.dead_list.size(), 1u);
  EXPECT_EQ(rp.effects.dead_list[0][1], 2);
  EXPECT_EQ(rp.effects.calibration_error, 0.05);
  EXPECT_EQ(rp.effects.crosstalk, 0.05);
  EXPECT_EQ(rp.effects.creep_fraction, 0.1);
  EXPECT_EQ(rp.effects.creep_tau_s, 2.0);
  EXPECT_EQ(rp.effects.hysteresis, 0.05);
  EXPECT_TRUE(rp.effects.device_noise);
  ASSERT_TRUE(loadScene(f, sc).ok());
  EXPECT_FALSE(responseParams(sc).effects.any()) << "off by default";
  struct Bad {
    std::string set, key, range;
  };
  for (const Bad& b : {Bad{"effects.wts_transfer_delay_s=2", "effects.wts_transfer_delay_s", "[0, 1]"},
                       Bad{"effects.gain_spread=-0.1", "effects.gain_spread", "[0, 0.5]"},
                       Bad{"effects.dead_taxels=85", "effects.dead_taxels", "[0, 84]"},
                       Bad{"effects.dead_taxels=[[6, 0]]", "effects.dead_taxels[0]", "row in [0, 5]"},
                       Bad{"effects.calibration_error=0.6", "effects.calibration_error", "[0, 0.5]"},
                       Bad{"effects.crosstalk=0.3", "effects.crosstalk", "[0, 0.25]"},
                       Bad{"effects.creep={fraction: 2}", "effects.creep.fraction", "[0, 1]"},
                       Bad{"effects.creep={fraction: 0.1, tau_s: 0}", "effects.creep.tau_s", "(0, 1000]"},
                       Bad{"effects.hysteresis=0.7", "effects.hysteresis", "[0, 0.5]"},
                       Bad{"effects.creep_tau=1", "creep_tau", ""}}) {
    const ConfigResult r = loadScene(f, sc, {b.set});
    ASSERT_FALSE(r.ok()) << b.set;
    EXPECT_NE(r.message().find(f), std::string::npos) << r.message();
    EXPECT_NE(r.message().find(b.key), std::string::npos) << r.message();
    EXPECT_NE(r.message().find(b.range), std::string::npos) << r.message();
  }
}
