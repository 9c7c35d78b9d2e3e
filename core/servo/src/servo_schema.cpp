#include "tactile_servo/servo_schema.hpp"

#include <vector>


namespace tactile {

const schema::Block<ServoParams>& controllerSchema() {
  using S = ServoParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "controller",
      "the law's mode and constants (ControlLaw, control_law.hpp); also motion_sign (S of Eq. 13, per axis) and "
      "sensor_mount ({e}T{s}: xyz m, rpy_deg)",
      {F::choice(
           "mode", "proposed|baseline|no_rotation", [](const S& s) { return static_cast<int>(s.mode); },
           [](S& s, int i) { s.mode = static_cast<ControllerMode>(i); },
           "the inverse tactile Jacobian: Eq. 8 (proposed), Li et al.'s (baseline) or the ablation"),
       F::choice(
           "pose_update", "measured|integrated", [](const S& s) { return static_cast<int>(s.pose_update); },
           [](S& s, int i) { s.pose_update = static_cast<PoseUpdate>(i); },
           "the pose the increment is added to: the measured one (Eq. 12) or the last command (Eq. 15)"),
       F::num("c_z", "m/N", "> 0", TACTILE_SCHEMA_REF(S, c_z), "the pad's compliance: d_z = C_z f (Eq. 2)"),
       F::str("initial_phase", TACTILE_SCHEMA_REF(S, initial_phase), "the phase the program starts in ('': the first)").form("a phase")}};
  return b;
}

const schema::Block<SafetyParams>& safetySchema() {
  using S = SafetyParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "safety",
      "the limits on every command (SafetySupervisor, safety_supervisor.hpp)",
      {F::num("max_trans_speed", "m/s", "(0, 1]", TACTILE_SCHEMA_REF(S, max_trans_speed),
              "the norm of the commanded translation rate"),
       F::deg("max_rot_speed_deg", "deg/s", "(0, 573]", TACTILE_SCHEMA_REF(S, max_rot_speed),
              "the norm of the commanded rotation rate"),
       F::num("max_step_dt", "s", "(0, 1]", TACTILE_SCHEMA_REF(S, max_step_dt),
              "the longest cycle the speed limits integrate over: a stalled loop never allows a jump"),
       F::xyz("workspace.min", "m", TACTILE_SCHEMA_REF(S, workspace_min),
              "the flange's lowest position in {g} (below workspace.max on every axis)"),
       F::xyz("workspace.max", "m", TACTILE_SCHEMA_REF(S, workspace_max), "the flange's highest position in {g}"),
       F::num("force_ceiling", "N", "> 0", TACTILE_SCHEMA_REF(S, force_ceiling),
              "the tactile force that latches a retreat along -z_s by ceiling_retreat"),
       F::num("ceiling_retreat", "m", "[0, 0.2]", TACTILE_SCHEMA_REF(S, ceiling_retreat),
              "the retreat along -z_s after the ceiling"),
       F::num("stale_timeout", "s", "> 0", TACTILE_SCHEMA_REF(S, stale_timeout),
              "the age at which a frame or a measured pose is stale (the servo holds)"),
       F::choice(
           "contact_loss.mode", "hold|backoff|search",
           [](const S& s) { return static_cast<int>(s.contact_loss); },
           [](S& s, int i) { s.contact_loss = static_cast<ContactLossMode>(i); },
           "what the servo does when the contact is lost in a phase that requires it"),
       F::num("contact_loss.backoff_distance", "m", "[0, 0.2]", TACTILE_SCHEMA_REF(S, backoff_distance),
              "backoff: the retreat along -z_s"),
       F::num("contact_loss.search_speed", "m/s", "[0, 0.1]", TACTILE_SCHEMA_REF(S, search_speed),
              "search: the approach speed along z_s"),
       F::num("contact_loss.search_max_distance", "m", "[0, 0.2]", TACTILE_SCHEMA_REF(S, search_max_distance),
              "search: the longest approach"),
       F::num("frozen_image.travel_m", "m", "[0, 0.05]", TACTILE_SCHEMA_REF(S, frozen_image_travel),
              "a loaded image repeated bit for bit while the flange moves this far is stale (0: off)"),
       F::num("frozen_image.min_s", "s", "(0, 5]", TACTILE_SCHEMA_REF(S, frozen_image_s),
              "and for at least this long")}};
  return b;
}

const schema::Block<WatchdogParams>& watchdogSchema() {
  using S = WatchdogParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "watchdogs",
      "fatal statuses: what must never pass silently (ServoWatchdogs, watchdog.hpp); a window of 0 turns one off",
      {F::num("arm_stall.window_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, stall_window_s),
              "arm stalled: the window over which the arm must follow the command (0: off)"),
       F::num("arm_stall.min_distance", "m", "(0, 1]", TACTILE_SCHEMA_REF(S, stall_min_distance),
              "the commanded translation in a window from which it is checked"),
       F::deg("arm_stall.min_angle_deg", "deg", "(0, 180]", TACTILE_SCHEMA_REF(S, stall_min_angle),
              "the commanded rotation in a window from which it is checked"),
       F::num("arm_stall.min_fraction", "", "(0, 1]", TACTILE_SCHEMA_REF(S, stall_min_fraction),
              "the share of the commanded motion the measured one must reach"),
       F::num("force_mismatch.window_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, mismatch_window_s),
              "the wrench above Eq. 2's tactile force f for this long stops the servo (0: off)"),
       F::num("force_mismatch.tolerance_n", "N", "(0, 1e4]", TACTILE_SCHEMA_REF(S, mismatch_tolerance_n),
              "f_w - f allowed (the larger of this and tolerance_rel f_w, plus the estimate's bound)"),
       F::num("force_mismatch.tolerance_rel", "", "[0, 1]", TACTILE_SCHEMA_REF(S, mismatch_tolerance_rel),
              "f_w - f allowed, as a share of f_w"),
       F::num("phantom_contact.window_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, phantom_window_s),
              "the taxels above the wrench for this long stop the servo (0: off)"),
       F::num("phantom_contact.tolerance_n", "N", "(0, 1e4]", TACTILE_SCHEMA_REF(S, phantom_tolerance_n),
              "f - f_w allowed (the larger of this and tolerance_rel f)"),
       F::num("phantom_contact.tolerance_rel", "", "[0, 1]", TACTILE_SCHEMA_REF(S, phantom_tolerance_rel),
              "f - f_w allowed, as a share of f"),
       F::num("unseen_load.window_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, unseen_window_s),
              "a wrench without tactile contact for this long stops the servo (0: off)"),
       F::num("unseen_load.max_n", "N", "(0, 1e4]", TACTILE_SCHEMA_REF(S, unseen_max_n),
              "the wrench allowed without tactile contact"),
       F::num("correction_saturated.window_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, correction_window_s),
              "the fused correction's demand beyond its bound for this long stops the servo (0: off)"),
       F::num("correction_saturated.margin_n", "N", "[0, 50]", TACTILE_SCHEMA_REF(S, correction_margin_n),
              "the demand allowed above force_estimate.max_correction_n"),
       F::num("correction_drift.max_change_n", "N", "[0, 50]", TACTILE_SCHEMA_REF(S, drift_max_change_n),
              "the low-passed demand's largest move from its anchor in a force-holding phase (0: off)"),
       F::num("correction_drift.tau_s", "s", "(0, 10]", TACTILE_SCHEMA_REF(S, drift_tau_s),
              "the demand's and the image extent's low-pass"),
       F::num("correction_drift.settle_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, drift_settle_s),
              "the anchor is taken this long into the contact"),
       F::num("correction_drift.min_extent_ratio", "", "(0, 1]", TACTILE_SCHEMA_REF(S, drift_min_extent_ratio),
              "an extent outside [r, 1/r] of the anchor's takes a new anchor"),
       F::choice(
           "on_fault", "hold|retreat", [](const S& s) { return s.fault_retreat ? 1 : 0; },
           [](S& s, int i) { s.fault_retreat = i == 1; },
           "after a watchdog's stop: hold the last command, or retreat along -z_s by retreat_m"),
       F::num("retreat_m", "m", "[0, 0.1]", TACTILE_SCHEMA_REF(S, fault_retreat_m), "the retreat of on_fault: retreat"),
       F::num("surface_too_curved.tau_s", "s", "[0, 10]", TACTILE_SCHEMA_REF(S, curved_tau_s),
              "the low-pass of the wrench's excess over the set point (0: off)"),
       F::num("surface_too_curved.excess_n", "N", "(0, 1e4]", TACTILE_SCHEMA_REF(S, curved_excess_n),
              "the excess that stops the servo while the image is short or carries little of the wrench"),
       F::num("surface_too_curved.max_extent_m", "m", "(0, 1]", TACTILE_SCHEMA_REF(S, curved_max_extent_m),
              "an image at most this long is short"),
       F::num("surface_too_curved.max_tactile_share", "", "[0, 1]",
              TACTILE_SCHEMA_REF(S, curved_max_tactile_share), "the tactile force's share of the wrench below which "
                                                               "the load has left the taxels"),
       F::num("surface_too_curved.lift_n", "N", "[0, 1e4]", TACTILE_SCHEMA_REF(S, curved_lift_n),
              "the first reaction: above this excess the law regulates f_d + the excess (0: off)")}};
  return b;
}

const schema::Block<ForceEstimateParams>& forceEstimateSchema() {
  using S = ForceEstimateParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "force_estimate",
      "the force the law and the transitions use (ForceEstimator, force_estimator.hpp)",
      {F::choice(
           "source", "tactile|fused", [](const S& s) { return s.fused ? 1 : 0; },
           [](S& s, int i) { s.fused = i == 1; },
           "tactile: Eq. 2's f (the paper); fused: f corrected towards the arm's wrench"),
       F::num("tau_s", "s", "(0, 100]", TACTILE_SCHEMA_REF(S, tau_s), "the time constant of the correction c"),
       F::num("max_correction_n", "N", "(0, 50]", TACTILE_SCHEMA_REF(S, max_correction_n), "the bound of |c|"),
       F::num("tare_tau_s", "s", "(0, 100]", TACTILE_SCHEMA_REF(S, tare_tau_s),
              "the time constant of the wrench's zero without contact"),
       F::num("tare_gate_n", "N", "(0, 50]", TACTILE_SCHEMA_REF(S, tare_gate_n),
              "the tare's largest step along z_s (a load building up is held)"),
       F::num("tare_hold_s", "s", "(0, 10]", TACTILE_SCHEMA_REF(S, tare_hold_s),
              "the interval of the tare's snapshots"),
       F::num("tare_max_n", "N", "(0, 50]", TACTILE_SCHEMA_REF(S, tare_max_n),
              "the largest offset taken for the zero (a larger one is a load)"),
       F::num("image_margin_n", "N", "[0, 50]", TACTILE_SCHEMA_REF(S, image_margin_n),
              "the load above the firing threshold the correction leaves on the image (0: no image bound)"),
       F::num("firing_threshold_n", "N", "[0, 50]", TACTILE_SCHEMA_REF(S, firing_threshold_n),
              "a taxel's firing threshold (the WTS: 0.2 N)")}};
  return b;
}

const schema::Block<SpeedLawParams>& speedLawSchema() {
  using S = SpeedLawParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "speed_law",
      "the slide speed from the contact (SpeedLaw, speed_law.hpp)",
      {F::num("v_max", "m/s", "(0, 1]", TACTILE_SCHEMA_REF(S, v_max), "the fastest slide (the safety limit)"),
       F::num("v_min", "m/s", "[0, v_max]", TACTILE_SCHEMA_REF(S, v_min),
              "the slowest slide while the law allows none"),
       F::num("accel_mps2", "m/s^2", "(0, 10]", TACTILE_SCHEMA_REF(S, accel_mps2), "the largest rise of the speed"),
       F::num("force_budget_n", "N", "(0, 50]", TACTILE_SCHEMA_REF(S, force_budget_n),
              "the user's error budget for the true force"),
       F::num("force_deadband_n", "N", "[0, force_budget_n)", TACTILE_SCHEMA_REF(S, force_deadband_n),
              "the predicted force error that does not slow the slide"),
       F::num("horizon_s", "s", "[0, 10]", TACTILE_SCHEMA_REF(S, horizon_s),
              "how far ahead the force error is predicted"),
       F::num("angle_rate_ref", "rad/s", "(0, 100]", TACTILE_SCHEMA_REF(S, angle_rate_ref),
              "the edge angle's rate that stops the slide"),
       F::num("curvature_ref", "1/m", "(0, 1e4]", TACTILE_SCHEMA_REF(S, curvature_ref),
              "the edge line's curvature that stops the slide"),
       F::num("extent_min_m", "m", "[0, 1)", TACTILE_SCHEMA_REF(S, extent_min_m),
              "the image's extent at which the slide stops"),
       F::num("extent_full_m", "m", "(extent_min_m, 1]", TACTILE_SCHEMA_REF(S, extent_full_m),
              "the image's extent at full speed"),
       F::num("excess_ref_n", "N", "(0, 1e4]", TACTILE_SCHEMA_REF(S, excess_ref_n),
              "the wrench's excess over the taxels that stops the slide"),
       F::num("excess_deadband_n", "N", "[0, excess_ref_n)", TACTILE_SCHEMA_REF(S, excess_deadband_n),
              "the excess that does not slow the slide"),
       F::num("excess_deadband_per_m", "N/m", "[0, 1e4]", TACTILE_SCHEMA_REF(S, excess_deadband_per_m),
              "the dead band's growth with the extent of a short image"),
       F::num("excess_short_max_m", "m", "[0, 1]", TACTILE_SCHEMA_REF(S, excess_short_max_m),
              "the longest image whose extent grows the dead band"),
       F::num("drive_fraction", "", "[0, 1]", TACTILE_SCHEMA_REF(S, drive_fraction),
              "the slide's least share of the allowed speed in the pull's direction (0: a cap only)"),
       F::num("guard_excess_n", "N", "(0, 1e4]", TACTILE_SCHEMA_REF(S, guard_excess_n),
              "the excess above which the slide is not driven and rises slowly"),
       F::num("guard_accel_mps2", "m/s^2", "(0, 10]", TACTILE_SCHEMA_REF(S, guard_accel_mps2),
              "the slide's largest rise while guarded"),
       F::num("crawl_mps", "m/s", "[0, v_max]", TACTILE_SCHEMA_REF(S, crawl_mps),
              "the slide the excess allows once it has stopped it for crawl_after_s"),
       F::num("crawl_after_s", "s", "[0, 10]", TACTILE_SCHEMA_REF(S, crawl_after_s),
              "how long the excess stops the slide before the crawl")}};
  return b;
}

const schema::Block<SpeedLawConfig>& speedLawServoSchema() {
  using S = SpeedLawConfig;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "speed_law",
      "the slide speed from the contact: where it acts and what it reads (SpeedLawConfig, servo_params.hpp), then the law (SpeedLawParams, speed_law.hpp)",
      {F::list("phases", TACTILE_SCHEMA_REF(S, phases), "the phases it acts in ([]: off)"),
       F::choice(
           "axis", "x|y", [](const S& s) { return s.axis; }, [](S& s, int i) { s.axis = i; },
           "the slide axis of {s}"),
       F::num("rate_tau_s", "s", "(0, 10]", TACTILE_SCHEMA_REF(S, rate_tau_s),
              "the low-pass of the force error, its rate, the angle's rate and the curvature"),
       F::num("excess_tau_s", "s", "[0, 10]", TACTILE_SCHEMA_REF(S, excess_tau_s),
              "the low-pass of the wrench's excess (0: rate_tau_s)"),
       F::choice(
           "excess_against", "estimate|tactile", [](const S& s) { return s.excess_against_tactile ? 1 : 0; },
           [](S& s, int i) { s.excess_against_tactile = i == 1; },
           "the excess is the wrench less the estimate f_hat, or less Eq. 2's tactile f")}};
  return b;
}

const schema::Block<SlopeFeedforwardConfig>& slopeFeedforwardSchema() {
  using S = SlopeFeedforwardConfig;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "slope_feedforward",
      "the slide's slope fed forward along z_s (SlopeFeedforward, slope_feedforward.hpp)",
      {F::list("phases", TACTILE_SCHEMA_REF(S, phases), "the phases it acts in ([]: off)"),
       F::choice(
           "axis", "x|y", [](const S& s) { return s.axis; }, [](S& s, int i) { s.axis = i; },
           "the slide axis of {s}"),
       F::num("window_m", "m", "[0, 0.05]", TACTILE_SCHEMA_REF(S, window_m),
              "the slide over which the slope is measured (0: off)")}};
  return b;
}

namespace {

constexpr const char* kAxes = "x|y|z|wx|wy|wz";
constexpr const char* kTwist = "vx|vy|vz|wx|wy|wz";

/// The gains and limits of a phase (Eq. 13 as a rate): declared once, for a
/// phase and for phase_defaults.
std::vector<schema::Field<PhaseParams>> gainFields() {
  using S = PhaseParams;
  using F = schema::Field<S>;
  return {F::vector("kp_per_s", "1/s", kAxes, ">= 0", TACTILE_SCHEMA_VEC(S, kp),
                    "K_P: the rate per unit feature error, per task axis"),
          F::vector("ki_per_s2", "1/s^2", kAxes, ">= 0", TACTILE_SCHEMA_VEC(S, ki), "K_I, per task axis"),
          F::vector("integral_limit_per_s", "m/s, rad/s", kAxes, ">= 0", TACTILE_SCHEMA_VEC(S, integral_limit),
                    "the bound of |K_I integral|, per task axis"),
          F::vector("u_max_per_s", "m/s, rad/s", kAxes, "> 0", TACTILE_SCHEMA_VEC(S, u_max),
                    "the bound of the PI rate, per task axis"),
          F::num("max_duration_s", "s", ">= 0", TACTILE_SCHEMA_REF(S, max_duration_s),
                 "the time in the phase after which the servo stops with PhaseTimeout (0: no limit; a terminal "
                 "phase's default is 0)")};
}

}  // namespace

const schema::Block<PhaseParams>& phaseSchema() {
  using S = PhaseParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b = [] {
    schema::Block<S> blk{"phases[]", "one phase of the program (PhaseProgram, phase_program.hpp; ControlLaw, "
                                     "control_law.hpp); a gain not given is phase_defaults'",
                         {}};
    blk.fields = {
        F::str("name", TACTILE_SCHEMA_REF(S, name), "the phase's name (1 to 31 characters, unique)").needed(),
        F::custom("s_d", "m, rad", "a list of 6 or a mapping over cop_x, cop_y, d_z, dzmp_x, dzmp_y, alpha_z; "
                                   "force (N) for d_z = C_z f (Eq. 2)",
                  "[0, 0, 0, 0, 0, 0]", "s_d: the desired features, rows of the feature error"),
        F::custom("jacobian", "", "touch; {beta: 0 or 1}; {point: 6x6, edge: 6x6}; {matrix: 6x6}", "touch",
                  "the inverse tactile Jacobian (Eq. 8): from the contact type each cycle, or fixed"),
        F::custom("P", "", "a mapping of gammas over x, y, z, wx, wy, wz, com; or a 6x6 matrix", "0",
                  "the task projection (Eq. 10)")};
    for (const F& f : gainFields()) blk.fields.push_back(f);
    const std::vector<F> rest = {
        F::vector("feedforward", "m/s, rad/s", kTwist, "[-0.5, 0.5]", TACTILE_SCHEMA_VEC(S, feedforward),
                  "a twist in {s} added to the PI rate"),
        F::num("unwind_rate", "rad/s", "[0, 0.87]", TACTILE_SCHEMA_REF(S, unwind_rate),
               "the rate about z_s against the wrist yaw accumulated when the phase was entered (0: none)"),
        F::yesNo("requires_contact", TACTILE_SCHEMA_REF(S, requires_contact),
                 "safety.contact_loss applies in this phase"),
        F::yesNo("reset_integrator", TACTILE_SCHEMA_REF(S, reset_integrator), "zero the integral on entering"),
        F::yesNo("terminal", TACTILE_SCHEMA_REF(S, terminal), "entering it ends the program (status Done, hold)"),
        F::custom("transitions", "", "a list of transitions[] (below)", "[]",
                  "the events that leave the phase, checked in order")};
    blk.fields.insert(blk.fields.end(), rest.begin(), rest.end());
    return blk;
  }();
  return b;
}

const schema::Block<PhaseParams>& phaseDefaultsSchema() {
  static const schema::Block<PhaseParams> b{
      "phase_defaults", "the gains and the time limit of every phase that does not give its own", gainFields()};
  return b;
}

const schema::Block<TransitionParams>& transitionSchema() {
  using S = TransitionParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "transitions[]",
      "an event that leaves a phase (PhaseProgram, phase_program.hpp); its keys depend on the event `on`",
      {F::choice(
           "on", transitionEventNames(), [](const S& s) { return static_cast<int>(s.on); },
           [](S& s, int i) { s.on = static_cast<TransitionEvent>(i); }, "the event")
           .needed(),
       F::str("to", TACTILE_SCHEMA_REF(S, to), "the phase it leads to").form("a phase").needed(),
       F::num("for_s", "s", "[0, 3600]", TACTILE_SCHEMA_REF(S, for_s),
              "how long the event must hold (0: the first cycle it does)"),
       F::num("filter_s", "s", "[0, 60]", TACTILE_SCHEMA_REF(S, filter_s),
              "the low-pass of the errors the tolerances test (0: the raw samples)")
           .only("aligned"),
       F::custom("tolerance", "m, rad, N",
                 ">= 0, over cop_x, cop_y, d_z, dzmp_x, dzmp_y, alpha_z, force, coc_x, coc_y; at least one", "{}",
                 "the errors (s_d - s, the force error, the CoC) whose magnitudes must all be within their tolerance")
           .only("aligned")
           .needed(),
       F::num("timeout_s", "s", "> 0", TACTILE_SCHEMA_REF(S, timeout_s), "the time in the phase").only("timeout").needed(),
       F::num("force_n", "N", "> 0", TACTILE_SCHEMA_REF(S, force_n), "the force above which it fires")
           .only("force_above")
           .needed(),
       F::deg("angle_deg", "deg", "(0, 720]", TACTILE_SCHEMA_REF(S, angle_rad),
              "the wrist yaw accumulated (wound) or given back since the phase was entered (unwound)")
           .only("wrist_wound|wrist_unwound")
           .needed(),
       F::deg("angle_deg", "deg", "(0, 30]", TACTILE_SCHEMA_REF(S, angle_rad),
              "the margin of a measured joint to its limit")
           .only("joint_margin")
           .needed(),
       F::num("radius_m", "m", "(0, 1]", TACTILE_SCHEMA_REF(S, radius_m),
              "the distance from the loop's anchor within which the loop is closed")
           .only("loop_closed")
           .needed(),
       F::num("leave_m", "m", "(radius_m, 10]", TACTILE_SCHEMA_REF(S, leave_m),
              "the distance the contact must first go away from the anchor")
           .only("loop_closed")
           .needed()},
      "on"};
  return b;
}

namespace {

/// The rows of a table without its two header lines.
std::string rows(const std::string& table) {
  const std::size_t second = table.find('\n', table.find('\n') + 1);
  return table.substr(second + 1);
}

}  // namespace

std::string programSchemaMarkdown() {
  const std::string speed_law = schema::markdownSection(speedLawServoSchema()) + rows(schema::markdownTable(speedLawSchema()));
  return schema::markdownSection(controllerSchema()) + "\n" + schema::markdownSection(safetySchema()) + "\n" +
         schema::markdownSection(watchdogSchema()) + "\n" + schema::markdownSection(forceEstimateSchema()) + "\n" +
         speed_law + "\n" + schema::markdownSection(slopeFeedforwardSchema()) + "\n" +
         schema::markdownSection(phaseDefaultsSchema()) + "\n" + schema::markdownSection(phaseSchema()) + "\n" +
         schema::markdownSection(transitionSchema());
}

}  // namespace tactile
