#include "tactile_servo/phase_program.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "servo_config.hpp"
#include "tactile_servo/servo_schema.hpp"

namespace tactile {

using servo_config::err;
using servo_config::where;

const char* toString(TransitionEvent e) {
  switch (e) {
    case TransitionEvent::Contact: return "contact";
    case TransitionEvent::Edge: return "edge";
    case TransitionEvent::Point: return "point";
    case TransitionEvent::Aligned: return "aligned";
    case TransitionEvent::ContactLost: return "contact_lost";
    case TransitionEvent::ForceAbove: return "force_above";
    case TransitionEvent::Timeout: return "timeout";
    case TransitionEvent::WristWound: return "wrist_wound";
    case TransitionEvent::WristUnwound: return "wrist_unwound";
    case TransitionEvent::LoopClosed: return "loop_closed";
    case TransitionEvent::Multiple: return "multiple";
    case TransitionEvent::JointMargin: return "joint_margin";
  }
  return "unknown";
}

const char* transitionEventNames() {
  static const std::string names = [] {  // toString's names, in the enum's order
    std::string all;
    for (int i = 0; i <= static_cast<int>(kLastTransitionEvent); ++i)
      all += (i ? "|" : "") + std::string(toString(static_cast<TransitionEvent>(i)));
    return all;
  }();
  return names.c_str();
}

ConfigResult PhaseProgram::configure(const ServoParams& p) {
  configured_ = false;
  if (p.phases.empty()) return ConfigResult::failure(where(p, "", "phases") + ": at least one phase is required");
  const int n = static_cast<int>(p.phases.size());
  auto indexOfName = [&](const std::string& name) {
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
    if (indexOfName(nm) != i) return err(p, nm, "name", nm, "duplicate phase name");
    for (std::size_t t = 0; t < ph.transitions.size(); ++t) {
      const TransitionParams& tr = ph.transitions[t];
      const std::string f = "transitions[" + std::to_string(t) + "]";
      if (indexOfName(tr.to) < 0) return err(p, nm, f + ".to", "'" + tr.to + "'", "unknown phase");
      if (const ConfigResult r = schema::checkRanges(transitionSchema(), tr, where(p, nm, f)); !r) return r;
      if (tr.on == TransitionEvent::Aligned) {
        bool any = false;
        for (int k = 0; k < kNumTol; ++k) {
          if (!std::isfinite(tr.tolerance[static_cast<std::size_t>(k)]))
            return err(p, nm, f + ".tolerance." + kToleranceNames[k], "non-finite", "must be finite");
          any = any || tr.tolerance[static_cast<std::size_t>(k)] >= 0;
        }
        if (!any) return err(p, nm, f + ".tolerance", "{}", "'aligned' needs at least one tolerance");
      }
    }
  }
  const int init = p.initial_phase.empty() ? 0 : indexOfName(p.initial_phase);
  if (init < 0) return err(p, "", "initial_phase", "'" + p.initial_phase + "'", "unknown phase");
  // Reachability from the initial phase through transitions.
  std::vector<char> reach(static_cast<std::size_t>(n), 0);
  std::vector<int> stack{init};
  reach[static_cast<std::size_t>(init)] = 1;
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    for (const TransitionParams& tr : p.phases[static_cast<std::size_t>(i)].transitions) {
      const int j = indexOfName(tr.to);
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

  phases_.clear();
  transitions_.clear();
  phases_.reserve(static_cast<std::size_t>(n));
  for (const PhaseParams& ph : p.phases) {
    Phase q;
    std::strncpy(q.name.data(), ph.name.c_str(), q.name.size() - 1);
    q.requires_contact = ph.requires_contact;
    q.reset_integrator = ph.reset_integrator;
    q.terminal = ph.terminal;
    q.free_motion = ph.P.isZero(0.0);
    q.first_transition = static_cast<int>(transitions_.size());
    q.num_transitions = static_cast<int>(ph.transitions.size());
    for (const TransitionParams& tr : ph.transitions)
      transitions_.push_back({tr.on, indexOfName(tr.to), tr.for_s, tr.filter_s, tr.tolerance, tr.timeout_s, tr.force_n,
                              tr.angle_rad, tr.radius_m, tr.leave_m, 0.0, false, {}, false});
    phases_.push_back(q);
  }
  initial_ = init;
  configured_ = true;
  reset();
  return ConfigResult::success();
}

void PhaseProgram::reset() {
  current_ = initial_;
  pending_ = -1;
  entered_ = false;
  signals_ = ProgramSignals{};
  yaw_enter_ = 0.0;
  anchor_valid_ = left_anchor_ = false;
  for (Transition& t : transitions_) t.held_s = 0.0, t.holding = false, t.filtered_valid = false;
}

int PhaseProgram::indexOf(const char* name) const {
  if (name == nullptr) return -1;
  for (std::size_t i = 0; i < phases_.size(); ++i)
    if (std::strncmp(phases_[i].name.data(), name, phases_[i].name.size()) == 0) return static_cast<int>(i);
  return -1;
}

bool PhaseProgram::request(int index) {
  if (!configured_ || index < 0 || index >= count()) return false;
  pending_ = index;
  return true;
}

void PhaseProgram::enter(int index, double now) {
  current_ = index;
  t_enter_ = now;
  entered_ = true;
  yaw_enter_ = signals_.wrist_yaw;
  const Phase& ph = phases_[static_cast<std::size_t>(index)];
  for (int k = 0; k < ph.num_transitions; ++k) {
    Transition& t = transitions_[static_cast<std::size_t>(ph.first_transition + k)];
    t.held_s = 0.0;
    t.holding = false;
    t.filtered_valid = false;
  }
}

bool PhaseProgram::evaluate(const ContactFeatures& f, const Vec6& e, double now, double dt, double c_z, int& target) {
  const Phase& ph = phases_[static_cast<std::size_t>(current_)];
  const bool contact = hasContact(f);
  for (int k = 0; k < ph.num_transitions; ++k) {
    Transition& t = transitions_[static_cast<std::size_t>(ph.first_transition + k)];
    bool cond = false;
    switch (t.on) {
      case TransitionEvent::Contact: cond = contact; break;
      case TransitionEvent::Edge: cond = contact && f.contact == ContactType::Edge; break;
      case TransitionEvent::Point: cond = contact && f.contact == ContactType::Point; break;
      case TransitionEvent::Multiple: cond = contact && f.contact == ContactType::Multiple; break;
      case TransitionEvent::ContactLost: cond = !contact; break;
      case TransitionEvent::ForceAbove: cond = f.force > t.force_n; break;
      case TransitionEvent::Timeout: cond = now - t_enter_ >= t.timeout_s; break;
      case TransitionEvent::WristWound: cond = std::fabs(signals_.wrist_yaw) >= t.angle_rad; break;
      case TransitionEvent::WristUnwound: cond = std::fabs(signals_.wrist_yaw - yaw_enter_) >= t.angle_rad; break;
      case TransitionEvent::JointMargin: cond = signals_.joint_margin <= t.angle_rad; break;
      case TransitionEvent::LoopClosed: {
        if (!contact || !signals_.have_point) break;
        if (!anchor_valid_) {
          for (int i = 0; i < 3; ++i) anchor_[static_cast<std::size_t>(i)] = signals_.point[i];
          anchor_valid_ = true;
        }
        double d2 = 0.0;
        for (int i = 0; i < 3; ++i) {
          const double d = signals_.point[i] - anchor_[static_cast<std::size_t>(i)];
          d2 += d * d;
        }
        const double d = std::sqrt(d2);
        if (d > t.leave_m) left_anchor_ = true;
        cond = left_anchor_ && d <= t.radius_m;
        break;
      }
      case TransitionEvent::Aligned: {
        // Signed errors: the rows of Δs, Δforce = Δd_z / c_z, CoC.
        double q[kNumTol];
        for (int i = 0; i < 6; ++i) q[i] = e(i);
        q[kTolForce] = e(kZ) / c_z;
        q[kTolCocX] = f.coc_x;
        q[kTolCocY] = f.coc_y;
        // An alpha_z not resolved above the noise is not "aligned" (its error row is 0).
        const bool alpha_ok = !(t.tol[kTolAlphaZ] >= 0) || f.alpha_defined;
        if (t.filter_s > 0.0 && contact && alpha_ok) {
          // First-order low-pass, exact for an input held over dt: the same
          // time constant at every servo rate. It starts at the first sample.
          const double a = t.filtered_valid ? 1.0 - std::exp(-dt / t.filter_s) : 1.0;
          for (int i = 0; i < kNumTol; ++i) {
            double& y = t.filtered[static_cast<std::size_t>(i)];
            y += a * (q[i] - y);
            q[i] = y;
          }
          t.filtered_valid = true;
        } else if (!contact) {
          t.filtered_valid = false;
        }
        cond = contact && alpha_ok;
        for (int i = 0; i < kNumTol; ++i)
          if (t.tol[static_cast<std::size_t>(i)] >= 0 && !(std::fabs(q[i]) <= t.tol[static_cast<std::size_t>(i)]))
            cond = false;
        break;
      }
    }
    // Held time: each cycle the condition holds counts its dt (the first one
    // included), so `for_s` means the same at every servo rate. 1 us slack
    // absorbs the rounding of sums of dt.
    t.held_s = cond ? (t.holding ? t.held_s + dt : dt) : 0.0;
    t.holding = cond;
    if (cond && t.held_s >= t.for_s - 1e-6) {
      target = t.to;
      return true;
    }
  }
  return false;
}

}  // namespace tactile
