#include "tactile_sim_lwr/lwr_arm.hpp"

#include "tactile_sim_lwr/sim_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <kdl/chaindynparam.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>
#include <kdl/segment.hpp>

namespace tactile {
namespace sim {

const char* toString(SimStatus s) {
  switch (s) {
    case SimStatus::Ok: return "ok";
    case SimStatus::InvalidCommand: return "invalid_command";
    case SimStatus::NotConverged: return "not_converged";
    case SimStatus::StepRejected: return "step_rejected";
    case SimStatus::JointLimit: return "joint_limit";
    case SimStatus::Singularity: return "singularity";
    case SimStatus::ForceCeiling: return "force_ceiling";
    case SimStatus::NumericalFailure: return "numerical_failure";
    case SimStatus::NotConfigured: return "not_configured";
  }
  return "unknown";
}

KDL::Rotation rotationFromVector(const KDL::Vector& w) {
  const double th2 = KDL::dot(w, w);
  const double th = std::sqrt(th2);
  // R = I + a [w]x + b [w]x^2, a = sin(th)/th, b = (1 - cos(th))/th^2 (series below 1e-4).
  const double a = th < 1e-4 ? 1.0 - th2 / 6.0 : std::sin(th) / th;
  const double b = th < 1e-4 ? 0.5 - th2 / 24.0 : (1.0 - std::cos(th)) / th2;
  const double x = w.x(), y = w.y(), z = w.z();
  return KDL::Rotation(1.0 - b * (y * y + z * z), -a * z + b * x * y, a * y + b * x * z,
                       a * z + b * x * y, 1.0 - b * (x * x + z * z), -a * x + b * y * z,
                       -a * y + b * x * z, a * x + b * y * z, 1.0 - b * (x * x + y * y));
}

namespace {
constexpr double kAlpha[kLwrJoints] = {kPi / 2, -kPi / 2, -kPi / 2, kPi / 2, kPi / 2, -kPi / 2, 0.0};
constexpr double kD[kLwrJoints] = {0.31, 0.0, 0.4, 0.0, 0.39, 0.0, 0.078};

bool finite3(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

Vec6 toVec(const KDL::Twist& t) {
  Vec6 v;
  v << t.vel.x(), t.vel.y(), t.vel.z(), t.rot.x(), t.rot.y(), t.rot.z();
  return v;
}
}  // namespace

LwrArm::LwrArm() = default;
LwrArm::~LwrArm() = default;

ConfigResult LwrArm::configure(const ArmParams& p) {
  configured_ = false;
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (const ConfigResult declared = schema::checkRanges(armSchema(), p, "arm"); !declared) return declared;
  if (!nonneg(p.null_stiffness)) return rangeError("arm.null_stiffness", p.null_stiffness, "must be >= 0 (N m/rad)");
  if (!nonneg(p.null_damping)) return rangeError("arm.null_damping", p.null_damping, "must be >= 0 (N m s/rad)");
  if (!nonneg(p.joint_damping)) return rangeError("arm.joint_damping", p.joint_damping, "must be >= 0 (N m s/rad)");
  if (!nonneg(p.min_manipulability) || p.min_manipulability > 1.0)
    return rangeError("arm.min_manipulability", p.min_manipulability, "must be in [0, 1]");
  if (!positive(p.max_joint_speed)) return rangeError("arm.max_joint_speed", p.max_joint_speed, "must be > 0 (rad/s)");
  if (!finite3(p.gravity)) return ConfigResult::failure("arm.gravity: must be finite (m/s^2)");
  if (p.ik_iterations < 1 || p.ik_iterations > 100)
    return rangeError("arm.ik_iterations", p.ik_iterations, "must be in [1, 100]");
  if (!positive(p.ik_damping) || p.ik_damping > 1.0) return rangeError("arm.ik_damping", p.ik_damping, "must be in (0, 1]");
  if (!nonneg(p.tool_mass)) return rangeError("arm.tool_mass", p.tool_mass, "must be >= 0 (kg)");
  if (!finite3(p.tool_com)) return ConfigResult::failure("arm.tool_com: must be finite (m)");
  for (int i = 0; i < kLwrJoints; ++i) {
    const std::string j = std::to_string(i);
    const double lim = i % 2 == 0 ? 2.967 : 2.094;  // +-170 / +-120 deg hardware limits
    if (!std::isfinite(p.q_min[i]) || p.q_min[i] < -lim - 1e-9 || !std::isfinite(p.q_max[i]) ||
        p.q_max[i] > lim + 1e-9 || p.q_min[i] >= p.q_max[i])
      return ConfigResult::failure("arm.q_min[" + j + "], arm.q_max[" + j + "] = " + std::to_string(p.q_min[i]) +
                                   ", " + std::to_string(p.q_max[i]) + ": need -" + std::to_string(lim) +
                                   " <= q_min < q_max <= " + std::to_string(lim) + " (rad)");
    if (!std::isfinite(p.q_init[i]) || p.q_init[i] < p.q_min[i] || p.q_init[i] > p.q_max[i])
      return rangeError("arm.q_init[" + j + "]", p.q_init[i],
                        "must be within [q_min, q_max] = [" + std::to_string(p.q_min[i]) + ", " +
                            std::to_string(p.q_max[i]) + "] (rad)");
    const auto& L = p.links[i];
    if (!positive(L.mass)) return rangeError("arm.links[" + j + "].mass", L.mass, "must be > 0 (kg)");
    if (!finite3(L.com)) return ConfigResult::failure("arm.links[" + j + "].com: must be finite (m)");
    if (!positive(L.inertia[0]) || !positive(L.inertia[1]) || !positive(L.inertia[2]))
      return ConfigResult::failure("arm.links[" + j + "].inertia: must be > 0 (kg m^2)");
  }

  params_ = p;
  chain_ = KDL::Chain();
  for (int i = 0; i < kLwrJoints; ++i) {
    const auto& L = p.links[i];
    KDL::RigidBodyInertia I(L.mass, KDL::Vector(L.com[0], L.com[1], L.com[2]),
                            KDL::RotationalInertia(L.inertia[0], L.inertia[1], L.inertia[2], 0, 0, 0));
    if (i == kLwrJoints - 1 && p.tool_mass > 0.0)
      I = I + KDL::RigidBodyInertia(p.tool_mass, KDL::Vector(p.tool_com[0], p.tool_com[1], p.tool_com[2]),
                                    KDL::RotationalInertia(1e-4, 1e-4, 1e-4, 0, 0, 0));
    chain_.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), KDL::Frame::DH(0.0, kAlpha[i], kD[i], 0.0), I));
  }
  for (int i = 0; i < kLwrJoints; ++i) {
    const KDL::Segment& seg = chain_.getSegment(static_cast<unsigned int>(i));
    if (seg.getJoint().getType() != KDL::Joint::RotZ)  // forward()/kinematics() rely on it
      return ConfigResult::failure("arm chain: joint " + std::to_string(i) + " is not a RotZ joint");
    tips_[i] = seg.getFrameToTip();
  }
  dyn_ = std::make_unique<KDL::ChainDynParam>(chain_, KDL::Vector(p.gravity[0], p.gravity[1], p.gravity[2]));
  kq_.resize(kLwrJoints);
  kqd_.resize(kLwrJoints);
  kout_.resize(kLwrJoints);
  kM_.resize(kLwrJoints);
  for (int i = 0; i < kLwrJoints; ++i) {
    q_rest_[i] = p.q_init[i];
    q_min_[i] = p.q_min[i];
    q_max_[i] = p.q_max[i];
  }

  // Damping from the damping ratio and the Cartesian inertia at q_init:
  // Lambda = (J M^-1 J^T)^-1, D = 2 zeta sqrt(K * lambda) per block.
  Eigen::Matrix<double, 7, 7> M;
  massMatrix(q_rest_, M);
  Jac67 J;
  jacobian(q_rest_, J);
  const Mat6 Linv = J * M.ldlt().solve(J.transpose());
  double m_t = 3.0, i_r = 0.05;  // fallback for a singular q_init
  Eigen::LDLT<Mat6> ll(Linv);
  if (ll.info() == Eigen::Success && manipulability(J) > 1e-6) {
    const Mat6 Lambda = ll.solve(Mat6::Identity());
    const double mt = (Lambda(0, 0) + Lambda(1, 1) + Lambda(2, 2)) / 3.0;
    const double ir = (Lambda(3, 3) + Lambda(4, 4) + Lambda(5, 5)) / 3.0;
    if (std::isfinite(mt) && mt > 0.0) m_t = mt;
    if (std::isfinite(ir) && ir > 0.0) i_r = ir;
  }
  d_trans_ = 2.0 * p.damping_ratio * std::sqrt(p.k_trans * m_t);
  d_rot_ = 2.0 * p.damping_ratio * std::sqrt(p.k_rot * i_r);
  configured_ = true;
  dyn_evaluations_ = 0;
  reset(q_rest_);
  return ConfigResult::success();
}

void LwrArm::reset(const JointVec& q) {
  state_.q = q;
  state_.qd.setZero();
  dyn_valid_ = false;
  refreshKinematics();
}

void LwrArm::forward(const JointVec& q, KDL::Frame& T) const {
  // T = prod_i RotZ(q_i) * tip_i over the chain's segments (all joints are
  // KDL::Joint::RotZ, checked in configure()): KDL frames, without the
  // general joint-axis path of Segment::pose() (a test compares with
  // KDL::ChainFkSolverPos_recursive).
  T = KDL::Frame::Identity();
  for (int i = 0; i < kLwrJoints; ++i) T = T * jointToTip(i, q[i]);
}

KDL::Frame LwrArm::jointToTip(int i, double q) const {
  // KDL::Frame(KDL::Rotation::RotZ(q)) * tips_[i], written out: RotZ only
  // mixes the first two rows (12 products instead of KDL's general 27 + 9).
  const double c = std::cos(q), s = std::sin(q);
  const KDL::Frame& t = tips_[i];
  KDL::Frame f;
  for (int j = 0; j < 3; ++j) {
    f.M(0, j) = c * t.M(0, j) - s * t.M(1, j);
    f.M(1, j) = s * t.M(0, j) + c * t.M(1, j);
    f.M(2, j) = t.M(2, j);
  }
  f.p = KDL::Vector(c * t.p.x() - s * t.p.y(), s * t.p.x() + c * t.p.y(), t.p.z());
  return f;
}

void LwrArm::jacobian(const JointVec& q, Jac67& J) const {
  KDL::Frame T;
  kinematics(q, T, J);
}

void LwrArm::kinematics(const JointVec& q, KDL::Frame& T, Jac67& J) const {
  // One pass over the KDL segments: the frame before each joint gives its
  // axis z_i and a point o_i in {g}; after the pass, with p the flange
  // position, column i = [z_i x (p - o_i); z_i] (reference point at the
  // flange, {g} coordinates: KDL::ChainJntToJacSolver's convention).
  // Every joint is a KDL::Joint::RotZ at its segment's root (configure()).
  KDL::Vector z[kLwrJoints], o[kLwrJoints];
  T = KDL::Frame::Identity();
  for (int i = 0; i < kLwrJoints; ++i) {
    z[i] = T.M.UnitZ();
    o[i] = T.p;
    T = T * jointToTip(i, q[i]);
  }
  for (int c = 0; c < kLwrJoints; ++c) {
    const KDL::Vector v = z[c] * (T.p - o[c]);
    J.col(c) << v.x(), v.y(), v.z(), z[c].x(), z[c].y(), z[c].z();
  }
}

double LwrArm::manipulability(const Jac67& J) {
  // sqrt(det(J J^T)) = prod(diag(L)) of the Cholesky factor (0 if not positive definite).
  const Mat6 JJt = J.lazyProduct(J.transpose());
  const Eigen::LLT<Mat6> llt(JJt);
  if (llt.info() != Eigen::Success) return 0.0;
  const double d = llt.matrixLLT().diagonal().prod();
  return d > 0.0 ? d : 0.0;
}

void LwrArm::massMatrix(const JointVec& q, Eigen::Matrix<double, 7, 7>& M) const {
  kq_.data = q;
  dyn_->JntToMass(kq_, kM_);
  M = kM_.data;
}

void LwrArm::gravity(const JointVec& q, JointVec& g) const {
  kq_.data = q;
  dyn_->JntToGravity(kq_, kout_);
  g = kout_.data;
}

void LwrArm::refreshKinematics() {
  kinematics(state_.q, state_.T_ge, J_);
  state_.twist = J_ * state_.qd;
  state_.manipulability = manipulability(J_);
}

Vec6 LwrArm::impedanceWrench(const KDL::Frame& T_cmd, const KDL::Frame& T, const Vec6& twist) const {
  // x_d - x: translation p_d - p, rotation vector of R_d R^T, both in {g}.
  const Vec6 e = toVec(KDL::diff(T, T_cmd));
  Vec6 w;
  w.head<3>() = params_.k_trans * e.head<3>() - d_trans_ * twist.head<3>();
  w.tail<3>() = params_.k_rot * e.tail<3>() - d_rot_ * twist.tail<3>();
  return w;
}

SimStatus LwrArm::checkState() {
  SimStatus s = SimStatus::Ok;
  for (int i = 0; i < kLwrJoints; ++i) {
    if (state_.q[i] <= q_min_[i]) {
      state_.q[i] = q_min_[i];
      if (state_.qd[i] < 0.0) state_.qd[i] = 0.0;
      s = SimStatus::JointLimit;
    } else if (state_.q[i] >= q_max_[i]) {
      state_.q[i] = q_max_[i];
      if (state_.qd[i] > 0.0) state_.qd[i] = 0.0;
      s = SimStatus::JointLimit;
    }
  }
  refreshKinematics();
  if (s == SimStatus::Ok && state_.manipulability < params_.min_manipulability) s = SimStatus::Singularity;
  return s;
}

SimStatus LwrArm::stepDynamics(const KDL::Frame& T_cmd, const Vec6& W_ext, double dt) {
  if (!configured_) return SimStatus::NotConfigured;
  const ArmState saved = state_;
  // State at the start of the step (J_, T_ge, twist are current).
  // Stiffness part of Eq. 11 + contact wrench, explicit:
  const Vec6 W = impedanceWrench(T_cmd, state_.T_ge, Vec6::Zero()) + W_ext;
  JointVec tau = J_.transpose() * W;
  // Null-space posture term, projected with N = I - J^T (J#)^T, J# = J^T (J J^T + l^2 I)^-1.
  // N = I - J^T (J J^T + l^2 I)^-1 J (symmetric).
  const Mat6 JJt = J_.lazyProduct(J_.transpose()) + 1e-6 * Mat6::Identity();
  const Jac67 X = JJt.llt().solve(J_);  // SPD (+1e-6 I)
  Eigen::Matrix<double, 7, 7> N = -J_.transpose().lazyProduct(X);
  N.diagonal().array() += 1.0;
  tau += N * (params_.null_stiffness * (q_rest_ - state_.q));
  // Damping (Eq. 11's -D xdot, null-space and joint damping) as one joint-space
  // matrix B, integrated implicitly: the wrist links are light, so explicit
  // damping at 1 kHz would be unstable (dt * B / M > 2).
  Jac67 DJ = J_;  // D J, D = diag(d_trans I3, d_rot I3)
  DJ.topRows<3>() *= d_trans_;
  DJ.bottomRows<3>() *= d_rot_;
  Eigen::Matrix<double, 7, 7> B = J_.transpose().lazyProduct(DJ) + params_.null_damping * N;
  B.diagonal().array() += params_.joint_damping;
  // M qdd + C qd + g = tau_cmd + tau_ext, tau_cmd containing g(q): gravity cancels.
  // M and C qd are re-evaluated when q or qd moved beyond dyn_refresh_q/qd.
  if (!dyn_valid_ || (state_.q - q_dyn_).cwiseAbs().maxCoeff() > params_.dyn_refresh_q ||
      (state_.qd - qd_dyn_).cwiseAbs().maxCoeff() > params_.dyn_refresh_qd) {
    kq_.data = state_.q;
    kqd_.data = state_.qd;
    dyn_->JntToMass(kq_, kM_);
    dyn_->JntToCoriolis(kq_, kqd_, kout_);
    M_dyn_ = kM_.data;
    C_dyn_ = kout_.data;
    q_dyn_ = state_.q;
    qd_dyn_ = state_.qd;
    dyn_valid_ = true;
    ++dyn_evaluations_;
  }
  const Eigen::Matrix<double, 7, 7>& M = M_dyn_;
  // Semi-implicit Euler with implicit damping: (M + dt B) qd' = M qd + dt (tau - C).
  // A = M + dt B is symmetric positive definite (M SPD, B PSD): Cholesky,
  // LU only if that fails numerically.
  const Eigen::Matrix<double, 7, 7> A = M + dt * B;
  const JointVec rhs = M * state_.qd + dt * (tau - C_dyn_);
  const Eigen::LLT<Eigen::Matrix<double, 7, 7>> llt(A);
  state_.qd = llt.info() == Eigen::Success ? JointVec(llt.solve(rhs)) : JointVec(A.partialPivLu().solve(rhs));
  for (int i = 0; i < kLwrJoints; ++i) {
    const double v = params_.max_joint_speed;
    if (state_.qd[i] > v) state_.qd[i] = v;
    if (state_.qd[i] < -v) state_.qd[i] = -v;
  }
  state_.q += dt * state_.qd;
  if (!state_.q.allFinite() || !state_.qd.allFinite()) {
    state_ = saved;
    return SimStatus::NumericalFailure;
  }
  return checkState();
}

SimStatus LwrArm::settle(const KDL::Frame& T_target, double dt) {
  if (!configured_) return SimStatus::NotConfigured;
  const ArmState saved = state_;
  const double l2 = params_.ik_damping * params_.ik_damping;
  // Chord Newton: the Jacobian and its damped factorisation at the start q
  // serve the following iterations, each of which then costs one FK pass.
  // Between servo steps the joints move ~1e-4 rad: the first step leaves
  // ~1e-8 m, the second ~1e-12 m (contraction ~|dq|), i.e. 1 fused FK +
  // Jacobian pass and 2 FK passes instead of 2 FK + 2 Jacobian passes for a
  // full Newton. Where the error shrinks by less than 10x per iteration (a
  // large motion), the Jacobian is refreshed at the current q.
  JointVec q = state_.q;
  KDL::Frame T;
  kinematics(q, T, J_);
  Eigen::LLT<Mat6> chol(J_.lazyProduct(J_.transpose()) + l2 * Mat6::Identity());  // SPD (l2 > 0)
  bool moved = false;
  double e_prev = std::numeric_limits<double>::infinity();
  for (int it = 0; it <= params_.ik_iterations; ++it) {
    const Vec6 e = toVec(KDL::diff(T, T_target));
    const double en = std::max(e.head<3>().norm(), e.tail<3>().norm());
    if (en < 1e-9 || it == params_.ik_iterations) break;
    if (moved && en > 0.1 * e_prev) {
      kinematics(q, T, J_);
      chol.compute(J_.lazyProduct(J_.transpose()) + l2 * Mat6::Identity());
    }
    e_prev = en;
    q += J_.transpose() * chol.solve(e);  // Eq. 11's quasi-static case: joints follow the Cartesian equilibrium
    forward(q, T);
    moved = true;
  }
  if (!q.allFinite()) {
    state_ = saved;
    return SimStatus::NumericalFailure;
  }
  if (dt > 0.0)
    state_.qd = (q - state_.q) / dt;
  else
    state_.qd.setZero();
  state_.q = q;
  // Limits. T is the FK of exactly q; J_ (at the start q) is within |dq|
  // (~1e-4 relative) of the final one, well inside what twist and
  // manipulability need; a clamp recomputes both.
  bool clamped = false;
  for (int i = 0; i < kLwrJoints; ++i) {
    if (state_.q[i] < q_min_[i]) { state_.q[i] = q_min_[i]; clamped = true; }
    if (state_.q[i] > q_max_[i]) { state_.q[i] = q_max_[i]; clamped = true; }
  }
  if (clamped) return checkState();
  state_.T_ge = T;
  state_.twist = J_ * state_.qd;
  if (moved) state_.manipulability = manipulability(J_);
  return state_.manipulability < params_.min_manipulability ? SimStatus::Singularity : SimStatus::Ok;
}

}  // namespace sim
}  // namespace tactile
