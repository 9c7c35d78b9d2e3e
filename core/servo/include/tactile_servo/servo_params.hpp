// Parameter and shared types of the tactile servo (paper Sec. 4, Eq. 7-15):
// the phase program (PhaseParams, TransitionParams), the safety limits
// (SafetyParams) and the whole program (ServoParams), plus the paper's
// matrices. See servo.hpp for the decisions behind them (6x6 J^-1, P, motion
// sign, units). Used by the control law, the phase program and the safety
// supervisor, each configured from the same ServoParams.
#pragma once

#include <Eigen/Core>
#include <kdl/frames.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tactile_servo/force_estimator.hpp"
#include "tactile_servo/speed_law.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Row/axis indices.
enum Axis : int { kX = 0, kY = 1, kZ = 2, kWX = 3, kWY = 4, kWZ = 5 };

/// Feature vector s (Eq. 6) from the extractor's output.
Vec6 featureVector(const ContactFeatures& f);

/// Inverse tactile Jacobian J^-1(β) (Eq. 8, 6x6 form, see the header comment).
Mat6 paperJinv(double beta);

/// The baseline: Li et al. (RSS 2013), the paper's ref. [7] (Sec. 2, Table 1,
/// Sec. 5.2.1). Constant J^-1 on their four features CoP_x, CoP_y, force (d_z)
/// and alpha_z, with the CoP -> rotation rows kept (a point contact is
/// centred by rolling: wx from CoP_y, wy from CoP_x) and alpha_z always on.
/// What it lacks against Eq. 8: no CoC columns (no DZMP_x/DZMP_y, Eq. 3) and
/// no touch dependence (β of Eq. 5): the same rows for a point and an edge.
Mat6 liJinv();

/// Ablation "no_rotation": constant diag(1,1,1,0,0,1): Li et al.'s features
/// without the rotation rows; never rotates about x_s or y_s.
Mat6 noRotationJinv();

/// Projection matrix of Eq. 10.
Mat6 projection(double gx, double gy, double gz, double gwx, double gwy, double gwz, double gcom = 0.0);

/// Default motion sign S (see the header comment).
Vec6 defaultMotionSign();

enum class TransitionEvent : uint8_t {
  Contact, Edge, Point, Aligned, ContactLost, ForceAbove, Timeout,
  WristWound,    ///< |accumulated yaw of {s} about z_s, from the measured poses| >= angle_rad
  WristUnwound,  ///< the accumulated yaw has come back by >= angle_rad since the phase was entered
  LoopClosed,    ///< the loop point (servo.hpp, WRIST) is back within radius_m of its anchor, after leaving it by > leave_m
  Multiple,      ///< contact in two or more separate regions (ContactType::Multiple): e.g. a gap in the edge under the pad
  JointMargin    ///< a measured joint is within angle_rad of its limit (kArmJointLimit): the arm has no room to go on
};
constexpr TransitionEvent kLastTransitionEvent = TransitionEvent::JointMargin;
/// The event's name in a program file ("contact", ..., "multiple").
const char* toString(TransitionEvent e);

/// Tolerance quantities for the `aligned` event. The first six are the rows of
/// Δs (|Δs_i|); Force is |Δs_dz| / c_z (N); CocX/CocY are |CoC| (m), the
/// distance of the centre of contact from the sensor centre.
enum ToleranceIndex : int { kTolCopX = 0, kTolCopY, kTolDz, kTolDzmpX, kTolDzmpY, kTolAlphaZ, kTolForce, kTolCocX, kTolCocY, kNumTol };
/// Names used in files for ToleranceIndex (and, first six, for rows of Δs / s_d).
extern const char* const kToleranceNames[kNumTol];
/// Names of the six entries of s (columns of J^-1).
extern const char* const kFeatureNames[6];
/// Names of the task axes (rows of P, gains): x y z wx wy wz.
extern const char* const kAxisNames[6];

struct TransitionParams {
  TransitionEvent on = TransitionEvent::Contact;
  std::string to;          ///< target phase name
  double for_s = 0.0;      ///< s the condition must hold (>= 0; 0 = the first cycle it holds)
  /// aligned: time constant (s, >= 0) of a first-order low-pass on the signed
  /// errors the tolerances test; 0 = the raw samples. Against the flicker of
  /// taxels at the firing threshold, which moves the features of a still contact.
  double filter_s = 0.0;
  std::array<double, kNumTol> tolerance;  ///< aligned: per quantity, < 0 = unused
  double timeout_s = 0.0;  ///< timeout: seconds in the phase (> 0)
  double force_n = 0.0;    ///< force_above: threshold (N, > 0)
  double angle_rad = 0.0;  ///< wrist_wound / wrist_unwound: yaw; joint_margin: the margin (rad, > 0; files: angle_deg)
  double radius_m = 0.0;   ///< loop_closed: closure radius (m, > 0)
  double leave_m = 0.0;    ///< loop_closed: distance the contact must first go away from the anchor (m, > radius_m)
  TransitionParams() { tolerance.fill(-1.0); }
};

enum class JacobianMode : uint8_t {
  Touch = 0,  ///< β from the contact type each cycle: edge -> jinv_edge, otherwise jinv_point
  Fixed = 1   ///< always jinv_edge if fixed_beta_edge, else jinv_point
};

struct PhaseParams {
  std::string name;
  Vec6 s_d = Vec6::Zero();                 ///< desired features, rows of Δs
  JacobianMode jacobian = JacobianMode::Touch;
  bool fixed_edge = true;                  ///< for Fixed: use jinv_edge (true) or jinv_point
  Mat6 jinv_point = paperJinv(0.0);
  Mat6 jinv_edge = paperJinv(1.0);
  Mat6 P = Mat6::Zero();                   ///< Eq. 10
  Vec6 kp = Vec6::Zero();                  ///< 1/s (rate per unit feature error), >= 0
  Vec6 ki = Vec6::Zero();                  ///< 1/s^2, >= 0
  Vec6 integral_limit = Vec6::Constant(0.1);   ///< |K_I ∫Δ| per axis (m/s or rad/s), >= 0
  Vec6 u_max = Vec6::Constant(1e9);        ///< per-axis limit of the PI rate (m/s or rad/s), > 0
  Vec6 feedforward = Vec6::Zero();         ///< twist in {s} (m/s, rad/s)
  /// rad/s (>= 0) about z_s against the accumulated wrist yaw the phase was
  /// entered with (unwinding the last joint: servo.hpp, WRIST); 0 = none.
  double unwind_rate = 0.0;
  bool requires_contact = true;            ///< contact-loss recovery applies in this phase
  bool reset_integrator = true;            ///< zero the integrator on entering this phase
  bool terminal = false;                   ///< entering it -> status Done, hold
  /// s in the phase after which the servo reports PhaseTimeout (fatal, a
  /// phase that never ends); 0 = no limit. Not for terminal phases.
  double max_duration_s = 0.0;
  std::vector<TransitionParams> transitions;
};

enum class PoseUpdate : uint8_t { Measured = 0, Integrated = 1 };  ///< Eq. 12 / Eq. 15
/// Proposed: Eq. 8 (touch-dependent, DZMP rows). Baseline: Li et al. (liJinv).
/// NoRotation: the ablation noRotationJinv. P, s_d, gains, feed-forward and
/// safety come from the program in every mode.
enum class ControllerMode : uint8_t { Proposed = 0, Baseline = 1, NoRotation = 2 };
/// "proposed" | "baseline" | "no_rotation".
const char* toString(ControllerMode m);
/// Parses a name of toString(); false (mode unchanged) for any other string.
bool parseControllerMode(const std::string& name, ControllerMode& mode);
/// For messages: "proposed, baseline or no_rotation".
extern const char* const kControllerModeNames;
enum class ContactLossMode : uint8_t { Hold = 0, Backoff = 1, Search = 2 };

struct SafetyParams {
  double max_trans_speed = 0.05;                ///< m/s (norm of the commanded translation rate), > 0
  double max_rot_speed = 50.0 * kPi / 180.0;    ///< rad/s (norm of the commanded rotation rate), > 0
  /// s: the longest cycle the speed limits integrate over, so that a stalled
  /// loop (a long dt) never allows a jump; (0, 1].
  double max_step_dt = 0.1;
  std::array<double, 3> workspace_min{{-2.0, -2.0, -2.0}};  ///< m, flange position in {g}
  std::array<double, 3> workspace_max{{2.0, 2.0, 2.0}};
  double force_ceiling = 40.0;                  ///< N, > 0
  double ceiling_retreat = 0.01;                ///< m, >= 0
  double stale_timeout = 0.05;                  ///< s, > 0
  ContactLossMode contact_loss = ContactLossMode::Hold;
  double backoff_distance = 0.005;              ///< m, >= 0
  double search_speed = 0.005;                  ///< m/s, >= 0
  double search_max_distance = 0.01;            ///< m, >= 0
  /// A frozen image (SafetySupervisor::frozenImage): in contact, new frames
  /// whose image is bit-identical to the last changed one (force, CoP, CoC,
  /// PCA eigenvalues, peak taxel, area) for at least frozen_image_s while the
  /// measured flange moved more than frozen_image_travel: a stream that
  /// re-sends its last frame. Held as stale data until the image changes.
  /// A live pad never repeats a loaded image (its noise, some counts per
  /// taxel); a noise-free simulated pad sliding along a uniform edge does,
  /// so the check is off unless a program states it.
  double frozen_image_travel = 0.0;             ///< m, [0, 0.05]; 0 = off
  double frozen_image_s = 0.1;                  ///< s, (0, 5]
};

/// Watchdogs (beyond the paper): what must never pass silently. Each ends in
/// a fatal, latched status (see watchdog.hpp). A window of 0 switches it off.
struct WatchdogParams {
  /// Arm stalled: over each window of commanded motion, the measured sensor
  /// origin must move at least min_fraction of the commanded translation
  /// (when that is >= min_distance) and turn at least min_fraction of the
  /// commanded rotation (when that is >= min_angle).
  double stall_window_s = 1.0;                   ///< s, 0 = off
  double stall_min_distance = 0.005;             ///< m, > 0
  double stall_min_angle = 5.0 * kPi / 180.0;    ///< rad, > 0
  double stall_min_fraction = 0.2;               ///< (0, 1]
  /// The two sensors checked against each other (ServoWatchdogs::sensorsAgree),
  /// always with Eq. 2's tactile force f (never the fused estimate f_hat) and
  /// the arm's wrench along z_s less its zero, f_w:
  /// Force mismatch, held for window_s: with tactile contact, the wrench above
  /// the taxels, f_w - f > max(tolerance_n, tolerance_rel * f_w) + the load
  /// the fused estimate may carry below the firing threshold (its
  /// max_correction_n; 0 with source tactile).
  double mismatch_window_s = 0.5;                ///< s, 0 = off
  double mismatch_tolerance_n = 4.0;             ///< N, > 0
  double mismatch_tolerance_rel = 0.3;           ///< [0, 1]
  /// Phantom contact, held for window_s: with tactile contact, the taxels
  /// above the wrench, f - f_w > max(tolerance_n, tolerance_rel * f): a load
  /// the arm does not carry. Short: the arm must not chase it.
  double phantom_window_s = 0.05;                ///< s, [0, 60], 0 = off
  double phantom_tolerance_n = 2.0;              ///< N, (0, 1e4]
  double phantom_tolerance_rel = 0.4;            ///< [0, 1]
  /// Unseen load, held for window_s: no tactile contact, f_w > max_n (load on
  /// the housing or the cable, a wrong load model).
  double unseen_window_s = 0.1;                  ///< s, [0, 60], 0 = off
  double unseen_max_n = 10.0;                    ///< N, (0, 1e4]
  /// Correction saturated, held for window_s: the fused estimate's demand
  /// (ForceEstimator::demand(): c without its bounds) at or beyond
  /// force_estimate.max_correction_n + margin_n (source fused only): the
  /// sensors disagree by more than the estimate may bridge. While it holds,
  /// the clamp costs the true force up to margin_n above the set point; a
  /// trough the pad bridges holds it for at most about 1 s (the family of
  /// bars, docs/design.md), a calibration or a wrench off holds it for good.
  double correction_window_s = 2.0;              ///< s, [0, 60], 0 = off
  double correction_margin_n = 0.5;              ///< N, [0, 50]
  /// Correction drift (source fused only; off unless max_change_n > 0): in a
  /// phase that holds a force set point, the demand low-passed with tau_s
  /// moves more than max_change_n away from its value settle_s after the
  /// contact began in that phase (the anchor). Where the pad's hidden load is
  /// stationary (a straight edge at a constant set point), a correction that
  /// keeps moving is the wrench drifting, not the contact: the estimate would
  /// carry the drift into the true force. The anchor restarts on a phase
  /// change, when the contact or the fresh wrench lapses, and when the
  /// image's extent (low-passed with tau_s) leaves [min_extent_ratio,
  /// 1 / min_extent_ratio] times its value at the anchor: another contact
  /// geometry (the pad running off the edge's end), another hidden load.
  double drift_max_change_n = 0.0;               ///< N, [0, 50], 0 = off
  double drift_tau_s = 1.0;                      ///< s, (0, 10]
  double drift_settle_s = 2.0;                   ///< s, [0, 60]
  double drift_min_extent_ratio = 0.5;           ///< (0, 1]
  /// What the servo does once one of the checks above stops it: hold the
  /// last command, or retreat along -z_s by retreat_m at the step limit, then
  /// hold.
  bool fault_retreat = false;                    ///< on_fault: hold (false) | retreat (true)
  double fault_retreat_m = 0.01;                 ///< m, [0, 0.1]
  /// Surface too curved (ServoWatchdogs::surfaceTooCurved): the arm's wrench
  /// along z_s, low-passed with tau_s, above the phase's force set point by
  /// more than excess_n while the image spans at most max_extent_m, or its
  /// taxels carry at most max_tactile_share of the wrench, or no taxel fires:
  /// the load has moved to the pad's ends or its housing.
  double curved_tau_s = 0.0;                     ///< s, [0, 10], 0 = off
  double curved_excess_n = 1.2;                  ///< N, (0, 1e4]
  double curved_max_extent_m = 0.0238;           ///< m, (0, 1]: half the pad's 47.6 mm by default
  double curved_max_tactile_share = 0.5;         ///< [0, 1]: the tactile force's share of the wrench's
  /// The first reaction: while the image is short and the low-passed excess
  /// is above lift_n, the law regulates f_d + the excess instead of f_hat
  /// (the larger of the two): it lifts the pad by the load the taxels miss.
  double curved_lift_n = 0.0;                    ///< N, [0, 1e4], 0 = off
};

/// The slide speed from the contact (tactile_servo/speed_law.hpp; beyond the
/// paper): in the listed phases the speed law caps the motion along the slide
/// axis, each cycle, at the fastest speed that keeps the true force within
/// the budget. The phase's K_P sets how hard the slide pulls; the law sets
/// how fast it may go.
struct SpeedLawConfig {
  std::vector<std::string> phases;  ///< the phases it acts in; empty = off
  int axis = 0;                     ///< the slide axis of {s}: 0 x_s, 1 y_s
  double rate_tau_s = 0.05;         ///< s, (0, 10]: low-pass of the force error, its rate, the angle's rate, the curvature
  /// s, [0, 10]: low-pass of the wrench's excess (0: rate_tau_s). Shorter
  /// than rate_tau_s, the excess sees the pad start to bridge a trough within
  /// a few cycles, at the price of more of the wrench's noise (its dead band
  /// must cover it).
  double excess_tau_s = 0.0;
  /// The wrench's excess against Eq. 2's tactile force f (true; files:
  /// excess_against: tactile) or against the force estimate f_hat (false;
  /// estimate). A force estimate that follows the wrench within a few cycles
  /// (force_estimate.tau_s 0.02 s, its bound the whole set point) leaves no
  /// excess over f_hat to see; against f the excess is the load the taxels
  /// miss, which grows as the pad starts to bridge a trough.
  bool excess_against_tactile = false;
  SpeedLawParams law;
};

/// The slide's slope fed forward along z_s (slope_feedforward.hpp).
struct SlopeFeedforwardConfig {
  std::vector<std::string> phases;  ///< the phases it acts in; empty = off
  int axis = 0;                     ///< the slide axis of {s}: 0 x_s, 1 y_s
  double window_m = 0.0005;         ///< m, [0, 0.05]: the slide over which the slope is measured (0: off)
};

struct ServoParams {
  KDL::Frame sensor_mount = KDL::Frame::Identity();  ///< {e}T{s}
  Vec6 motion_sign = defaultMotionSign();
  PoseUpdate pose_update = PoseUpdate::Integrated;
  ControllerMode mode = ControllerMode::Proposed;
  double c_z = 1.0 / 1800.0;                          ///< m/N (Eq. 2), > 0
  SafetyParams safety;
  WatchdogParams watchdogs;
  ForceEstimateParams force_estimate;                 ///< the force the law and the transitions use (force_estimator.hpp)
  SpeedLawConfig speed_law;                           ///< the slide speed from the contact (speed_law.hpp)
  SlopeFeedforwardConfig slope_feedforward;           ///< the slide's slope along z_s (slope_feedforward.hpp)
  std::vector<PhaseParams> phases;
  std::string initial_phase;                          ///< empty = first phase
  std::string source;                                 ///< file name, for messages
};

}  // namespace tactile
