// Feature extractor: configuration errors, extremes, analytic ground truth,
// real-time discipline. The OpenCV reference check is in test_opencv_reference.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"

using namespace tactile;

namespace {

constexpr double kDeg = kPi / 180.0;

TactileFrame blankFrame(int rows = kDefaultRows, int cols = kDefaultCols) {
  TactileFrame f;
  f.rows = static_cast<uint16_t>(rows);
  f.cols = static_cast<uint16_t>(cols);
  f.force.fill(0.0);
  return f;
}

FeatureExtractor makeExtractor(FeatureParams p = {}) {
  FeatureExtractor ex;
  const ConfigResult r = ex.configure(p);
  EXPECT_TRUE(r.ok()) << r.message();
  return ex;
}

void expectAllFinite(const ContactFeatures& f) {
  for (double v : {f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.dzmp_x, f.dzmp_y, f.alpha_z, f.force, f.d_z, f.lambda1,
                   f.lambda2, f.max_taxel})
    EXPECT_TRUE(std::isfinite(v));
}

// Axis-angle difference modulo pi, in (-pi/2, pi/2].
double axisDiff(double a, double b) {
  double d = std::fmod(a - b, kPi);
  if (d > kPi / 2) d -= kPi;
  if (d <= -kPi / 2) d += kPi;
  return d;
}

sim::PadGeometry pad(int k = 8) {
  sim::PadGeometry g;
  g.subsamples = k;
  return g;
}

}  // namespace

// ---------------------------------------------------------------- configuration

TEST(FeatureConfig, RejectsBadParametersNamingThemAndTheirRange) {
  struct Case {
    FeatureParams p;
    const char* name;
    const char* range;
  };
  std::vector<Case> cases;
  FeatureParams p;
  p.threshold = -0.1;
  cases.push_back({p, "features.threshold", ">= 0"});
  p = {};
  p.pitch = 0.0;
  cases.push_back({p, "features.pitch", "> 0"});
  p = {};
  p.pitch = -0.001;
  cases.push_back({p, "features.pitch", "> 0"});
  p = {};
  p.rows = 0;
  cases.push_back({p, "features.rows", "[1, 16]"});
  p = {};
  p.cols = 33;
  cases.push_back({p, "features.cols", "[1, 32]"});
  p = {};
  p.edge_ratio = 0.5;
  cases.push_back({p, "features.edge_ratio", ">= 1"});
  p = {};
  p.edge_ratio_exit = 6.0;
  cases.push_back({p, "features.edge_ratio_exit", "[1, edge_ratio"});
  p = {};
  p.contact_threshold = std::nan("");
  cases.push_back({p, "features.contact_threshold", ">= 0"});
  for (const auto& c : cases) {
    FeatureExtractor ex;
    const ConfigResult r = ex.configure(c.p);
    ASSERT_FALSE(r.ok()) << c.name;
    EXPECT_NE(r.message().find(c.name), std::string::npos) << r.message();
    EXPECT_NE(r.message().find(c.range), std::string::npos) << r.message();
    // A failed configure leaves the extractor unusable, not half-configured.
    ContactFeatures out;
    EXPECT_EQ(ex.step(blankFrame(), out), FeatureStatus::NotConfigured);
  }
}

TEST(FeatureConfig, WrongFrameDimensionsGiveAStatus) {
  FeatureExtractor ex = makeExtractor();
  TactileFrame f = blankFrame(6, 13);
  ContactFeatures out;
  EXPECT_EQ(ex.step(f, out), FeatureStatus::BadDimensions);
  EXPECT_EQ(out.status, FeatureStatus::BadDimensions);
  EXPECT_FALSE(usable(out.status));
}

TEST(CalibrationConfig, TableSizeMismatchIsRejectedWithTheExpectedSize) {
  CalibrationParams p;
  p.taxels.assign(83, {0.0, 0.001, 0.0, 0.0});
  Calibration cal;
  const ConfigResult r = cal.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("calibration.taxels"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("84"), std::string::npos) << r.message();
}

TEST(Calibration, PolynomialTareBorderAndSaturation) {
  CalibrationParams p;
  p.coeffs = {0.0, 0.002, 1e-6, 0.0};
  p.use_border = true;
  p.border_coeffs = {0.0, 0.001, 0.0, 0.0};
  p.max_tare = 4095;  // this test tares a loaded frame on purpose (max_tare: test ExtremeTares)
  Calibration cal;
  ASSERT_TRUE(cal.configure(p).ok());
  RawTactileFrame raw;
  raw.counts.fill(0);
  raw.counts[2 * 14 + 5] = 1000;  // interior
  raw.counts[0] = 1000;           // border (corner)
  raw.counts[1] = 4095;           // saturated border taxel
  TactileFrame f;
  EXPECT_EQ(cal.step(raw, f), CalibrationStatus::Saturated);
  EXPECT_EQ(f.saturated_count, 1);
  EXPECT_NEAR(f.at(2, 5), 0.002 * 1000 + 1e-6 * 1e6, 1e-12);  // 3.0 N
  EXPECT_NEAR(f.at(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(f.at(3, 3), 0.0, 0.0);
  // Tare: the same raw frame now reads zero everywhere.
  ASSERT_EQ(cal.tare(raw), CalibrationStatus::Ok);
  raw.counts[1] = 100;  // below its tare -> clamped at 0, never negative
  cal.step(raw, f);
  for (int i = 0; i < 84; ++i) EXPECT_EQ(f.force[static_cast<std::size_t>(i)], 0.0);
}

// ---------------------------------------------------------------- extremes

TEST(FeatureExtremes, AllZeroFrame) {
  FeatureExtractor ex = makeExtractor();
  ContactFeatures out;
  EXPECT_EQ(ex.step(blankFrame(), out), FeatureStatus::NoContact);
  expectAllFinite(out);
  EXPECT_EQ(out.contact, ContactType::None);
  EXPECT_EQ(out.force, 0.0);
  EXPECT_EQ(out.area, 0);
}

TEST(FeatureExtremes, OneTaxel) {
  FeatureExtractor ex = makeExtractor();
  TactileFrame f = blankFrame();
  f.at(1, 11) = 1.5;
  ContactFeatures out;
  EXPECT_EQ(ex.step(f, out), FeatureStatus::Ok);
  expectAllFinite(out);
  EXPECT_NEAR(out.cop_x, (11 - 6.5) * 0.0034, 1e-15);
  EXPECT_NEAR(out.cop_y, (1 - 2.5) * 0.0034, 1e-15);
  EXPECT_DOUBLE_EQ(out.coc_x, out.cop_x);
  EXPECT_EQ(out.dzmp_x, 0.0);
  EXPECT_EQ(out.lambda1, 0.0);
  EXPECT_EQ(out.lambda2, 0.0);
  EXPECT_EQ(out.contact, ContactType::Point);
  EXPECT_EQ(out.area, 1);
  EXPECT_DOUBLE_EQ(out.force, 1.5);
}

// A single taxel has no direction. Where its centre is not exactly
// representable, m20/m00 - cx^2 leaves rounding (lambda1 ~ 1e-20 m^2) that the
// noise model (which scales with the spread) cannot tell from a real spread:
// every position and load must still give alpha_z undefined, with and without
// the noise model.
TEST(FeatureExtremes, OneTaxelAnywhereHasNoAngle) {
  int rounded = 0;
  for (double noise : {0.0, 0.02}) {
    FeatureParams p;
    p.taxel_noise = noise;
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 14; ++c) {
        for (double v : {0.3, 1.7, 9.1}) {
          FeatureExtractor ex = makeExtractor(p);
          TactileFrame f = blankFrame();
          f.at(r, c) = v;
          ContactFeatures out;
          ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
          EXPECT_FALSE(out.alpha_defined) << "taxel (" << r << ", " << c << "), " << v << " N, lambda1 " << out.lambda1;
          rounded += out.lambda1 > 0.0;
        }
      }
    }
  }
  // The case exists: some positions leave a rounding residue.
  EXPECT_GT(rounded, 0);
}

TEST(FeatureExtremes, FullySaturatedFrame) {
  FeatureExtractor ex = makeExtractor();
  TactileFrame f = blankFrame();
  for (int i = 0; i < 84; ++i) f.force[static_cast<std::size_t>(i)] = 10.0;
  f.saturated_count = 84;
  ContactFeatures out;
  EXPECT_EQ(ex.step(f, out), FeatureStatus::Saturated);
  EXPECT_TRUE(usable(out.status));
  expectAllFinite(out);
  EXPECT_NEAR(out.cop_x, 0.0, 1e-15);
  EXPECT_NEAR(out.cop_y, 0.0, 1e-15);
  EXPECT_EQ(out.area, 84);
  // A uniform 6x14 image: variances pitch^2 (14^2-1)/12 and pitch^2 (6^2-1)/12.
  EXPECT_NEAR(out.lambda1, 0.0034 * 0.0034 * 195.0 / 12.0, 1e-18);
  EXPECT_NEAR(out.lambda2, 0.0034 * 0.0034 * 35.0 / 12.0, 1e-18);
  EXPECT_NEAR(out.alpha_z, 0.0, 1e-12);
}

TEST(FeatureExtremes, IsotropicBlobHasFiniteStableAngleAndIsAPoint) {
  FeatureExtractor ex = makeExtractor();
  TactileFrame f = blankFrame();
  f.at(2, 6) = f.at(2, 7) = f.at(3, 6) = f.at(3, 7) = 1.0;  // lambda1 == lambda2
  ContactFeatures out;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-1e-12, 1e-12);
  for (int k = 0; k < 100; ++k) {
    TactileFrame g = f;
    for (int r = 2; r <= 3; ++r)
      for (int c = 6; c <= 7; ++c) g.at(r, c) += jitter(rng);  // round-off level noise
    ASSERT_EQ(ex.step(g, out), FeatureStatus::Ok);
    ASSERT_TRUE(std::isfinite(out.alpha_z));
    EXPECT_EQ(out.alpha_z, 0.0) << "alpha_z must not follow round-off noise on an isotropic contact";
    EXPECT_EQ(out.contact, ContactType::Point);
    EXPECT_NEAR(out.lambda1, out.lambda2, 1e-15);
  }
}

TEST(FeatureExtremes, SubThresholdNoiseOnly) {
  FeatureExtractor ex = makeExtractor();
  TactileFrame f = blankFrame();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.05, 0.19);
  for (int i = 0; i < 84; ++i) f.force[static_cast<std::size_t>(i)] = noise(rng);
  ContactFeatures out;
  EXPECT_EQ(ex.step(f, out), FeatureStatus::NoContact);
  EXPECT_EQ(out.contact, ContactType::None);
  EXPECT_EQ(out.area, 0);
  expectAllFinite(out);
}

TEST(FeatureExtremes, TinyAndHugeForcesGiveTheSameGeometry) {
  // Geometric features are scale invariant; thresholds scale with the load.
  const sim::EdgeIndent edge{0.004, -0.002, 20 * kDeg, 0.003, 0.002, 0.04, 0.01};
  TactileFrame base;
  sim::integratePad(pad(), edge, base);
  for (double scale : {1e-9 / 0.5, 1e4 / 0.5}) {
    TactileFrame f = base;
    for (int i = 0; i < 84; ++i) f.force[static_cast<std::size_t>(i)] *= scale;
    FeatureParams p;
    p.threshold = 0.2 * scale;
    p.contact_threshold = 0.2 * scale;
    p.region_min_force = 0.5 * scale;
    p.max_taxel_force = 1000.0 * scale;
    FeatureExtractor ex = makeExtractor(p), ref = makeExtractor();
    ContactFeatures a, b;
    ASSERT_EQ(ex.step(f, a), FeatureStatus::Ok) << scale;
    ASSERT_EQ(ref.step(base, b), FeatureStatus::Ok);
    expectAllFinite(a);
    // 1e-9 relative: only round-off separates the two (values are ~1e-3 m).
    EXPECT_NEAR(a.cop_x, b.cop_x, 1e-12);
    EXPECT_NEAR(a.cop_y, b.cop_y, 1e-12);
    EXPECT_NEAR(a.alpha_z, b.alpha_z, 1e-9);
    EXPECT_NEAR(a.lambda1 / b.lambda1, 1.0, 1e-9);
    EXPECT_EQ(a.contact, b.contact);
    EXPECT_NEAR(a.force / (b.force * scale), 1.0, 1e-12);
  }
}

TEST(FeatureExtremes, NaNAndInfAreRejectedAndNeverPropagated) {
  FeatureExtractor ex = makeExtractor();
  // Establish an edge with a known angle first.
  TactileFrame good;
  sim::integratePad(pad(), sim::EdgeIndent{0, 0, 30 * kDeg, 0.002}, good);
  ContactFeatures out;
  ASSERT_EQ(ex.step(good, out), FeatureStatus::Ok);
  ASSERT_EQ(out.contact, ContactType::Edge);
  const double alpha = out.alpha_z;
  for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    TactileFrame f = good;
    f.at(3, 3) = bad;
    EXPECT_EQ(ex.step(f, out), FeatureStatus::InvalidInput);
    EXPECT_FALSE(usable(out.status));
    expectAllFinite(out);
    EXPECT_EQ(out.force, 0.0);
    EXPECT_EQ(out.contact, ContactType::None);
  }
  // Finite inputs whose sums overflow are caught too: beyond max_taxel_force
  // they are out of range (test_feature_robustness.cpp).
  TactileFrame f = good;
  for (int i = 0; i < 84; ++i) f.force[static_cast<std::size_t>(i)] = 1e308;
  EXPECT_EQ(ex.step(f, out), FeatureStatus::OutOfRange);
  expectAllFinite(out);
  // History untouched: the next good frame continues where we were.
  ASSERT_EQ(ex.step(good, out), FeatureStatus::Ok);
  EXPECT_EQ(out.contact, ContactType::Edge);
  EXPECT_DOUBLE_EQ(out.alpha_z, alpha);
}

TEST(FeatureExtremes, EdgeNearVerticalDoesNotFlipSign) {
  // A slowly rotating edge through +-90 deg, with noise, back and forth.
  FeatureExtractor ex = makeExtractor();
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  ContactFeatures out;
  double prev = 0.0;
  bool first = true;
  int frames = 0;
  auto run = [&](double from, double to, double stepDeg) {
    const int n = static_cast<int>(std::fabs(to - from) / stepDeg);
    for (int i = 0; i <= n; ++i) {
      const double a = (from + (to - from) * i / n) * kDeg;
      TactileFrame f;
      sim::integratePad(pad(4), sim::EdgeIndent{0, 0, a, 0.002, 0.002, 0.018}, f);
      for (int k = 0; k < 84; ++k)  // noise where the taxel fires (a WTS reads 0 below ~0.2 N)
        if (f.force[static_cast<std::size_t>(k)] > 0.1) f.force[static_cast<std::size_t>(k)] += noise(rng);
      ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
      ASSERT_EQ(out.contact, ContactType::Edge);
      // The reported angle represents the edge axis (mod pi) ...
      EXPECT_LT(std::fabs(axisDiff(out.alpha_z, a)), 3 * kDeg) << "true " << a / kDeg;
      // ... and never jumps between +pi/2 and -pi/2 from one frame to the next.
      if (!first) {
        EXPECT_LT(std::fabs(out.alpha_z - prev), 5 * kDeg) << "at " << a / kDeg << " deg";
      }
      // It stays within the documented band (-pi/2 - h, pi/2 + h].
      EXPECT_LE(std::fabs(out.alpha_z), kPi / 2 + ex.params().alpha_hysteresis + 1e-12);
      prev = out.alpha_z;
      first = false;
      ++frames;
    }
  };
  run(80, 98, 0.25);
  run(98, 82, 0.25);
  run(82, 99, 0.25);
  EXPECT_GT(frames, 200);
}

TEST(FeatureExtremes, WithoutHysteresisTheAngleIsThePlainWrap) {
  FeatureParams p;
  p.alpha_hysteresis = 0.0;
  FeatureExtractor ex = makeExtractor(p);
  ContactFeatures out;
  TactileFrame f;
  sim::integratePad(pad(), sim::EdgeIndent{0, 0, 89 * kDeg, 0.002, 0.002, 0.018}, f);
  ex.step(f, out);
  EXPECT_NEAR(out.alpha_z, 89 * kDeg, 1 * kDeg);
  sim::integratePad(pad(), sim::EdgeIndent{0, 0, 91 * kDeg, 0.002, 0.002, 0.018}, f);
  ex.step(f, out);
  EXPECT_NEAR(out.alpha_z, -89 * kDeg, 1 * kDeg);
}

TEST(FeatureExtremes, ContactTypeHysteresisDoesNotChatter) {
  // Elongation ratio oscillating around edge_ratio = 5 must not toggle the type.
  FeatureExtractor ex = makeExtractor();
  ContactFeatures out;
  // An elliptical blob with a controllable aspect: two rows of taxels with
  // weights w on the ends; lambda1/lambda2 is swept around 5.
  auto frameWithRatio = [](double ratio) {
    TactileFrame f = blankFrame();
    // Three taxels in a row along x plus a y-spread pair: tune x spread.
    const double wy = 1.0, wx = ratio;  // rough aspect control
    f.at(2, 7) = f.at(3, 7) = 2.0 * wy;
    f.at(2, 6) = f.at(3, 6) = 2.0 * wy;
    f.at(2, 5) = f.at(3, 5) = f.at(2, 8) = f.at(3, 8) = wx;
    return f;
  };
  // Find weights giving ratios just above and just below 5 (and above 4).
  double above = 0, below = 0;
  for (double w = 0.1; w < 5.0; w += 0.001) {
    FeatureExtractor probe = makeExtractor();
    probe.step(frameWithRatio(w), out);
    const double r = out.lambda1 / out.lambda2;
    if (!below && r > 4.6) below = w;
    if (!above && r > 5.2) above = w;
  }
  ASSERT_GT(below, 0);
  ASSERT_GT(above, below);
  int toggles = 0;
  ContactType prev = ContactType::None;
  ex.step(frameWithRatio(above), out);
  ASSERT_EQ(out.contact, ContactType::Edge);
  prev = out.contact;
  for (int k = 0; k < 50; ++k) {
    ex.step(frameWithRatio(k % 2 ? above : below), out);
    if (out.contact != prev) ++toggles;
    prev = out.contact;
  }
  EXPECT_EQ(toggles, 0);
  EXPECT_EQ(prev, ContactType::Edge);
}

// ---------------------------------------------------------------- ground truth

TEST(FeatureGroundTruth, SphereCoPWithinTenthOfAMillimetre) {
  // Tolerance 0.1 mm (the ground-truth target): the taxel quantisation of a smooth, compact
  // pressure field. Truth: the sphere's lowest point, the analytic pressure
  // centre of a rotationally symmetric field fully inside the active area.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-0.016, 0.016), uy(-0.0035, 0.0035);
  double worst = 0;
  for (int k = 0; k < 50; ++k) {
    const double x0 = ux(rng), y0 = uy(rng);
    TactileFrame f;
    sim::integratePad(pad(8), sim::SphereIndent{x0, y0, 0.010, 0.002}, f);
    FeatureExtractor ex = makeExtractor();
    ContactFeatures out;
    ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
    EXPECT_EQ(out.contact, ContactType::Point);
    worst = std::max(worst, std::hypot(out.cop_x - x0, out.cop_y - y0));
  }
  EXPECT_LT(worst, 1e-4);
}

TEST(FeatureGroundTruth, LineLoadAngleWithinOneDegreeAndOffset) {
  // Edges spanning >= 6 taxels: alpha_z within 1 deg of the true angle; the
  // CoP within 0.1 mm of the true pressure centre (the continuous field's
  // centroid, integrated on a fine 16x16-per-taxel grid).
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ua(-80.0, 80.0), uo(-0.002, 0.002);
  double worstAngle = 0, worstOffset = 0;
  for (int k = 0; k < 100; ++k) {
    const double a = ua(rng) * kDeg, off = uo(rng);
    // Line through (-off sin a, off cos a) = perpendicular offset `off`.
    const double x0 = -off * std::sin(a), y0 = off * std::cos(a);
    const double span = 6 * 0.0034;  // >= 6 taxels long, fully on the pad
    TactileFrame f;
    sim::PadTruth truth;
    const sim::EdgeIndent edge{x0, y0, a, 0.002, 0.0015, span};
    sim::integratePad(pad(16), edge, f, &truth);
    FeatureExtractor ex = makeExtractor();
    ContactFeatures out;
    ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
    ASSERT_EQ(out.contact, ContactType::Edge) << a / kDeg;
    worstAngle = std::max(worstAngle, std::fabs(axisDiff(out.alpha_z, a)));
    worstOffset = std::max(worstOffset, std::hypot(out.cop_x - truth.cop_x, out.cop_y - truth.cop_y));
    // And the true centre lies on the line (perpendicular distance ~0).
    EXPECT_LT(std::fabs(-(truth.cop_x - x0) * std::sin(a) + (truth.cop_y - y0) * std::cos(a)), 2e-5);  // quadrature error of the 16x16 midpoint grid
  }
  EXPECT_LT(worstAngle, 1.0 * kDeg);
  EXPECT_LT(worstOffset, 1e-4);
}

TEST(FeatureGroundTruth, DzmpSignAndProportionalityToTheAppliedMoment) {
  // A line load along x with a linear depth gradient along the edge applies a
  // moment about y_s; DZMP_y = CoP_x - CoC_x must have its sign and be
  // proportional to it (Eq. 2-3), while DZMP_x stays ~0. Likewise an edge along
  // y_s with a gradient gives DZMP_x proportional to the moment about x_s.
  std::vector<double> ratios;
  for (double slope : {-0.02, -0.01, -0.005, 0.005, 0.01, 0.02}) {
    sim::PadTruth truth;
    TactileFrame f;
    sim::integratePad(pad(8), sim::EdgeIndent{0, 0, 0.0, 0.003, 0.0015, 1.0, slope}, f, &truth);
    FeatureExtractor ex = makeExtractor();
    ContactFeatures out;
    ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
    // More depth at +x (slope > 0): pressure centre moves to +x: DZMP_y > 0 and
    // the moment about y_s (-sum x p) is negative.
    EXPECT_EQ(out.dzmp_y > 0, slope > 0) << slope;
    EXPECT_LT(std::fabs(out.dzmp_x), 1e-9);
    ratios.push_back(out.dzmp_y / (-truth.moment_y / truth.force));
  }
  // Proportional: the same gain for every load (5 %: binarisation footprint).
  for (double r : ratios) EXPECT_NEAR(r / ratios.front(), 1.0, 0.05);
  for (double slope : {-0.01, 0.01}) {
    sim::PadTruth truth;
    TactileFrame f;
    sim::integratePad(pad(8), sim::EdgeIndent{0, 0, kPi / 2, 0.003, 0.0015, 1.0, 2 * slope}, f, &truth);
    FeatureExtractor ex = makeExtractor();
    ContactFeatures out;
    ASSERT_EQ(ex.step(f, out), FeatureStatus::Ok);
    EXPECT_EQ(out.dzmp_x > 0, slope > 0);
    EXPECT_EQ(out.dzmp_x > 0, truth.moment_x > 0);
  }
}

// ---------------------------------------------------------------- real time

TEST(FeatureRealTime, NoHeapAllocationPerFrame) {
  TactileFrame f;
  sim::integratePad(pad(), sim::EdgeIndent{0.002, 0, 0.3, 0.002}, f);
  for (ThresholdMode mode : {ThresholdMode::Fixed, ThresholdMode::Otsu}) {
    FeatureParams p;
    p.threshold_mode = mode;
    FeatureExtractor ex = makeExtractor(p);
    ContactFeatures out;
    tactile::test::AllocationScope scope;
    for (int i = 0; i < 1000; ++i) {
      f.seq = static_cast<uint32_t>(i);
      ex.step(f, out);
    }
    EXPECT_EQ(scope.count(), 0u);
    EXPECT_EQ(out.status, FeatureStatus::Ok);
  }
  Calibration cal;
  ASSERT_TRUE(cal.configure({}).ok());
  RawTactileFrame raw;
  tactile::test::AllocationScope scope;
  for (int i = 0; i < 1000; ++i) cal.step(raw, f);
  EXPECT_EQ(scope.count(), 0u);
}

TEST(FeatureRealTime, AllocationCounterDetectsAllocations) {
  // Guard against a counter that cannot fail.
  tactile::test::AllocationScope scope;
  std::vector<int> v(100);
  volatile int* keep = v.data();
  (void)keep;
  EXPECT_GE(scope.count(), 1u);
}

TEST(FeatureContactType, ShortBlobsAreNotEdgesEvenWithZeroMinorSpread) {
  FeatureExtractor ex = makeExtractor();
  ContactFeatures out;
  TactileFrame f = blankFrame();
  f.at(2, 6) = f.at(2, 7) = 1.0;  // two taxels: lambda2 = 0, length sqrt(3) pitch
  ex.step(f, out);
  EXPECT_EQ(out.contact, ContactType::Point);
  f.at(2, 8) = 1.0;  // three: length sqrt(8) pitch > 2.5 pitch
  ex.reset();
  ex.step(f, out);
  EXPECT_EQ(out.contact, ContactType::Edge);
  FeatureParams p;
  p.edge_min_length = -1.0;
  FeatureExtractor bad;
  EXPECT_NE(bad.configure(p).message().find("features.edge_min_length"), std::string::npos);
}
