#include "tactile_sim_lwr/world.hpp"
#include "tactile_sim_lwr/sim_schema.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace tactile {
namespace sim {

const char* toString(Fidelity f) { return f == Fidelity::Dynamics ? "dynamics" : "quasi_static"; }

bool parseFidelity(const std::string& s, Fidelity& out) {
  if (s == "quasi_static") out = Fidelity::QuasiStatic;
  else if (s == "dynamics") out = Fidelity::Dynamics;
  else return false;
  return true;
}

namespace {
constexpr double kTrayAngleLimit = 0.6;  // rad, mechanical stops of the tray bearing

bool sameFrame(const KDL::Frame& a, const KDL::Frame& b) {
  for (int i = 0; i < 3; ++i)
    if (a.p(i) != b.p(i)) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.M(i, j) != b.M(i, j)) return false;
  return true;
}

SimStatus worst(SimStatus a, SimStatus b) { return static_cast<uint8_t>(a) >= static_cast<uint8_t>(b) ? a : b; }

Vec6 toVec(const KDL::Twist& t) {
  Vec6 v;
  v << t.vel.x(), t.vel.y(), t.vel.z(), t.rot.x(), t.rot.y(), t.rot.z();
  return v;
}

/// A maps a flange twist ({g}, at the flange) to the sensor twist ({s}, at the
/// sensor origin): A = [R^T, -R^T [r]x; 0, R^T], r = p_s - p_e in {g}, R = {g}R{s}.
/// Wrenches map back with A^T (power preserving).
Mat6 twistMap(const KDL::Frame& T_ge, const KDL::Frame& T_gs) {
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = T_gs.M(i, j);
  const KDL::Vector rv = T_gs.p - T_ge.p;
  Eigen::Matrix3d rx;
  rx << 0, -rv.z(), rv.y(), rv.z(), 0, -rv.x(), -rv.y(), rv.x(), 0;
  Mat6 A = Mat6::Zero();
  A.topLeftCorner<3, 3>() = R.transpose();
  A.topRightCorner<3, 3>() = -R.transpose() * rx;
  A.bottomRightCorner<3, 3>() = R.transpose();
  return A;
}

// The parameters' ranges; the FRI delay and the KRC cycle in whole physics
// steps (the loop's time base).
ConfigResult checkParams(const WorldParams& p, long& delay_steps, long& krc_steps) {
  if (p.fidelity != Fidelity::QuasiStatic && p.fidelity != Fidelity::Dynamics)
    return rangeError("fidelity", static_cast<int>(p.fidelity), "must be quasi_static or dynamics");
  if (!(p.force_ceiling > 0.0) || !std::isfinite(p.force_ceiling))
    return rangeError("force_ceiling", p.force_ceiling, "must be > 0 (N)");
  if (p.qs_max_iterations < 1 || p.qs_max_iterations > 200)
    return rangeError("qs_max_iterations", p.qs_max_iterations, "must be in [1, 200]");
  if (!(p.qs_tolerance > 0.0) || !std::isfinite(p.qs_tolerance)) return rangeError("qs_tolerance", p.qs_tolerance, "must be > 0 (N)");
  if (!(p.qs_max_step > 0.0) || p.qs_max_step > 0.1) return rangeError("qs_max_step", p.qs_max_step, "must be in (0, 0.1] m");
  if (!(p.max_step_s > 0.0) || p.max_step_s > 0.1) return rangeError("max_step_s", p.max_step_s, "must be in (0, 0.1] s");
  char buf[128];
  if (!(p.physics_step_s > 0.0) || p.physics_step_s > p.max_step_s) {
    std::snprintf(buf, sizeof buf, "must be in (0, max_step_s = %g] s", p.max_step_s);
    return rangeError("physics_step_s (1 / rates.sim)", p.physics_step_s, buf);
  }
  const ConfigResult declared = schema::checkRanges(worldEffectsSchema(), p, "effects");
  if (!declared) return declared;
  // The delay and the KRC cycle in whole physics steps (the loop's time base).
  auto steps = [&p](const char* name, double v, long& n) {
    const double k = v / p.physics_step_s;
    n = std::lround(k);
    if (std::fabs(k - static_cast<double>(n)) > 1e-6) {
      char b[128];
      std::snprintf(b, sizeof b, "must be a whole number of physics steps (1 / rates.sim = %g s)", p.physics_step_s);
      return rangeError(name, v, b);
    }
    return ConfigResult::success();
  };
  {
    ConfigResult rs = steps("effects.fri_delay_s", p.fri_delay_s, delay_steps);
    if (!rs) return rs;
    if (!(rs = steps("effects.krc_cycle_s", p.krc_cycle_s, krc_steps))) return rs;
  }
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(p.external_wrench[static_cast<std::size_t>(i)]))
      return ConfigResult::failure("external_wrench[" + std::to_string(i) + "]: must be finite (N, N m)");
  return ConfigResult::success();
}

// The arm at initial_flange_pose (when given), at rest; its posture not singular.
ConfigResult initialPosture(LwrArm& arm, const WorldParams& p) {
  if (p.use_initial_flange_pose) {
    if (!validPose(p.initial_flange_pose))
      return ConfigResult::failure("initial_flange_pose: position must be finite and the quaternion a unit quaternion (|q| within 1e-3 of 1)");
    const KDL::Frame T0 = toFrame(p.initial_flange_pose);
    SimStatus s = SimStatus::Ok;
    for (int k = 0; k < 30; ++k) s = arm.settle(T0);
    const Vec6 e = toVec(KDL::diff(arm.state().T_ge, T0));
    if (fatal(s) || e.head<3>().norm() > 1e-5 || e.tail<3>().norm() > 1e-4)
      return ConfigResult::failure(std::string("initial_flange_pose: not reachable from arm.q_init (residual ") +
                                   std::to_string(e.head<3>().norm()) + " m, " + std::to_string(e.tail<3>().norm()) +
                                   " rad; status " + toString(s) + "): choose q_init near the pose");
    arm.reset(arm.state().q);
  }
  if (arm.state().manipulability < p.arm.min_manipulability)
    return rangeError("arm.q_init (manipulability)", arm.state().manipulability,
                      "initial posture is singular: must be >= arm.min_manipulability = " +
                          std::to_string(p.arm.min_manipulability));
  return ConfigResult::success();
}

// An object that starts inside the sensor is a scene error.
ConfigResult startsOutside(const PadSensor& pad_sensor, const ObjectSet& objects, const PadParams& pad) {
  double dl = 0, dh = 0;
  int obj = -1;
  pad_sensor.maxPenetration(objects, dl, dh, obj);
  if (dl > pad.layer_thickness || dh > 0.0) {
    const ObjectParams& o = objects.params(obj < 0 ? 0 : obj);
    const std::string name = "objects[" + std::to_string(obj) + "]" + (o.name.empty() ? "" : " (" + o.name + ")");
    if (dh > 0.0)
      return rangeError(name + ": starts inside the sensor housing, penetration", dh,
                        "must be 0 at start (move the object or the initial pose)");
    return rangeError(name + ": starts inside the sensor, layer penetration", dl,
                      "must be <= pad.layer_thickness = " + std::to_string(pad.layer_thickness) + " m at start");
  }
  return ConfigResult::success();
}

}  // namespace

ConfigResult World::configure(const WorldParams& p) {
  configured_ = false;
  long delay_steps = 0, krc_steps = 0;
  if (ConfigResult rc = checkParams(p, delay_steps, krc_steps); !rc) return rc;

  ConfigResult r = arm_.configure(p.arm);
  if (!r) return r;
  PadParams pad = p.pad;
  pad.seed = p.seed;
  r = pad_.configure(pad);
  if (!r) return r;
  r = objects_.configure(p.objects);
  if (!r) return r;
  // Contact is only evaluated over the sensor outline: drop everything else early.
  const double hx = 0.5 * pad.housing_size_x + 1e-4, hy = 0.5 * pad.housing_size_y + 1e-4;
  objects_.setRegion(-hx, hx, -hy, hy);
  params_ = p;
  params_.pad.seed = p.seed;
  for (int i = 0; i < 6; ++i) W_ext_[i] = p.external_wrench[static_cast<std::size_t>(i)];

  // Initial posture.
  if (ConfigResult rp = initialPosture(arm_, p); !rp) return rp;

  tray_ = TrayPose{};
  tray_rate_.setZero();
  if (objects_.hasTray()) {
    tray_.pitch = objects_.tray().initial_pitch;
    tray_.roll = objects_.tray().initial_roll;
  }
  if (p.tray_dynamics && !objects_.hasTray())
    return ConfigResult::failure("objects[].fidelity: only a tray has a fidelity of its own (no tray in the scene)");
  if (p.tray_dynamics && p.fidelity != Fidelity::QuasiStatic)
    return ConfigResult::failure("objects[].fidelity: dynamics on a tray needs fidelity: quasi_static for the arm "
                                 "(in dynamics the tray is integrated anyway)");
  tray_dynamic_ = p.tray_dynamics;
  T_eq_ = arm_.state().T_ge;
  T_cmd_ = T_eq_;
  T_set_ = T_eq_;
  delay_steps_ = delay_steps;
  krc_steps_ = krc_steps;
  cmd_path_ = delay_steps > 0 || krc_steps > 1;
  cmd_line_.assign(static_cast<std::size_t>(delay_steps + 1), T_eq_);  // the initial command, delay + 1 deep
  friction_on_ = p.friction_mu > 0.0;
  stuck_valid_ = false;
  fric_.setZero();
  fric_u_.setZero();
  fric_mz_ = fric_n_ = 0.0;
  slip_ = false;
  placeObjects(T_eq_, tray_);

  if (ConfigResult ro = startsOutside(pad_, objects_, pad); !ro) return ro;
  evaluateContact(T_eq_, tray_);
  acq_seq_ = 0;
  qs_valid_ = false;
  acq_valid_ = false;
  state_.time_s = 0.0;
  state_.step = 0;
  if ((p.fidelity == Fidelity::Dynamics || tray_dynamic_) && p.start_in_equilibrium) {
    // The quasi-static solve of the initial command (tray angles jointly), then rest there.
    tray_dynamic_ = false;
    const SimStatus s = stepQuasiStatic(T_cmd_, 0.0);
    tray_dynamic_ = p.tray_dynamics;
    if (fatal(s) || s == SimStatus::NotConverged)
      return ConfigResult::failure(std::string("start_in_equilibrium: no static equilibrium at the initial pose (") +
                                   toString(s) + "); move the objects or set start_in_equilibrium: false");
    arm_.reset(arm_.state().q);  // zero joint velocity, kinematics refreshed
    tray_rate_.setZero();
    evaluateContact(arm_.state().T_ge, tray_);
    qs_valid_ = false;
  }
  configured_ = true;
  held_ = false;
  last_cmd_valid_ = false;
  if (friction_on_) friction(state_.T_gs, tray_, true);  // stuck where it starts (no tangential load)
  fillState(SimStatus::Ok);
  return ConfigResult::success();
}

void World::setExternalWrench(const std::array<double, 6>& w) {
  qs_valid_ = false;
  for (int i = 0; i < 6; ++i) {
    const double v = w[static_cast<std::size_t>(i)];
    W_ext_[i] = std::isfinite(v) ? v : 0.0;
  }
}

std::array<double, 3> World::trayMassPosition() const {
  if (!objects_.hasTray()) return {0.0, 0.0, 0.0};
  const KDL::Rotation R = KDL::Rotation::RotX(tray_.pitch) * KDL::Rotation::RotY(tray_.roll);
  const KDL::Vector p = objects_.bearing() + R * objects_.trayMassPosition(state_.time_s);
  return {p.x(), p.y(), p.z()};
}

void World::placeObjects(const KDL::Frame& T_ge, const TrayPose& tp) {
  state_.T_gs = T_ge * pad_.mount();
  objects_.pose(state_.T_gs, tp);
}

void World::evaluateContact(const KDL::Frame& T_ge, const TrayPose& tp) {
  placeObjects(T_ge, tp);
  pad_.evaluate(objects_, state_.T_gs, contact_);
  contact_T_ge_ = T_ge;
  contact_tray_ = tp;
}

SimStatus World::step(const tactile::Pose& cmd, double dt, SimState& out) {
  if (!configured_) {
    out.status = SimStatus::NotConfigured;
    return out.status;
  }
  SimStatus s = SimStatus::Ok;
  if (!(dt > 0.0) || !std::isfinite(dt) || dt > params_.max_step_s) {
    state_.status = SimStatus::StepRejected;
    out = state_;
    return state_.status;
  }
  if (cmd.p == last_cmd_.p && cmd.q == last_cmd_.q && last_cmd_valid_) {
    // Same command as the previous step (the servo runs at a tenth of the
    // physics rate): T_cmd_ already holds it.
  } else if (validPose(cmd)) {
    T_cmd_ = toFrame(cmd);
    last_cmd_ = cmd;
    last_cmd_valid_ = true;
  } else {
    s = SimStatus::InvalidCommand;
  }
  state_.time_s += dt;
  const bool was_held = held_;
  held_ = false;
  const KDL::Frame& T_use = cmd_path_ ? setPoint() : T_cmd_;
  s = worst(s, params_.fidelity == Fidelity::QuasiStatic ? stepQuasiStatic(T_use, dt) : stepDynamics(T_use, dt));
  ++state_.step;
  if (held_ && was_held) {  // nothing moved since the previous step: only time and status change
    fillStatus(s);
    if (cmd_path_) state_.command_g = toPose(T_cmd_);  // a new command may be on its way to the KRC
  } else {
    fillState(s);
  }
  out = state_;
  return state_.status;
}

const KDL::Frame& World::setPoint() {
  // Step i (state_.step before it is counted) writes its command into slot
  // i mod (D + 1); the slot after it holds the command of step i - D (the
  // initial command while i < D): the FRI delay of D physics steps.
  const std::size_t cap = cmd_line_.size();
  const std::size_t i = static_cast<std::size_t>(state_.step % cap);
  cmd_line_[i] = T_cmd_;
  const KDL::Frame& delayed = cmd_line_[(i + 1) % cap];
  // The KRC samples what has arrived at t = k * krc_cycle_s and holds it.
  if (krc_steps_ <= 1 || state_.step % static_cast<uint64_t>(krc_steps_) == 0) T_set_ = delayed;
  return T_set_;
}

void World::integrateTray(double dt) {
  const TrayParams& tp = objects_.tray();
  const KDL::Vector g(params_.arm.gravity[0], params_.arm.gravity[1], params_.arm.gravity[2]);
  double gx, gy;
  objects_.trayGravityTorque(tray_, state_.time_s, g, gx, gy);
  // Linearised backward Euler for the bearing damping, the springs and the
  // contact's angular stiffness (unconditionally stable for the tiny roll
  // inertia): (I + dt C - dt^2 K) w' = I w + dt tau(theta, w = 0).
  double tx = gx - tp.pitch_stiffness * tray_.pitch + contact_.tau_tray(0);
  double ty = gy - tp.roll_stiffness * tray_.roll + contact_.tau_tray(1);
  if (friction_on_ && stuck_valid_) {
    const Eigen::Vector2d tf = frictionTrayTorque(state_.T_gs);
    tx += tf(0);
    ty += tf(1);
  }
  Eigen::Matrix2d K = contact_.dtau_dth;
  K(0, 0) -= tp.pitch_stiffness;
  K(1, 1) -= tp.roll_stiffness;
  Eigen::Matrix2d Mi = Eigen::Matrix2d::Zero();
  Mi(0, 0) = objects_.trayInertiaX() + dt * tp.bearing_damping;
  Mi(1, 1) = objects_.trayInertiaY() + dt * tp.bearing_damping;
  Mi -= dt * dt * K;
  const Eigen::Vector2d rhs(objects_.trayInertiaX() * tray_rate_(0) + dt * tx,
                            objects_.trayInertiaY() * tray_rate_(1) + dt * ty);
  tray_rate_ = Mi.partialPivLu().solve(rhs);
  tray_.pitch += dt * tray_rate_(0);
  tray_.roll += dt * tray_rate_(1);
  // The pivot cannot swing the tray through the floor: bound the angles.
  const double lim = kTrayAngleLimit;
  if (std::fabs(tray_.pitch) > lim) { tray_.pitch = std::copysign(lim, tray_.pitch); tray_rate_(0) = 0; }
  if (std::fabs(tray_.roll) > lim) { tray_.roll = std::copysign(lim, tray_.roll); tray_rate_(1) = 0; }
}

namespace {
KDL::Rotation trayRotation(const TrayPose& tp) { return KDL::Rotation::RotX(tp.pitch) * KDL::Rotation::RotY(tp.roll); }
}  // namespace

void World::friction(const KDL::Frame& T_gs, const TrayPose& tp, bool commit) {
  // Elasto-plastic (spring-slider) Coulomb model: the layer shears by u (the
  // sensor origin's tangential displacement from the stuck point) with the
  // force -k_t u on the sensor until |k_t u| reaches mu N; beyond, the force
  // is mu N against u (sliding) and the stuck point follows (return mapping).
  const double N = contact_.layer_force + contact_.housing_force;
  const bool tray = objects_.hasTray();
  if (!(N > 0.0)) {
    fric_.setZero();
    fric_u_.setZero();
    fric_mz_ = fric_n_ = 0.0;
    slip_ = false;
    if (commit) stuck_valid_ = false;
    return;
  }
  if (!stuck_valid_) {  // first touch: stuck here, no shear yet
    fric_.setZero();
    fric_u_.setZero();
    fric_mz_ = 0.0;
    fric_n_ = N;
    slip_ = false;
    if (commit) {
      anchor_ = tray ? trayRotation(tp).Inverse() * (T_gs.p - objects_.bearing()) : T_gs.p;
      stuck_valid_ = true;
    }
    return;
  }
  const KDL::Vector a = tray ? objects_.bearing() + trayRotation(tp) * anchor_ : anchor_;
  const KDL::Vector d = T_gs.p - a;
  const KDL::Vector xs = T_gs.M.UnitX(), ys = T_gs.M.UnitY();
  const Eigen::Vector2d u(KDL::dot(xs, d), KDL::dot(ys, d));
  const double kt = params_.friction_stiffness, lim = params_.friction_mu * N;
  Eigen::Vector2d f = -kt * u;
  const double fn = f.norm();
  slip_ = fn > lim;
  if (slip_) f *= lim / fn;
  fric_ = f;
  fric_u_ = u;
  fric_n_ = N;
  // At the pressure centre on the surface (x_c, y_c, 0): W_s(3) = -y_c N, W_s(4) = x_c N.
  const double xc = contact_.W_s(4) / N, yc = -contact_.W_s(3) / N;
  fric_mz_ = xc * f(1) - yc * f(0);
  if (commit && slip_) {
    // The stuck point moves so that the shear is the limit's: u' = -f / k_t.
    const KDL::Vector an = T_gs.p + (f(0) / kt) * xs + (f(1) / kt) * ys;
    anchor_ = tray ? trayRotation(tp).Inverse() * (an - objects_.bearing()) : an;
  }
}

Eigen::Vector2d World::frictionTrayTorque(const KDL::Frame& T_gs) const {
  // The reaction -F on the tray's bar at the pressure centre, about the bearing (x_g, y_g).
  const double N = fric_n_;
  if (!(N > 0.0)) return Eigen::Vector2d::Zero();
  const double xc = contact_.W_s(4) / N, yc = -contact_.W_s(3) / N;
  const KDL::Vector pc = T_gs * KDL::Vector(xc, yc, 0.0);
  const KDL::Vector F = -(fric_(0) * T_gs.M.UnitX() + fric_(1) * T_gs.M.UnitY());
  const KDL::Vector t = (pc - objects_.bearing()) * F;
  return Eigen::Vector2d(t.x(), t.y());
}

// The residual of the quasi-static equilibrium at one Newton iterate and the
// friction law's derivatives that enter its Jacobian.
struct World::QsResidual {
  Vec6 re;             // flange wrench: impedance + external + contact (+ friction)
  Eigen::Vector2d rt;  // tray torques about its bearing (pitch, roll); 0 without a quasi-static tray
  Eigen::Matrix2d G;   // d f / d u
  Eigen::Vector2d gN;  // d f / d N (sliding)
  double norm() const { return std::max(re.cwiseAbs().maxCoeff(), rt.cwiseAbs().maxCoeff()); }
};

namespace {
// The damped, relaxed Newton step's scale: translation <= maxs, rotation and
// tray <= 10 maxs; with friction, half steps from the first iterate whose
// residual r_now does not halve r_prev (relax is sticky for the solve).
double newtonStepScale(const Vec6& de, const Eigen::Vector2d& dth, double maxs, bool friction_on, double r_now,
                       double r_prev, double& relax) {
  // Step limit (damped Newton): translation <= maxs, rotation and tray <= 10 maxs.
  double scale = 1.0;
  const double nt = de.head<3>().norm(), nr = de.tail<3>().norm(), na = dth.cwiseAbs().maxCoeff();
  if (nt > maxs) scale = std::min(scale, maxs / nt);
  if (nr > 10 * maxs) scale = std::min(scale, 10 * maxs / nr);
  if (na > 10 * maxs) scale = std::min(scale, 10 * maxs / na);
  // Relaxation with friction, where the residual does not halve: the
  // sliding friction's dependence on the tray angles (its stuck point rides
  // on the tray) and its torque on the tray are not in J, and the kink of
  // the friction law at |k_t u| = mu N is not smooth: the iteration can oscillate
  // (u alternating about the solution, contracting by ~0.94 per step).
  // Once that shows, half steps for the rest of the solve turn that mode's
  // factor of ~-0.94 into ~0.03 and cost the well-modelled modes a factor
  // 1/2 per step.
  if (friction_on && r_now > 0.5 * r_prev) relax = 0.5;  // from then on, for this solve
  return scale * relax;
}
}  // namespace

bool World::quasiStaticHolds(const KDL::Frame& T_cmd, double dt) const {
  // Unchanged command and a static world: the previous (converged) equilibrium holds.
  bool moving = tray_dynamic_;
  if (objects_.hasTray() && !moving) {
    const TrayParams& tp = objects_.tray();
    moving = state_.time_s - dt <= tp.move_start_s + tp.move_duration_s && state_.time_s >= tp.move_start_s;
  }
  return qs_valid_ && !moving && sameFrame(T_cmd, qs_cmd_);
}

bool World::reuseLastContact(const TrayPose& th, KDL::Frame& T) {
  // contact_ was evaluated at the previous solve's last Newton iterate, which
  // the arm reached to the IK tolerance: start there and reuse it (the
  // objects do not move between solves; the tray angles are state).
  const Vec6 d = toVec(KDL::diff(contact_T_ge_, T_eq_));
  const bool reuse = contact_tray_.pitch == th.pitch && contact_tray_.roll == th.roll && d.head<3>().norm() < 1e-7 &&
                     d.tail<3>().norm() < 1e-6;
  if (reuse) {
    T = contact_T_ge_;
    state_.T_gs = T * pad_.mount();
  }
  return reuse;
}

void World::quasiStaticResidual(const KDL::Frame& T_cmd, const KDL::Frame& T, const TrayPose& th, const Mat6& A,
                                bool tray, QsResidual& r) {
  const KDL::Vector g(params_.arm.gravity[0], params_.arm.gravity[1], params_.arm.gravity[2]);
  const double kx = tray ? objects_.tray().pitch_stiffness : 0.0, ky = tray ? objects_.tray().roll_stiffness : 0.0;
  // Residual: impedance (Eq. 11, at rest) + external + contact wrench on the flange.
  // The contact wrench and stiffness live in the (z, wx, wy) rows of {s}
  // (PadSensor::evaluate): only those rows of A enter.
  const Eigen::Matrix<double, 3, 6> Ar = A.middleRows<3>(2);
  r.re = arm_.impedanceWrench(T_cmd, T, Vec6::Zero()) + W_ext_ + Ar.transpose() * contact_.W_s.segment<3>(2);
  // Friction (x, y and the moment about z_s at the sensor origin; A^T
  // carries its moment about the flange, the sensor mount's lever arm).
  r.G = Eigen::Matrix2d::Zero();
  r.gN = Eigen::Vector2d::Zero();
  if (friction_on_) {
    friction(state_.T_gs, th, false);
    r.re += A.row(0).transpose() * fric_(0) + A.row(1).transpose() * fric_(1) + A.row(5).transpose() * fric_mz_;
    if (stuck_valid_ && fric_n_ > 0.0) {
      if (slip_) {
        const double un = fric_u_.norm();
        const Eigen::Vector2d uh = fric_u_ / un;
        r.G = -(params_.friction_mu * fric_n_ / un) * (Eigen::Matrix2d::Identity() - uh * uh.transpose());
        r.gN = -params_.friction_mu * uh;
      } else {
        r.G = -params_.friction_stiffness * Eigen::Matrix2d::Identity();
      }
    }
  }
  r.rt = Eigen::Vector2d::Zero();
  if (tray) {
    double gx, gy;
    objects_.trayGravityTorque(th, state_.time_s, g, gx, gy);
    r.rt << gx - kx * th.pitch + contact_.tau_tray(0), gy - ky * th.roll + contact_.tau_tray(1);
    if (friction_on_) r.rt += frictionTrayTorque(state_.T_gs);
    // On a stop, the stop's reaction takes whatever pushes into it.
    if ((th.pitch <= -kTrayAngleLimit && r.rt(0) < 0) || (th.pitch >= kTrayAngleLimit && r.rt(0) > 0)) r.rt(0) = 0;
    if ((th.roll <= -kTrayAngleLimit && r.rt(1) < 0) || (th.roll >= kTrayAngleLimit && r.rt(1) > 0)) r.rt(1) = 0;
  }
}

void World::newtonStep(const Mat6& A, bool tray, const QsResidual& r, Vec6& de, Eigen::Vector2d& dth) const {
  const Eigen::Matrix<double, 3, 6> Ar = A.middleRows<3>(2);
  const double kx = tray ? objects_.tray().pitch_stiffness : 0.0, ky = tray ? objects_.tray().roll_stiffness : 0.0;
  const double kt = arm_.kTrans(), kr = arm_.kRot();
  Mat6 Jee = -Ar.transpose() * (contact_.K_s.middleRows<3>(2) * A);
  Jee.diagonal().head<3>().array() -= kt;
  Jee.diagonal().tail<3>().array() -= kr;
  if (friction_on_) {
    // d f = G du + gN dN, du = (sensor velocity x, y in {s}) = A.topRows<2> de, dN = K_s(2, :) A de.
    const Eigen::Matrix<double, 2, 6> A2 = A.topRows<2>();
    const Eigen::Matrix<double, 2, 6> dF = r.G * A2 + r.gN * (contact_.K_s.row(2) * A);
    Jee += A2.transpose() * dF;
  }
  dth = Eigen::Vector2d::Zero();
  if (tray) {
    Eigen::Matrix<double, 8, 8> J;
    J.topLeftCorner<6, 6>() = Jee;
    J.topRightCorner<6, 2>() = A.transpose() * contact_.dW_dth;
    J.bottomLeftCorner<2, 6>() = contact_.dtau_ds * A;
    J.bottomRightCorner<2, 2>() = contact_.dtau_dth;
    J(6, 6) -= kx;
    J(7, 7) -= ky;
    // Keep the tray block invertible while the bar is off the pad (free fall
    // of the tray is limited by the step limit below).
    J(6, 6) -= 1e-3;
    J(7, 7) -= 1e-3;
    Eigen::Matrix<double, 8, 1> r8;
    r8 << r.re, r.rt;
    const Eigen::Matrix<double, 8, 1> d = J.partialPivLu().solve(-r8);
    de = d.head<6>();
    dth = d.tail<2>();
  } else {
    de = Jee.partialPivLu().solve(-r.re);  // the sliding columns make it non-symmetric
    if (!de.allFinite()) {
      // Degenerate sliding columns (not reached by the tests or scenes): the
      // compression block alone is symmetric negative definite.
      Mat6 Js = -Ar.transpose() * (contact_.K_s.block<3, 3>(2, 2) * Ar);
      Js.diagonal().head<3>().array() -= kt;
      Js.diagonal().tail<3>().array() -= kr;
      de = (-Js).llt().solve(r.re);
    }
  }
}

SimStatus World::settleQuasiStatic(const KDL::Frame& T_cmd, const KDL::Frame& T, const TrayPose& th, double dt,
                                   bool converged, bool evaluated, int iterations) {
  last_iterations_ = iterations;
  tray_ = th;
  SimStatus s = arm_.settle(T, dt);  // joints follow; limits / singularity detected
  const KDL::Frame& Ta = arm_.state().T_ge;
  const Vec6 e = toVec(KDL::diff(Ta, T));
  T_eq_ = Ta;
  if (!evaluated || e.head<3>().norm() > 1e-7 || e.tail<3>().norm() > 1e-6) {
    evaluateContact(Ta, tray_);
  }
  if (friction_on_) friction(state_.T_gs, tray_, true);  // the stuck point follows a slip
  if (!converged) s = worst(s, SimStatus::NotConverged);
  qs_valid_ = converged && !fatal(s);
  qs_cmd_ = T_cmd;
  qs_status_ = s;
  return s;
}

SimStatus World::stepQuasiStatic(const KDL::Frame& T_cmd, double dt) {
  // Per-body fidelity: a dynamic tray takes one time step with the contact
  // as it is, then the arm balances with the tray angles fixed.
  const bool tray = objects_.hasTray() && !tray_dynamic_;
  if (tray_dynamic_ && dt > 0.0) integrateTray(dt);
  if (quasiStaticHolds(T_cmd, dt)) {
    arm_.hold();
    held_ = true;
    last_iterations_ = 0;
    return qs_status_;
  }
  KDL::Frame T = T_eq_;
  TrayPose th = tray_;
  const bool reuse = reuseLastContact(th, T);
  bool converged = false, evaluated = false;
  int it = 0;
  double r_prev = std::numeric_limits<double>::infinity();
  double relax = 1.0;
  QsResidual r;
  for (; it < params_.qs_max_iterations; ++it) {
    if (!(it == 0 && reuse)) evaluateContact(T, th);
    evaluated = true;
    const Mat6 A = twistMap(T, state_.T_gs);
    quasiStaticResidual(T_cmd, T, th, A, tray, r);
    last_residual_ = r.norm();
    if (last_residual_ < params_.qs_tolerance) {
      converged = true;
      break;
    }
    Vec6 de;
    Eigen::Vector2d dth;
    newtonStep(A, tray, r, de, dth);
    if (!de.allFinite() || !dth.allFinite()) return SimStatus::NumericalFailure;
    const double r_now = r.norm();
    const double scale = newtonStepScale(de, dth, params_.qs_max_step, friction_on_, r_now, r_prev, relax);
    r_prev = r_now;
    de *= scale;
    dth *= scale;
    // (KDL::addDelta / KDL::Rot drop rotations below ~1e-6 rad.)
    T = KDL::Frame(rotationFromVector(KDL::Vector(de[3], de[4], de[5])) * T.M, T.p + KDL::Vector(de[0], de[1], de[2]));
    // A tray that lost its support rests on its stops (+-kTrayAngleLimit).
    th.pitch = std::clamp(th.pitch + dth(0), -kTrayAngleLimit, kTrayAngleLimit);
    th.roll = std::clamp(th.roll + dth(1), -kTrayAngleLimit, kTrayAngleLimit);
    evaluated = false;
  }
  return settleQuasiStatic(T_cmd, T, th, dt, converged, evaluated, it);
}

SimStatus World::stepDynamics(const KDL::Frame& T_cmd, double dt) {
  // contact_ holds the contact at the current state (evaluated at the end of
  // the previous step, or in configure()); so does the friction (fric_).
  const Mat6 A = twistMap(arm_.state().T_ge, state_.T_gs);
  Vec6 Ws = contact_.W_s;
  if (friction_on_) {
    Ws(0) += fric_(0);
    Ws(1) += fric_(1);
    Ws(5) += fric_mz_;
  }
  const Vec6 W = A.transpose() * Ws + W_ext_;
  if (objects_.hasTray()) integrateTray(dt);
  const SimStatus s = arm_.stepDynamics(T_cmd, W, dt);
  evaluateContact(arm_.state().T_ge, tray_);
  // The shear at the new state; a slip moves the stuck point.
  if (friction_on_) friction(state_.T_gs, tray_, true);
  last_iterations_ = 0;
  last_residual_ = 0.0;
  return s;
}

void World::fillState(SimStatus s) {
  const ArmState& a = arm_.state();
  state_.q = a.q;
  state_.qd = a.qd;
  state_.T_ge = a.T_ge;
  state_.T_gs = a.T_ge * pad_.mount();
  state_.flange_g = toPose(state_.T_ge);
  state_.sensor_g = toPose(state_.T_gs);
  state_.command_g = toPose(T_cmd_);
  state_.setpoint_g = cmd_path_ ? toPose(T_set_) : state_.command_g;
  for (int i = 0; i < 6; ++i) state_.wrench_s[static_cast<std::size_t>(i)] = contact_.W_s[i];
  if (friction_on_) {
    state_.wrench_s[0] += fric_(0);
    state_.wrench_s[1] += fric_(1);
    state_.wrench_s[5] += fric_mz_;
  }
  state_.slipping = friction_on_ && slip_;
  state_.normal_force = contact_.layer_force;
  state_.housing_force = contact_.housing_force;
  state_.tray_pitch = tray_.pitch;
  state_.tray_roll = tray_.roll;
  state_.manipulability = a.manipulability;
  fillStatus(s);
}

void World::fillStatus(SimStatus s) {
  state_.solver_iterations = last_iterations_;
  state_.solver_residual = last_residual_;
  if (contact_.layer_force + contact_.housing_force > params_.force_ceiling) s = worst(s, SimStatus::ForceCeiling);
  state_.status = s;
}

void World::addFriction(SensorTruth& truth) const {
  truth.wrench_s[0] += fric_(0);
  truth.wrench_s[1] += fric_(1);
  truth.wrench_s[5] += fric_mz_;
}

void World::acquireForces(tactile::TactileFrame& forces, SensorTruth& truth) {
  if (!configured_) return;
  const KDL::Frame T_gs = state_.T_ge * pad_.mount();
  if (acq_valid_ && sameFrame(T_gs, acq_T_gs_) && tray_.pitch == acq_tray_.pitch && tray_.roll == acq_tray_.roll) {
    pad_.integrateRepeat(state_.time_s, truth);  // nothing moved: same integral
  } else {
    placeObjects(state_.T_ge, tray_);
    pad_.integrate(objects_, state_.T_gs, state_.time_s, truth);
    acq_valid_ = true;
    acq_T_gs_ = state_.T_gs;
    acq_tray_ = tray_;
  }
  if (friction_on_) addFriction(truth);
  forces = pad_.trueTaxelForces();
  forces.seq = acq_seq_++;
}

void World::acquire(tactile::RawTactileFrame& raw, SensorTruth& truth) {
  if (!configured_) return;
  const KDL::Frame T_gs = state_.T_ge * pad_.mount();
  if (acq_valid_ && sameFrame(T_gs, acq_T_gs_) && tray_.pitch == acq_tray_.pitch && tray_.roll == acq_tray_.roll) {
    pad_.acquireRepeat(state_.time_s, raw, truth);  // nothing moved: same integral, new noise
  } else {
    placeObjects(state_.T_ge, tray_);
    pad_.acquire(objects_, state_.T_gs, state_.time_s, raw, truth);
    acq_valid_ = true;
    acq_T_gs_ = state_.T_gs;
    acq_tray_ = tray_;
  }
  if (friction_on_) addFriction(truth);
  raw.seq = acq_seq_++;
  raw.device_time_ms = static_cast<uint32_t>(std::llround(state_.time_s * 1000.0));
}

}  // namespace sim
}  // namespace tactile
