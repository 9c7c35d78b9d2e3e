// Headless KUKA LWR 4+ arm: KDL chain, forward kinematics, Jacobian, joint-space
// rigid-body dynamics (KDL::ChainDynParam) and the robot's own Cartesian
// impedance law (paper Eq. 11):
//
//     tau = J^T ( K (x_d - x) - D xdot ) + g(q)            (Eq. 11)
//
// with the contact wrench acting on the flange: tau_ext = J^T W_contact.
//
// Kinematics: DH as used by the public LWR stacks (standard DH, a = 0):
//   alpha = [pi/2, -pi/2, -pi/2, pi/2, pi/2, -pi/2, 0],
//   d     = [0.31, 0, 0.4, 0, 0.39, 0, 0.078] m,
//   joint limits +-170 deg (joints 1,3,5,7) / +-120 deg (joints 2,4,6).
// q = 0 is the stretched (singular) configuration with the flange at
// z = 1.178 m above the base.
//
// Frames: {g} base, {e} flange (conventions.hpp). Twists and wrenches are
// [v; w] / [f; m], expressed in {g}, reference point at the flange origin
// (what KDL::ChainJntToJacSolver returns).
//
// Stiffness is isotropic (k_trans N/m, k_rot N m/rad); damping follows
// D = 2 * zeta * sqrt(K * Lambda), with Lambda the Cartesian inertia at the
// configure-time posture (translational mean and rotational mean of its
// diagonal), computed once in configure().
//
// Per-cycle calls (stepDynamics, settle, forward, jacobian, ...) do not
// allocate, do not throw and never read a clock.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include <Eigen/Core>
#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>

#include "tactile_types/config_result.hpp"
#include "tactile_types/kdl_pose.hpp"
#include "tactile_types/types.hpp"

namespace KDL {
class ChainDynParam;
}  // namespace KDL

namespace tactile {
namespace sim {

constexpr int kLwrJoints = 7;
static_assert(kLwrJoints == kArmJoints, "the simulated arm is the LWR 4+ of tactile_types");
/// -kArmJointLimit: the LWR's lower joint limits (rad).
constexpr std::array<double, kLwrJoints> lwrLowerLimits() {
  std::array<double, kLwrJoints> q{};
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = -kArmJointLimit[i];
  return q;
}
using JointVec = Eigen::Matrix<double, kLwrJoints, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Jac67 = Eigen::Matrix<double, 6, kLwrJoints>;

/// Status of the arm and of the whole simulator, ordered by severity.
/// Values >= kSimStatusFatal mean "stop the run" (the state stays finite).
enum class SimStatus : uint8_t {
  Ok = 0,
  InvalidCommand = 1,   ///< NaN/Inf/non-unit command: last valid command held
  NotConverged = 2,     ///< quasi-static solve hit its iteration cap (state usable)
  StepRejected = 3,     ///< dt not in (0, max_step_s]: the step is refused, state and time unchanged
  JointLimit = 10,      ///< a joint reached its limit: clamped there, velocity zeroed
  Singularity = 11,     ///< manipulability below arm.min_manipulability
  ForceCeiling = 12,    ///< contact force above world.force_ceiling
  NumericalFailure = 13,///< NaN state or failed solve: previous state restored
  NotConfigured = 14
};
constexpr uint8_t kSimStatusFatal = 10;
inline bool fatal(SimStatus s) { return static_cast<uint8_t>(s) >= kSimStatusFatal; }
const char* toString(SimStatus s);

/// Inertial data of one link, in that link's DH frame (KDL segment tip frame).
struct LinkInertia {
  double mass = 1.0;                          ///< kg
  std::array<double, 3> com{0.0, 0.0, 0.0};   ///< m
  std::array<double, 3> inertia{0.01, 0.01, 0.01};  ///< principal moments about the COM (kg m^2)
};

struct ArmParams {
  /// Initial joint angles (rad); also the null-space rest posture. Default:
  /// flange pointing down (z_e = -z_g) at about (0.58, 0, 0.40) m.
  std::array<double, kLwrJoints> q_init{0.0, -0.6, 0.0, 1.4, 0.0, -1.1416, 0.0};
  std::array<double, kLwrJoints> q_min = lwrLowerLimits();
  std::array<double, kLwrJoints> q_max = kArmJointLimit;  ///< the LWR's range, as the servo's joint_margin reads it
  double k_trans = 1000.0;        ///< N/m (paper default), Eq. 11
  double k_rot = 100.0;           ///< N m/rad
  double damping_ratio = 0.7;     ///< zeta (paper default)
  double null_stiffness = 2.0;    ///< N m/rad, pulls toward q_init in the null space (dynamics)
  double null_damping = 1.0;      ///< N m s/rad in the null space (dynamics)
  double joint_damping = 0.0;     ///< N m s/rad on every joint (dynamics; viscous friction)
  double min_manipulability = 1e-3;  ///< sqrt(det(J J^T)) below this -> Singularity
  double max_joint_speed = 3.0;   ///< rad/s, clamp in dynamics (LWR: ~110-180 deg/s)
  std::array<double, 3> gravity{0.0, 0.0, -9.81};  ///< m/s^2 in {g}
  /// Plausible LWR 4+ link data (about 15 kg in total); link 7 includes the
  /// sensor and adapter (tool_mass).
  std::array<LinkInertia, kLwrJoints> links{{
      {2.7, {0.0, -0.06, 0.0}, {0.020, 0.020, 0.010}},
      {2.7, {0.0, 0.0, 0.20}, {0.040, 0.040, 0.010}},
      {2.5, {0.0, 0.06, 0.0}, {0.020, 0.020, 0.010}},
      {2.5, {0.0, 0.0, 0.20}, {0.035, 0.035, 0.008}},
      {1.7, {0.0, -0.05, 0.0}, {0.010, 0.010, 0.005}},
      {1.6, {0.0, 0.0, 0.0}, {0.006, 0.006, 0.004}},
      {0.3, {0.0, 0.0, 0.0}, {0.0005, 0.0005, 0.0005}}}};
  double tool_mass = 0.25;                          ///< kg, sensor + adapter on the flange
  std::array<double, 3> tool_com{0.0, 0.0, 0.015};  ///< m in {e}
  /// Quasi-static differential IK (settle()): iterations and damping.
  int ik_iterations = 6;
  double ik_damping = 1e-4;       ///< lambda of (J J^T + lambda^2 I)
  /// Dynamics: M(q) and the Coriolis torque C(q, qd) qd (two KDL recursions)
  /// are re-evaluated only when q moved by more than dyn_refresh_q (rad, max
  /// over the joints) or qd changed by more than dyn_refresh_qd (rad/s) since
  /// they were last evaluated; 0 and 0 = every step. The defaults keep the
  /// relative error of M below ~1e-4 and that of C qd below ~1e-3 N m.
  double dyn_refresh_q = 1e-4;
  double dyn_refresh_qd = 1e-2;
};

/// Joint-space state of the arm.
struct ArmState {
  JointVec q = JointVec::Zero();
  JointVec qd = JointVec::Zero();
  KDL::Frame T_ge;            ///< flange pose {g}T{e} (FK of q)
  Vec6 twist = Vec6::Zero();  ///< flange twist in {g} at the flange (J qd)
  double manipulability = 0.0;
};

class LwrArm {
 public:
  LwrArm();
  ~LwrArm();
  LwrArm(const LwrArm&) = delete;
  LwrArm& operator=(const LwrArm&) = delete;

  /// Validates (names the parameter and its range) and builds chain and solvers.
  ConfigResult configure(const ArmParams& params);
  bool configured() const { return configured_; }
  const ArmParams& params() const { return params_; }
  const KDL::Chain& chain() const { return chain_; }

  /// Resets the state to q (rest) without checks; recomputes FK.
  void reset(const JointVec& q);
  const ArmState& state() const { return state_; }

  // ---- kinematics (no allocation) ------------------------------------------
  void forward(const JointVec& q, KDL::Frame& T_ge) const;
  void jacobian(const JointVec& q, Jac67& J) const;
  /// FK and Jacobian in one pass over the chain (same conventions as
  /// forward() and jacobian(): {g}, reference point at the flange).
  void kinematics(const JointVec& q, KDL::Frame& T_ge, Jac67& J) const;
  static double manipulability(const Jac67& J);  ///< sqrt(det(J J^T))

  // ---- impedance (Eq. 11) ---------------------------------------------------
  /// Cartesian impedance wrench K (x_d - x) - D xdot in {g} at the flange.
  Vec6 impedanceWrench(const KDL::Frame& T_cmd, const KDL::Frame& T, const Vec6& twist) const;
  double kTrans() const { return params_.k_trans; }
  double kRot() const { return params_.k_rot; }
  double dTrans() const { return d_trans_; }  ///< N s/m, from the damping ratio
  double dRot() const { return d_rot_; }      ///< N m s/rad

  /// Rigid-body dynamics step (semi-implicit Euler):
  ///   M qdd = J^T (K (x_d - x) - D xdot + W_ext) + tau_null - C(q, qd) - d_j qd
  /// (gravity cancels: the robot compensates g(q) with its own model, Eq. 11).
  /// W_ext: external wrench on the flange ({g}, reference point flange).
  SimStatus stepDynamics(const KDL::Frame& T_cmd, const Vec6& W_ext, double dt);

  /// Quasi-static: move the joints (damped differential IK from the current q)
  /// so that the flange reaches T_target; clamps at joint limits. qd is set to
  /// the finite difference over dt (zero when dt <= 0).
  SimStatus settle(const KDL::Frame& T_target, double dt = 0.0);

  /// Quasi-static hold: zero joint and Cartesian velocity, pose unchanged.
  void hold() {
    state_.qd.setZero();
    state_.twist.setZero();
  }

  /// Joint-space inertia matrix at q (for tests / effective masses).
  void massMatrix(const JointVec& q, Eigen::Matrix<double, 7, 7>& M) const;
  /// Gravity torque g(q).
  void gravity(const JointVec& q, JointVec& g) const;

 private:
  SimStatus checkState();
  void refreshKinematics();

  bool configured_ = false;
  ArmParams params_;
  KDL::Chain chain_;
  KDL::Frame jointToTip(int i, double q) const;  ///< RotZ(q) * tips_[i]
  KDL::Frame tips_[kLwrJoints];  ///< segment i: joint frame -> tip (DH), from the chain
  std::unique_ptr<KDL::ChainDynParam> dyn_;
  // Pre-sized KDL buffers (mutable: KDL solvers take non-const outputs).
  mutable KDL::JntArray kq_, kqd_, kout_;
  mutable KDL::JntSpaceInertiaMatrix kM_;
  ArmState state_;
  Jac67 J_ = Jac67::Zero();
  JointVec q_rest_ = JointVec::Zero(), q_min_ = JointVec::Zero(), q_max_ = JointVec::Zero();
  double d_trans_ = 0.0, d_rot_ = 0.0;
  // Cached M(q_dyn_) and C(q_dyn_, qd_dyn_) qd_dyn_ (see ArmParams::dyn_refresh_q).
  Eigen::Matrix<double, 7, 7> M_dyn_ = Eigen::Matrix<double, 7, 7>::Zero();
  JointVec C_dyn_ = JointVec::Zero(), q_dyn_ = JointVec::Zero(), qd_dyn_ = JointVec::Zero();
  bool dyn_valid_ = false;
  long dyn_evaluations_ = 0;

 public:
  /// Number of M/C evaluations by stepDynamics() since configure() (for tests/benchmarks).
  long dynEvaluations() const { return dyn_evaluations_; }
};

/// tactile::Pose <-> KDL::Frame.
using tactile::toFrame;  // tactile_types/kdl_pose.hpp
using tactile::toPose;
/// Rotation matrix of a rotation vector (Rodrigues), exact for small angles
/// (KDL::Rot and KDL::addDelta return the identity below ~1e-6 rad).
KDL::Rotation rotationFromVector(const KDL::Vector& w);
/// The project's pose-validity rule (finite, unit quaternion; tactile_types/types.hpp).
using tactile::validPose;

}  // namespace sim
}  // namespace tactile
