// Equations against hand-computed numbers, the paper's matrices (Eq. 16-20)
// reproduced from the shipped programs, App. C Table C.3 reciprocity.
#include <random>

#include "servo_test_util.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

Mat6 mat(std::initializer_list<double> v) {
  Mat6 m;
  auto it = v.begin();
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) m(r, c) = *it++;
  return m;
}

// J^-1 the configured core uses for `phase` and contact type `c`; also checks
// that Eq. 7 in the core applies exactly this matrix (column j = J e_j).
Mat6 effectiveJinv(const TactileServo& s, int phase, ContactType c) {
  const Mat6 j = s.jacobian(phase, c);
  for (int k = 0; k < 6; ++k) {
    ContactFeatures f = makeFeatures(0, 0, 0, 0, 0, 0, 0, c);
    double* fields[6] = {&f.cop_x, &f.cop_y, &f.d_z, &f.coc_x, &f.coc_y, &f.alpha_z};
    *fields[k] = 1.0;
    const Vec6 col = s.phase(phase).s_d - s.featureError(phase, f);
    EXPECT_LT((col - j.col(k)).cwiseAbs().maxCoeff(), 1e-15) << "column " << k;  // s_d - (s_d - J e) rounding
  }
  return j;
}

// Paper matrices, written out by hand (see servo.hpp for the 6x6 reading).
const Mat6 kJ16 = mat({1, 0, 0, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       0, 0, 1, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       1, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 0});
const Mat6 kJ17 = mat({1, 0, 0, 0, 0, 0,   //
                       0, 1, 0, 0, 0, 0,   //
                       0, 0, 1, 0, 0, 0,   //
                       0, 1, 0, 0, -1, 0,  //
                       1, 0, 0, -1, 0, 0,  //
                       0, 0, 0, 0, 0, 1});
const Mat6 kP16 = mat({0, 0, 0, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       0, 0, 1, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 1, 0,  //
                       0, 0, 0, 0, 0, 0});
const Mat6 kP17 = mat({0, 0, 0, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       0, 0, 1, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 1, 0,  //
                       0, 0, 0, 0, 0, 1});
const Mat6 kP18 = mat({1, 0, 0, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       0, 0, 1, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 1, 0,  //
                       0, 0, 0, 0, 0, 1});
const Mat6 kP20 = mat({0, 0, 0, 0, 1, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       0, 0, 1, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 1});

}  // namespace

TEST(ServoEquations, Eq8JacobianMatchesHandWrittenForm) {
  EXPECT_EQ(paperJinv(0.0), kJ16);
  EXPECT_EQ(paperJinv(1.0), kJ17);
  const Mat6 base = mat({1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0,  //
                         0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1});
  EXPECT_EQ(noRotationJinv(), base);
  // Li et al. (RSS 2013): CoP_x, CoP_y, d_z, alpha_z; wx from CoP_y, wy from
  // CoP_x (rolling), no CoC column (no DZMP, Eq. 3).
  const Mat6 li = mat({1, 0, 0, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       0, 0, 1, 0, 0, 0,  //
                       0, 1, 0, 0, 0, 0,  //
                       1, 0, 0, 0, 0, 0,  //
                       0, 0, 0, 0, 0, 1});
  EXPECT_EQ(liJinv(), li);
  // It is Eq. 8 for a point (β = 0) plus the alpha_z row, and it differs from
  // the edge form (β = 1) exactly in the CoC columns and nowhere else.
  Mat6 d16 = liJinv() - paperJinv(0.0);
  EXPECT_EQ(d16(5, 5), 1.0);
  d16(5, 5) = 0.0;
  EXPECT_TRUE(d16.isZero());
  const Mat6 d17 = liJinv() - paperJinv(1.0);
  EXPECT_TRUE(d17.leftCols(3).isZero());
  EXPECT_TRUE(d17.rightCols(1).isZero());
  EXPECT_EQ(d17(3, 4), 1.0);
  EXPECT_EQ(d17(4, 3), 1.0);
}

TEST(ServoEquations, ControllerModeNames) {
  for (ControllerMode m : {ControllerMode::Proposed, ControllerMode::Baseline, ControllerMode::NoRotation}) {
    ControllerMode back = m == ControllerMode::Proposed ? ControllerMode::NoRotation : ControllerMode::Proposed;
    EXPECT_TRUE(parseControllerMode(toString(m), back)) << toString(m);
    EXPECT_EQ(back, m);
  }
  EXPECT_STREQ(toString(ControllerMode::Baseline), "baseline");
  EXPECT_STREQ(toString(ControllerMode::NoRotation), "no_rotation");
  for (const char* bad : {"", "Baseline", "li", "no-rotation", "proposed "}) {
    ControllerMode m = ControllerMode::NoRotation;
    EXPECT_FALSE(parseControllerMode(bad, m)) << bad;
    EXPECT_EQ(m, ControllerMode::NoRotation) << bad;
  }
}

TEST(ServoEquations, Eq7FeatureErrorHandComputed) {
  // s = [CoP_x, CoP_y, d_z, CoC_x, CoC_y, alpha_z] = [0.01, -0.004, 0.002, 0.006, -0.001, 0.1]
  // s_d = [-0.025, 0, 0.0025, 0, 0, 0]
  // edge  (β=1): J s = [0.01, -0.004, 0.002, -0.003, 0.004, 0.1] -> Δs = [-0.035, 0.004, 0.0005, 0.003, -0.004, -0.1]
  // point (β=0): J s = [0.01, -0.004, 0.002, -0.004, 0.01, 0]    -> Δs = [-0.035, 0.004, 0.0005, 0.004, -0.01, 0]
  PhaseParams ph = identityPhase("p", 0.1, 1.0);
  ph.s_d << -0.025, 0, 0.0025, 0, 0, 0;
  TactileServo s;
  ASSERT_TRUE(s.configure(singlePhase(ph)).ok());
  uint8_t beta = 9;
  Vec6 e = s.featureError(0, makeFeatures(0, 0.01, -0.004, 0.002, 0.006, -0.001, 0.1, ContactType::Edge), &beta);
  Vec6 expect;
  expect << -0.035, 0.004, 0.0005, 0.003, -0.004, -0.1;
  EXPECT_EQ(beta, 1);
  EXPECT_LT((e - expect).cwiseAbs().maxCoeff(), 1e-15);  // a few ulps of the inputs
  e = s.featureError(0, makeFeatures(0, 0.01, -0.004, 0.002, 0.006, -0.001, 0.1, ContactType::Point), &beta);
  expect << -0.035, 0.004, 0.0005, 0.004, -0.01, 0;
  EXPECT_EQ(beta, 0);
  EXPECT_LT((e - expect).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ServoEquations, Eq9Eq10ProjectionWithComanipulationCoupling) {
  Vec6 ds;
  ds << 1, 2, 3, 4, 5, 6;
  Vec6 expect;  // γ = (0,1,1,0,0,1), γ_com = 1: row x takes the wy-row error
  expect << 5, 2, 3, 0, 0, 6;
  EXPECT_EQ(projection(0, 1, 1, 0, 0, 1, 1) * ds, expect);
  EXPECT_EQ(projection(0, 1, 1, 0, 0, 1, 1), kP20);
}

TEST(ServoEquations, Eq13PiAndMotionSignHandComputed) {
  // P = I, kp = 0.1, ki = 1/s, dt = 0.01, Δs as in the edge case above.
  // step 1: PI = Δ (0.1 + 1*0.01) = 0.11 Δ; step 2: 0.12 Δ; u_s = S PI.
  PhaseParams ph = identityPhase("p", 0.1, 1.0);
  ph.s_d << -0.025, 0, 0.0025, 0, 0, 0;
  TactileServo s;
  ASSERT_TRUE(s.configure(singlePhase(ph)).ok());
  ServoInput in;
  in.flange_measured = Pose();  // the robot at the base origin
  in.features = makeFeatures(0, 0.01, -0.004, 0.002, 0.006, -0.001, 0.1, ContactType::Edge);
  ServoOutput out;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);  // commands the measured pose
  EXPECT_EQ(out.u_s, Vec6::Zero());
  Vec6 d;
  d << -0.035, 0.004, 0.0005, 0.003, -0.004, -0.1;
  Vec6 S;
  S << -1, -1, 1, 1, -1, -1;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Ok);
  Vec6 u1;
  u1 << 0.00385, -0.00044, 0.000055, 0.00033, 0.00044, 0.011;  // by hand: S * 0.11 * Δ
  EXPECT_LT((out.u_s - u1).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((out.error_task - d).cwiseAbs().maxCoeff(), 1e-15);
  in.time_s = 0.01;
  in.features.time_s = 0.01;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Ok);
  EXPECT_LT((out.u_s - S.cwiseProduct(0.12 * d)).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ServoEquations, Eq13IntegratorClampAndOutputLimit) {
  PhaseParams ph = identityPhase("p", 0.0, 10.0);
  ph.integral_limit = Vec6::Constant(1e-4 / kTestPeriod);  // |K_I ∫| <= 0.1 mm per cycle (10 mm/s)
  ph.s_d(kZ) = 0.01;                          // Δd_z = 0.01 - 0.001 = 0.009 m
  TactileServo s;
  ServoParams sp = singlePhase(ph);
  sp.watchdogs.stall_window_s = 0.0;  // no arm here: the measured pose never moves
  ASSERT_TRUE(s.configure(sp).ok());
  ServoInput in;
  in.flange_measured = Pose();
  ServoOutput out;
  for (int k = 0; k < 200; ++k) {
    in.time_s = 0.01 * k;
    in.features = makeFeatures(in.time_s, 0, 0, 0.001, 0, 0, 0, ContactType::Point);
    s.step(in, 0.01, out);
  }
  EXPECT_NEAR(out.u_s(kZ), 1e-4, 1e-15);  // clamped (unclamped: 10 * 0.009 * 2 = 0.18 m per cycle)
  // u_max caps the PI output per axis.
  ph = identityPhase("p", 1.0, 0.0);
  ph.u_max = Vec6::Constant(2e-4 / kTestPeriod);  // 0.2 mm per cycle
  ph.s_d(kZ) = 0.01;
  ASSERT_TRUE(s.configure(singlePhase(ph)).ok());
  in.features.time_s = in.time_s = 0;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);  // configure() started over
  s.step(in, 0.01, out);
  EXPECT_DOUBLE_EQ(out.u_s(kZ), 2e-4);
}

TEST(ServoEquations, Eq13SensorToBaseTransformHandComputed) {
  // {g}T{e}: Rz(90 deg), p = (0.5, 0, 0.4); {e}T{s}: Rx(180 deg), p = (0.02, 0, 0.03).
  // R_gs = Rz90 Rx180: x_s -> +y_g, z_s -> -z_g; sensor origin at (0.5, 0.02, 0.43).
  ServoParams p = singlePhase(identityPhase("p", 0.0, 0.0));
  p.sensor_mount = KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.02, 0, 0.03));
  const KDL::Frame T_ge(KDL::Rotation::RotZ(kPi / 2), KDL::Vector(0.5, 0, 0.4));
  // (a) translation 1 mm along x_s -> the flange moves +1 mm along y_g.
  p.phases[0].feedforward << 0.1, 0, 0, 0, 0, 0;  // 0.1 m/s * 0.01 s
  TactileServo s;
  const ConfigResult cr = s.configure(p);
  ASSERT_TRUE(cr.ok()) << cr.message();
  ServoInput in;
  in.flange_measured = toPose(T_ge);
  in.features = makeFeatures(0, 0, 0, 0.001, 0, 0, 0);
  ServoOutput out;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
  EXPECT_EQ(out.command.pose.p, in.flange_measured.p);  // the first command is the measured pose
  s.step(in, 0.01, out);
  EXPECT_NEAR(out.command.pose.p[0], 0.5, 1e-15);
  EXPECT_NEAR(out.command.pose.p[1], 0.001, 1e-15);
  EXPECT_NEAR(out.command.pose.p[2], 0.4, 1e-15);
  EXPECT_LT(rotDist(out.command.pose, in.flange_measured), 1e-15);
  // (b) rotation 0.01 rad about z_s (= -z_g) through the sensor origin: the
  // flange, 20 mm off that axis, swings: p = (0.5 - 0.02 sin 0.01, 0.02 - 0.02 cos 0.01, 0.4),
  // R = Rz(90 deg - 0.01).
  p.phases[0].feedforward << 0, 0, 0, 0, 0, 0.5;  // 0.5 rad/s * 0.02 s
  ASSERT_TRUE(s.configure(p).ok());
  ASSERT_EQ(s.step(in, 0.02, out), ServoStatus::Starting);
  s.step(in, 0.02, out);
  EXPECT_NEAR(out.command.pose.p[0], 0.5 - 0.02 * std::sin(0.01), 1e-15);
  EXPECT_NEAR(out.command.pose.p[1], 0.02 - 0.02 * std::cos(0.01), 1e-15);
  EXPECT_NEAR(out.command.pose.p[2], 0.4, 1e-15);
  const Pose expect = toPose(KDL::Frame(KDL::Rotation::RotZ(kPi / 2 - 0.01)));
  EXPECT_LT(rotDist(out.command.pose, expect), 1e-14);
}

TEST(ServoEquations, Eq12MeasuredVersusEq15Integrated) {
  ServoParams p = singlePhase(identityPhase("p", 0.0, 0.0));
  p.phases[0].feedforward << 0, 0, 0.1, 0, 0, 0;  // 1 mm per 10 ms cycle along z_s
  ServoInput in;
  in.flange_measured = Pose();  // measured pose stays at the origin (robot does not move)
  in.features = makeFeatures(0, 0, 0, 0.001, 0, 0, 0);
  ServoOutput out;
  for (PoseUpdate mode : {PoseUpdate::Measured, PoseUpdate::Integrated}) {
    p.pose_update = mode;
    TactileServo s;
    ASSERT_TRUE(s.configure(p).ok());
    in.time_s = in.features.time_s = 0.0;
    ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);  // x(0) = the measured pose
    for (int k = 0; k < 3; ++k) {
      in.time_s = in.features.time_s = 0.01 * k;
      s.step(in, 0.01, out);
    }
    // Eq. 12: x_d = x_a + u = 1 mm; Eq. 15: x(t) = x(t-1) + u -> 3 mm.
    EXPECT_NEAR(out.command.pose.p[2], mode == PoseUpdate::Measured ? 0.001 : 0.003, 1e-15);
  }
}

TEST(ServoEquations, PaperMatricesReproducedFromShippedPrograms) {
  TactileServo s;
  ASSERT_TRUE(s.configure(loadShipped("edge_exploration.yaml")).ok());
  ASSERT_EQ(s.phaseCount(), 5);
  // Phase I: P = 0 (free motion).
  EXPECT_EQ(s.phase(s.phaseIndexOf("free_motion")).P, Mat6::Zero());
  // Phase II, point contact: Eq. 16.
  const int p2 = s.phaseIndexOf("align"), p3 = s.phaseIndexOf("edge_control"), p4 = s.phaseIndexOf("explore");
  EXPECT_EQ(effectiveJinv(s, p2, ContactType::Point), kJ16);
  EXPECT_EQ(s.phase(p2).P, kP16);
  // Phase III, edge: Eq. 17.
  EXPECT_EQ(effectiveJinv(s, p3, ContactType::Edge), kJ17);
  EXPECT_EQ(s.phase(p3).P, kP17);
  // Phase IV: Eq. 18, Jacobian as phase III; CoP_x^des = -0.025 m.
  EXPECT_EQ(effectiveJinv(s, p4, ContactType::Edge), kJ17);
  EXPECT_EQ(s.phase(p4).P, kP18);
  EXPECT_EQ(s.phase(p4).s_d(kX), -0.025);
  EXPECT_NEAR(s.phase(p4).s_d(kZ), 5.0 * s.params().c_z, 1e-18);
  // Co-manipulation: Eq. 19 (for any contact type: β fixed to 1) and Eq. 20.
  ASSERT_TRUE(s.configure(loadShipped("co_manipulation.yaml")).ok());
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Edge), kJ17);
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Point), kJ17);
  EXPECT_EQ(s.phase(0).P, kP20);
  EXPECT_NEAR(s.phase(0).s_d(kZ), 6.0 * s.params().c_z, 1e-18);  // 6 N
  EXPECT_NEAR(s.params().c_z, 1.0 / 1800.0, 1e-9);               // C_z as written in the file (6 digits)
  // Bent bar (Sec. 5.2.1): J^-1 and P of phase IV.
  ASSERT_TRUE(s.configure(loadShipped("bent_bar.yaml")).ok());
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Edge), kJ17);
  EXPECT_EQ(s.phase(0).P, kP18);
  // Baseline (Li et al.) and the no-rotation ablation: their constant J^-1
  // in every phase, whatever the contact, P unchanged.
  ServoParams b = loadShipped("bent_bar.yaml");
  b.mode = ControllerMode::Baseline;
  ASSERT_TRUE(s.configure(b).ok());
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Edge), liJinv());
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Point), liJinv());
  EXPECT_EQ(s.phase(0).P, kP18);
  b.mode = ControllerMode::NoRotation;
  ASSERT_TRUE(s.configure(b).ok());
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Edge), noRotationJinv());
  EXPECT_EQ(effectiveJinv(s, 0, ContactType::Point), noRotationJinv());
  EXPECT_EQ(s.phase(0).P, kP18);
}

// App. C, Table C.3: for a point contact the natural constraint μ_z = w_z = 0
// (no commanded w_z whatever the features); for an edge along x the rotation
// about y is driven by ΔDZMP_y only, about x by ΔDZMP_x only. Checked on one
// step from a fresh core for random features, every axis selected (P = I).
TEST(ServoReciprocity, TableC3PointAndEdge) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  ServoParams p = singlePhase(identityPhase("p", 0.1, 1.0));
  auto command = [&](const ContactFeatures& f) { return servo_test::secondCycleIncrement(p, f); };
  for (int trial = 0; trial < 200; ++trial) {
    const double cx = u(rng), cy = u(rng), dz = 0.001 + std::fabs(u(rng)), ox = u(rng), oy = u(rng), a = 20 * u(rng);
    // Point contact: no w_z.
    const Vec6 up = command(makeFeatures(0, cx, cy, dz, ox, oy, a, ContactType::Point));
    EXPECT_EQ(up(kWZ), 0.0);
    // Point: w_y ~ ΔCoC_x (= CoP_x for a point), w_x ~ ΔCoC_y: shifting CoC alone changes nothing.
    const Vec6 up2 = command(makeFeatures(0, cx, cy, dz, ox + 0.003, oy - 0.002, a, ContactType::Point));
    EXPECT_EQ(up2(kWY), up(kWY));
    EXPECT_EQ(up2(kWX), up(kWX));
    // Edge: w_y depends on DZMP_y = CoP_x - CoC_x only; shift CoP_x and CoC_x
    // together and change every other feature.
    const Vec6 ue = command(makeFeatures(0, cx, cy, dz, ox, oy, a, ContactType::Edge));
    const Vec6 ue2 = command(makeFeatures(0, cx + 0.004, -cy, dz * 2, ox + 0.004, oy + 0.003, -a, ContactType::Edge));
    EXPECT_NEAR(ue2(kWY), ue(kWY), 1e-15);
    // w_x depends on DZMP_x = CoP_y - CoC_y only.
    const Vec6 ue3 = command(makeFeatures(0, -cx, cy + 0.002, dz * 3, ox + 0.001, oy + 0.002, a / 2, ContactType::Edge));
    EXPECT_NEAR(ue3(kWX), ue(kWX), 1e-15);
    // and the edge angle is servoed (artificial constraint w_z ~ Δα_z) unless α_z = 0.
    if (std::fabs(a) > 1e-6) {
      EXPECT_NE(ue(kWZ), 0.0);
    }
  }
}

TEST(ServoReciprocity, NoRotationNeverCommandsRotationsAboutXY) {
  ServoParams p = singlePhase(identityPhase("p", 0.1, 1.0));
  p.mode = ControllerMode::NoRotation;
  TactileServo s;
  ASSERT_TRUE(s.configure(p).ok());
  ServoInput in;
  in.flange_measured = Pose();
  in.features = makeFeatures(0, 0.004, -0.003, 0.002, -0.002, 0.003, 0.2, ContactType::Edge);
  ServoOutput out;
  ASSERT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
  s.step(in, 0.01, out);
  EXPECT_EQ(out.u_s(kWX), 0.0);
  EXPECT_EQ(out.u_s(kWY), 0.0);
  EXPECT_NE(out.u_s(kWZ), 0.0);
  EXPECT_NE(out.u_s(kX), 0.0);
}

// Li et al.'s rows (liJinv): on an edge, the rotation about y_s follows CoP_x
// (rolling to centre the contact), not DZMP_y = CoP_x - CoC_x as Eq. 8 does:
// moving CoC_x alone changes the proposed controller's w_y and not the
// baseline's; moving CoP_x changes both. Same for w_x with CoP_y / CoC_y.
TEST(ServoReciprocity, BaselineRollsOnCoPNotOnDzmp) {
  auto command = [](ControllerMode mode, const ContactFeatures& f) {
    ServoParams p = singlePhase(identityPhase("p", 0.1, 1.0));
    p.mode = mode;
    return servo_test::secondCycleIncrement(p, f);
  };
  const ContactFeatures f = makeFeatures(0, 0.004, -0.003, 0.002, 0.001, 0.002, 0.2, ContactType::Edge);
  const ContactFeatures coc = makeFeatures(0, 0.004, -0.003, 0.002, -0.006, -0.004, 0.2, ContactType::Edge);
  const ContactFeatures cop = makeFeatures(0, -0.005, 0.004, 0.002, 0.001, 0.002, 0.2, ContactType::Edge);
  const Vec6 b = command(ControllerMode::Baseline, f), bc = command(ControllerMode::Baseline, coc),
             bp = command(ControllerMode::Baseline, cop);
  const Vec6 p = command(ControllerMode::Proposed, f), pc = command(ControllerMode::Proposed, coc);
  EXPECT_NE(b(kWY), 0.0);
  EXPECT_NE(b(kWX), 0.0);
  EXPECT_EQ(bc(kWY), b(kWY));
  EXPECT_EQ(bc(kWX), b(kWX));
  EXPECT_NE(bp(kWY), b(kWY));
  EXPECT_NE(bp(kWX), b(kWX));
  EXPECT_NE(pc(kWY), p(kWY));
  EXPECT_NE(pc(kWX), p(kWX));
  // For a point contact the two agree on w_x, w_y (Eq. 8 with β = 0), and the
  // baseline also servoes alpha_z (no touch dependence).
  const ContactFeatures pt = makeFeatures(0, 0.004, -0.003, 0.002, 0.004, -0.003, 0.2, ContactType::Point);
  const Vec6 bpt = command(ControllerMode::Baseline, pt), ppt = command(ControllerMode::Proposed, pt);
  EXPECT_EQ(bpt(kWY), ppt(kWY));
  EXPECT_EQ(bpt(kWX), ppt(kWX));
  EXPECT_EQ(ppt(kWZ), 0.0);
  EXPECT_NE(bpt(kWZ), 0.0);
}
