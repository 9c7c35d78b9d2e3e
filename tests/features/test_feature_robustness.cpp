// Features that must not pass silently: separate contacts, an edge angle
// inside its own noise, out-of-range and denormal values, extreme tares, and
// the force of a line load whose taxels the noise switches off (extractor.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_features/sensor_stage.hpp"

using namespace tactile;

namespace {

TactileFrame blank() {
  TactileFrame f;
  f.force.fill(0.0);
  return f;
}

FeatureExtractor configured(const FeatureParams& p = {}) {
  FeatureExtractor ex;
  const ConfigResult r = ex.configure(p);
  EXPECT_TRUE(r.ok()) << r.message();
  return ex;
}

void fill(TactileFrame& f, int r0, int r1, int c0, int c1, double v) {
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) f.at(r, c) = v;
}

void expectFiniteAndZero(const ContactFeatures& f) {
  for (double v : {f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.dzmp_x, f.dzmp_y, f.alpha_z, f.force, f.d_z, f.lambda1,
                   f.lambda2, f.max_taxel})
    EXPECT_EQ(v, 0.0);
  EXPECT_EQ(f.contact, ContactType::None);
  EXPECT_FALSE(f.alpha_defined);
}

// Linear test calibration: 0.4 mN per count (the WTS0614's slope at low load).
constexpr double kNPerCount = 0.0004;

CalibrationParams linearCalibration(double noise_counts = 0.0) {
  CalibrationParams c;
  c.coeffs = {0.0, kNPerCount, 0.0, 0.0};
  c.noise_counts = noise_counts;
  return c;
}

// The device's electronics as in core/sim/lwr TaxelResponse: counts of `force`
// plus Gaussian noise, rounded, 0 below the firing threshold's count.
void acquire(const TactileFrame& truth, double noise_counts, double threshold, std::mt19937_64& rng,
             RawTactileFrame& raw) {
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < truth.size(); ++i) {
    const double f = truth.force[static_cast<std::size_t>(i)];
    double n = f > 0.0 ? std::round(f / kNPerCount + noise_counts * n01(rng)) : 0.0;
    if (n < threshold / kNPerCount) n = 0.0;
    raw.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(std::min(4095.0, n));
  }
}

}  // namespace

// ---------------------------------------------------------------- separate contacts

TEST(FeatureRegions, TwoSeparateContactsAreMultipleNotOneLongEdge) {
  FeatureExtractor ex = configured();
  ContactFeatures out;
  // An edge at a known angle first: the angle the multiple contact must hold.
  TactileFrame line = blank();
  for (int c = 1; c <= 12; ++c) line.at(c < 7 ? 2 : 3, c) = 0.5;  // slightly tilted line
  ASSERT_EQ(ex.step(line, out), FeatureStatus::Ok);
  ASSERT_EQ(out.contact, ContactType::Edge);
  ASSERT_TRUE(out.alpha_defined);
  const double alpha_edge = out.alpha_z;

  // Two 2x2 blobs, 2 N each, 8 taxels apart: one-region moments would call
  // this a 40 mm edge (lambda2 = 0 along the line).
  TactileFrame two = blank();
  fill(two, 2, 3, 1, 2, 0.5);
  fill(two, 2, 3, 11, 12, 0.5);
  EXPECT_EQ(ex.step(two, out), FeatureStatus::Ok);
  EXPECT_EQ(out.contact, ContactType::Multiple);
  EXPECT_EQ(ex.lastRegionCount(), 2);
  EXPECT_FALSE(out.alpha_defined);
  EXPECT_EQ(out.alpha_z, alpha_edge);  // held, not the angle of the line between them
  EXPECT_NEAR(out.force, 4.0, 1e-12);   // f is still the total force (Eq. 2)
  EXPECT_GT(out.lambda1, 20.0 * out.lambda2);  // what made it an "edge" before

  // Two silent columns between them: still two contacts.
  TactileFrame near2 = blank();
  fill(near2, 2, 3, 3, 5, 0.5);
  fill(near2, 2, 3, 8, 10, 0.5);
  ex.step(near2, out);
  EXPECT_EQ(out.contact, ContactType::Multiple);

  // One continuous line of the same extent is one edge; a one-column dropout
  // (noise) does not split it (region_gap = 1).
  TactileFrame full = blank();
  fill(full, 2, 3, 1, 12, 0.5);
  ex.reset();
  ex.step(full, out);
  EXPECT_EQ(out.contact, ContactType::Edge);
  full.at(2, 6) = full.at(3, 6) = 0.0;
  ex.step(full, out);
  EXPECT_EQ(out.contact, ContactType::Edge);
  EXPECT_EQ(ex.lastRegionCount(), 1);

  // A single weak taxel far away (< region_min_force) is not a second contact.
  TactileFrame spur = blank();
  fill(spur, 2, 3, 1, 6, 0.5);
  spur.at(0, 13) = 0.3;
  ex.reset();
  ex.step(spur, out);
  EXPECT_NE(out.contact, ContactType::Multiple);
  EXPECT_EQ(ex.lastRegionCount(), 1);
}

TEST(FeatureRegions, AGapSplitsTheLineOnceSilentForTauLnOneOverRegionMinRate) {
  // A line load slides onto a gap (two collinear bars, docs/simulator.md, "A gap under the pad"):
  // three columns fall silent at t_off. A silent taxel keeps joining regions
  // while its firing rate p = exp(-(t - t_off) / censor_tau) (t_off: the
  // last frame they fired) is at least
  // region_min_rate, so the line splits into two contacts exactly when
  // t - t_off first reaches censor_tau ln(1 / region_min_rate) (0.391 s at
  // 0.1 s and 0.02), to one frame (5 ms); a shorter silence (a dropout,
  // a sag of the load near the threshold) does not split it. Exact: the
  // rate recursion is exp(-dt/tau) per frame, so the first multiple frame
  // is the first k with exp(-k dt / tau) < region_min_rate.
  for (double rate : {0.02, 0.1}) {
    FeatureParams p;
    p.taxel_noise = 0.012;  // the rates run only with a noise model
    p.region_min_rate = rate;
    FeatureExtractor ex = configured(p);
    TactileFrame line = blank();
    fill(line, 2, 3, 0, 13, 0.3);
    ContactFeatures out;
    const double dt = 0.005;
    double t = 0.0;
    for (int k = 0; k < 200; ++k, t += dt) {  // 1 s: every rate -> 1
      line.time_s = t;
      ex.step(line, out);
    }
    ASSERT_EQ(out.contact, ContactType::Edge);
    TactileFrame gap = line;
    fill(gap, 2, 3, 6, 8, 0.0);
    const double t_off = t - dt;  // the last frame the columns fired
    double first_multiple = -1.0;
    for (int k = 0; k < 200; ++k, t += dt) {
      gap.time_s = t;
      ex.step(gap, out);
      if (out.contact == ContactType::Multiple && first_multiple < 0.0) first_multiple = t - t_off;
      if (first_multiple < 0.0) {
        EXPECT_EQ(out.contact, ContactType::Edge) << "t - t_off " << t - t_off;
      }
    }
    const double expected = p.censor_tau * std::log(1.0 / rate);
    EXPECT_GE(first_multiple, expected - 1e-9) << "rate " << rate;
    EXPECT_LT(first_multiple, expected + dt + 1e-9) << "rate " << rate;
    EXPECT_EQ(out.contact, ContactType::Multiple);
    EXPECT_EQ(ex.lastRegionCount(), 2);
  }
  // Out of range: a configuration error naming the key.
  FeatureParams bad;
  bad.region_min_rate = 0.0;
  FeatureExtractor ex;
  const ConfigResult r = ex.configure(bad);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("region_min_rate"), std::string::npos) << r.message();
}

// ---------------------------------------------------------------- alpha_z within the noise

TEST(FeatureAlphaNoise, IsotropicContactUnderNoiseIsUndefinedAndHeldNotJumping) {
  // A round 3x3 blob (lambda1 = lambda2 without noise) read through 6-count
  // noise: the PCA angle of each frame is the angle of the noise.
  FeatureParams p;
  p.taxel_noise = 6.0 * kNPerCount;  // 6 counts through the slope
  FeatureParams p_off = p;
  p_off.alpha_max_sigma = 1e6;  // "always defined": today's behaviour before the test existed
  FeatureExtractor ex = configured(p), raw_pca = configured(p_off);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, p.taxel_noise);
  double held = NAN, min_raw = 1e9, max_raw = -1e9;
  int defined = 0;
  for (int k = 0; k < 200; ++k) {
    TactileFrame f = blank();
    for (int r = 1; r <= 3; ++r)
      for (int c = 5; c <= 7; ++c) f.at(r, c) = 0.6 + noise(rng);
    f.time_s = 0.007 * k;
    ContactFeatures out, ref;
    ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
    raw_pca.step(f, ref);
    EXPECT_EQ(out.contact, ContactType::Point);
    defined += out.alpha_defined;
    if (k == 0) held = out.alpha_z;
    EXPECT_EQ(out.alpha_z, held) << "frame " << k;  // no frame-to-frame jump
    EXPECT_GT(ex.lastAlphaSigma(), p.alpha_max_sigma);
    min_raw = std::min(min_raw, ref.alpha_z);
    max_raw = std::max(max_raw, ref.alpha_z);
  }
  EXPECT_EQ(defined, 0);
  EXPECT_GT(max_raw - min_raw, 1.0) << "without the noise test the angle jumps over the whole range";
}

TEST(FeatureAlphaNoise, PropagatedSigmaMatchesTheScatterOfTheAngle) {
  // The threshold rests on sigma_alpha (extractor.hpp, Eq. B.4/B.5 to first
  // order). A mildly elongated blob, many noisy frames: the predicted sigma
  // must match the empirical scatter of alpha_z.
  FeatureParams p;
  p.taxel_noise = 0.01;
  p.alpha_max_sigma = 10.0;  // always defined: measure the scatter
  p.alpha_hysteresis = 0.0;
  FeatureExtractor ex = configured(p);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, p.taxel_noise);
  TactileFrame base = blank();
  fill(base, 1, 3, 4, 8, 0.5);  // 3 x 5 taxels: lambda1 > lambda2
  ContactFeatures out;
  ex.step(base, out);
  const double sigma_pred = ex.lastAlphaSigma();
  ASSERT_GT(sigma_pred, 0.0);
  double s = 0.0, s2 = 0.0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    TactileFrame f = base;
    for (int r = 1; r <= 3; ++r)
      for (int c = 4; c <= 8; ++c) f.at(r, c) += noise(rng);
    ex.step(f, out);
    ASSERT_TRUE(out.alpha_defined);
    s += out.alpha_z;
    s2 += out.alpha_z * out.alpha_z;
  }
  const double sd = std::sqrt(s2 / n - (s / n) * (s / n));
  EXPECT_NEAR(sd / sigma_pred, 1.0, 0.1) << "empirical " << sd << " rad, predicted " << sigma_pred << " rad";
}

TEST(FeatureAlphaNoise, SensorStageDerivesTheNoiseFromCountsThroughTheCalibration) {
  // 6 counts on the WTS0614 polynomial [0, 4e-4, 0, 2e-11] at the 0.2 N
  // threshold (n = 496.8 counts): slope 4e-4 + 3 * 2e-11 * n^2 = 4.148e-4 N/count.
  CalibrationParams c;
  c.coeffs = {0.0, 0.0004, 0.0, 2.0e-11};
  c.noise_counts = 6.0;
  FeatureParams fp;
  SensorStage st;
  ASSERT_TRUE(st.configure(fp, c).ok());
  double n = 0.2 / 0.0004;
  for (int i = 0; i < 50; ++i) n -= (0.0004 * n + 2e-11 * n * n * n - 0.2) / (0.0004 + 6e-11 * n * n);
  EXPECT_NEAR(st.extractor().params().taxel_noise, 6.0 * (0.0004 + 6e-11 * n * n), 1e-9);
  c.noise_counts = 0.0;
  ASSERT_TRUE(st.configure(fp, c).ok());
  EXPECT_EQ(st.extractor().params().taxel_noise, 0.0);
}

TEST(FeatureAlphaNoise, ACleanEdgeStaysDefinedUnderTheSameNoise) {
  FeatureParams p;
  p.taxel_noise = 6.0 * kNPerCount;
  FeatureExtractor ex = configured(p);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, p.taxel_noise);
  for (int k = 0; k < 200; ++k) {
    TactileFrame f = blank();
    for (int c = 1; c <= 12; ++c) f.at(2, c) = f.at(3, c) = 0.25 + noise(rng);
    ContactFeatures out;
    ex.step(f, out);
    ASSERT_EQ(out.contact, ContactType::Edge);
    EXPECT_TRUE(out.alpha_defined);
    EXPECT_LT(std::fabs(out.alpha_z), 0.05);
  }
}

// ---------------------------------------------------------------- extreme values

TEST(FeatureExtremeValues, HugeFiniteValuesAreOutOfRangeAndKeepTheHistory) {
  FeatureExtractor ex = configured();
  ContactFeatures out;
  TactileFrame edge = blank();
  for (int c = 1; c <= 12; ++c) edge.at(2, c) = edge.at(3, c) = 0.5;
  ex.step(edge, out);
  ASSERT_EQ(out.contact, ContactType::Edge);
  for (double huge : {1e200, std::numeric_limits<double>::max(), 1.0e3 + 1.0, -1e300}) {
    TactileFrame f = edge;
    f.at(4, 4) = huge;
    f.at(5, 5) = huge;  // two of them: their sum overflows, still out of range (not NaN/Inf input)
    EXPECT_EQ(ex.step(f, out), FeatureStatus::OutOfRange) << huge;
    EXPECT_FALSE(usable(out.status));
    expectFiniteAndZero(out);
  }
  // The history (contact type, alpha) survived: the next good frame is the same edge.
  ex.step(edge, out);
  EXPECT_EQ(out.contact, ContactType::Edge);
  EXPECT_EQ(out.status, FeatureStatus::Ok);
}

TEST(FeatureExtremeValues, DenormalsAreZeroAndGiveNoJump) {
  FeatureParams p;
  p.contact_threshold = 0.0;  // the harshest case: any positive value would be a contact
  p.threshold = 0.0;
  FeatureExtractor ex = configured(p);
  ContactFeatures out;
  TactileFrame f = blank();
  const double den = std::numeric_limits<double>::denorm_min();
  for (int i = 0; i < f.size(); ++i) f.force[static_cast<std::size_t>(i)] = (i % 3 == 0) ? den * (1 + i) : -den;
  ASSERT_TRUE(std::fpclassify(f.force[3]) == FP_SUBNORMAL);
  EXPECT_EQ(ex.step(f, out), FeatureStatus::NoContact);
  expectFiniteAndZero(out);
  // Denormals mixed into a real contact change nothing.
  TactileFrame edge = blank(), mixed;
  for (int c = 1; c <= 12; ++c) edge.at(2, c) = edge.at(3, c) = 0.5;
  mixed = edge;
  for (int i = 0; i < mixed.size(); ++i)
    if (mixed.force[static_cast<std::size_t>(i)] == 0.0) mixed.force[static_cast<std::size_t>(i)] = 1e-310 * (i + 1);
  ContactFeatures a, b;
  ex.reset();
  ex.step(edge, a);
  ex.reset();
  ex.step(mixed, b);
  EXPECT_EQ(a.cop_x, b.cop_x);
  EXPECT_EQ(a.cop_y, b.cop_y);
  EXPECT_EQ(a.alpha_z, b.alpha_z);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.area, b.area);
  EXPECT_EQ(a.contact, b.contact);
}

TEST(FeatureExtremeValues, ExtremeTaresAreRejectedAndCountsBelowTheTareReadZero) {
  SensorStage st;
  CalibrationParams c = linearCalibration();
  ASSERT_TRUE(st.configure(FeatureParams{}, c).ok());
  RawTactileFrame raw;
  raw.counts.fill(0);
  TactileFrame frame;
  ContactFeatures out;
  bool valid = false;

  // A small no-load offset is a valid tare.
  for (int i = 0; i < 84; ++i) raw.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(i % 5);
  st.requestTare();
  EXPECT_EQ(st.step(raw, frame, out, valid), FeatureStatus::NoContact);

  // A tare taken under load (offset near or at full scale) is rejected:
  // the previous tare stays and every frame says so until a tare succeeds.
  RawTactileFrame loaded = raw;
  for (uint16_t big : {uint16_t(4000), uint16_t(4095), uint16_t(410)}) {
    loaded.counts[30] = big;
    st.requestTare();
    EXPECT_EQ(st.step(loaded, frame, out, valid), FeatureStatus::TareRejected) << big;
    EXPECT_TRUE(valid);
    EXPECT_TRUE(usable(out.status));
    // The load is measured against the old tare, not zeroed.
    EXPECT_NEAR(frame.force[30], (big - 30 % 5) * kNPerCount, 1e-12);
    if (big >= 4000) {
      EXPECT_EQ(out.contact, ContactType::Point);
    }
  }
  // Still reported on the next frames (a one-frame status would pass silently).
  EXPECT_EQ(st.step(raw, frame, out, valid), FeatureStatus::TareRejected);
  // Counts below the tare read exactly 0, never negative.
  RawTactileFrame low = raw;
  for (auto& v : low.counts) v = 0;
  st.step(low, frame, out, valid);
  for (int i = 0; i < 84; ++i) EXPECT_EQ(frame.force[static_cast<std::size_t>(i)], 0.0);
  // A valid tare clears the status.
  st.requestTare();
  EXPECT_EQ(st.step(raw, frame, out, valid), FeatureStatus::NoContact);
  // max_tare is checked at configuration.
  c.max_tare = 4096;
  EXPECT_FALSE(st.configure(FeatureParams{}, c).ok());
}

// ---------------------------------------------------------------- the noise's bias on the force

TEST(FeatureCensoring, NoiseDoesNotBiasTheForceOfALineLoadAtTheThreshold) {
  // 2 rows x 12 taxels at 0.21 N (5.04 N) against the WTS's 0.2 N firing
  // threshold, read through 30 counts (12 mN) of noise: each taxel fires in
  // ~80 % of the frames. Without the estimate the mean measured force is
  // ~20 % low (the servo would press the true force up by that much); with
  // it the mean is within 3 % of the noise-free reading.
  TactileFrame truth = blank();
  fill(truth, 2, 3, 1, 12, 0.21);
  const double f_true = 24 * 0.21;
  for (double tau : {0.1, 0.0}) {
    FeatureParams fp;
    fp.censor_tau = tau;
    SensorStage st;
    ASSERT_TRUE(st.configure(fp, linearCalibration(30.0)).ok());
    std::mt19937_64 rng(5);
    RawTactileFrame raw;
    TactileFrame frame;
    ContactFeatures out;
    bool valid = false;
    double sum = 0.0;
    int n = 0, multiple = 0;
    for (int k = 0; k < 3000; ++k) {
      acquire(truth, 30.0, 0.2, rng, raw);
      raw.time_s = k / 140.0;  // WTS frame rate
      st.step(raw, frame, out, valid);
      if (k < 100) continue;  // the rate estimate's start (~ 5 censor_tau)
      sum += out.force;
      ++n;
      multiple += out.contact == ContactType::Multiple;
    }
    const double mean = sum / n;
    if (tau > 0.0) {
      EXPECT_NEAR(mean / f_true, 1.0, 0.03) << "mean " << mean << " N";
      EXPECT_EQ(multiple, 0) << "dropouts must not split the line into contacts";
    } else {
      EXPECT_LT(mean / f_true, 0.9) << "the bias the estimate removes (mean " << mean << " N)";
    }
  }
}

TEST(FeatureCensoring, NoNoiseNoEstimateAndAPhantomDiesWithinTauLn2) {
  // Without noise (taxel_noise = 0) the image is the readings, exactly.
  TactileFrame line = blank();
  fill(line, 2, 3, 1, 12, 0.3);
  FeatureExtractor plain = configured();
  ContactFeatures out;
  plain.step(line, out);
  EXPECT_NEAR(out.force, 24 * 0.3, 1e-12);
  EXPECT_EQ(plain.lastSubthresholdForce(), 0.0);
  // With noise: a taxel that stops firing is estimated for at most
  // censor_tau ln 2, then it reads 0 again.
  FeatureParams p;
  p.taxel_noise = 0.012;
  FeatureExtractor ex = configured(p);
  double t = 0.0;
  for (int k = 0; k < 100; ++k, t += 0.005) {
    line.time_s = t;
    ex.step(line, out);
  }
  TactileFrame part = line;
  fill(part, 2, 3, 7, 12, 0.0);  // half the line lifts off
  double last_estimated = -1.0;
  const double t_off = t;
  for (int k = 0; k < 100; ++k, t += 0.005) {
    part.time_s = t;
    ex.step(part, out);
    if (ex.lastSubthresholdForce() > 0.0) last_estimated = t - t_off;
  }
  EXPECT_GE(last_estimated, 0.0);
  EXPECT_LE(last_estimated, p.censor_tau * std::log(2.0) + 1e-9);
  EXPECT_NEAR(out.force, 12 * 0.3, 1e-12);
}

// ---------------------------------------------------------------- real time

TEST(FeatureRobustnessRealTime, NoAllocationWithRegionsNoiseEstimateAndTares) {
  SensorStage st;
  ASSERT_TRUE(st.configure(FeatureParams{}, linearCalibration(30.0)).ok());
  TactileFrame truth = blank();
  fill(truth, 2, 3, 1, 4, 0.21);
  fill(truth, 2, 3, 9, 12, 0.21);
  std::mt19937_64 rng(1);
  std::array<RawTactileFrame, 64> raws;
  for (std::size_t k = 0; k < raws.size(); ++k) {
    acquire(truth, 30.0, 0.2, rng, raws[k]);
    raws[k].time_s = static_cast<double>(k) / 140.0;
  }
  TactileFrame frame;
  ContactFeatures out;
  bool valid = false;
  tactile::test::AllocationScope scope;
  for (int k = 0; k < 2000; ++k) {
    RawTactileFrame& r = raws[static_cast<std::size_t>(k % 64)];
    r.time_s = k / 140.0;
    if (k % 500 == 0) st.requestTare();  // loaded: rejected
    st.step(r, frame, out, valid);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(out.contact, ContactType::Multiple);
}
