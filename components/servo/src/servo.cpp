#include "tactile_servo/servo.hpp"
#include "tactile_types/kdl_pose.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace tactile {

const char* const kToleranceNames[kNumTol] = {"cop_x", "cop_y", "d_z", "dzmp_x", "dzmp_y", "alpha_z",
                                              "force", "coc_x", "coc_y"};
const char* const kFeatureNames[6] = {"cop_x", "cop_y", "d_z", "coc_x", "coc_y", "alpha_z"};
const char* const kAxisNames[6] = {"x", "y", "z", "wx", "wy", "wz"};

const char* toString(TransitionEvent e) {
  switch (e) {
    case TransitionEvent::Contact: return "contact";
    case TransitionEvent::Edge: return "edge";
    case TransitionEvent::Point: return "point";
    case TransitionEvent::Aligned: return "aligned";
    case TransitionEvent::ContactLost: return "contact_lost";
    case TransitionEvent::ForceAbove: return "force_above";
    case TransitionEvent::Timeout: return "timeout";
  }
  return "unknown";
}

// Eq. 6: s = [CoP_x, CoP_y, d_z, CoC_x, CoC_y, alpha_z].
Vec6 featureVector(const ContactFeatures& f) {
  Vec6 s;
  s << f.cop_x, f.cop_y, f.d_z, f.coc_x, f.coc_y, f.alpha_z;
  return s;
}

// Eq. 8 in its 6x6 form (decision documented in servo.hpp).
Mat6 paperJinv(double beta) {
  Mat6 j = Mat6::Zero();
  j(0, 0) = 1.0;    // CoP_x
  j(1, 1) = 1.0;    // CoP_y
  j(2, 2) = 1.0;    // d_z
  j(3, 1) = 1.0;    // DZMP_x = CoP_y - β CoC_y (Eq. 3)
  j(3, 4) = -beta;
  j(4, 0) = 1.0;    // DZMP_y = CoP_x - β CoC_x (Eq. 3)
  j(4, 3) = -beta;
  j(5, 5) = beta;   // α_z, edge only
  return j;
}

// Li et al. (RSS 2013) as compared in Sec. 5.2.1: constant, no DZMP rows.
Mat6 baselineJinv() {
  Vec6 d;
  d << 1, 1, 1, 0, 0, 1;
  return d.asDiagonal();
}

// Eq. 10.
Mat6 projection(double gx, double gy, double gz, double gwx, double gwy, double gwz, double gcom) {
  Vec6 d;
  d << gx, gy, gz, gwx, gwy, gwz;
  Mat6 p = d.asDiagonal();
  p(kX, kWY) = gcom;
  return p;
}

Vec6 defaultMotionSign() {
  Vec6 s;
  s << -1, -1, 1, 1, -1, -1;
  return s;
}

namespace {

bool finite6(const Vec6& v) { return v.allFinite(); }

bool frameFinite(const KDL::Frame& f) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(f.p(i))) return false;
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(f.M(i, j))) return false;
  }
  return true;
}

bool featuresFinite(const ContactFeatures& f) {
  const double v[] = {f.time_s, f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.dzmp_x, f.dzmp_y, f.alpha_z, f.force, f.d_z};
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

bool hasContact(const ContactFeatures& f) {
  return f.contact != ContactType::None && f.status != FeatureStatus::NoContact;
}

std::string where(const ServoParams& p, const std::string& phase, const std::string& field) {
  std::string s = p.source.empty() ? std::string("<memory>") : p.source;
  s += ": ";
  if (!phase.empty()) s += "phases." + phase + ".";
  return s + field;
}

template <typename T>
ConfigResult err(const ServoParams& p, const std::string& phase, const std::string& field, const T& value,
                 const std::string& req) {
  return rangeError(where(p, phase, field), value, req);
}

}  // namespace

ConfigResult TactileServo::configure(const ServoParams& p) {
  configured_ = false;
  const SafetyParams& s = p.safety;
  // ---- program-level parameters
  if (!(std::isfinite(p.c_z) && p.c_z > 0)) return err(p, "", "c_z", p.c_z, "must be > 0 (m/N)");
  for (int i = 0; i < 6; ++i)
    if (p.motion_sign(i) != 1.0 && p.motion_sign(i) != -1.0)
      return err(p, "", std::string("motion_sign.") + kAxisNames[i], p.motion_sign(i), "must be +1 or -1");
  if (!frameFinite(p.sensor_mount)) return err(p, "", "sensor_mount", "non-finite", "must be finite");
  if (!(std::isfinite(s.max_trans_step) && s.max_trans_step > 0 && s.max_trans_step <= 0.01))
    return err(p, "", "safety.max_trans_step", s.max_trans_step, "must be in (0, 0.01] m per cycle");
  if (!(std::isfinite(s.max_rot_step) && s.max_rot_step > 0 && s.max_rot_step <= 0.1))
    return err(p, "", "safety.max_rot_step", s.max_rot_step, "must be in (0, 0.1] rad per cycle");
  for (int i = 0; i < 3; ++i)
    if (!(std::isfinite(s.workspace_min[i]) && std::isfinite(s.workspace_max[i]) &&
          s.workspace_min[i] < s.workspace_max[i]))
      return err(p, "", "safety.workspace", s.workspace_min[i], "min must be finite and < max on every axis");
  if (!(std::isfinite(s.force_ceiling) && s.force_ceiling > 0))
    return err(p, "", "safety.force_ceiling", s.force_ceiling, "must be > 0 (N)");
  if (!(std::isfinite(s.ceiling_retreat) && s.ceiling_retreat >= 0 && s.ceiling_retreat <= 0.2))
    return err(p, "", "safety.ceiling_retreat", s.ceiling_retreat, "must be in [0, 0.2] m");
  if (!(std::isfinite(s.stale_timeout) && s.stale_timeout > 0))
    return err(p, "", "safety.stale_timeout", s.stale_timeout, "must be > 0 (s)");
  if (!(std::isfinite(s.backoff_distance) && s.backoff_distance >= 0 && s.backoff_distance <= 0.2))
    return err(p, "", "safety.contact_loss.backoff_distance", s.backoff_distance, "must be in [0, 0.2] m");
  if (!(std::isfinite(s.search_speed) && s.search_speed >= 0 && s.search_speed <= 0.1))
    return err(p, "", "safety.contact_loss.search_speed", s.search_speed, "must be in [0, 0.1] m/s");
  if (!(std::isfinite(s.search_max_distance) && s.search_max_distance >= 0 && s.search_max_distance <= 0.2))
    return err(p, "", "safety.contact_loss.search_max_distance", s.search_max_distance, "must be in [0, 0.2] m");
  if (p.phases.empty()) return ConfigResult::failure(where(p, "", "phases") + ": at least one phase is required");

  // ---- phases
  const int n = static_cast<int>(p.phases.size());
  auto indexOf = [&](const std::string& name) {
    for (int i = 0; i < n; ++i)
      if (p.phases[static_cast<std::size_t>(i)].name == name) return i;
    return -1;
  };
  for (int i = 0; i < n; ++i) {
    const PhaseParams& ph = p.phases[static_cast<std::size_t>(i)];
    const std::string& nm = ph.name;
    if (nm.empty() || nm.size() >= static_cast<std::size_t>(kPhaseNameLen))
      return err(p, "[" + std::to_string(i) + "]", "name", "'" + nm + "'",
                 "must have 1.." + std::to_string(kPhaseNameLen - 1) + " characters");
    if (indexOf(nm) != i) return err(p, nm, "name", nm, "duplicate phase name");
    if (!finite6(ph.s_d)) return err(p, nm, "s_d", "non-finite", "must be finite");
    if (!ph.jinv_point.allFinite()) return err(p, nm, "jacobian.point", "non-finite", "must be finite");
    if (!ph.jinv_edge.allFinite()) return err(p, nm, "jacobian.edge", "non-finite", "must be finite");
    if (!ph.P.allFinite()) return err(p, nm, "P", "non-finite", "must be finite");
    for (int a = 0; a < 6; ++a) {
      const std::string ax = kAxisNames[a];
      if (!(std::isfinite(ph.kp(a)) && ph.kp(a) >= 0)) return err(p, nm, "kp." + ax, ph.kp(a), "must be >= 0 (per cycle)");
      if (!(std::isfinite(ph.ki(a)) && ph.ki(a) >= 0)) return err(p, nm, "ki." + ax, ph.ki(a), "must be >= 0 (1/s)");
      if (!(std::isfinite(ph.integral_limit(a)) && ph.integral_limit(a) >= 0))
        return err(p, nm, "integral_limit." + ax, ph.integral_limit(a), "must be >= 0 (m or rad per cycle)");
      if (!(ph.u_max(a) > 0)) return err(p, nm, "u_max." + ax, ph.u_max(a), "must be > 0 (m or rad per cycle)");
      if (!std::isfinite(ph.feedforward(a)) || std::fabs(ph.feedforward(a)) > 0.5)
        return err(p, nm, "feedforward." + ax, ph.feedforward(a), "must be in [-0.5, 0.5] (m/s or rad/s)");
    }
    for (std::size_t t = 0; t < ph.transitions.size(); ++t) {
      const TransitionParams& tr = ph.transitions[t];
      const std::string f = "transitions[" + std::to_string(t) + "]";
      if (indexOf(tr.to) < 0) return err(p, nm, f + ".to", "'" + tr.to + "'", "unknown phase");
      if (tr.cycles < 1) return err(p, nm, f + ".cycles", tr.cycles, "must be >= 1");
      if (tr.on == TransitionEvent::Aligned) {
        bool any = false;
        for (int k = 0; k < kNumTol; ++k) {
          if (!std::isfinite(tr.tolerance[static_cast<std::size_t>(k)]))
            return err(p, nm, f + ".tolerance." + kToleranceNames[k], "non-finite", "must be finite");
          any = any || tr.tolerance[static_cast<std::size_t>(k)] >= 0;
        }
        if (!any) return err(p, nm, f + ".tolerance", "{}", "'aligned' needs at least one tolerance");
      }
      if (tr.on == TransitionEvent::Timeout && !(std::isfinite(tr.timeout_s) && tr.timeout_s > 0))
        return err(p, nm, f + ".timeout_s", tr.timeout_s, "must be > 0 (s)");
      if (tr.on == TransitionEvent::ForceAbove && !(std::isfinite(tr.force_n) && tr.force_n > 0))
        return err(p, nm, f + ".force_n", tr.force_n, "must be > 0 (N)");
    }
  }
  const int init = p.initial_phase.empty() ? 0 : indexOf(p.initial_phase);
  if (init < 0) return err(p, "", "initial_phase", "'" + p.initial_phase + "'", "unknown phase");
  // Reachability from the initial phase through transitions.
  std::vector<char> reach(static_cast<std::size_t>(n), 0);
  std::vector<int> stack{init};
  reach[static_cast<std::size_t>(init)] = 1;
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    for (const TransitionParams& tr : p.phases[static_cast<std::size_t>(i)].transitions) {
      const int j = indexOf(tr.to);
      if (!reach[static_cast<std::size_t>(j)]) {
        reach[static_cast<std::size_t>(j)] = 1;
        stack.push_back(j);
      }
    }
  }
  for (int i = 0; i < n; ++i)
    if (!reach[static_cast<std::size_t>(i)])
      return ConfigResult::failure(where(p, p.phases[static_cast<std::size_t>(i)].name, "transitions") +
                                   ": phase unreachable from the initial phase '" +
                                   p.phases[static_cast<std::size_t>(init)].name + "'");

  // ---- build the RT representation
  params_ = p;
  phases_.clear();
  transitions_.clear();
  phases_.reserve(static_cast<std::size_t>(n));
  for (const PhaseParams& ph : p.phases) {
    Phase q;
    std::strncpy(q.name.data(), ph.name.c_str(), q.name.size() - 1);
    q.s_d = ph.s_d;
    q.j_point = ph.jinv_point;
    q.j_edge = ph.jinv_edge;
    q.touch = ph.jacobian == JacobianMode::Touch;
    q.fixed_edge = ph.fixed_edge;
    q.P = ph.P;
    q.kp = ph.kp;
    q.ki = ph.ki;
    q.i_lim = ph.integral_limit;
    q.u_max = ph.u_max;
    q.ff = ph.feedforward;
    q.requires_contact = ph.requires_contact;
    q.reset_integrator = ph.reset_integrator;
    q.terminal = ph.terminal;
    q.free_motion = ph.P.isZero(0.0);
    q.first_transition = static_cast<int>(transitions_.size());
    q.num_transitions = static_cast<int>(ph.transitions.size());
    for (const TransitionParams& tr : ph.transitions)
      transitions_.push_back({tr.on, indexOf(tr.to), tr.cycles, tr.tolerance, tr.timeout_s, tr.force_n, 0});
    phases_.push_back(q);
  }
  T_es_ = p.sensor_mount;
  T_se_ = p.sensor_mount.Inverse();
  initial_ = init;
  configured_ = true;
  reset();
  return ConfigResult::success();
}

void TactileServo::reset() {
  current_ = initial_;
  pending_ = -1;
  entered_ = false;
  integral_.setZero();
  has_cmd_ = false;
  ceiling_latched_ = false;
  ceiling_moved_ = 0.0;
  recovery_moved_ = 0.0;
  for (Transition& t : transitions_) t.count = 0;
}

int TactileServo::phaseIndexOf(const char* name) const {
  if (name == nullptr) return -1;
  for (std::size_t i = 0; i < phases_.size(); ++i)
    if (std::strncmp(phases_[i].name.data(), name, phases_[i].name.size()) == 0) return static_cast<int>(i);
  return -1;
}

bool TactileServo::requestPhase(const char* name) { return requestPhase(phaseIndexOf(name)); }

bool TactileServo::requestPhase(int index) {
  if (!configured_ || index < 0 || index >= static_cast<int>(phases_.size())) return false;
  pending_ = index;
  ceiling_latched_ = false;
  return true;
}

void TactileServo::enterPhase(int idx, double now) {
  current_ = idx;
  t_enter_ = now;
  entered_ = true;
  const Phase& ph = phases_[static_cast<std::size_t>(idx)];
  if (ph.reset_integrator) integral_.setZero();
  for (int k = 0; k < ph.num_transitions; ++k) transitions_[static_cast<std::size_t>(ph.first_transition + k)].count = 0;
  recovery_moved_ = 0.0;
}

// Touch dependence (Eq. 8 with Eq. 5): edge -> β = 1, point/none -> β = 0.
const Mat6& TactileServo::jacobianFor(const Phase& ph, ContactType c, uint8_t& beta) const {
  if (params_.mode == ControllerMode::Baseline) {
    beta = 0;
    return baseline_;
  }
  const bool edge = ph.touch ? (c == ContactType::Edge) : ph.fixed_edge;
  beta = edge ? 1 : 0;
  return edge ? ph.j_edge : ph.j_point;
}

const Mat6& TactileServo::jacobian(int phase, ContactType c, uint8_t* beta_out) const {
  uint8_t beta = 0;
  const Mat6& j = jacobianFor(phases_[static_cast<std::size_t>(phase)], c, beta);
  if (beta_out) *beta_out = beta;
  return j;
}

Vec6 TactileServo::featureError(int phase, const ContactFeatures& f, uint8_t* beta_out) const {
  if (phase < 0 || phase >= static_cast<int>(phases_.size())) return Vec6::Zero();
  const Phase& ph = phases_[static_cast<std::size_t>(phase)];
  uint8_t beta = 0;
  const Mat6& j = jacobianFor(ph, f.contact, beta);
  if (beta_out) *beta_out = beta;
  return ph.s_d - j * featureVector(f);  // Eq. 7
}

bool TactileServo::evaluateTransitions(const ContactFeatures& f, const Vec6& e, double now, int& target) {
  const Phase& ph = phases_[static_cast<std::size_t>(current_)];
  const bool contact = hasContact(f);
  for (int k = 0; k < ph.num_transitions; ++k) {
    Transition& t = transitions_[static_cast<std::size_t>(ph.first_transition + k)];
    bool cond = false;
    switch (t.on) {
      case TransitionEvent::Contact: cond = contact; break;
      case TransitionEvent::Edge: cond = contact && f.contact == ContactType::Edge; break;
      case TransitionEvent::Point: cond = contact && f.contact == ContactType::Point; break;
      case TransitionEvent::ContactLost: cond = !contact; break;
      case TransitionEvent::ForceAbove: cond = f.force > t.force_n; break;
      case TransitionEvent::Timeout: cond = now - t_enter_ >= t.timeout_s; break;
      case TransitionEvent::Aligned: {
        double q[kNumTol];
        for (int i = 0; i < 6; ++i) q[i] = std::fabs(e(i));
        q[kTolForce] = std::fabs(e(kZ)) / params_.c_z;
        q[kTolCocX] = std::fabs(f.coc_x);
        q[kTolCocY] = std::fabs(f.coc_y);
        cond = contact;
        for (int i = 0; i < kNumTol; ++i)
          if (t.tol[static_cast<std::size_t>(i)] >= 0 && !(q[i] <= t.tol[static_cast<std::size_t>(i)])) cond = false;
        break;
      }
    }
    t.count = cond ? t.count + 1 : 0;
    if (t.count >= t.cycles) {
      target = t.to;
      return true;
    }
  }
  return false;
}

// Per-cycle step limits: translation and rotation norms, scaled (direction kept).
bool TactileServo::limitIncrement(Vec6& u) const {
  bool limited = false;
  const double nt = u.head<3>().norm();
  if (nt > params_.safety.max_trans_step) {
    u.head<3>() *= params_.safety.max_trans_step / nt;
    limited = true;
  }
  const double nr = u.tail<3>().norm();
  if (nr > params_.safety.max_rot_step) {
    u.tail<3>() *= params_.safety.max_rot_step / nr;
    limited = true;
  }
  return limited;
}

ServoStatus TactileServo::finish(ServoStatus st, double now, ServoOutput& out) {
  const double t = std::isfinite(now) ? now : 0.0;
  if (has_cmd_) toPose(cmd_, out.command.pose);
  out.valid = has_cmd_;
  out.command.time_s = t;
  out.command.seq = seq_;
  out.command.status = st;
  out.phase.time_s = t;
  out.phase.t_enter_s = t_enter_;
  out.phase.index = static_cast<uint16_t>(current_);
  out.phase.name = phases_[static_cast<std::size_t>(current_)].name;
  out.phase.status = st;
  return st;
}

ServoStatus TactileServo::applyIncrement(const KDL::Frame& base, Vec6 u_s, ServoStatus st, double now,
                                         ServoOutput& out) {
  if (!finite6(u_s)) return finish(ServoStatus::InvalidInput, now, out);
  const bool limited = limitIncrement(u_s);
  // Eq. 13: {g}T{s} = {g}T{e} {e}T{s}; the increment, expressed in {s} and
  // applied at the origin of {s}, is rotated into {g} (same reference point).
  const KDL::Frame T_gs = base * T_es_;
  const KDL::Twist t_s(KDL::Vector(u_s(0), u_s(1), u_s(2)), KDL::Vector(u_s(3), u_s(4), u_s(5)));
  const KDL::Twist t_g = T_gs.M * t_s;
  // Eq. 12 / Eq. 15: x_d = x + u.
  const KDL::Frame T_gs_new = KDL::addDelta(T_gs, t_g, 1.0);
  KDL::Frame T_ge_new = T_gs_new * T_se_;
  // Workspace box on the flange position. A base pose already outside the box
  // widens it to include that pose: an increment may only move back towards
  // the box, never jump onto it.
  bool clipped = false;
  const KDL::Vector p0 = base.p;
  for (int i = 0; i < 3; ++i) {
    const double lo = std::min(params_.safety.workspace_min[static_cast<std::size_t>(i)], p0(i));
    const double hi = std::max(params_.safety.workspace_max[static_cast<std::size_t>(i)], p0(i));
    if (T_ge_new.p(i) < lo) { T_ge_new.p(i) = lo; clipped = true; }
    if (T_ge_new.p(i) > hi) { T_ge_new.p(i) = hi; clipped = true; }
  }
  if (!frameFinite(T_ge_new)) return finish(ServoStatus::InvalidInput, now, out);
  cmd_ = T_ge_new;
  out.u_s = u_s;
  if ((limited || clipped) && (st == ServoStatus::Ok || st == ServoStatus::FreeMotion)) st = ServoStatus::Limited;
  return finish(st, now, out);
}

ServoStatus TactileServo::step(const ServoInput& in, double dt, ServoOutput& out) {
  out.error.setZero();
  out.error_task.setZero();
  out.u_s.setZero();
  out.beta = 0;
  if (!configured_) {
    out.valid = false;
    out.command.status = ServoStatus::NotConfigured;
    out.phase.status = ServoStatus::NotConfigured;
    return ServoStatus::NotConfigured;
  }
  ++seq_;
  const double now = in.time_s;
  const bool time_ok = std::isfinite(now);
  KDL::Frame meas;
  const bool pose_ok = toFrame(in.flange_measured, meas);
  if (!has_cmd_) {
    // Start (or after reset): no command before a valid measured pose; the
    // first command is that pose, x(0) of Eq. 15.
    if (!pose_ok)
      return finish(isNoPose(in.flange_measured) ? ServoStatus::WaitingForPose : ServoStatus::InvalidInput, now, out);
    if (!time_ok) return finish(ServoStatus::InvalidInput, now, out);
    cmd_ = meas;
    has_cmd_ = true;
    enterPhase(pending_ >= 0 ? pending_ : current_, now);
    pending_ = -1;
    return finish(ServoStatus::Starting, now, out);
  }
  if (time_ok && pending_ >= 0) {
    enterPhase(pending_, now);
    pending_ = -1;
  }
  if (time_ok && !entered_) enterPhase(current_, now);
  if (!time_ok || !pose_ok || !(std::isfinite(dt) && dt > 0)) return finish(ServoStatus::InvalidInput, now, out);

  const SafetyParams& sp = params_.safety;
  const KDL::Frame base = params_.pose_update == PoseUpdate::Measured ? meas : cmd_;
  const ContactFeatures& f = in.features;
  Vec6 u = Vec6::Zero();

  // Force ceiling, latched: retreat along -z_s, then hold.
  const bool f_finite = featuresFinite(f);
  if (!ceiling_latched_ && f_finite && usable(f.status) && f.force > sp.force_ceiling) {
    ceiling_latched_ = true;
    ceiling_moved_ = 0.0;
  }
  if (ceiling_latched_) {
    const double d = std::min(sp.max_trans_step, sp.ceiling_retreat - ceiling_moved_);
    if (d <= 0.0) return finish(ServoStatus::ForceCeiling, now, out);
    ceiling_moved_ += d;
    u(kZ) = -d;
    return applyIncrement(base, u, ServoStatus::ForceCeiling, now, out);
  }
  if (!f_finite) return finish(ServoStatus::InvalidInput, now, out);
  // Stale-features watchdog.
  if (!usable(f.status) || now - f.time_s > sp.stale_timeout || f.time_s - now > sp.stale_timeout)
    return finish(ServoStatus::Holding, now, out);

  // Eq. 7-8 and the phase program.
  uint8_t beta = 0;
  Vec6 e = featureError(current_, f, &beta);
  int target = -1;
  if (evaluateTransitions(f, e, now, target)) {
    enterPhase(target, now);
    e = featureError(current_, f, &beta);
  }
  const Phase& ph = phases_[static_cast<std::size_t>(current_)];
  out.error = e;
  out.beta = beta;
  if (ph.terminal) return finish(ServoStatus::Done, now, out);

  // Contact loss.
  if (ph.requires_contact && !hasContact(f)) {
    switch (sp.contact_loss) {
      case ContactLossMode::Hold: return finish(ServoStatus::ContactLost, now, out);
      case ContactLossMode::Backoff: {
        const double d = std::min(sp.max_trans_step, sp.backoff_distance - recovery_moved_);
        if (d <= 0.0) return finish(ServoStatus::ContactLost, now, out);
        recovery_moved_ += d;
        u(kZ) = -d;
        return applyIncrement(base, u, ServoStatus::ContactLost, now, out);
      }
      case ContactLossMode::Search: {
        const double d =
            std::min(std::min(sp.max_trans_step, sp.search_speed * dt), sp.search_max_distance - recovery_moved_);
        if (d <= 0.0) return finish(ServoStatus::ContactLost, now, out);
        recovery_moved_ += d;
        u(kZ) = d;
        return applyIncrement(base, u, ServoStatus::ContactLost, now, out);
      }
    }
  }
  recovery_moved_ = 0.0;

  // Eq. 9: task projection.
  const Vec6 task = ph.P * e;
  out.error_task = task;
  // Eq. 13: PI per axis, integrator clamped so that |K_I ∫| <= integral_limit.
  integral_ += task * dt;
  for (int a = 0; a < 6; ++a) {
    if (ph.ki(a) > 0.0) {
      const double lim = ph.i_lim(a) / ph.ki(a);
      integral_(a) = std::max(-lim, std::min(lim, integral_(a)));
    } else {
      integral_(a) = 0.0;
    }
  }
  Vec6 pi = ph.kp.cwiseProduct(task) + ph.ki.cwiseProduct(integral_);
  pi = pi.cwiseMax(-ph.u_max).cwiseMin(ph.u_max);
  u = params_.motion_sign.cwiseProduct(pi) + ph.ff * dt;
  return applyIncrement(base, u, ph.free_motion ? ServoStatus::FreeMotion : ServoStatus::Ok, now, out);
}

}  // namespace tactile
