// Reference check: FeatureExtractor against an independent OpenCV pipeline
// (opencv_reference.hpp) on thousands of random frames.
//
// Tolerance: 1e-9 relative, with an absolute floor of 1e-9 * pitch for
// positions near zero and 1e-9 * lambda1 for eigenvalues: both sides compute
// the same sums in double precision in a different order, so they differ by
// round-off (~1e-15 relative); 1e-9 leaves room for the eigen solver.
// Intended differences: none for the fixed threshold. Otsu: ours is exact on
// the frame's float values; OpenCV's works on CV_8U levels only, so the Otsu
// comparison uses frames whose forces are 8-bit levels times a step.
// The edge angle is compared where it is defined: when the eigenvalue gap is
// > 1e-6 of their sum (the extractor holds the previous angle below that).
#include <gtest/gtest.h>

#include <random>

#include "opencv_reference.hpp"
#include "tactile_features/extractor.hpp"

using namespace tactile;

namespace {

double axisDiff(double a, double b) {
  double d = std::fmod(a - b, kPi);
  if (d > kPi / 2) d -= kPi;
  if (d <= -kPi / 2) d += kPi;
  return d;
}

// Random frames of three kinds: sparse random taxels, blobs, and lines.
TactileFrame randomFrame(std::mt19937_64& rng) {
  TactileFrame f;
  f.force.fill(0.0);
  std::uniform_int_distribution<int> kind(0, 2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  switch (kind(rng)) {
    case 0:
      for (int i = 0; i < 84; ++i)
        if (u(rng) < 0.4) f.force[static_cast<std::size_t>(i)] = 3.0 * u(rng);
      break;
    case 1: {
      const double cx = 13 * u(rng), cy = 5 * u(rng), s = 0.5 + 2 * u(rng), amp = 0.1 + 5 * u(rng);
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 14; ++c) f.at(r, c) = amp * std::exp(-((c - cx) * (c - cx) + (r - cy) * (r - cy)) / (2 * s * s));
      break;
    }
    default: {
      const double a = kPi * u(rng), off = 4 * u(rng) - 2, amp = 0.1 + 5 * u(rng), g = u(rng) - 0.5;
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 14; ++c) {
          const double x = c - 6.5, y = r - 2.5;
          const double d = -x * std::sin(a) + y * std::cos(a) - off;
          const double along = x * std::cos(a) + y * std::sin(a);
          f.at(r, c) = std::max(0.0, amp * (1 + 0.1 * g * along) * std::exp(-d * d));
        }
    }
  }
  return f;
}

void expectRel(double ours, double ref, double floor, const char* what, int frame) {
  EXPECT_LE(std::fabs(ours - ref), 1e-9 * std::max(std::fabs(ref), floor)) << what << " frame " << frame;
}

}  // namespace

TEST(OpenCvReference, FixedThresholdAgreesOnThousandsOfRandomFrames) {
  FeatureExtractor ex;
  // One region whatever the frame: the reference is the whole-image PCA (a
  // random frame often has separate blobs, which the extractor reports as a
  // multiple contact with alpha_z held; test_feature_robustness.cpp).
  FeatureParams one_region;
  one_region.region_min_force = 1e9;
  ASSERT_TRUE(ex.configure(one_region).ok());
  std::mt19937_64 rng(1234);
  const double pitch = kDefaultPitch;
  int compared = 0, anglesCompared = 0;
  for (int k = 0; k < 5000; ++k) {
    const TactileFrame f = randomFrame(rng);
    ex.reset();
    ContactFeatures o;
    ex.step(f, o);
    ASSERT_TRUE(usable(o.status));
    const auto r = test::referenceFeatures(f, pitch, ex.params().threshold);
    if (r.force <= 0) continue;
    ++compared;
    expectRel(o.force, r.force, 1e-12, "force", k);
    expectRel(o.cop_x, r.cop_x, pitch, "cop_x", k);
    expectRel(o.cop_y, r.cop_y, pitch, "cop_y", k);
    expectRel(o.coc_x, r.coc_x, pitch, "coc_x", k);
    expectRel(o.coc_y, r.coc_y, pitch, "coc_y", k);
    expectRel(o.dzmp_x, r.dzmp_x, pitch, "dzmp_x", k);
    expectRel(o.dzmp_y, r.dzmp_y, pitch, "dzmp_y", k);
    expectRel(o.lambda1, r.lambda1, r.lambda1, "lambda1", k);
    expectRel(o.lambda2, r.lambda2, r.lambda1, "lambda2", k);
    EXPECT_EQ(o.area, r.area) << k;
    // Without contact (no taxel above contact_threshold) alpha_z is held, not measured.
    if (o.contact != ContactType::None && r.lambda1 - r.lambda2 > 1e-6 * (r.lambda1 + r.lambda2)) {
      ++anglesCompared;
      EXPECT_LE(std::fabs(axisDiff(o.alpha_z, r.alpha_z)), 1e-9) << "alpha_z frame " << k;
    }
  }
  EXPECT_GT(compared, 4900);
  EXPECT_GT(anglesCompared, 4000) << anglesCompared;  // undefined on a handful, held without contact
}

TEST(OpenCvReference, OtsuAgreesWithOpenCvOn8BitFrames) {
  FeatureParams p;
  p.threshold_mode = ThresholdMode::Otsu;
  FeatureExtractor ex;
  ASSERT_TRUE(ex.configure(p).ok());
  std::mt19937_64 rng(99);
  const double step = 0.01;  // N per level
  int compared = 0;
  for (int k = 0; k < 3000; ++k) {
    TactileFrame f = randomFrame(rng);
    cv::Mat img8(6, 14, CV_8U);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 14; ++c) {
        const int level = std::min(255, static_cast<int>(std::lround(f.at(r, c) / step * 40.0)));
        img8.at<uint8_t>(r, c) = static_cast<uint8_t>(level);
        f.at(r, c) = level * step;
      }
    ex.reset();
    ContactFeatures o;
    ex.step(f, o);
    const auto r = test::referenceFeatures(f, kDefaultPitch, 0.0, &img8, step);
    if (r.force <= 0) continue;
    ++compared;
    EXPECT_EQ(o.area, r.area) << k;
    expectRel(o.coc_x, r.coc_x, kDefaultPitch, "coc_x", k);
    expectRel(o.coc_y, r.coc_y, kDefaultPitch, "coc_y", k);
  }
  EXPECT_GT(compared, 2900);
}

TEST(OpenCvReference, OtsuThresholdSplitsBimodalDataBetweenTheModes) {
  // Independent of OpenCV: two clusters must be separated.
  std::array<double, 20> v{};
  for (int i = 0; i < 10; ++i) v[static_cast<std::size_t>(i)] = 0.1 + 0.01 * i;
  for (int i = 10; i < 20; ++i) v[static_cast<std::size_t>(i)] = 2.0 + 0.01 * i;
  const double t = FeatureExtractor::otsuThreshold(v.data(), 20);
  EXPECT_GE(t, 0.19 - 1e-12);
  EXPECT_LT(t, 2.0);
}
