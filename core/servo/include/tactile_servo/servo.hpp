// Touch-driven tactile servo core (Kappassov, Corrales & Perdereau, RAS 123
// (2020), Sec. 4, Algorithm 1, Eq. 7-15, Sec. 5.2/5.3, App. C). The reasons
// for each choice below (the 6x6 J^-1, P, the motion sign, the start, safety,
// the KRC's state, the wrist) are in docs/design.md.
//
// One step (Algorithm 1), vectors ordered as in conventions.hpp:
//   s        = [CoP_x, CoP_y, d_z, CoC_x, CoC_y, alpha_z]            (Eq. 6)
//   Δs       = s_d - J^-1(β) s, β = 1 edge, 0 point (6x6)           (Eq. 7, 8)
//   Δs_task  = P Δs                                                   (Eq. 9, 10)
//   u_s      = (S (K_P Δs_task + K_I ∫Δs_task dt) + v_ff) dt          (Eq. 13)
//   {g}T{s}' = addDelta({g}T{e} {e}T{s}, R_gs u_s)                    (Eq. 13)
//   x(t)     = x_a + u (Eq. 12) or x(t-1) + u (Eq. 15) -> {g}T{e}' = {g}T{s}' {e}T{s}^-1
// Rows of Δs in programs: cop_x, cop_y, d_z, dzmp_x, dzmp_y, alpha_z.
// S = motion_sign (entries +-1). Units: per second (K_P 1/s, K_I 1/s^2,
// integral_limit and u_max m/s or rad/s, step limits as speeds, transitions
// hold for `for_s` s): the behaviour does not depend on the servo rate.
//
// Contract of step():
//  * no command (out.valid false, WaitingForPose / InvalidInput) before a
//    valid measured pose (validPose); the first valid pose is commanded as is
//    (Starting), servoing starts the next cycle; reset() starts over;
//  * every increment within the phase's u_max and the speed limits, the
//    commanded flange position within the workspace box (from outside: only
//    back towards it);
//  * force above force_ceiling -> ForceCeiling: retreat along -z_s by
//    ceiling_retreat, hold; latched until reset() or requestPhase();
//  * features older than stale_timeout or unusable -> Holding (last command);
//    NaN/Inf inputs or dt <= 0 -> InvalidInput, hold; no output is ever NaN;
//  * watchdogs (watchdog.hpp) PhaseTimeout, ArmStalled, ForceMismatch,
//    SurfaceTooCurved, PhantomContact, UnseenLoad, CorrectionSaturated: fatal,
//    latched, command held (the sensor checks may first retreat, on_fault);
//  * contact lost in a phase that requires contact -> contact_loss: hold,
//    backoff (along -z_s) or search (along +z_s, at most search_max_distance);
//  * in.robot_ready false (no dry run) -> WaitingForRobot: the command is the
//    KRC's set point and integrators, program, timers, phase time, force
//    estimate and watchdogs stand still; resumes from that pose without a jump;
//  * wrist_yaw: the rotation of {s} about z_s integrated from the measured
//    poses (events wrist_wound / wrist_unwound, unwind_rate); loop_closed
//    follows {g}T{e} {e}T{s} (0, CoP_y, 0);
//  * in the phases of the program's speed_law block, the slide axis's
//    increment capped at the speed law's speed x dt (speed_law.hpp), which starts at v_min
//    on entering such a phase and after a contact loss;
//  * transitions of the current phase evaluated in order each cycle with
//    valid features (first to fire wins, after holding `for_s` s); the new
//    phase acts in the same cycle; not evaluated while holding.
// Parts: ServoControlLaw (control_law.hpp, Eq. 7-15), PhaseProgram
// (phase_program.hpp), SafetySupervisor (safety_supervisor.hpp).
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
#include "tactile_servo/slope_feedforward.hpp"
#include "tactile_servo/speed_law.hpp"
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
  /// The measured joint positions (RobotState::q, rad) when have_q: the
  /// phase program's joint_margin event. Unknown: that event never fires.
  std::array<double, kArmJoints> q{};
  bool have_q = false;
};

struct ServoOutput {
  PoseCommand command;   ///< {g}T{e} desired
  PhaseState phase;
  Vec6 error = Vec6::Zero();       ///< Δs (Eq. 7)
  Vec6 error_task = Vec6::Zero();  ///< Δs_task (Eq. 9)
  Vec6 u_s = Vec6::Zero();         ///< increment applied this cycle, in {s}
  uint8_t beta = 0;                ///< 1 when the edge Jacobian was used
  double force = 0.0;              ///< N: the force the law and the transitions used (f_hat, force_estimator.hpp)
  /// N: the press the arm's wrench less its zero reads along z_s (f_w,
  /// force_estimator.hpp; signed), NaN without a fresh wrench; and the fused
  /// estimate's correction c and its demand (0 with source tactile): both
  /// sensors side by side, whatever the law used.
  double force_wrench = 0.0;
  double force_correction = 0.0;
  double force_demand = 0.0;
  /// m/s: the speed law's cap on the slide axis this cycle (speed_law.hpp);
  /// 0 in a phase without the law.
  double slide_speed = 0.0;
  SpeedLimiter speed_limiter = SpeedLimiter::None;  ///< the input that decided it
  SpeedLawInput speed_inputs;                       ///< what the law saw (filtered; speed_law.hpp)
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
  /// A latched sensor fault (watchdog.hpp): this cycle's retreat along -z_s
  /// (on_fault: retreat), else the held command.
  ServoStatus onSensorFault(const KDL::Frame& base, double dt, double now, ServoOutput& out);
  /// This cycle's forces: f_hat (force_estimator.hpp), the force the law holds,
  /// the wrench's excess over it and the image's extent.
  struct ForceStage {
    double f_hat = 0.0, f_law = 0.0, excess = 0.0, extent = 0.0;
  };
  /// The force estimate, the two sensors against each other and the surface
  /// check on one cycle: Ok, or the watchdog status that ends it.
  ServoStatus forceStage(const ServoInput& in, const KDL::Frame& meas, double dt, double now, ForceStage& fs,
                         ServoOutput& out);
  /// step()'s gates before the law (the start, a latched watchdog, the
  /// robot's state, a phase request or timeout, invalid input): true when the
  /// cycle ends there, with its status in `st`.
  bool gate(const ServoInput& in, const KDL::Frame& meas, bool pose_ok, double dt, ServoStatus& st,
            ServoOutput& out);
  /// step() past the gates: the force ceiling, stale data, the force stage,
  /// the phase program and contact loss, then law().
  ServoStatus control(const ServoInput& in, const KDL::Frame& meas, double dt, ServoOutput& out);
  /// Eq. 9 and 13 in phase `ph` on the feature error `e`, the speed law, the
  /// slope feed-forward and the wrist's unwinding: the cycle's increment.
  ServoStatus law(int ph, const Vec6& e, const ContactFeatures& f, const ForceStage& fs, const KDL::Frame& base,
                  double dt, double now, ServoOutput& out);

  bool configured_ = false;
  ServoParams params_;
  ServoControlLaw law_;
  PhaseProgram program_;
  SafetySupervisor safety_;
  ServoWatchdogs watchdogs_;
  ForceEstimator force_est_;
  SpeedLaw speed_law_;
  SpeedLawFilter speed_filter_;
  std::vector<char> speed_phase_;  ///< per phase: the speed law acts in it (configuration time)
  SlopeFeedforward slope_ff_;
  std::vector<char> slope_phase_;  ///< per phase: the slope is fed forward in it (configuration time)
  /// The speed law's cap on the slide axis for this cycle (m/s; < 0: none).
  double slideCap(int phase, const ContactFeatures& f, double f_hat, double f_d, double extent, double excess,
                  double dt, ServoOutput& out);
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
  void observePose(const ServoInput& in, const KDL::Frame& meas, bool first);
  uint32_t seq_ = 0;
};

}  // namespace tactile
