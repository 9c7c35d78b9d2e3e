// The simulated pad's fault schedule (tactile::sim::SensorFaultSchedule
// through tactile::sim::TaxelResponse, tactile_sim_faults/sensor_faults.hpp): each
// fault's effect on the frames at known times against counts computed here
// (noise off: the response is the calibration's exact inverse, rounded), the
// stream's faults on the frames that reach the reader, configuration errors
// naming the key and the range, no allocation per acquisition, and nothing
// changed before a fault starts.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {

constexpr int kRows = 6, kCols = 14, kN = kRows * kCols;
constexpr double kRate = 140.0;  // Hz, the WTS's

// The pad's default response (pad_sensor.hpp): f(n) = 4e-4 n + 2e-11 n^3 on every taxel; noise off.
TaxelResponseParams params(std::vector<FaultSpec> faults, double noise = 0.0) {
  TaxelResponseParams p;
  p.calibration.rows = kRows;
  p.calibration.cols = kCols;
  p.calibration.coeffs = {0.0, 4.0e-4, 0.0, 2.0e-11};
  p.noise_counts = noise;
  p.threshold = 0.2;
  p.seed = 3;
  p.faults = std::move(faults);
  return p;
}

// A load that changes with time (so that a repeated frame differs from a new
// one): 0.6 + 0.1 sin(t) N on row 2, 0 elsewhere.
TactileFrame load(double t) {
  TactileFrame f;
  f.rows = kRows;
  f.cols = kCols;
  for (int c = 0; c < kCols; ++c) f.force[static_cast<std::size_t>(2 * kCols + c)] = 0.6 + 0.1 * std::sin(3.0 * t);
  return f;
}

// Counts of force f on taxel i without a fault (noise off): round(p^-1(f)), 0 below the threshold.
uint16_t expected(const TaxelResponse& r, int i, double f) {
  const double n = std::round(r.countsFor(i, f));
  return n < r.thresholdCounts(i) ? 0 : static_cast<uint16_t>(std::min(n, 4095.0));
}

FaultSpec spec(SensorFault k, double start, double duration = 0.0) {
  FaultSpec f;
  f.kind = k;
  f.start_s = start;
  f.duration_s = duration;
  return f;
}

struct Frame {
  double t;
  bool delivered;
  RawTactileFrame raw;
};

// Acquisitions at 140 Hz for `seconds` from t = 0 (the load of load()).
std::vector<Frame> run(TaxelResponse& r, double seconds) {
  std::vector<Frame> out;
  for (int k = 0; k < static_cast<int>(seconds * kRate); ++k) {
    const double t = k / kRate;
    Frame f{t, false, RawTactileFrame()};
    f.delivered = r.acquire(load(t), t, f.raw);
    out.push_back(f);
  }
  return out;
}

bool inRegion(int i, int r0, int r1, int c0, int c1) {
  const int r = i / kCols, c = i % kCols;
  return r >= r0 && r <= r1 && c >= c0 && c <= c1;
}

}  // namespace

// A fault that has not started changes nothing: the same frames, bit for bit,
// as without a schedule (the noise stream included).
TEST(SensorFaults, NothingChangesBeforeAFaultStarts) {
  TaxelResponse plain, faulty;
  ASSERT_TRUE(plain.configure(params({}, 6.0)).ok());
  FaultSpec stuck = spec(SensorFault::Stuck, 5.0);
  stuck.counts = 3000;
  ASSERT_TRUE(faulty.configure(params({stuck, spec(SensorFault::Repeat, 5.0, 1.0), spec(SensorFault::TareCreep, 5.0),
                                       spec(SensorFault::Calibration, 5.0)},
                                      6.0))
                  .ok());
  EXPECT_TRUE(faulty.faults().any());
  EXPECT_FALSE(plain.faults().any());
  const std::vector<Frame> a = run(plain, 2.0), b = run(faulty, 2.0);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(a[k].delivered && b[k].delivered);
    EXPECT_EQ(a[k].raw.counts, b[k].raw.counts) << "t " << a[k].t;
  }
  EXPECT_FALSE(faulty.faults().fired());
}

// stuck: the region reads its counts from start_s on, no noise, the rest unchanged;
// force_n: spread evenly, the reader's calibration maps each taxel back to force_n / taxels.
TEST(SensorFaults, StuckRegionInCountsAndInNewtons) {
  FaultSpec c = spec(SensorFault::Stuck, 1.0);
  c.row0 = 1, c.row1 = 2, c.col0 = 3, c.col1 = 5, c.counts = 2000;
  FaultSpec n = spec(SensorFault::Stuck, 0.0);
  n.row0 = 1, n.row1 = 4, n.col0 = 5, n.col1 = 8, n.force_n = 8.0;  // the phantom press: 16 taxels, 0.5 N each
  TaxelResponse r, rn;
  ASSERT_TRUE(r.configure(params({c})).ok());
  ASSERT_TRUE(rn.configure(params({n})).ok());
  for (const Frame& f : run(r, 2.0)) {
    for (int i = 0; i < kN; ++i) {
      const bool stuck = f.t >= 1.0 && inRegion(i, 1, 2, 3, 5);
      const uint16_t want = stuck ? 2000 : expected(r, i, load(f.t).force[static_cast<std::size_t>(i)]);
      ASSERT_EQ(f.raw.counts[static_cast<std::size_t>(i)], want) << "t " << f.t << " taxel " << i;
    }
  }
  for (const Frame& f : run(rn, 0.5)) {
    double total = 0.0;
    for (int i = 0; i < kN; ++i) {
      const uint16_t v = f.raw.counts[static_cast<std::size_t>(i)];
      if (inRegion(i, 1, 4, 5, 8)) {
        EXPECT_NEAR(rn.forceFor(i, v), 0.5, 4e-4) << "one count of 0.5 N's";
        total += rn.forceFor(i, v);
      } else if (i / kCols != 2) {
        EXPECT_EQ(v, 0);
      }
    }
    EXPECT_NEAR(total, 8.0, 16 * 4e-4);
  }
  EXPECT_TRUE(rn.faults().fired());
}

// dead: the region (a column band) reads 0 from start_s, the rest of row 2 still reads.
TEST(SensorFaults, DeadColumnBandFromItsStart) {
  FaultSpec d = spec(SensorFault::Dead, 1.0);
  d.col0 = 0, d.col1 = 4;  // rows: the whole pad
  TaxelResponse r;
  ASSERT_TRUE(r.configure(params({d})).ok());
  for (const Frame& f : run(r, 2.0))
    for (int c = 0; c < kCols; ++c) {
      const int i = 2 * kCols + c;
      const uint16_t want = f.t >= 1.0 && c <= 4 ? 0 : expected(r, i, load(f.t).force[static_cast<std::size_t>(i)]);
      ASSERT_EQ(f.raw.counts[static_cast<std::size_t>(i)], want) << "t " << f.t << " col " << c;
    }
}

// tare_creep: counts + rate (t - start) / 60 before the threshold, so an
// unloaded taxel fires once its zero passes the threshold; a duration ends it.
TEST(SensorFaults, TareCreepDriftsEveryZero) {
  FaultSpec tc = spec(SensorFault::TareCreep, 1.0, 10.0);
  tc.counts_per_min = 3000.0;  // 50 counts/s: an unloaded taxel reaches the ~494-count threshold after ~9.9 s
  TaxelResponse r;
  ASSERT_TRUE(r.configure(params({tc})).ok());
  const int loaded = 2 * kCols + 6, unloaded = 4 * kCols + 6;
  const double thr = r.thresholdCounts(unloaded);
  int fired_at = -1;
  for (const Frame& f : run(r, 12.0)) {
    const double off = f.t >= 1.0 && f.t < 11.0 ? 50.0 * (f.t - 1.0) : 0.0;
    const double want_loaded = std::round(r.countsFor(loaded, load(f.t).force[static_cast<std::size_t>(loaded)]) + off);
    ASSERT_EQ(f.raw.counts[static_cast<std::size_t>(loaded)], static_cast<uint16_t>(want_loaded)) << "t " << f.t;
    const double u = std::round(off);
    ASSERT_EQ(f.raw.counts[static_cast<std::size_t>(unloaded)], u < thr ? 0 : static_cast<uint16_t>(u)) << "t " << f.t;
    if (fired_at < 0 && f.raw.counts[static_cast<std::size_t>(unloaded)] > 0) fired_at = static_cast<int>(f.t * kRate);
  }
  EXPECT_NEAR(fired_at / kRate, 1.0 + thr / 50.0, 2.0 / kRate) << "the unloaded taxel fires when the drift passes its threshold";
}

// calibration: the reader's force = scale x the true force from start_s (0.5x and 2x).
TEST(SensorFaults, CalibrationScaleHalfAndDouble) {
  for (double scale : {0.5, 2.0}) {
    FaultSpec cf = spec(SensorFault::Calibration, 1.0);
    cf.scale = scale;
    TaxelResponse r;
    ASSERT_TRUE(r.configure(params({cf})).ok());
    for (const Frame& f : run(r, 2.0)) {
      const int i = 2 * kCols + 7;
      const double truth = load(f.t).force[static_cast<std::size_t>(i)];
      const double k = f.t >= 1.0 ? scale : 1.0;
      ASSERT_EQ(f.raw.counts[static_cast<std::size_t>(i)], expected(r, i, k * truth)) << "scale " << scale << " t " << f.t;
      EXPECT_NEAR(r.forceFor(i, f.raw.counts[static_cast<std::size_t>(i)]), k * truth, 1e-3);
    }
  }
}

// saturated: exactly one frame, the first at or after start_s, at full scale.
TEST(SensorFaults, SaturatedIsOneFrame) {
  TaxelResponse r;
  ASSERT_TRUE(r.configure(params({spec(SensorFault::Saturated, 1.0)})).ok());
  int full = 0;
  for (const Frame& f : run(r, 2.0)) {
    bool all = true;
    for (int i = 0; i < kN; ++i) all = all && f.raw.counts[static_cast<std::size_t>(i)] == 4095;
    EXPECT_EQ(all, f.t >= 1.0 && f.t < 1.0 + 1.0 / kRate) << "t " << f.t;
    full += all ? 1 : 0;
  }
  EXPECT_EQ(full, 1);
  EXPECT_EQ(r.faults().shots(), 1);
}

// stale: nothing reaches the reader in the window (the caller's frame is left
// as it was); disconnect: the same with the link named as the reader names it.
TEST(SensorFaults, StaleAndDisconnectWithholdTheWindow) {
  TaxelResponse s, d;
  ASSERT_TRUE(s.configure(params({spec(SensorFault::Stale, 1.0, 0.1)})).ok());
  ASSERT_TRUE(d.configure(params({spec(SensorFault::Disconnect, 1.0, 0.5)})).ok());
  RawTactileFrame raw;
  raw.seq = 777;
  int withheld = 0;
  for (int k = 0; k < 280; ++k) {
    const double t = k / kRate;
    const RawTactileFrame before = raw;
    const bool got = s.acquire(load(t), t, raw);
    EXPECT_EQ(got, !(t >= 1.0 && t < 1.1)) << "t " << t;
    if (!got) {
      ++withheld;
      EXPECT_EQ(raw.counts, before.counts);
      EXPECT_EQ(raw.time_s, before.time_s);
    }
    RawTactileFrame rd;
    const bool gd = d.acquire(load(t), t, rd);
    const SensorLink l = d.faults().link();
    if (t >= 1.0 && t < 1.5) {
      EXPECT_FALSE(gd);
      EXPECT_EQ(l, SensorLink::Disconnected) << "t " << t;
      EXPECT_TRUE(d.faults().linkDown(t));
    } else if (t >= 1.5 && t < 1.5 + 1.0 / kRate) {
      EXPECT_TRUE(gd);
      EXPECT_EQ(l, SensorLink::Reconnected) << "the first frame after, t " << t;
    } else {
      EXPECT_TRUE(gd);
      EXPECT_EQ(l, SensorLink::NewFrame) << "t " << t;
    }
  }
  EXPECT_EQ(withheld, 14);  // 0.1 s at 140 Hz
  EXPECT_TRUE(s.faults().stalled(1.05));
  EXPECT_FALSE(s.faults().stalled(1.1));
}

// repeat: in the window every frame carries the counts of the last frame
// delivered before it (new time stamps); after it, new content again.
TEST(SensorFaults, RepeatResendsTheLastFrame) {
  TaxelResponse r, plain;
  ASSERT_TRUE(r.configure(params({spec(SensorFault::Repeat, 1.0, 0.5)})).ok());
  ASSERT_TRUE(plain.configure(params({})).ok());
  const std::vector<Frame> a = run(plain, 2.0), b = run(r, 2.0);
  const int last_before = static_cast<int>(std::ceil(1.0 * kRate)) - 1;  // the last acquisition before 1.0 s
  int repeated = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(b[k].delivered);
    EXPECT_EQ(b[k].raw.time_s, a[k].t) << "a new time stamp";
    const bool in = a[k].t >= 1.0 && a[k].t < 1.5;
    EXPECT_EQ(b[k].raw.counts, in ? a[static_cast<std::size_t>(last_before)].raw.counts : a[k].raw.counts) << "t " << a[k].t;
    if (in) EXPECT_NE(a[k].raw.counts, a[static_cast<std::size_t>(last_before)].raw.counts) << "the load moved, t " << a[k].t;
    repeated += in ? 1 : 0;
  }
  EXPECT_EQ(repeated, 70);
}

// With a transfer delay the stream's faults act on the frames as they reach
// the reader, by their acquisition time.
TEST(SensorFaults, StreamFaultsThroughTheTransferDelay) {
  TaxelResponseParams p = params({spec(SensorFault::Stale, 1.0, 0.1)});
  p.effects.wts_transfer_delay_s = 0.0157;
  p.effects.max_frame_rate_hz = kRate;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(p).ok());
  int arrived = 0, in_window = 0;
  RawTactileFrame raw;
  for (int tick = 0; tick < 2000; ++tick) {  // 1 kHz ticks, an acquisition every 7 (~143 Hz)
    const double now = tick * 1e-3;
    if (tick % 7 == 0) EXPECT_FALSE(r.acquire(load(now), now, raw)) << "queued";
    if (r.deliver(now, raw)) {
      ++arrived;
      EXPECT_GE(now - raw.time_s, 0.0157 - 1e-9);
      if (raw.time_s >= 1.0 && raw.time_s < 1.1) ++in_window;
    }
  }
  EXPECT_EQ(in_window, 0);
  EXPECT_GT(arrived, 250);
}

// The one-fault form of the RTT sensor's properties, and the scene list's
// ranges: each error names the key, the value and the valid range.
TEST(SensorFaults, ConfigurationErrorsNameTheKeyAndTheRange) {
  SensorFaultSchedule s;
  EXPECT_TRUE(s.configure("", 0.0, 0.0).ok());
  EXPECT_FALSE(s.any());
  EXPECT_NE(s.configure("stuck", 1.0, 0.1).message().find("fault = 'stuck'"), std::string::npos);
  EXPECT_NE(s.configure("stale", -1.0, 0.1).message().find("fault_start"), std::string::npos);
  EXPECT_NE(s.configure("disconnect", 1.0, 61.0).message().find("(0, 60]"), std::string::npos);
  struct Case {
    FaultSpec f;
    const char* text;
  };
  auto with = [](SensorFault k, auto edit) {
    FaultSpec f = spec(k, 1.0);
    edit(f);
    return f;
  };
  const std::vector<Case> cases = {
      {with(SensorFault::None, [](FaultSpec&) {}), "faults[1].kind: required"},
      {with(SensorFault::Stale, [](FaultSpec& f) { f.start_s = -0.5; }), "faults[1].start_s = -0.5: must be >= 0 s"},
      {with(SensorFault::Repeat, [](FaultSpec&) {}), "faults[1].duration_s = 0: must be in (0, 60] s"},
      {with(SensorFault::Stuck, [](FaultSpec&) {}), "faults[1].counts / force_n: give exactly one"},
      {with(SensorFault::Stuck, [](FaultSpec& f) { f.counts = 5000; }), "faults[1].counts = 5000: must be in [0, 4095]"},
      {with(SensorFault::Stuck, [](FaultSpec& f) { f.force_n = 2000; }), "faults[1].force_n = 2000: must be in [0, 1000] N"},
      {with(SensorFault::Dead, [](FaultSpec& f) { f.row0 = 2, f.row1 = 9; }),
       "faults[1].rows = [2, 9]: must be [first, last] within [0, 5]"},
      {with(SensorFault::Dead, [](FaultSpec& f) { f.col0 = 5, f.col1 = 3; }), "faults[1].cols = [5, 3]"},
      {with(SensorFault::TareCreep, [](FaultSpec& f) { f.counts_per_min = 5000; }), "counts_per_min = 5000: must be in [-4095, 4095]"},
      {with(SensorFault::Calibration, [](FaultSpec& f) { f.scale = 0.0; }), "faults[1].scale = 0: must be in [0.1, 10]"},
      {with(SensorFault::WrenchBias, [](FaultSpec& f) { f.bias_n[2] = 200; }), "faults[1].bias_n.z = 200: must be in [-100, 100] N"},
      {with(SensorFault::WrenchDrift, [](FaultSpec& f) { f.drift_n_per_min[0] = -101; }), "drift_n_per_min.x = -101"},
      {with(SensorFault::WrenchFrame, [](FaultSpec& f) { f.axes = WrenchAxes::Base; }), "faults[1].axes = base"},
      {with(SensorFault::PadMass, [](FaultSpec& f) { f.mass_kg = 6; }), "faults[1].mass_kg = 6: must be in [-5, 5] kg"},
  };
  for (const Case& c : cases) {
    const ConfigResult r = s.configure({spec(SensorFault::Saturated, 0.0), c.f});
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.message().find(c.text), std::string::npos) << r.message();
    EXPECT_FALSE(s.any()) << "a failed configure leaves no fault";
  }
  std::vector<FaultSpec> nine(9, spec(SensorFault::Saturated, 0.0));
  EXPECT_NE(s.configure(nine).message().find("at most 8"), std::string::npos);
  // Through TaxelResponse: the same message.
  TaxelResponse r;
  const ConfigResult rr = r.configure(params({with(SensorFault::Dead, [](FaultSpec& f) { f.col1 = 14; })}));
  EXPECT_NE(rr.message().find("faults[0].cols = [0, 14]"), std::string::npos) << rr.message();
}

// No allocation per acquisition with every pad fault configured (and active).
TEST(SensorFaults, AcquireWithFaultsDoesNotAllocate) {
  FaultSpec st = spec(SensorFault::Stuck, 0.1);
  st.force_n = 8.0;
  st.row0 = 1, st.row1 = 4, st.col0 = 5, st.col1 = 8;
  FaultSpec dead = spec(SensorFault::Dead, 0.2);
  dead.col1 = 2;
  FaultSpec tc = spec(SensorFault::TareCreep, 0.1);
  tc.counts_per_min = 600;
  FaultSpec cal = spec(SensorFault::Calibration, 0.1);
  cal.scale = 2.0;
  TaxelResponse r;
  ASSERT_TRUE(r.configure(params({st, dead, tc, cal, spec(SensorFault::Saturated, 0.3),
                                  spec(SensorFault::Repeat, 0.4, 0.2), spec(SensorFault::Disconnect, 0.7, 0.1),
                                  spec(SensorFault::Stale, 0.9, 0.1)},
                                 6.0))
                  .ok());
  RawTactileFrame raw;
  std::vector<TactileFrame> loads;
  for (int k = 0; k < 200; ++k) loads.push_back(load(k / kRate));
  test::AllocationScope scope;
  int delivered = 0;
  for (int k = 0; k < 200; ++k) delivered += r.acquire(loads[static_cast<std::size_t>(k)], k / kRate, raw) ? 1 : 0;
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(delivered, 200 - 28);  // the disconnect's and the stale's 0.1 s each
  EXPECT_TRUE(r.faults().fired());
}

// Reseeding arms the one-shot faults again: a second run is the first's.
TEST(SensorFaults, ReseedArmsTheScheduleAgain) {
  TaxelResponse r;
  ASSERT_TRUE(r.configure(params({spec(SensorFault::Saturated, 0.5), spec(SensorFault::Repeat, 0.2, 0.2)}, 6.0)).ok());
  const std::vector<Frame> a = run(r, 1.0);
  r.reseed(3);
  const std::vector<Frame> b = run(r, 1.0);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].raw.counts, b[k].raw.counts) << "t " << a[k].t;
  EXPECT_EQ(r.faults().shots(), 1);
}
