#include "tactile_servo/servo.hpp"
#include "tactile_servo/servo_schema.hpp"
#include "tactile_types/kdl_pose.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tactile {

namespace {
/// Per phase of `p`: listed in `names` (a block's `phases`); a name that is no
/// phase, or a terminal one (nothing slides there), is an error naming `key`.
ConfigResult phaseFlags(const ServoParams& p, const std::vector<std::string>& names, const char* key,
                        std::vector<char>& flags) {
  flags.assign(p.phases.size(), 0);
  for (const std::string& name : names) {
    std::size_t i = 0;
    while (i < p.phases.size() && p.phases[i].name != name) ++i;
    if (i == p.phases.size())
      return ConfigResult::failure(p.source + ": " + key + ".phases: no phase '" + name + "'");
    if (p.phases[i].terminal)
      return ConfigResult::failure(p.source + ": " + key + ".phases: '" + name + "' is terminal (nothing to slide)");
    flags[i] = 1;
  }
  return ConfigResult::success();
}
}  // namespace

ConfigResult TactileServo::configure(const ServoParams& p) {
  configured_ = false;
  ConfigResult r = law_.configure(p);  // c_z, motion sign, mount; per phase s_d, J^-1, P, gains
  if (r) r = safety_.configure(p);     // step limits, box, ceiling, stale, contact loss
  if (r) r = program_.configure(p);    // names, transitions, initial phase, reachability
  if (r) r = watchdogs_.configure(p);  // phase timeout, arm stall, force mismatch
  if (r) r = force_est_.configure(p.force_estimate, (p.source + ": force_estimate").c_str());
  if (r) r = speed_law_.configure(p.speed_law.law, (p.source + ": speed_law").c_str());
  if (!r) return r;
  if (!(r = phaseFlags(p, p.speed_law.phases, "speed_law", speed_phase_))) return r;
  if (!(r = phaseFlags(p, p.slope_feedforward.phases, "slope_feedforward", slope_phase_))) return r;
  if (!(r = slope_ff_.configure(p.slope_feedforward.window_m, p.slope_feedforward.axis,
                                (p.source + ": slope_feedforward").c_str())))
    return r;
  if (!(r = schema::checkRanges(speedLawServoSchema(), p.speed_law, p.source + ": speed_law"))) return r;
  speed_filter_.configure(p.speed_law.rate_tau_s, p.speed_law.excess_tau_s);
  params_ = p;
  configured_ = true;
  reset();
  return ConfigResult::success();
}

void TactileServo::reset() {
  program_.reset();
  law_.resetIntegrator();
  safety_.reset();
  watchdogs_.reset();
  force_est_.reset();
  speed_law_.reset();
  speed_filter_.reset();
  slope_ff_.reset();
  has_cmd_ = false;
  waiting_ = false;
}

bool TactileServo::requestPhase(const char* name) { return requestPhase(phaseIndexOf(name)); }

bool TactileServo::requestPhase(int index) {
  if (!configured_ || !program_.request(index)) return false;
  safety_.clearCeiling();
  watchdogs_.clear();
  return true;
}

void TactileServo::enterPhase(int idx, double now) {
  program_.enter(idx, now);
  if (program_.resetsIntegrator(idx)) law_.resetIntegrator();
  speed_law_.reset();  // a new phase slides from v_min
  speed_filter_.reset();
  slope_ff_.reset();  // and measures its slope afresh
  safety_.resetRecovery();
}

const Mat6& TactileServo::jacobian(int phase, ContactType c, uint8_t* beta_out) const {
  uint8_t beta = 0;
  const Mat6& j = law_.jacobian(phase, c, beta);
  if (beta_out) *beta_out = beta;
  return j;
}

Vec6 TactileServo::featureError(int phase, const ContactFeatures& f, uint8_t* beta_out) const {
  uint8_t beta = 0;
  const Vec6 e = law_.featureError(phase, f, beta);
  if (beta_out && phase >= 0 && phase < law_.phaseCount()) *beta_out = beta;
  return e;
}

ServoStatus TactileServo::finish(ServoStatus st, double now, ServoOutput& out) {
  if (!motion_cycle_) watchdogs_.restartStall();
  const double t = std::isfinite(now) ? now : 0.0;
  if (has_cmd_) toPose(cmd_, out.command.pose);
  out.valid = has_cmd_;
  out.command.time_s = t;
  out.command.seq = seq_;
  out.command.status = st;
  out.phase.time_s = t;
  out.phase.t_enter_s = program_.enteredAt();
  out.phase.index = static_cast<uint16_t>(program_.current());
  out.phase.name = program_.name(program_.current());
  out.phase.status = st;
  return st;
}

ServoStatus TactileServo::onSensorFault(const KDL::Frame& base, double dt, double now, ServoOutput& out) {
  // The retreat is along -z_s: u_s's z in {s} (Eq. 13).
  const ServoStatus st = watchdogs_.latched();
  const double d = watchdogs_.faultRetreat(safety_.maxTransStep(dt));
  if (d <= 0.0) return finish(st, now, out);
  Vec6 u = Vec6::Zero();
  u(kZ) = -d;
  return applyIncrement(base, u, dt, st, now, out);
}

ServoStatus TactileServo::applyIncrement(const KDL::Frame& base, Vec6 u_s, double dt, ServoStatus st, double now,
                                         ServoOutput& out) {
  if (!u_s.allFinite()) return finish(ServoStatus::InvalidInput, now, out);
  const bool limited = safety_.limitStep(u_s, dt);
  KDL::Frame T_ge_new = law_.apply(base, u_s);  // Eq. 12/13/15
  const bool clipped = safety_.clipWorkspace(base.p, T_ge_new);
  // Commanded motion (not the ceiling's retreat, not held at the workspace
  // box): the measured pose must follow.
  if (st != ServoStatus::ForceCeiling && !watchdogStatus(st) && !clipped && !dry_run_) {
    motion_cycle_ = true;
    if (watchdogs_.armStalled(meas_ * law_.sensorMount(), u_s, in_contact_, now))
      return finish(ServoStatus::ArmStalled, now, out);
  }
  if (!frameFinite(T_ge_new)) return finish(ServoStatus::InvalidInput, now, out);
  cmd_ = T_ge_new;
  out.u_s = u_s;
  if ((limited || clipped) && (st == ServoStatus::Ok || st == ServoStatus::FreeMotion)) st = ServoStatus::Limited;
  return finish(st, now, out);
}

double TactileServo::slideCap(int phase, const ContactFeatures& f, double f_hat, double f_d, double extent,
                              double excess, double dt, ServoOutput& out) {
  out.slide_speed = 0.0;
  out.speed_limiter = SpeedLimiter::None;
  if (phase < 0 || static_cast<std::size_t>(phase) >= speed_phase_.size() || !speed_phase_[static_cast<std::size_t>(phase)])
    return -1.0;
  SpeedLawSignals s;
  s.force_error_n = f_d - f_hat;
  s.alpha_z = f.alpha_z;
  s.alpha_defined = f.alpha_defined;
  s.curvature = f.curvature;
  s.extent_m = extent;
  s.wrench_excess_n = excess;
  SpeedLawInput& in = out.speed_inputs;
  speed_filter_.step(s, dt, in);
  speed_law_.step(in, dt);  // InvalidInput: v_min
  out.slide_speed = speed_law_.speed();
  out.speed_limiter = speed_law_.limiter();
  return out.slide_speed;
}

void TactileServo::observePose(const ServoInput& in, const KDL::Frame& meas, bool first) {
  const ContactFeatures& f = in.features;
  const KDL::Frame T_gs = meas * law_.sensorMount();
  if (first) {
    wrist_yaw_ = 0.0;
  } else {
    const KDL::Vector rot = (yaw_prev_.Inverse() * T_gs.M).GetRot();  // rotation vector in {s}(t-1)
    wrist_yaw_ += rot.z();
  }
  yaw_prev_ = T_gs.M;
  ProgramSignals sig;
  sig.wrist_yaw = wrist_yaw_;
  sig.have_point = PhaseProgram::hasContact(f) && std::isfinite(f.cop_x) && std::isfinite(f.cop_y);
  if (sig.have_point) {
    const KDL::Vector p = T_gs * KDL::Vector(0.0, f.cop_y, 0.0);  // the edge at the pad's centre (WRIST)
    sig.point[0] = p.x(), sig.point[1] = p.y(), sig.point[2] = p.z();
  }
  if (in.have_q) {  // the joint closest to its limit (kArmJointLimit)
    for (int j = 0; j < kArmJoints; ++j) {
      const auto k = static_cast<std::size_t>(j);
      sig.joint_margin = std::min(sig.joint_margin, kArmJointLimit[k] - std::fabs(in.q[k]));
    }
  }
  program_.observe(sig);
}

ServoStatus TactileServo::forceStage(const ServoInput& in, const KDL::Frame& meas, double dt, double now,
                                     ForceStage& fs, ServoOutput& out) {
  // The force the law and the transitions use: Eq. 2's f, or f corrected by
  // the wrench at low frequency (force_estimator.hpp), which also keeps the
  // wrench's zero (tare).
  const ContactFeatures& f = in.features;
  const KDL::Vector z_s = (meas * law_.sensorMount()).M.UnitZ();
  const bool contact = PhaseProgram::hasContact(f);
  const bool wrench_fresh = in.have_wrench && std::fabs(now - in.wrench.time_s) <= params_.safety.stale_timeout;
  const KDL::Vector F(in.wrench.w[0], in.wrench.w[1], in.wrench.w[2]);
  fs.f_hat = force_est_.step(f.force, contact, wrench_fresh, F, z_s, dt, f.area);
  fs.f_law = fs.f_hat;
  fs.extent = std::sqrt(12.0 * std::max(0.0, f.lambda1));  // the image's length along the edge (a uniform line's)
  // The taxels (Eq. 2's f, never f_hat) against the arm's estimated wrench
  // (less its zero) along z_s, and the estimate's correction against its limit.
  const double f_w = ForceEstimator::press(F, force_est_.tare(), z_s);
  out.force_wrench = wrench_fresh ? f_w : std::numeric_limits<double>::quiet_NaN();
  out.force_correction = force_est_.correction();
  out.force_demand = force_est_.demand();
  const int phc = program_.current();
  const double f_d = params_.phases[static_cast<std::size_t>(phc)].s_d(kZ) / law_.c_z();
  const bool regulated = program_.requiresContact(phc) && f_d > 0.0;  // the phase holds a force set point
  ServoWatchdogs::SensorSample ss;
  ss.f = f.force;
  ss.contact = contact;
  ss.fresh = wrench_fresh;
  ss.f_w = f_w;
  ss.hidden_n = ss.c_max = params_.force_estimate.fused ? params_.force_estimate.max_correction_n : 0.0;
  ss.c = force_est_.demand();
  ss.phase = phc;
  ss.regulated = regulated;
  ss.extent_m = fs.extent;
  const ServoStatus disagree = watchdogs_.sensorsAgree(ss, dt);
  if (disagree != ServoStatus::Ok) return disagree;
  // The surface curves more tightly than the pad (watchdog.hpp): the
  // wrench well above the set point the law holds, the image shrunk.
  if (wrench_fresh && contact) fs.excess = f_w - (params_.speed_law.excess_against_tactile ? f.force : fs.f_hat);
  if (watchdogs_.surfaceTooCurved(f_w, f_d, regulated, contact, f.force, fs.extent, wrench_fresh, dt))
    return ServoStatus::SurfaceTooCurved;
  // The first reaction: lift by the load the taxels miss (0 unless configured).
  const double lift = watchdogs_.curvedLift();
  if (lift > 0.0) fs.f_law = std::max(fs.f_hat, f_d + lift);
  return ServoStatus::Ok;
}

ServoStatus TactileServo::step(const ServoInput& in, double dt, ServoOutput& out) {
  out.error.setZero();
  out.error_task.setZero();
  out.u_s.setZero();
  out.beta = 0;
  out.force = in.features.force;
  out.slide_speed = 0.0;
  out.speed_limiter = SpeedLimiter::None;
  if (!configured_) {
    out.valid = false;
    out.command.status = ServoStatus::NotConfigured;
    out.phase.status = ServoStatus::NotConfigured;
    return ServoStatus::NotConfigured;
  }
  ++seq_;
  motion_cycle_ = false;
  dry_run_ = in.dry_run;
  in_contact_ = false;
  KDL::Frame meas;
  const bool pose_ok = toFrame(in.flange_measured, meas);
  ServoStatus gated = ServoStatus::Ok;
  if (gate(in, meas, pose_ok, dt, gated, out)) return gated;
  return control(in, meas, dt, out);
}

bool TactileServo::gate(const ServoInput& in, const KDL::Frame& meas, bool pose_ok, double dt, ServoStatus& st,
                        ServoOutput& out) {
  const double now = in.time_s;
  const bool time_ok = std::isfinite(now);
  const bool dt_ok = std::isfinite(dt) && dt > 0.0;
  if (!has_cmd_) {
    // Start (or after reset): no command before a valid measured pose; the
    // first command is that pose, x(0) of Eq. 15.
    if (!pose_ok) {
      st = finish(isNoPose(in.flange_measured) ? ServoStatus::WaitingForPose : ServoStatus::InvalidInput, now, out);
      return true;
    }
    if (!time_ok) {
      st = finish(ServoStatus::InvalidInput, now, out);
      return true;
    }
    cmd_ = meas;
    has_cmd_ = true;
    observePose(in, meas, true);
    enterPhase(program_.pending() >= 0 ? program_.pending() : program_.current(), now);
    program_.clearPending();
    st = finish(ServoStatus::Starting, now, out);
    return true;
  }
  // Watchdogs: a latched one holds (a sensor fault may first retreat, on_fault).
  if (watchdogs_.latched() != ServoStatus::Ok) {
    if (pose_ok && time_ok && dt_ok && (in.robot_ready || in.dry_run)) {
      const KDL::Frame base = params_.pose_update == PoseUpdate::Measured ? meas : cmd_;
      meas_ = meas;
      st = onSensorFault(base, dt, now, out);
    } else {
      st = finish(watchdogs_.latched(), now, out);
    }
    return true;
  }
  // ROBOT STATE: hold at the measured pose, everything frozen.
  if (!in.robot_ready && !in.dry_run) {
    if (pose_ok && time_ok) {
      KDL::Frame held;  // where the KRC holds the arm; the start gate passes on it
      cmd_ = toFrame(in.robot_setpoint, held) ? held : meas;
      observePose(in, meas, false);
    }
    if (time_ok && dt_ok) program_.delayEntry(dt);  // the time in the phase stands still
    waiting_ = true;
    st = finish(ServoStatus::WaitingForRobot, now, out);
    return true;
  }
  waiting_ = false;
  if (time_ok && program_.pending() >= 0) {
    enterPhase(program_.pending(), now);
    program_.clearPending();
  }
  if (time_ok && !program_.entered()) enterPhase(program_.current(), now);
  // A phase longer than its limit latches.
  if (time_ok && !program_.terminal(program_.current()) &&
      watchdogs_.phaseTimeout(now - program_.enteredAt(),
                              params_.phases[static_cast<std::size_t>(program_.current())].max_duration_s)) {
    st = finish(ServoStatus::PhaseTimeout, now, out);
    return true;
  }
  if (!time_ok || !pose_ok || !dt_ok) {
    st = finish(ServoStatus::InvalidInput, now, out);
    return true;
  }
  meas_ = meas;
  observePose(in, meas, false);
  return false;
}

ServoStatus TactileServo::control(const ServoInput& in, const KDL::Frame& meas, double dt, ServoOutput& out) {
  const double now = in.time_s;
  const KDL::Frame base = params_.pose_update == PoseUpdate::Measured ? meas : cmd_;
  const ContactFeatures& f = in.features;
  Vec6 u = Vec6::Zero();

  // Force ceiling, latched: retreat along -z_s, then hold.
  const bool f_finite = SafetySupervisor::featuresFinite(f);
  double retreat = 0.0;
  if (safety_.forceCeiling(f, f_finite, dt, retreat)) {
    if (retreat <= 0.0) return finish(ServoStatus::ForceCeiling, now, out);
    u(kZ) = -retreat;
    return applyIncrement(base, u, dt, ServoStatus::ForceCeiling, now, out);
  }
  if (!f_finite) return finish(ServoStatus::InvalidInput, now, out);
  // Stale features, and a stream that re-sends its last image while the arm moves: hold.
  if (safety_.frozenImage(f, meas.p, now) || safety_.stale(f, now)) return finish(ServoStatus::Holding, now, out);
  // The force the law and the transitions use, and the two sensors against each other.
  ForceStage fs;
  const ServoStatus fst = forceStage(in, meas, dt, now, fs, out);
  if (fst == ServoStatus::SurfaceTooCurved) return finish(fst, now, out);
  if (fst != ServoStatus::Ok) return onSensorFault(base, dt, now, out);  // the sensors disagree
  ContactFeatures fc = in.features;
  fc.d_z += law_.c_z() * (fs.f_law - f.force);  // Eq. 2: d_z = C_z f
  fc.force = fs.f_law;
  out.force = fs.f_law;

  // Eq. 7-8 and the phase program.
  uint8_t beta = 0;
  Vec6 e = law_.featureError(program_.current(), fc, beta);
  int target = -1;
  if (program_.evaluate(fc, e, now, dt, law_.c_z(), target)) {
    enterPhase(target, now);
    e = law_.featureError(program_.current(), fc, beta);
  }
  const int ph = program_.current();
  out.error = e;
  out.beta = beta;
  if (program_.terminal(ph)) return finish(ServoStatus::Done, now, out);

  in_contact_ = PhaseProgram::hasContact(f);
  // Contact loss.
  if (program_.requiresContact(ph) && !PhaseProgram::hasContact(f)) {
    speed_law_.reset();  // back in contact: slide from v_min
    speed_filter_.reset();
    slope_ff_.reset();
    const double dz = safety_.contactLoss(dt);
    if (dz == 0.0) return finish(ServoStatus::ContactLost, now, out);
    u(kZ) = dz;
    return applyIncrement(base, u, dt, ServoStatus::ContactLost, now, out);
  }
  safety_.resetRecovery();
  return law(ph, e, f, fs, base, dt, now, out);
}

ServoStatus TactileServo::law(int ph, const Vec6& e, const ContactFeatures& f, const ForceStage& fs,
                              const KDL::Frame& base, double dt, double now, ServoOutput& out) {
  // Eq. 9: task projection; Eq. 13: PI, motion sign, feed-forward.
  const Vec6 task = law_.project(ph, e);
  out.error_task = task;
  Vec6 u = law_.increment(ph, task, dt);
  const double cap = slideCap(ph, f, fs.f_hat, params_.phases[static_cast<std::size_t>(ph)].s_d(kZ) / law_.c_z(),
                              fs.extent, fs.excess, dt, out);
  if (cap >= 0.0) {
    const int a = params_.speed_law.axis;
    u(a) = speed_law_.slide(u(a) / dt, dt) * dt;  // capped, driven, guarded (speed_law.hpp)
  }
  if (static_cast<std::size_t>(ph) < slope_phase_.size() && slope_phase_[static_cast<std::size_t>(ph)]) {
    // The slide's slope along z_s (slope_feedforward.hpp): a change of the
    // slide speed or of the slope does not wait for the force PI's integral.
    const int a = params_.slope_feedforward.axis;
    u(kZ) += slope_ff_.step(meas_ * law_.sensorMount()) * u(a);
  }
  const double unwind = params_.phases[static_cast<std::size_t>(ph)].unwind_rate;
  if (unwind > 0.0)  // WRIST: against the yaw the phase was entered with (its wrist_unwound ends it)
    u(5) += program_.yawAtEnter() > 0.0 ? -unwind * dt : unwind * dt;
  return applyIncrement(base, u, dt, program_.freeMotion(ph) ? ServoStatus::FreeMotion : ServoStatus::Ok, now, out);
}

}  // namespace tactile
