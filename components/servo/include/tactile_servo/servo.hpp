// Touch-driven tactile servo core (Kappassov, Corrales & Perdereau, RAS 123
// (2020), Sec. 4, Algorithm 1, Eq. 7-15, Sec. 5.2/5.3, App. C).
//
// One step (Algorithm 1), all vectors ordered as in conventions.hpp:
//
//   s        = [CoP_x, CoP_y, d_z, CoC_x, CoC_y, alpha_z]            (Eq. 6)
//   J^-1     = touch-dependent inverse tactile Jacobian (6x6)          (Eq. 8)
//   Δs       = s_d - J^-1 s                                           (Eq. 7)
//   Δs_task  = P Δs                                                   (Eq. 9, 10)
//   u_s      = (S (K_P Δs_task + K_I ∫Δs_task dt) + v_ff) dt          (Eq. 13)
//   {g}T{s}  = {g}T{e} {e}T{s};  t_g = R_gs u_s (reference point: the
//              origin of {s});  {g}T{s}' = addDelta({g}T{s}, t_g)      (Eq. 13)
//   x_d      = x_a + u  (measured pose each cycle, Eq. 12)   or
//   x(t)     = x(t-1) + u (previous command, Eq. 15)  -> {g}T{e}' = {g}T{s}' {e}T{s}^-1
//
// DECISION: the 6x6 J^-1 (the paper prints Eq. 8 as 6x5 while s has 6
// entries; its text extraction also garbles Eq. 16-19). We use
//
//            CoP_x CoP_y d_z CoC_x CoC_y alpha_z
//   J^-1 = [  1     0     0    0     0     0   ]   -> CoP_x
//          [  0     1     0    0     0     0   ]   -> CoP_y
//          [  0     0     1    0     0     0   ]   -> d_z   (the printed row 3 "0 1 0 0 0" is a typo)
//          [  0     1     0    0    -β     0   ]   -> CoP_y - β CoC_y  (= DZMP_x for β = 1, Eq. 3)
//          [  1     0     0   -β     0     0   ]   -> CoP_x - β CoC_x  (= DZMP_y for β = 1, Eq. 3)
//          [  0     0     0    0     0     β   ]   -> β alpha_z (the edge angle is undefined for a point)
//
// so that Eq. 16 (phase II, point contact) is J^-1(0) and Eq. 17 = Eq. 19 =
// J^-1(1). β = 1 for an edge contact, 0 for a point contact (Eq. 5). A phase
// may instead give both 6x6 matrices explicitly (jinv_point / jinv_edge) or fix β.
// The row names of Δs used in parameter files are therefore
//   cop_x, cop_y, d_z, dzmp_x, dzmp_y, alpha_z
// (with β = 0 the rows "dzmp_x"/"dzmp_y" read CoP_y/CoP_x, which equal CoC_y/CoC_x
// for a point contact: this is the paper's "rotation about y linked to CoC_x").
//
// DECISION: P (Eq. 10) = diag(γ_x, γ_y, γ_z, γ_wx, γ_wy, γ_wz) with P(0,4) = γ_com
// (the wy-row error drives translation along x_s, Sec. 5.3). A phase may also
// give a full 6x6 P.
//
// DECISION: motion sign. Gains K_P, K_I are non-negative; the direction of
// motion is the constant S = diag(-1, -1, +1, +1, -1, -1) applied after the PI.
// With z_s pointing at the object:
//   x, y : a contact at +x_s is centred by moving the sensor along +x_s, but
//          Δ = 0 - CoP_x < 0, so S_x = -1 (same for y).
//   z    : too little penetration (Δd_z > 0) needs motion along +z_s: S_z = +1.
//   wx   : more pressure on the +y_s side (DZMP_x > 0, Δ < 0) is relieved by a
//          negative rotation about x_s (a positive one lifts +y_s points
//          towards +z_s): S_wx = +1.
//   wy   : more pressure on the +x_s side (DZMP_y > 0, Δ < 0) is relieved by a
//          positive rotation about y_s (it moves +x_s points towards -z_s): S_wy = -1.
//   wz   : an edge seen at alpha_z > 0 is aligned with x_s by rotating the
//          sensor by +alpha_z about z_s: S_wz = -1.
// S is the program parameter `motion_sign` (entries +-1).
//
// UNITS. Everything is per second, so that the behaviour does not depend on
// the servo rate. u is the pose increment of one cycle [m m m rad rad rad],
// expressed in {s} and applied at the origin of {s}: the commanded rate times
// dt. K_P is in 1/s (rate per unit feature error), K_I in 1/s^2 (the integral
// is ∫Δs_task dt), integral_limit and u_max in m/s, rad/s, the feed-forward
// twist in m/s, rad/s in {s}; the step limits are speeds (max_trans_speed m/s,
// max_rot_speed rad/s) and transitions hold for `for_s` seconds.
//
// START (beyond the paper): nothing is commanded before a valid measured pose
// (validPose in tactile_types/types.hpp: finite, unit quaternion) has
// arrived: until then out.valid is false and the status is WaitingForPose
// (input kNoPose, nothing measured yet) or InvalidInput (a measured pose that
// is not valid). The cycle that first sees a valid pose commands exactly that
// pose (status Starting): x(0) of Eq. 15, and the phase program is entered at
// that time; servoing starts at the next cycle. reset() starts over.
//
// SAFETY (beyond the paper):
//  * per-axis rate limits per phase (u_max) and translational and rotational
//    speed limits (norms, times dt per cycle) for every increment, recovery
//    moves included;
//  * a workspace box on the commanded flange position {g}p{e} (from a pose
//    already outside it, only motion back towards it is allowed: no jumps);
//  * a force ceiling: features.force > ceiling -> status ForceCeiling, retreat
//    along -z_s (away from the object) by `ceiling_retreat` at the step limit,
//    then hold; latched until reset() or requestPhase();
//  * a stale-features watchdog: features older than `stale_timeout` or with an
//    unusable status -> hold the last command (status Holding);
//  * NaN/Inf in features, pose or dt, dt <= 0 -> hold (status InvalidInput);
//    no output is ever NaN;
//  * the force the law regulates is Eq. 2's tactile force, or (force_estimate:
//    source: fused) that force corrected at low frequency by the arm's
//    estimated wrench (force_estimator.hpp: the load below the taxels' firing
//    threshold); the force ceiling reads the tactile force itself, the
//    force-mismatch watchdog the force the law uses (the correction is
//    bounded: a wrench beyond max_correction_n still shows);
//  * watchdogs (watchdog.hpp), fatal and latched, the command held: a phase
//    longer than its max_duration_s (PhaseTimeout), commanded motion the
//    measured pose does not follow (ArmStalled), a tactile force the arm's
//    estimated wrench contradicts (ForceMismatch);
//  * contact loss (the paper's limitation: "as soon as the contact disappears
//    the controller does not send new set points"): in a phase that requires
//    contact, losing it triggers `contact_loss`: hold, backoff (retreat along
//    -z_s by a distance, then hold) or search (move along +z_s, i.e. towards the
//    object along the surface normal, at a speed until contact returns, at most
//    `search_max_distance`, then hold). A "search along -z of {s}" in the
//    convention where z_s points into the object
//    is +z_s here because our z_s points out of the surface at the object.
//
// ROBOT STATE (beyond the paper). The KRC starts in monitor mode (KRL
// friOpen) and is switched to command mode later (friStart); friStop, a drop
// of the link quality or the drives going off make the arm uncommandable in
// the middle of a run. While in.robot_ready is false (and no dry run) the
// servo holds: the command is the pose the arm is held at, the KRC's set
// point (in.robot_setpoint; the measured pose where it is unknown): in free
// space the two agree, in a pressing contact the set point lies inside the
// object by force / stiffness and holding it keeps the force. The bridge's
// start gate passes on it when commanding becomes possible. The status is
// WaitingForRobot, and
// nothing advances: the PI integrators, the phase program (a requested phase
// switch stays pending), the transitions' timers, the time in the phase (its
// entry time moves on with the clock: timeouts and max_duration_s count only
// commandable time), the force estimate and the watchdogs. When it becomes
// true again the servo goes on from that pose (Eq. 15's x(t-1) := the held
// set point): no jump, the program where it was. A latched watchdog stays
// latched. A dry run steps normally.
//
// WRIST (beyond the paper). Following a closed contour turns the sensor about
// z_s without end; the arm's last joint (coaxial with z_s) runs out of range.
// The servo integrates the rotation of {s} about its own z axis between
// consecutive measured poses ({g}R{s}(t-1)^T {g}R{s}(t), the z component of
// its rotation vector): wrist_yaw, zero at the start. The phase program's
// wrist_wound / wrist_unwound events read it, and a phase with unwind_rate > 0
// adds a rotation about z_s against the yaw it was entered with, through zero
// (the phase's wrist_unwound transition says how far): lift off,
// unwind, come back down, as an operator would (programs/closed_contour.yaml).
// The point loop_closed follows is where the edge passes the pad's centre:
// {g}T{e} {e}T{s} (0, CoP_y, 0), from the measured flange pose. Along the
// edge it is the pad's own position (the kinematics, exact); across it the
// CoP's lateral offset. Not the CoP itself: along the edge the CoP is the
// centroid of the taxels above the firing threshold, which moves by 1-6 mm
// against the true pressure centre with the load's distribution along the
// pad (a tilt, a curve, a corner under it), so the same place on a contour
// read 3-9 mm apart at the start and at the end of a loop (README "Whole
// closed contours", Closure).
//
// PHASE PROGRAM. Each cycle with valid features, the current phase's
// transitions are evaluated in their listed order (first to fire wins; a
// transition fires once its condition held for `for_s` seconds of consecutive
// valid cycles, each cycle counting its dt) and the new phase acts in the same cycle. Events: contact, edge,
// point (the extractor's contact type), aligned (chosen |Δs| rows, |Δforce|,
// |CoC| below tolerances; with `filter_s` > 0 the signed errors low-passed
// first, time constant filter_s), contact_lost, force_above, timeout (time in phase).
// While holding (stale/invalid input) transitions are not evaluated.
//
// STRUCTURE. TactileServo composes three parts, each usable and tested alone:
//   ServoControlLaw   (control_law.hpp)       Eq. 7-15: J^-1, P, PI, sensor-to-base
//   PhaseProgram      (phase_program.hpp)     phases and event-driven transitions
//   SafetySupervisor  (safety_supervisor.hpp) force ceiling, step limits,
//                                             workspace box, stale data, contact loss
// and owns the command (Eq. 15's x(t)) and the start from the measured pose.
//
// Real-time: step() and requestPhase() do not allocate, throw, log or block.
// They are not thread-safe: call them from the same thread (in RTT, run the
// requestPhase operation in the component's own thread).
#pragma once

#include <cstdint>

#include "tactile_servo/control_law.hpp"
#include "tactile_servo/phase_program.hpp"
#include "tactile_servo/safety_supervisor.hpp"
#include "tactile_servo/servo_params.hpp"
#include "tactile_servo/watchdog.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

struct ServoInput {
  double time_s = 0.0;
  ContactFeatures features;
  /// {g}T{e} measured. kNoPose until a measurement arrived: the servo then
  /// commands nothing (status WaitingForPose).
  Pose flange_measured = kNoPose;
  /// The arm's estimated external wrench ({g} axes; FRI: the KRC's
  /// estExtTcpFT, simulator: the contact wrench at the flange), for the
  /// force-mismatch watchdog; unused while have_wrench is false.
  Wrench wrench;
  bool have_wrench = false;
  /// The arm follows pose commands now (RobotState::commandable of the arm's
  /// side; true where nothing reports it). While false the servo holds
  /// (ROBOT STATE below).
  bool robot_ready = true;
  /// Where the arm is held while it cannot be commanded (RobotState::setpoint:
  /// the KRC's set point); kNoPose: unknown, the measured pose is used.
  Pose robot_setpoint = kNoPose;
  /// Bring-up dry run (RobotState::dry_run): the servo runs as if the arm
  /// followed, but the arm is held, so the stall watchdog is off.
  bool dry_run = false;
};

struct ServoOutput {
  PoseCommand command;   ///< {g}T{e} desired
  PhaseState phase;
  Vec6 error = Vec6::Zero();       ///< Δs (Eq. 7)
  Vec6 error_task = Vec6::Zero();  ///< Δs_task (Eq. 9)
  Vec6 u_s = Vec6::Zero();         ///< increment applied this cycle, in {s}
  uint8_t beta = 0;                ///< 1 when the edge Jacobian was used
  double force = 0.0;              ///< N: the force the law and the transitions used (f_hat, force_estimator.hpp)
  bool valid = false;              ///< false until a valid measured pose was seen (validPose, types.hpp)
};

class TactileServo {
 public:
  TactileServo() = default;

  /// Validate and take the program. Allocates (configuration time).
  ConfigResult configure(const ServoParams& params);

  /// One servo cycle. `dt` is the time since the previous step (s).
  ServoStatus step(const ServoInput& in, double dt, ServoOutput& out);

  /// Switch phase by name at the next step (RT-safe). Clears the force-ceiling
  /// latch. Returns false (and changes nothing) for an unknown name.
  bool requestPhase(const char* name);
  bool requestPhase(int index);

  /// Back to the initial phase; the next step re-reads the measured pose.
  void reset();

  int phaseCount() const { return configured_ ? program_.count() : 0; }
  int phaseIndex() const { return program_.current(); }
  /// True while holding for the robot (ROBOT STATE).
  bool waitingForRobot() const { return waiting_; }
  /// rad: rotation of {s} about z_s accumulated from the measured poses since the start (WRIST).
  double wristYaw() const { return wrist_yaw_; }
  int phaseIndexOf(const char* name) const { return program_.indexOf(name); }  ///< -1 if unknown
  const PhaseParams& phase(int i) const { return params_.phases[static_cast<std::size_t>(i)]; }
  const ServoParams& params() const { return params_; }

  /// Δs for the given phase and features (Eq. 7), without any state change.
  Vec6 featureError(int phase, const ContactFeatures& f, uint8_t* beta_out = nullptr) const;

  /// The J^-1 (Eq. 8) used in `phase` for contact type `c` (baseline and no_rotation modes
  /// included), e.g. for reporting on a port. `phase` must be valid.
  const Mat6& jacobian(int phase, ContactType c, uint8_t* beta_out = nullptr) const;

  /// The parts (read-only), e.g. for tests and reporting.
  const ServoControlLaw& controlLaw() const { return law_; }
  const PhaseProgram& program() const { return program_; }
  const SafetySupervisor& safety() const { return safety_; }
  const ServoWatchdogs& watchdogs() const { return watchdogs_; }
  const ForceEstimator& forceEstimator() const { return force_est_; }

 private:
  void enterPhase(int idx, double now);
  ServoStatus finish(ServoStatus st, double now, ServoOutput& out);
  ServoStatus applyIncrement(const KDL::Frame& base, Vec6 u_s, double dt, ServoStatus st, double now, ServoOutput& out);

  bool configured_ = false;
  ServoParams params_;
  ServoControlLaw law_;
  PhaseProgram program_;
  SafetySupervisor safety_;
  ServoWatchdogs watchdogs_;
  ForceEstimator force_est_;
  KDL::Frame cmd_;
  KDL::Frame meas_;            ///< this cycle's measured flange pose
  bool motion_cycle_ = false;  ///< this cycle commanded motion (the stall watchdog's window)
  bool in_contact_ = false;    ///< this cycle's features report contact (the stall watchdog's axes)
  bool has_cmd_ = false;
  bool dry_run_ = false;       ///< this cycle is a dry run (no stall watchdog)
  bool waiting_ = false;       ///< the last cycle held for the robot (ROBOT STATE)
  KDL::Rotation yaw_prev_;     ///< {g}R{s} measured at the previous cycle (the wrist yaw's integration)
  double wrist_yaw_ = 0.0;     ///< rad about z_s accumulated since the start (WRIST)
  /// The pose-derived signals of the phase program (WRIST, loop_closed).
  void observePose(const KDL::Frame& meas, const ContactFeatures& f, bool first);
  uint32_t seq_ = 0;
};

}  // namespace tactile
