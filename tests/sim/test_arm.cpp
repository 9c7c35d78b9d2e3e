// LWR 4+ arm: kinematics against hand-computed / independent values, the
// Jacobian against finite differences, the impedance law (Eq. 11) in both
// fidelity levels, limits, singularities, bad input and allocations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include <Eigen/Eigenvalues>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "alloc_counter.hpp"
#include "tactile_sim_lwr/lwr_arm.hpp"
#include "tactile_sim_lwr/world.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {
JointVec J7(double a, double b, double c, double d, double e, double f, double g) {
  JointVec q;
  q << a, b, c, d, e, f, g;
  return q;
}
const JointVec kGeneric = J7(0.3, -0.4, 0.2, 1.1, -0.3, -0.9, 0.5);
}  // namespace

TEST(LwrKinematics, StretchedPoseIsStraightUp) {
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  KDL::Frame T;
  arm.forward(JointVec::Zero(), T);
  // Hand-computed: q = 0 stacks d = 0.31 + 0.4 + 0.39 + 0.078 along z_g, and
  // the alphas sum to zero -> identity orientation. Tolerance: double rounding.
  EXPECT_NEAR(T.p.x(), 0.0, 1e-12);
  EXPECT_NEAR(T.p.y(), 0.0, 1e-12);
  EXPECT_NEAR(T.p.z(), 1.178, 1e-12);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(T.M(i, j), i == j ? 1.0 : 0.0, 1e-12);
}

TEST(LwrKinematics, HandComputedShoulderRotations) {
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  KDL::Frame T;
  // Joint 2 axis at q = 0 is z_1 = RotX(pi/2) z = -y_g. Rotating the vertical
  // arm (0.868 m above the shoulder at z = 0.31) by +90 deg about -y_g lays it
  // along -x_g.
  arm.forward(J7(0, kPi / 2, 0, 0, 0, 0, 0), T);
  EXPECT_NEAR(T.p.x(), -0.868, 1e-12);
  EXPECT_NEAR(T.p.y(), 0.0, 1e-12);
  EXPECT_NEAR(T.p.z(), 0.31, 1e-12);
  // Joint 1 by +90 deg about z_g turns -x_g into -y_g.
  arm.forward(J7(kPi / 2, kPi / 2, 0, 0, 0, 0, 0), T);
  EXPECT_NEAR(T.p.x(), 0.0, 1e-12);
  EXPECT_NEAR(T.p.y(), -0.868, 1e-12);
  EXPECT_NEAR(T.p.z(), 0.31, 1e-12);
}

TEST(LwrKinematics, GenericPoseMatchesIndependentDhProduct) {
  // Reference: numpy product of 4x4 standard-DH matrices (a = 0), computed
  // independently of KDL for q = (0.3, -0.4, 0.2, 1.1, -0.3, -0.9, 0.5).
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  KDL::Frame T;
  arm.forward(kGeneric, T);
  const double R[3][3] = {{-0.72435153, -0.09876847, 0.68231932},
                          {0.01553668, 0.98709508, 0.15937976},
                          {-0.68925574, 0.12604794, -0.7134693}};
  const double p[3] = {0.54717652, 0.23750995, 0.6530593};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(T.p(i), p[i], 1e-8);  // reference printed with 8-9 decimals
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(T.M(i, j), R[i][j], 1e-7);
  }
}

TEST(LwrKinematics, JacobianMatchesFiniteDifferences) {
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  Jac67 J;
  arm.jacobian(kGeneric, J);
  KDL::Frame T0, T1, Tm;
  const double h = 1e-6;
  for (int j = 0; j < kLwrJoints; ++j) {
    JointVec qp = kGeneric, qm = kGeneric;
    qp[j] += h;
    qm[j] -= h;
    arm.forward(qp, T1);
    arm.forward(qm, Tm);
    const KDL::Twist d = KDL::diff(Tm, T1, 2 * h);  // central difference, {g}, flange reference point
    // Central differences at h = 1e-6: truncation O(h^2) ~ 1e-12, rounding ~1e-10.
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(J(i, j), d.vel(i), 1e-7) << "row " << i << " joint " << j;
      EXPECT_NEAR(J(i + 3, j), d.rot(i), 1e-7) << "row " << i + 3 << " joint " << j;
    }
  }
}

TEST(LwrKinematics, FusedPassMatchesKdlSolvers) {
  // kinematics() (one pass) and forward() against KDL's generic solvers
  // (ChainFkSolverPos_recursive, ChainJntToJacSolver) on the same chain, over
  // random postures. Tolerance 1e-12: the same products up to their order and
  // KDL's general joint-axis rotation.
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  KDL::ChainFkSolverPos_recursive fk(arm.chain());
  KDL::ChainJntToJacSolver jac(arm.chain());
  KDL::JntArray kq(kLwrJoints);
  KDL::Jacobian kjac(kLwrJoints);
  std::srand(7);
  for (int n = 0; n < 200; ++n) {
    JointVec q;
    for (int i = 0; i < kLwrJoints; ++i) q[i] = 4.0 * (std::rand() / static_cast<double>(RAND_MAX) - 0.5);
    KDL::Frame Tf, Tfw, Tk;
    Jac67 Jf, Jk;
    arm.kinematics(q, Tf, Jf);
    arm.forward(q, Tfw);
    kq.data = q;
    ASSERT_GE(fk.JntToCart(kq, Tk), 0);
    ASSERT_GE(jac.JntToJac(kq, kjac), 0);
    Jk = kjac.data;
    for (int i = 0; i < 3; ++i) {
      ASSERT_NEAR(Tf.p(i), Tk.p(i), 1e-12);
      ASSERT_NEAR(Tfw.p(i), Tk.p(i), 1e-12);
      for (int j = 0; j < 3; ++j) {
        ASSERT_NEAR(Tf.M(i, j), Tk.M(i, j), 1e-12);
        ASSERT_NEAR(Tfw.M(i, j), Tk.M(i, j), 1e-12);
      }
    }
    ASSERT_LT((Jf - Jk).cwiseAbs().maxCoeff(), 1e-12) << "posture " << n;
  }
}

TEST(LwrKinematics, SettleReachesLargeAndSmallTargetsToTheIkTolerance) {
  // The chord IK (Jacobian of the start posture, refreshed when the error
  // does not shrink 10x per iteration) must converge for a servo-sized step
  // (0.1 mm) within one call and for a 10 cm / 0.3 rad jump within a few.
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  const KDL::Frame T0 = arm.state().T_ge;
  const KDL::Frame small(T0.M, T0.p + KDL::Vector(1e-4, 0.0, 0.0));
  ASSERT_EQ(arm.settle(small, 0.01), SimStatus::Ok);
  KDL::Twist e = KDL::diff(arm.state().T_ge, small);
  EXPECT_LT(e.vel.Norm(), 1e-9);
  EXPECT_LT(e.rot.Norm(), 1e-9);
  KDL::Frame Tcheck;
  arm.forward(arm.state().q, Tcheck);  // T_ge is the FK of the final q
  EXPECT_LT(KDL::diff(Tcheck, arm.state().T_ge).vel.Norm(), 1e-15);
  const KDL::Frame big(KDL::Rotation::RotZ(0.3) * T0.M, T0.p + KDL::Vector(0.1, -0.05, 0.05));
  for (int k = 0; k < 3; ++k) arm.settle(big);
  e = KDL::diff(arm.state().T_ge, big);
  EXPECT_LT(e.vel.Norm(), 1e-9);
  EXPECT_LT(e.rot.Norm(), 1e-9);
}

TEST(LwrDynamics, MassMatrixSymmetricPositiveDefinite) {
  LwrArm arm;
  ASSERT_TRUE(arm.configure(ArmParams()).ok());
  Eigen::Matrix<double, 7, 7> M;
  arm.massMatrix(kGeneric, M);
  EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 7, 7>> es(M);
  EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
  JointVec g;
  arm.gravity(kGeneric, g);
  EXPECT_GT(g.norm(), 1.0);  // ~15 kg arm off the vertical: tens of N m
}

namespace {
WorldParams freeWorld(Fidelity f) {
  WorldParams p;
  p.fidelity = f;
  return p;
}
}  // namespace

class ImpedanceTest : public ::testing::TestWithParam<Fidelity> {};

TEST_P(ImpedanceTest, ConstantWrenchGivesDisplacementFOverK) {
  WorldParams p = freeWorld(GetParam());
  p.external_wrench = {5.0, -3.0, 8.0, 0.2, -0.1, 0.3};
  World w;
  ASSERT_TRUE(w.configure(p).ok());
  const KDL::Frame T0 = w.state().T_ge;
  const Pose cmd = toPose(T0);
  SimState s;
  const double dt = 0.001;
  const int n = GetParam() == Fidelity::QuasiStatic ? 5 : 6000;
  for (int i = 0; i < n; ++i) ASSERT_FALSE(fatal(w.step(cmd, dt, s)));
  const KDL::Twist d = KDL::diff(T0, s.T_ge);
  // Quasi-static: Newton tolerance 1e-4 N / 1000 N/m = 1e-7 m -> 1e-6 m.
  // Dynamics: after 6 s (damping ratio 0.7, ~10 time constants) the transient
  // of the Cartesian and the null-space loops is below 2e-5 m / 2e-4 rad.
  const double tol_p = GetParam() == Fidelity::QuasiStatic ? 1e-6 : 2e-5;
  const double tol_r = GetParam() == Fidelity::QuasiStatic ? 1e-6 : 2e-4;
  EXPECT_NEAR(d.vel.x(), 5.0 / 1000.0, tol_p);
  EXPECT_NEAR(d.vel.y(), -3.0 / 1000.0, tol_p);
  EXPECT_NEAR(d.vel.z(), 8.0 / 1000.0, tol_p);
  EXPECT_NEAR(d.rot.x(), 0.2 / 100.0, tol_r);
  EXPECT_NEAR(d.rot.y(), -0.1 / 100.0, tol_r);
  EXPECT_NEAR(d.rot.z(), 0.3 / 100.0, tol_r);
}

INSTANTIATE_TEST_SUITE_P(Fidelities, ImpedanceTest, ::testing::Values(Fidelity::QuasiStatic, Fidelity::Dynamics));

TEST(LwrDynamics, GravityCompensatedArmStaysAtRest) {
  World w;
  ASSERT_TRUE(w.configure(freeWorld(Fidelity::Dynamics)).ok());
  const JointVec q0 = w.state().q;
  const Pose cmd = toPose(w.state().T_ge);
  SimState s;
  for (int i = 0; i < 2000; ++i) ASSERT_EQ(w.step(cmd, 0.001, s), SimStatus::Ok);
  // g(q) of Eq. 11 cancels the model's gravity exactly: nothing moves.
  EXPECT_LT((s.q - q0).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(LwrDynamics, StepResponseIsStableAndWellDamped) {
  World w;
  ASSERT_TRUE(w.configure(freeWorld(Fidelity::Dynamics)).ok());
  KDL::Frame T0 = w.state().T_ge;
  KDL::Frame Tc = T0;
  Tc.p += KDL::Vector(0.0, 0.0, 0.05);
  const Pose cmd = toPose(Tc);
  SimState s;
  double peak = 0.0, energy_last = 0.0;
  for (int i = 0; i < 4000; ++i) {
    ASSERT_FALSE(fatal(w.step(cmd, 0.001, s)));
    const double z = s.T_ge.p.z() - T0.p.z();
    peak = std::max(peak, z);
    if (i == 3999) energy_last = s.qd.squaredNorm();
  }
  // zeta = 0.7 nominal gives ~5 % overshoot; allow 15 % since the damping is
  // computed from the configure-time Cartesian inertia, not the current one.
  EXPECT_LT(peak, 0.05 * 1.15);
  EXPECT_GT(peak, 0.05 * 0.9);
  EXPECT_NEAR(s.T_ge.p.z() - T0.p.z(), 0.05, 2e-4);  // settled after 4 s
  EXPECT_LT(energy_last, 1e-6);                      // at rest: no sustained oscillation
}

namespace {
/// Relative band (max - min) / E0 of the total energy over 1.5 s of undamped
/// motion under the impedance spring, and the largest kinetic energy / E0.
void energyBand(double dt, double& band, double& kin) {
  WorldParams p;
  p.fidelity = Fidelity::Dynamics;
  p.arm.damping_ratio = 0.0;
  p.arm.null_damping = 0.0;
  p.arm.null_stiffness = 0.0;
  p.arm.max_joint_speed = 100.0;  // the light wrist exceeds the 3 rad/s default clamp here
  World w;
  ASSERT_TRUE(w.configure(p).ok());
  KDL::Frame Tc = w.state().T_ge;
  Tc.p += KDL::Vector(0.02, -0.01, 0.015);
  Tc.M = KDL::Rotation::RPY(0.05, -0.03, 0.04) * Tc.M;
  const Pose cmd = toPose(Tc);
  Eigen::Matrix<double, 7, 7> M;
  double ekin = 0.0;
  auto energy = [&](const SimState& s) {
    w.arm().massMatrix(s.q, M);
    const KDL::Twist e = KDL::diff(s.T_ge, toFrame(cmd));
    ekin = 0.5 * s.qd.dot(M * s.qd);
    return ekin + 0.5 * 1000.0 * KDL::dot(e.vel, e.vel) + 0.5 * 100.0 * KDL::dot(e.rot, e.rot);
  };
  SimState s = w.state();
  const double E0 = energy(s);
  double emin = E0, emax = E0;
  kin = 0.0;
  for (int i = 0; i < static_cast<int>(1.5 / dt); ++i) {
    ASSERT_FALSE(fatal(w.step(cmd, dt, s)));
    const double E = energy(s);
    emin = std::min(emin, E);
    emax = std::max(emax, E);
    kin = std::max(kin, ekin / E0);
  }
  band = (emax - emin) / E0;
}
}  // namespace

TEST(LwrDynamics, UndampedImpedanceConservesEnergy) {
  // With every damping term at zero, the arm under the impedance spring of
  // Eq. 11 is conservative: E = 1/2 qd^T M(q) qd + 1/2 k_t |dp|^2 + 1/2 k_r |dtheta|^2.
  // Semi-implicit Euler keeps the energy error bounded and first order in dt
  // (no drift). A wrong M(q) or Coriolis term would not converge with dt.
  double b1, k1, b2, k2;
  energyBand(0.0005, b1, k1);
  energyBand(0.00025, b2, k2);
  EXPECT_GT(k1, 0.3);        // it really oscillates (kinetic energy > 30 % of E0)
  EXPECT_LT(b1, 0.05);       // measured 4.2 % at 0.5 ms
  EXPECT_LT(b2, 0.6 * b1);   // first-order convergence: halves with dt (measured 2.1 %)
}

TEST(LwrLimits, UnreachableCommandGivesFatalStatusAndFiniteState) {
  for (Fidelity f : {Fidelity::QuasiStatic, Fidelity::Dynamics}) {
    World w;
    ASSERT_TRUE(w.configure(freeWorld(f)).ok());
    KDL::Frame Tc = w.state().T_ge;
    Tc.p = KDL::Vector(0.0, 0.0, 1.6);  // beyond the 1.178 m reach: stretches into a singularity / limit
    SimState s;
    SimStatus st = SimStatus::Ok;
    for (int i = 0; i < 20000 && !fatal(st); ++i) st = w.step(toPose(Tc), 0.001, s);
    EXPECT_TRUE(st == SimStatus::Singularity || st == SimStatus::JointLimit) << toString(st);
    EXPECT_TRUE(s.q.allFinite());
    EXPECT_TRUE(std::isfinite(s.flange_g.p[0]) && std::isfinite(s.flange_g.p[2]));
  }
}

TEST(LwrLimits, JointLimitIsClampedAndReported) {
  WorldParams p = freeWorld(Fidelity::Dynamics);
  p.arm.q_max[6] = 0.2;  // narrow joint 7, then command a yaw of 1 rad about the flange axis
  World w;
  ASSERT_TRUE(w.configure(p).ok());
  KDL::Frame Tc = w.state().T_ge;
  Tc.M = w.state().T_ge.M * KDL::Rotation::RotZ(1.0);
  SimState s;
  SimStatus st = SimStatus::Ok;
  for (int i = 0; i < 5000 && st != SimStatus::JointLimit; ++i) st = w.step(toPose(Tc), 0.001, s);
  const JointVec qa = s.q;
  EXPECT_EQ(st, SimStatus::JointLimit);
  EXPECT_LE(qa[6], 0.2 + 1e-12);
  EXPECT_GE(qa[6], -2.967);
}

TEST(LwrBadInput, ConfigureErrorsNameTheParameter) {
  LwrArm arm;
  ArmParams p;
  p.k_trans = 0.0;
  ConfigResult r = arm.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("arm.k_trans"), std::string::npos) << r.message();
  p = ArmParams();
  p.q_init[3] = 3.0;
  r = arm.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("arm.q_init[3]"), std::string::npos) << r.message();
  p = ArmParams();
  p.q_max[1] = 2.5;  // beyond the +-120 deg hardware limit
  r = arm.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("arm.q_max[1]"), std::string::npos) << r.message();
  p = ArmParams();
  p.damping_ratio = std::nan("");
  EXPECT_FALSE(arm.configure(p).ok());
  // A singular start (stretched arm) is refused by the world.
  WorldParams wp;
  wp.arm.q_init = {0, 0, 0, 0, 0, 0, 0};
  World w;
  r = w.configure(wp);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("manipulability"), std::string::npos) << r.message();
}

TEST(LwrBadInput, NanCommandAndBadDtKeepStateFinite) {
  for (Fidelity f : {Fidelity::QuasiStatic, Fidelity::Dynamics}) {
    World w;
    ASSERT_TRUE(w.configure(freeWorld(f)).ok());
    const Pose good = toPose(w.state().T_ge);
    Pose bad = good;
    bad.p[0] = std::nan("");
    SimState s;
    EXPECT_EQ(w.step(bad, 0.001, s), SimStatus::InvalidCommand);
    EXPECT_TRUE(s.q.allFinite());
    bad = good;
    bad.q = {0, 0, 0, 0};
    EXPECT_EQ(w.step(bad, 0.001, s), SimStatus::InvalidCommand);
    const double t = s.time_s;
    EXPECT_EQ(w.step(good, 0.0, s), SimStatus::StepRejected);
    EXPECT_EQ(w.step(good, -1.0, s), SimStatus::StepRejected);
    EXPECT_EQ(w.step(good, std::numeric_limits<double>::infinity(), s), SimStatus::StepRejected);
    // A step beyond max_step_s (0.01 s by default; the 2 s) is refused too.
    EXPECT_EQ(w.step(good, 2.0, s), SimStatus::StepRejected);
    EXPECT_EQ(w.step(good, 0.0101, s), SimStatus::StepRejected);
    EXPECT_FALSE(fatal(SimStatus::StepRejected));  // the state is intact: the caller decides (EndRule)
    EXPECT_EQ(s.time_s, t);  // time did not advance
    EXPECT_EQ(w.step(good, 0.001, s), SimStatus::Ok);
    EXPECT_NEAR(s.flange_g.p[0], good.p[0], 1e-6);
  }
}
