// WTS0614 pad model: elastic-foundation integrals against closed forms,
// housing contact, taxel response (App. A), noise, quantisation, saturation,
// threshold, calibration round trip, determinism and allocations.
// Objects are placed with {g} = {s} (T_gs = identity) unless stated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_sim_lwr/lwr_arm.hpp"
#include "tactile_sim_lwr/pad_sensor.hpp"
#include "tactile_types/sensor_geometry.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {
ObjectParams flatPunch(double depth) {  // half-space z >= -depth in {s}, facing the pad
  ObjectParams o;
  o.name = "punch";
  o.type = ObjectType::Plane;
  o.point = {0.0, 0.0, -depth};
  o.normal = {0.0, 0.0, -1.0};
  return o;
}
ObjectParams sphere(double x, double y, double R, double depth) {
  ObjectParams o;
  o.name = "ball";
  o.type = ObjectType::Sphere;
  o.center = {x, y, R - depth};
  o.radius = R;
  return o;
}
struct Rig {
  PadSensor pad;
  ObjectSet objects;
  KDL::Frame T = KDL::Frame::Identity();
  explicit Rig(const std::vector<ObjectParams>& objs, PadParams p = PadParams()) {
    EXPECT_TRUE(pad.configure(p).ok());
    EXPECT_TRUE(objects.configure(objs).ok());
    objects.pose(T, TrayPose{});
  }
};
constexpr double kAx = 14 * 0.0034, kAy = 6 * 0.0034;  // active area (m)
}  // namespace

TEST(PadContact, FlatPunchForceIsModulusTimesDepthTimesArea) {
  const double depth = 0.001, k = PadParams().modulus;
  for (int ks : {1, 3}) {
    PadParams p;
    p.physics_subsamples = ks;
    Rig rig({flatPunch(depth)}, p);
    ContactEval e;
    rig.pad.evaluate(rig.objects, rig.T, e);
    // Uniform penetration: the integral is exact for any sampling (1e-9 relative).
    EXPECT_NEAR(e.layer_force, k * depth * kAx * kAy, 1e-9 * e.layer_force);
    EXPECT_EQ(e.housing_force, 0.0);  // 1 mm < 3 mm recess
    EXPECT_NEAR(e.W_s(2), -e.layer_force, 1e-12);
    EXPECT_NEAR(e.W_s(3), 0.0, 1e-12);  // centred: no moments
    EXPECT_NEAR(e.W_s(4), 0.0, 1e-12);
    // Contact stiffness of a flat punch: k A along z.
    EXPECT_NEAR(e.K_s(2, 2), k * kAx * kAy, 1e-6 * k * kAx * kAy);
  }
  Rig rig({flatPunch(depth)});
  RawTactileFrame raw;
  SensorTruth truth;
  rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
  EXPECT_NEAR(truth.layer.force, k * depth * kAx * kAy, 1e-9 * truth.layer.force);
  EXPECT_NEAR(truth.wrench_s[2], -truth.layer.force, 1e-12);
}

TEST(PadContact, SphereForceIsModulusTimesCapVolume) {
  // Winkler: F = k * (volume of the sphere below the surface) = k pi d^2 (3R - d) / 3.
  const double R = 0.01, d = 0.001, k = PadParams().modulus;
  const double exact = k * kPi * d * d * (3 * R - d) / 3.0;
  double err_coarse = 0, err_fine = 0;
  for (int K : {2, 16}) {
    PadParams p;
    p.subsamples = K;
    Rig rig({sphere(0.0017, 0.0, R, d)}, p);  // centred on a taxel-border line
    RawTactileFrame raw;
    SensorTruth truth;
    rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
    double sum = 0;
    const TactileFrame& img = rig.pad.trueTaxelForces();
    for (int i = 0; i < img.size(); ++i) sum += img.force[static_cast<std::size_t>(i)];
    EXPECT_NEAR(sum, truth.layer.force, 1e-12);  // taxel forces add up to the truth
    const double err = std::fabs(truth.layer.force - exact) / exact;
    (K == 2 ? err_coarse : err_fine) = err;
    EXPECT_NEAR(truth.layer.cop_x, 0.0017, 1e-4);
  }
  // Midpoint rule over a cap of radius 4.4 mm: 16 x 16 samples per taxel
  // (0.21 mm) must be within 0.5 %, and finer must be better than 2 x 2.
  EXPECT_LT(err_fine, 5e-3);
  EXPECT_LT(err_fine, err_coarse);
}

TEST(PadContact, AcquireMatchesIntegratePadWithFootprintCulling) {
  // acquire() skips taxel cells outside the objects' footprint; the result
  // must equal the reference integral of elastic_pad.hpp (no culling) to
  // rounding (1e-12 N), for a bent bar crossing part of the pad.
  ObjectParams bent;
  bent.type = ObjectType::BentBar;
  bent.radius = 0.003;
  bent.vertices = {{-0.2, -0.004, 0.0025}, {0.0, 0.002, 0.0018}, {0.2, 0.03, 0.005}};
  for (int K : {1, 3}) {
    PadParams p;
    p.subsamples = K;
    Rig rig({bent}, p);
    RawTactileFrame raw;
    SensorTruth truth;
    rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
    PadGeometry g;
    g.modulus = p.modulus;
    g.subsamples = K;
    TactileFrame ref;
    PadTruth rt;
    integratePad(
        g,
        [&](double x, double y) {
          int w;
          return -rig.objects.lowestZ(x, y, w);
        },
        ref, &rt);
    ASSERT_GT(rt.force, 0.1);
    EXPECT_NEAR(truth.layer.force, rt.force, 1e-12);
    EXPECT_NEAR(truth.layer.moment_x, rt.moment_x, 1e-12);
    EXPECT_NEAR(truth.layer.moment_y, rt.moment_y, 1e-12);
    for (int i = 0; i < 84; ++i)
      EXPECT_NEAR(rig.pad.trueTaxelForces().force[static_cast<std::size_t>(i)], ref.force[static_cast<std::size_t>(i)], 1e-12);
    int zero = 0;
    for (int i = 0; i < 84; ++i) zero += ref.force[static_cast<std::size_t>(i)] == 0.0;
    EXPECT_GT(zero, 20);  // the bar covers only part of the pad
  }
}

TEST(PadContact, HousingContactPushesButGivesNoTaxelSignal) {
  // A 3 mm ball over the housing ring at x = 28 mm (active area ends at 23.8),
  // 3 mm below the layer surface = 1 mm into the housing (recess 2 mm).
  Rig rig({sphere(0.028, 0.0, 0.003, 0.003)});
  ContactEval e;
  rig.pad.evaluate(rig.objects, rig.T, e);
  EXPECT_EQ(e.layer_force, 0.0);
  EXPECT_GT(e.housing_force, 1.0);
  EXPECT_NEAR(e.W_s(2), -e.housing_force, 1e-12);
  EXPECT_GT(e.W_s(4), 0.0);  // my = sum x f > 0 for x > 0
  RawTactileFrame raw;
  SensorTruth truth;
  rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
  for (int i = 0; i < 84; ++i) EXPECT_EQ(raw.counts[static_cast<std::size_t>(i)], 0);
  EXPECT_EQ(truth.layer.force, 0.0);
  EXPECT_GT(truth.housing_force, 1.0);
  EXPECT_FALSE(truth.in_contact);
  EXPECT_NEAR(truth.wrench_s[2], -truth.housing_force, 1e-12);
}

TEST(PadContact, ContactStiffnessMatchesFiniteDifference) {
  // K_s = -dW_s/d(sensor twist) over the (z, wx, wy) block: the material
  // stiffness of the foundation, used as the quasi-static Newton tangent.
  // It leaves out the geometric term of tilting the columns against a sloped
  // surface, of order F * slope (tilted punch: 24 N * 0.02 = 0.5 N/rad), so
  // the tolerance is 1e-4 of the diagonal scale plus F * |slope|. For a
  // curved bar only the z column (pure translation) is checked.
  ObjectParams tilted = flatPunch(0.0005);
  tilted.normal = {0.01, 0.02, -1.0};
  ObjectParams bar;
  bar.type = ObjectType::Bar;
  bar.radius = 0.003;
  bar.vertices = {{-0.1, 0.001, 0.003 - 0.0015 - 0.1 * 0.01}, {0.1, 0.001, 0.003 - 0.0015 + 0.1 * 0.01}};
  for (const ObjectParams& obj : {tilted, bar}) {
    const bool plane = obj.type == ObjectType::Plane;
    Rig rig({obj});
    ContactEval e0, ep, em;
    rig.pad.evaluate(rig.objects, rig.T, e0);
    ASSERT_GT(e0.layer_force, 0.5);
    EXPECT_GT(std::fabs(e0.W_s(4)), 1e-4);  // non-uniform load: a moment about y_s
    const double h = 1e-7;
    for (int a : plane ? std::vector<int>{2, 3, 4} : std::vector<int>{2}) {
      KDL::Vector v = KDL::Vector::Zero(), w = KDL::Vector::Zero();
      if (a == 2) v = KDL::Vector(0, 0, h);
      if (a == 3) w = KDL::Vector(h, 0, 0);
      if (a == 4) w = KDL::Vector(0, h, 0);
      const KDL::Frame Tp(rotationFromVector(w), v), Tm(rotationFromVector(-w), -v);
      rig.objects.pose(Tp, TrayPose{});
      rig.pad.evaluate(rig.objects, Tp, ep);
      rig.objects.pose(Tm, TrayPose{});
      rig.pad.evaluate(rig.objects, Tm, em);
      for (int b : {2, 3, 4}) {
        const double fd = -(ep.W_s(b) - em.W_s(b)) / (2 * h);
        const double geo = a == 2 ? 0.0 : e0.layer_force * 0.03;
        EXPECT_NEAR(e0.K_s(b, a), fd, 1e-4 * std::sqrt(std::fabs(e0.K_s(b, b) * e0.K_s(a, a))) + geo) << b << "," << a;
      }
    }
  }
}

namespace {
// Per-sample reference for PadSensor::evaluate() over the elastic layer: the
// plain sum over every physics sample of its force, the wrench about the
// sensor origin, the stiffness g g^T and the tray terms, each sample from
// ObjectSet::lowestZ() (the point query), in the order written in
// pad_sensor.hpp. evaluate() computes the same from per-row moments.
ContactEval referenceEvaluate(const PadParams& p, const ObjectSet& objects, const KDL::Frame& T_gs) {
  ContactEval out;
  const int k = p.physics_subsamples;
  const double h = p.pitch / k, ks = p.modulus * h * h;
  const SensorGeometry geometry{p.rows, p.cols, p.pitch};
  const int tray = objects.trayIndex();
  const KDL::Vector zs = T_gs.M.UnitZ();
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c)
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const double x = geometry.sampleX(c, j, k), y = geometry.sampleY(r, i, k);
          int which;
          const double d = -objects.lowestZ(x, y, which);
          if (!(d > 0.0) || d > p.depth_limit) continue;
          const double f = ks * d;
          const double g[6] = {0.0, 0.0, -1.0, -y, x, 0.0};
          out.layer_force += f;
          ++out.active;
          for (int a = 2; a < 5; ++a) {
            out.W_s(a) += g[a] * f;
            for (int b = 2; b < 5; ++b) out.K_s(a, b) += ks * g[a] * g[b];
          }
          if (which != tray || tray < 0) continue;
          const KDL::Vector rr = T_gs * KDL::Vector(x, y, 0.0) - objects.bearing();
          const double hh[2] = {-KDL::dot(zs, KDL::Vector(1, 0, 0) * rr), -KDL::dot(zs, KDL::Vector(0, 1, 0) * rr)};
          for (int m = 0; m < 2; ++m) {
            out.tau_tray(m) -= hh[m] * f;
            for (int a = 2; a < 5; ++a) {
              out.dW_dth(a, m) += ks * g[a] * hh[m];
              out.dtau_ds(m, a) += ks * hh[m] * g[a];
            }
            for (int n = 0; n < 2; ++n) out.dtau_dth(m, n) -= ks * hh[m] * hh[n];
          }
        }
  return out;
}
}  // namespace

TEST(PadContact, EvaluateMatchesThePerSampleReference) {
  // evaluate() sums per sample row with branch-free moments; this checks every
  // output against the per-sample reference above for a sphere, an inclined
  // bar and a tray bar under a tilted sensor (general tray lever arms), at
  // K_phys = 1, 2 and 3. Tolerance 1e-9 of each quantity's scale: only the
  // summation order differs (~1e-15 relative per term, ~1e3 terms).
  const KDL::Frame T_gs(KDL::Rotation::RPY(0.05, -0.03, 0.2), KDL::Vector(0.6, 0.02, 0.3));
  const KDL::Vector a_s(-0.03, 0.001, 0.003 - 0.0012), b_s(0.03, 0.0015, 0.003 - 0.0008);
  const KDL::Vector bearing = T_gs * KDL::Vector(0.002, -0.4, 0.05);
  ObjectParams tray;
  tray.name = "tray";
  tray.type = ObjectType::Tray;
  tray.tray.bearing = {bearing.x(), bearing.y(), bearing.z()};
  const KDL::Vector ta = T_gs * a_s - bearing, tb = T_gs * b_s - bearing;
  tray.tray.bar_from = {ta.x(), ta.y(), ta.z()};
  tray.tray.bar_to = {tb.x(), tb.y(), tb.z()};
  ObjectParams bar;
  bar.type = ObjectType::Bar;
  bar.radius = 0.003;
  bar.vertices = {{-0.1, 0.001, 0.003 - 0.0015 - 0.1 * 0.01}, {0.1, 0.001, 0.003 - 0.0015 + 0.1 * 0.01}};
  struct Case {
    std::vector<ObjectParams> objs;
    KDL::Frame T;
  };
  const std::vector<Case> cases = {{{sphere(0.004, -0.002, 0.02, 0.0015)}, KDL::Frame::Identity()},
                                   {{bar}, KDL::Frame::Identity()},
                                   {{tray}, T_gs}};
  for (int k = 1; k <= 3; ++k)
    for (std::size_t n = 0; n < cases.size(); ++n) {
      PadParams p;
      p.physics_subsamples = k;
      PadSensor pad;
      ASSERT_TRUE(pad.configure(p).ok());
      ObjectSet objects;
      ASSERT_TRUE(objects.configure(cases[n].objs).ok());
      objects.pose(cases[n].T, TrayPose{});
      ContactEval e;
      pad.evaluate(objects, cases[n].T, e);
      const ContactEval ref = referenceEvaluate(p, objects, cases[n].T);
      ASSERT_GT(ref.layer_force, 0.5) << "case " << n;
      EXPECT_EQ(e.housing_force, 0.0);
      EXPECT_EQ(e.active, ref.active);
      EXPECT_NEAR(e.layer_force, ref.layer_force, 1e-9 * ref.layer_force);
      auto near = [&](const auto& A, const auto& B, const char* what) {
        const double scale = std::max(B.cwiseAbs().maxCoeff(), 1e-30);
        EXPECT_LT((A - B).cwiseAbs().maxCoeff(), 1e-9 * scale) << what << " case " << n << " k " << k;
      };
      near(e.W_s, ref.W_s, "W_s");
      // The compression block; the sliding columns (x, y, wz) are checked
      // against finite differences in ContactStiffnessMatchesFiniteDifference.
      near(Eigen::Matrix3d(e.K_s.block<3, 3>(2, 2)), Eigen::Matrix3d(ref.K_s.block<3, 3>(2, 2)), "K_s");
      if (n == 2) {
        ASSERT_GT(ref.tau_tray.cwiseAbs().maxCoeff(), 1e-3);
        near(e.tau_tray, ref.tau_tray, "tau_tray");
        near(e.dW_dth, ref.dW_dth, "dW_dth");
        near(e.dtau_ds, ref.dtau_ds, "dtau_ds");
        near(e.dtau_dth, ref.dtau_dth, "dtau_dth");
      } else {
        EXPECT_EQ(e.tau_tray.cwiseAbs().maxCoeff(), 0.0);
      }
    }
}

TEST(PadContact, SlidingStiffnessMatchesFiniteDifference) {
  // The (x, y, wz) columns of K_s: the penetration field sliding under the
  // sensor, from the analytic surface slopes of the winning primitive. Central
  // differences of W_s (h = 1e-7 m / rad) on an inclined bar (a line load
  // whose depth varies along x), a bar crossing the pad at 30 deg and a
  // sphere. W_s is piecewise smooth (samples enter and leave contact with
  // zero force), so the tolerance is 2 % of the column's scale plus 1e-3 of
  // the compression diagonal.
  ObjectParams inclined;
  inclined.type = ObjectType::Bar;
  inclined.radius = 0.003;
  inclined.vertices = {{-0.1, 0.0007, 0.003 - 0.0008 - 0.1 * 0.01}, {0.1, 0.0007, 0.003 - 0.0008 + 0.1 * 0.01}};
  ObjectParams crossing = inclined;
  const double c30 = std::cos(0.5236), s30 = std::sin(0.5236);
  crossing.vertices = {{-0.1 * c30, -0.1 * s30, 0.003 - 0.0008}, {0.1 * c30, 0.1 * s30, 0.003 - 0.0006}};
  for (const ObjectParams& obj : {inclined, crossing, sphere(0.003, -0.002, 0.02, 0.0012)}) {
    Rig rig({obj});
    ContactEval e0, ep, em;
    rig.pad.evaluate(rig.objects, rig.T, e0);
    ASSERT_GT(e0.layer_force, 0.3);
    const double h = 1e-7;
    for (int a : {0, 1, 5}) {
      KDL::Vector v = KDL::Vector::Zero(), w = KDL::Vector::Zero();
      if (a == 0) v = KDL::Vector(h, 0, 0);
      if (a == 1) v = KDL::Vector(0, h, 0);
      if (a == 5) w = KDL::Vector(0, 0, h);
      const KDL::Frame Tp(rotationFromVector(w), v), Tm(rotationFromVector(-w), -v);
      rig.objects.pose(Tp, TrayPose{});
      rig.pad.evaluate(rig.objects, Tp, ep);
      rig.objects.pose(Tm, TrayPose{});
      rig.pad.evaluate(rig.objects, Tm, em);
      double scale = 0.0;
      for (int b : {2, 3, 4}) scale = std::max(scale, std::fabs((ep.W_s(b) - em.W_s(b)) / (2 * h)));
      for (int b : {2, 3, 4}) {
        const double fd = -(ep.W_s(b) - em.W_s(b)) / (2 * h);
        EXPECT_NEAR(e0.K_s(b, a), fd, 0.02 * scale + 1e-3 * e0.K_s(b, b)) << "object " << toString(obj.type) << " row " << b
                                                                             << " column " << a;
      }
    }
  }
}

TEST(PadContact, NonUniformLineLoadShiftsPressureCentreFromContactCentre) {
  // Eq. 2 / Eq. 3: an edge pressing harder at one end (bar inclined in the
  // x-z plane) moves the pressure centre away from the contact centre:
  // DZMP_y = CoP_x - CoC_x has the sign of the deeper end and grows with the
  // slope; a level edge gives DZMP_y = 0. CoC from the binarised true taxel
  // image (threshold 0.2 N).
  double prev = 0.0;
  for (double slope : {0.0, 0.005, 0.01, 0.02, -0.01}) {
    ObjectParams bar;
    bar.type = ObjectType::Bar;
    bar.radius = 0.003;
    // Along a taxel row (y = 1.7 mm), 1 mm deep at x = 0, deeper where slope * x < 0.
    bar.vertices = {{-0.1, 0.0017, 0.002 - 0.1 * slope}, {0.1, 0.0017, 0.002 + 0.1 * slope}};
    PadParams p;
    p.noise_counts = 0.0;
    Rig rig({bar}, p);
    RawTactileFrame raw;
    SensorTruth truth;
    rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
    const TactileFrame& img = rig.pad.trueTaxelForces();
    double n = 0, cx = 0;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 14; ++c)
        if (img.at(r, c) >= 0.2) {
          n += 1;
          cx += (c - 6.5) * 0.0034;
        }
    ASSERT_GT(n, 0);
    const double dzmp_y = truth.layer.cop_x - cx / n;
    EXPECT_NEAR(truth.wrench_s[4], truth.layer.cop_x * truth.layer.force, 1e-12);  // my = sum x f
    if (slope == 0.0) {
      EXPECT_NEAR(dzmp_y, 0.0, 1e-9);
    } else {
      EXPECT_LT(dzmp_y * slope, 0.0) << slope;  // towards the deeper end (x < 0 for slope > 0)
      if (slope > 0) {
        EXPECT_GT(std::fabs(dzmp_y), prev) << slope;  // grows with the slope
        prev = std::fabs(dzmp_y);
      }
    }
  }
  EXPECT_GT(prev, 0.002);  // 2 % slope: millimetres of DZMP
}

TEST(PadResponse, NoiseStatisticsQuantisationAndThreshold) {
  // Uniform 1 N per taxel (flat punch), noise 6 counts (1 sigma).
  const double f0 = 1.0;
  const double depth = f0 / (PadParams().modulus * 0.0034 * 0.0034);
  Rig rig({flatPunch(depth)});
  const double n0 = rig.pad.countsFor(2, 5, f0);  // interior taxel
  ASSERT_GT(n0, 100.0);
  ASSERT_LT(n0, 4000.0);
  RawTactileFrame raw;
  SensorTruth truth;
  const int N = 4000;
  double s = 0, s2 = 0;
  for (int i = 0; i < N; ++i) {
    rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
    const double c = raw.counts[2 * 14 + 5];
    s += c;
    s2 += c * c;
  }
  const double mean = s / N, sd = std::sqrt(s2 / N - mean * mean);
  // Standard error of the mean 6 / sqrt(4000) = 0.1 count; rounding adds no bias.
  EXPECT_NEAR(mean, n0, 0.5);
  // Sample sd of 4000 normals: relative standard error ~1.1 %; rounding adds
  // 1/12 count^2 of variance. Allow 5 %.
  EXPECT_NEAR(sd, std::sqrt(36.0 + 1.0 / 12.0), 0.05 * 6.0);

  // Noise-free: counts are the rounded response; border taxels weaker.
  PadParams p;
  p.noise_counts = 0.0;
  Rig quiet({flatPunch(depth)}, p);
  quiet.pad.acquire(quiet.objects, quiet.T, 0.0, raw, truth);
  EXPECT_EQ(raw.counts[2 * 14 + 5], static_cast<uint16_t>(std::lround(quiet.pad.countsFor(2, 5, f0))));
  EXPECT_LT(raw.counts[0], raw.counts[2 * 14 + 5]);  // corner taxel: border_sensitivity 0.6
  EXPECT_NEAR(quiet.pad.countsFor(0, 0, f0) / quiet.pad.countsFor(2, 5, f0), 0.6, 0.1);

  // Threshold (0.2 N): 0.15 N per taxel reads 0, 0.25 N does not.
  for (double f : {0.15, 0.25}) {
    Rig t({flatPunch(f / (PadParams().modulus * 0.0034 * 0.0034))}, p);
    t.pad.acquire(t.objects, t.T, 0.0, raw, truth);
    if (f < 0.2)
      EXPECT_EQ(raw.counts[2 * 14 + 5], 0);
    else
      EXPECT_GT(raw.counts[2 * 14 + 5], 0);
  }
}

TEST(PadResponse, SaturatesAtFullScale) {
  PadParams p;
  p.noise_counts = 0.0;
  const double depth = 10.0 / (p.modulus * 0.0034 * 0.0034);  // 10 N per taxel >> ~3 N full scale
  Rig rig({flatPunch(depth)}, p);
  RawTactileFrame raw;
  SensorTruth truth;
  rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
  for (int i = 0; i < 84; ++i) EXPECT_EQ(raw.counts[static_cast<std::size_t>(i)], 4095);
  Calibration cal;
  ASSERT_TRUE(cal.configure(rig.pad.calibration()).ok());
  TactileFrame f;
  EXPECT_EQ(cal.step(raw, f), CalibrationStatus::Saturated);
  EXPECT_EQ(f.saturated_count, 84);
}

TEST(PadResponse, CalibrationInvertsTheResponse) {
  PadParams p;
  p.noise_counts = 0.0;
  Rig rig({sphere(0.004, -0.002, 0.02, 0.0015)}, p);
  RawTactileFrame raw;
  SensorTruth truth;
  rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
  Calibration cal;
  ASSERT_TRUE(cal.configure(rig.pad.calibration()).ok());
  TactileFrame f;
  ASSERT_EQ(cal.step(raw, f), CalibrationStatus::Ok);
  const TactileFrame& tr = rig.pad.trueTaxelForces();
  int checked = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 14; ++c) {
      const double ft = tr.at(r, c);
      if (ft < 0.2) {
        EXPECT_EQ(f.at(r, c), 0.0);
        continue;
      }
      // Error bound: half a count times the local slope df/dn.
      const double n = rig.pad.countsFor(r, c, ft);
      const double slope = rig.pad.forceFor(r, c, n + 1.0) - rig.pad.forceFor(r, c, n);
      EXPECT_NEAR(f.at(r, c), ft, 0.5 * slope + 1e-12) << r << "," << c;
      ++checked;
    }
  EXPECT_GT(checked, 4);
}

TEST(PadResponse, CountsInvertTheCubicResponseExactly) {
  // countsFor() (guess from the inverse table, Newton polish; Newton from the
  // linear guess past the table) against forceFor(), its forward polynomial,
  // from 1 mN to 4 N (past saturation) on an interior and a border taxel, for
  // the default and a general cubic. Tolerance 1e-12 relative: a few
  // roundings of f(n).
  for (int variant = 0; variant < 2; ++variant) {
    PadParams p;
    if (variant == 1) p.response = {4e-4, 3e-8, 1e-11};  // general cubic (Newton path)
    PadSensor pad;
    ASSERT_TRUE(pad.configure(p).ok());
    for (double f = 1e-3; f < 4.0; f *= 1.07)
      for (int r : {0, 2}) {
        const double n = pad.countsFor(r, 5, f);
        ASSERT_GT(n, 0.0);
        EXPECT_NEAR(pad.forceFor(r, 5, n), f, 1e-12 * f) << "variant " << variant << " row " << r << " f " << f;
      }
    EXPECT_EQ(pad.countsFor(2, 5, 0.0), 0.0);
    EXPECT_EQ(pad.countsFor(2, 5, -1.0), 0.0);
    EXPECT_EQ(pad.countsFor(2, 5, std::nan("")), 0.0);
  }
}

TEST(PadResponse, DeterministicForASeed) {
  auto run = [](uint64_t seed) {
    PadParams p;
    p.seed = seed;
    Rig rig({flatPunch(0.0005)}, p);
    RawTactileFrame raw;
    SensorTruth truth;
    std::vector<uint16_t> out;
    for (int i = 0; i < 20; ++i) {
      rig.pad.acquire(rig.objects, rig.T, 0.0, raw, truth);
      out.insert(out.end(), raw.counts.begin(), raw.counts.begin() + 84);
    }
    return out;
  };
  EXPECT_EQ(run(7), run(7));
  EXPECT_NE(run(7), run(8));
}

TEST(PadBadInput, ParametersAreValidated) {
  PadSensor pad;
  PadParams p;
  p.subsamples = 0;
  ConfigResult r = pad.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("sensor.subsamples = 0: must be in [1, 32]"), std::string::npos) << r.message();
  p = PadParams();
  p.housing_size_x = 0.03;  // smaller than the 47.6 mm sensing area
  r = pad.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("sensor.housing_size_x = 0.03: must be in [cols * pitch"), std::string::npos) << r.message();
  p = PadParams();
  p.response[0] = -1.0;
  EXPECT_FALSE(pad.configure(p).ok());
  p = PadParams();
  p.modulus = std::nan("");
  EXPECT_FALSE(pad.configure(p).ok());

  ObjectSet objs;
  ObjectParams o;
  o.name = "weird";
  o.type = static_cast<ObjectType>(99);
  r = objs.configure({o});
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("objects[0] (weird).type"), std::string::npos) << r.message();
  ObjectType t;
  EXPECT_FALSE(parseObjectType("pyramid", t));
  EXPECT_TRUE(parseObjectType("bent_bar", t));
  EXPECT_EQ(t, ObjectType::BentBar);
  o.type = ObjectType::Bar;
  o.vertices = {{0, 0, 0}};
  r = objs.configure({o});
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("vertices"), std::string::npos) << r.message();
}

TEST(PadAllocation, EvaluateAndAcquireDoNotAllocate) {
  ObjectParams bent;
  bent.type = ObjectType::BentBar;
  bent.radius = 0.003;
  bent.vertices = {{-0.2, 0, 0.002}, {-0.05, 0.001, 0.0015}, {0.05, -0.002, 0.0016}, {0.2, 0.01, 0.003}};
  Rig rig({bent, flatPunch(-0.01)});
  ContactEval e;
  RawTactileFrame raw;
  SensorTruth truth;
  tactile::test::AllocationScope scope;
  for (int i = 0; i < 10; ++i) {
    rig.objects.pose(rig.T, TrayPose{});
    rig.pad.evaluate(rig.objects, rig.T, e);
    rig.pad.acquire(rig.objects, rig.T, 0.01 * i, raw, truth);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(e.layer_force, 0.0);
}

TEST(PadResponse, RepeatedAcquisitionEqualsAFullOne) {
  // acquireRepeat() reuses the contact integral of the previous acquire()
  // (World calls it when the sensor and the tray did not move): with the same
  // noise stream it must give bit-identical frames and truth (exact equality:
  // nothing is recomputed differently), and fresh noise on every call.
  ObjectParams bar;
  bar.type = ObjectType::Bar;
  bar.radius = 0.003;
  bar.vertices = {{-0.2, 0.0005, 0.0024}, {0.2, 0.0005, 0.0022}};
  Rig full({bar}), rep({bar});
  RawTactileFrame rf, rr;
  SensorTruth tf, tr;
  int differ = 0;
  std::array<uint16_t, kMaxTaxels> prev{};
  for (int i = 0; i < 5; ++i) {
    const double t = 0.01 * i;
    full.pad.acquire(full.objects, full.T, t, rf, tf);
    if (i == 0)
      rep.pad.acquire(rep.objects, rep.T, t, rr, tr);
    else
      rep.pad.acquireRepeat(t, rr, tr);
    ASSERT_GT(tf.layer.force, 1.0);
    EXPECT_EQ(rr.time_s, rf.time_s);
    EXPECT_EQ(tr.time_s, t);
    EXPECT_EQ(tr.layer.force, tf.layer.force);
    EXPECT_EQ(tr.layer.cop_x, tf.layer.cop_x);
    EXPECT_EQ(tr.layer.cop_y, tf.layer.cop_y);
    EXPECT_EQ(tr.housing_force, tf.housing_force);
    EXPECT_EQ(tr.max_count, tf.max_count);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(tr.wrench_s[static_cast<std::size_t>(k)], tf.wrench_s[static_cast<std::size_t>(k)]);
    for (int k = 0; k < 84; ++k) {
      EXPECT_EQ(rr.counts[static_cast<std::size_t>(k)], rf.counts[static_cast<std::size_t>(k)]);
      EXPECT_EQ(rep.pad.trueTaxelForces().force[static_cast<std::size_t>(k)], full.pad.trueTaxelForces().force[static_cast<std::size_t>(k)]);
    }
    if (i > 0)
      for (int k = 0; k < 84; ++k) differ += rr.counts[static_cast<std::size_t>(k)] != prev[static_cast<std::size_t>(k)];
    prev = rr.counts;
  }
  EXPECT_GT(differ, 0);  // the noise is drawn anew on each repeat
}

TEST(PadContact, LowestPointBoundsEveryColumn) {
  // ObjectSet::lowestPoint() lets the pad skip its housing ring; it must be a
  // lower bound of lowestZ() over the region (else housing contact would be
  // lost), and reasonably tight (within the 0.25 mm grid spacing's effect on
  // a sphere/bar bottom). Random spheres and inclined bars at random poses.
  std::srand(11);
  auto u = [](double a, double b) { return a + (b - a) * (std::rand() / static_cast<double>(RAND_MAX)); };
  int deep = 0;
  for (int n = 0; n < 60; ++n) {
    ObjectParams o;
    if (n % 2 == 0) {
      o.type = ObjectType::Sphere;
      o.radius = u(0.003, 0.03);
      o.center = {u(-0.02, 0.02), u(-0.01, 0.01), o.radius - u(-0.002, 0.004)};
    } else {
      o.type = ObjectType::Bar;
      o.radius = u(0.001, 0.006);
      o.vertices = {{-0.1, u(-0.01, 0.01), o.radius - u(-0.002, 0.004)}, {0.1, u(-0.01, 0.01), o.radius - u(-0.002, 0.004)}};
    }
    ObjectSet objects;
    ASSERT_TRUE(objects.configure({o}).ok());
    objects.setRegion(-0.032, 0.032, -0.017, 0.017);
    objects.pose(KDL::Frame(KDL::Rotation::RPY(u(-0.1, 0.1), u(-0.1, 0.1), u(-1, 1)), KDL::Vector(0, 0, 0)), TrayPose{});
    double zmin = std::numeric_limits<double>::infinity();
    for (double y = -0.017; y <= 0.017; y += 2.5e-4)
      for (double x = -0.032; x <= 0.032; x += 2.5e-4) {
        int w;
        zmin = std::min(zmin, objects.lowestZ(x, y, w));
      }
    if (!(zmin < 0.0)) continue;
    ASSERT_GE(zmin, objects.lowestPoint()) << "object " << n;
    EXPECT_LT(zmin - objects.lowestPoint(), 1e-3) << "object " << n;
    if (zmin < -0.002) ++deep;
  }
  EXPECT_GT(deep, 5);  // some reach below the housing top (recess 2 mm)
}

TEST(PadContact, RowEvaluationIsBitIdenticalToPointQueries) {
  // ObjectSet::lowestZRow (the branch-free row kernel behind acquire() and
  // evaluate()) must return exactly lowestZ() (value and object) at every
  // point: plane, sphere, bar and an inclined bent bar, at a tilted pose, on
  // 200 rows x 300 points over and beyond the pad. Exact equality: same
  // operations in the same order.
  ObjectParams table;
  table.type = ObjectType::Plane;
  table.point = {0.0, 0.0, 0.0};
  table.normal = {0.05, 0.02, -1.0};  // solid above the plane: faces the pad
  ObjectParams ball;
  ball.type = ObjectType::Sphere;
  ball.center = {0.01, -0.004, 0.006};
  ball.radius = 0.008;
  ObjectParams bar;
  bar.type = ObjectType::Bar;
  bar.radius = 0.003;
  bar.vertices = {{-0.2, 0.003, 0.0025}, {0.2, -0.002, 0.0015}};
  ObjectParams bent;
  bent.type = ObjectType::BentBar;
  bent.radius = 0.002;
  bent.vertices = {{-0.03, -0.02, 0.004}, {0.0, 0.0, 0.0005}, {0.01, 0.03, 0.001}, {0.012, 0.03, 0.02}};
  ObjectSet objects;
  ASSERT_TRUE(objects.configure({table, ball, bar, bent}).ok());
  const KDL::Frame T(KDL::Rotation::RPY(0.05, -0.03, 0.2), KDL::Vector(0.001, -0.002, 0.0));
  objects.pose(T, TrayPose{});
  constexpr int n = 300;
  double xs[n], z[n];
  int w[n];
  for (int i = 0; i < n; ++i) xs[i] = -0.04 + 0.08 * i / (n - 1);
  int below = 0, owners[4] = {0, 0, 0, 0};
  for (int r = 0; r < 200; ++r) {
    const double y = -0.025 + 0.05 * r / 199;
    objects.lowestZRow(y, xs, n, z, w);
    for (int i = 0; i < n; ++i) {
      int wi;
      const double zi = objects.lowestZ(xs[i], y, wi);
      ASSERT_EQ(z[i], zi) << "x " << xs[i] << " y " << y;
      ASSERT_EQ(w[i], wi);
      if (zi < 0.0) {
        ++below;
        ++owners[wi];
      }
    }
  }
  EXPECT_GT(below, 1000);
  for (int o = 0; o < 4; ++o) EXPECT_GT(owners[o], 10) << "object " << o;  // every kind is exercised
}
