// tactile::ServoControlLaw alone: Eq. 7-10 and 13 against hand-computed
// numbers, the integrator, the sensor-to-base transform, configuration errors.
#include "alloc_counter.hpp"
#include "servo_test_util.hpp"
#include "tactile_servo/control_law.hpp"

using namespace tactile;
using namespace servo_test;

namespace {
ServoControlLaw configured(const ServoParams& p) {
  ServoControlLaw law;
  const ConfigResult r = law.configure(p);
  EXPECT_TRUE(r.ok()) << r.message();
  return law;
}
}  // namespace

TEST(ControlLaw, Eq7Eq8FeatureErrorTouchDependent) {
  // Same numbers as ServoEquations.Eq7FeatureErrorHandComputed, on the law alone.
  PhaseParams ph = identityPhase("p", 0.1, 1.0);
  ph.s_d << -0.025, 0, 0.0025, 0, 0, 0;
  ServoControlLaw law = configured(singlePhase(ph));
  uint8_t beta = 9;
  Vec6 e = law.featureError(0, makeFeatures(0, 0.01, -0.004, 0.002, 0.006, -0.001, 0.1, ContactType::Edge), beta);
  Vec6 expect;
  expect << -0.035, 0.004, 0.0005, 0.003, -0.004, -0.1;
  EXPECT_EQ(beta, 1);
  EXPECT_LT((e - expect).cwiseAbs().maxCoeff(), 1e-15);
  e = law.featureError(0, makeFeatures(0, 0.01, -0.004, 0.002, 0.006, -0.001, 0.1, ContactType::Point), beta);
  expect << -0.035, 0.004, 0.0005, 0.004, -0.01, 0;
  EXPECT_EQ(beta, 0);
  EXPECT_LT((e - expect).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(law.featureError(7, makeFeatures(0, 1, 1, 1, 1, 1, 1), beta), Vec6::Zero());  // no such phase
  // Baseline (Li et al.) and no_rotation modes: their constant J^-1 whatever
  // the contact, β = 0.
  ServoParams b = singlePhase(ph);
  b.mode = ControllerMode::Baseline;
  ServoControlLaw base = configured(b);
  EXPECT_EQ(base.jacobian(0, ContactType::Edge, beta), liJinv());
  EXPECT_EQ(beta, 0);
  EXPECT_EQ(base.jacobian(0, ContactType::Point, beta), liJinv());
  b.mode = ControllerMode::NoRotation;
  ServoControlLaw norot = configured(b);
  EXPECT_EQ(norot.jacobian(0, ContactType::Edge, beta), noRotationJinv());
  EXPECT_EQ(norot.jacobian(0, ContactType::Point, beta), noRotationJinv());
}

TEST(ControlLaw, Eq9ProjectionAndEq13PiHandComputed) {
  // P = diag(1,1,1,1,1,1) with kp = 0.1, ki = 1/s, dt = 0.01:
  // step 1: PI = 0.11 Δ, step 2: 0.12 Δ; u_s = S PI.
  PhaseParams ph = identityPhase("p", 0.1, 1.0);
  ph.P = projection(1, 1, 1, 1, 1, 1, 0);
  ServoControlLaw law = configured(singlePhase(ph));
  Vec6 d;
  d << -0.035, 0.004, 0.0005, 0.003, -0.004, -0.1;
  const Vec6 task = law.project(0, d);
  EXPECT_EQ(task, d);
  const Vec6 S = defaultMotionSign();
  EXPECT_LT((law.increment(0, task, 0.01) - S.cwiseProduct(0.11 * d)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((law.increment(0, task, 0.01) - S.cwiseProduct(0.12 * d)).cwiseAbs().maxCoeff(), 1e-15);
  law.resetIntegrator();
  EXPECT_EQ(law.integral(), Vec6::Zero());
  // γ_com couples the wy-row error into x (Eq. 10, co-manipulation).
  ph.P = projection(0, 1, 1, 0, 0, 1, 1);
  ServoControlLaw com = configured(singlePhase(ph));
  Vec6 e6;
  e6 << 1, 2, 3, 4, 5, 6;
  Vec6 want;
  want << 5, 2, 3, 0, 0, 6;
  EXPECT_EQ(com.project(0, e6), want);
}

TEST(ControlLaw, Eq13IntegratorClampOutputLimitAndFeedForward) {
  PhaseParams ph = identityPhase("p", 0.0, 10.0);
  ph.integral_limit = Vec6::Constant(1e-4 / kTestPeriod);  // 0.1 mm per cycle
  ph.feedforward << 0, 0, 0.1, 0, 0, 0;  // 1 mm per 10 ms
  ServoControlLaw law = configured(singlePhase(ph));
  Vec6 task = Vec6::Zero();
  task(kZ) = 0.009;
  Vec6 u;
  for (int k = 0; k < 200; ++k) u = law.increment(0, task, 0.01);
  EXPECT_NEAR(u(kZ), 1e-4 + 0.001, 1e-15);   // clamped |K_I ∫| plus feed-forward (S_z = +1)
  EXPECT_NEAR(law.integral()(kZ), 1e-5, 1e-18);  // = integral_limit / K_I (m s)
  ph = identityPhase("p", 1.0, 0.0);
  ph.u_max = Vec6::Constant(2e-4 / kTestPeriod);
  ServoControlLaw lim = configured(singlePhase(ph));
  EXPECT_DOUBLE_EQ(lim.increment(0, task, 0.01)(kZ), 2e-4);
  EXPECT_EQ(lim.integral()(kZ), 0.0);  // K_I = 0: no integral kept
}

TEST(ControlLaw, Eq13SensorToBaseTransformHandComputed) {
  // {g}T{e}: Rz(90 deg), p = (0.5, 0, 0.4); {e}T{s}: Rx(180 deg), p = (0.02, 0, 0.03).
  ServoParams p = singlePhase(identityPhase("p", 0.0, 0.0));
  p.sensor_mount = KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.02, 0, 0.03));
  ServoControlLaw law = configured(p);
  const KDL::Frame T_ge(KDL::Rotation::RotZ(kPi / 2), KDL::Vector(0.5, 0, 0.4));
  Vec6 u = Vec6::Zero();
  u(kX) = 0.001;  // 1 mm along x_s = +y_g
  KDL::Frame T = law.apply(T_ge, u);
  EXPECT_NEAR(T.p.x(), 0.5, 1e-15);
  EXPECT_NEAR(T.p.y(), 0.001, 1e-15);
  EXPECT_NEAR(T.p.z(), 0.4, 1e-15);
  u.setZero();
  u(kWZ) = 0.01;  // about z_s = -z_g through the sensor origin, 20 mm from the flange axis
  T = law.apply(T_ge, u);
  EXPECT_NEAR(T.p.x(), 0.5 - 0.02 * std::sin(0.01), 1e-15);
  EXPECT_NEAR(T.p.y(), 0.02 - 0.02 * std::cos(0.01), 1e-15);
  EXPECT_LT(KDL::diff(T.M, KDL::Rotation::RotZ(kPi / 2 - 0.01)).Norm(), 1e-14);
  EXPECT_TRUE(KDL::Equal(law.apply(T_ge, Vec6::Zero()), T_ge, 1e-15));
}

TEST(ControlLaw, ConfigurationErrorsNameTheKey) {
  ServoParams p = singlePhase(identityPhase("p", 0.1, 0.1));
  p.source = "prog.yaml";
  ServoControlLaw law;
  ServoParams q = p;
  q.c_z = 0.0;
  EXPECT_NE(law.configure(q).message().find("prog.yaml: controller.c_z = 0: must be > 0 m/N"), std::string::npos);
  q = p;
  q.motion_sign(kWY) = 0.5;
  EXPECT_NE(law.configure(q).message().find("motion_sign.wy"), std::string::npos);
  q = p;
  q.phases[0].ki(kY) = -1.0;
  EXPECT_NE(law.configure(q).message().find("phases.p.ki_per_s2.y"), std::string::npos);
  q = p;
  q.phases[0].feedforward(kZ) = 0.6;
  EXPECT_NE(law.configure(q).message().find("[-0.5, 0.5]"), std::string::npos);
  EXPECT_FALSE(law.configured());
  EXPECT_TRUE(law.configure(p).ok());
}

TEST(ControlLaw, NoAllocationPerCycle) {
  ServoControlLaw law = configured(loadShipped("edge_exploration.yaml"));
  const KDL::Frame T(KDL::Rotation::RotX(kPi), KDL::Vector(0.5, 0, 0.3));
  tactile::test::AllocationScope scope;
  double sink = 0.0;
  for (int k = 0; k < 1000; ++k) {
    uint8_t beta = 0;
    const int ph = k % law.phaseCount();
    const Vec6 e = law.featureError(ph, makeFeatures(0, 0.001 * (k % 7), 0, 0.002, 0, 0, 0.1), beta);
    const Vec6 u = law.increment(ph, law.project(ph, e), 0.01);
    sink += law.apply(T, u).p.z();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_TRUE(std::isfinite(sink));
}

TEST(ControlLaw, UndefinedAlphaAndMultipleContactsDriveNoRotationAboutZ) {
  // alpha_z within the noise (features: alpha_defined = false) must not
  // drive the alpha_z row; a multiple contact gets no edge Jacobian (Eq. 8, beta = 0).
  PhaseParams ph = identityPhase("p", 0.1, 1.0);
  ServoControlLaw law = configured(singlePhase(ph));
  uint8_t beta = 9;
  ContactFeatures f = makeFeatures(0, 0.01, -0.004, 0.002, 0.006, -0.001, 0.3, ContactType::Edge);
  ASSERT_TRUE(f.alpha_defined);
  EXPECT_NEAR(law.featureError(0, f, beta)(5), -0.3, 1e-15);
  EXPECT_EQ(beta, 1);
  f.alpha_defined = false;
  EXPECT_EQ(law.featureError(0, f, beta)(5), 0.0);
  f.contact = ContactType::Multiple;
  const Vec6 e = law.featureError(0, f, beta);
  EXPECT_EQ(beta, 0);
  EXPECT_EQ(e(5), 0.0);
  EXPECT_NEAR(e(3), -f.cop_y, 1e-15);  // point rows: CoP, no DZMP
}
