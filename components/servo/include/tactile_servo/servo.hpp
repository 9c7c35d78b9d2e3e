// Touch-driven tactile servo core (Kappassov, Corrales & Perdereau, RAS 123
// (2020), Sec. 4, Algorithm 1, Eq. 7-15, Sec. 5.2/5.3, App. C).
//
// One step (Algorithm 1), all vectors ordered as in conventions.hpp:
//
//   s        = [CoP_x, CoP_y, d_z, CoC_x, CoC_y, alpha_z]            (Eq. 6)
//   J^-1     = touch-dependent inverse tactile Jacobian (6x6)          (Eq. 8)
//   Δs       = s_d - J^-1 s                                           (Eq. 7)
//   Δs_task  = P Δs                                                   (Eq. 9, 10)
//   u_s      = S (K_P Δs_task + K_I ∫Δs_task dt) + v_ff dt            (Eq. 13)
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
// UNITS. u is a pose increment per servo cycle [m m m rad rad rad], expressed
// in {s} and applied at the origin of {s}. K_P is per cycle (increment per unit
// feature error); K_I is in 1/s (the integral is ∫Δs_task dt, dt in s); the
// feed-forward twist is in m/s, rad/s in {s}.
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
//  * per-axis output limits per phase (u_max) and per-cycle translational and
//    rotational step limits (norms) for every increment, recovery moves included;
//  * a workspace box on the commanded flange position {g}p{e} (from a pose
//    already outside it, only motion back towards it is allowed: no jumps);
//  * a force ceiling: features.force > ceiling -> status ForceCeiling, retreat
//    along -z_s (away from the object) by `ceiling_retreat` at the step limit,
//    then hold; latched until reset() or requestPhase();
//  * a stale-features watchdog: features older than `stale_timeout` or with an
//    unusable status -> hold the last command (status Holding);
//  * NaN/Inf in features, pose or dt, dt <= 0 -> hold (status InvalidInput);
//    no output is ever NaN;
//  * contact loss (the paper's limitation: "as soon as the contact disappears
//    the controller does not send new set points"): in a phase that requires
//    contact, losing it triggers `contact_loss`: hold, backoff (retreat along
//    -z_s by a distance, then hold) or search (move along +z_s, i.e. towards the
//    object along the surface normal, at a speed until contact returns, at most
//    `search_max_distance`, then hold). The "search along -z of {s}"
//    is +z_s here because our z_s points out of the surface at the object.
//
// PHASE PROGRAM. Each cycle with valid features, the current phase's
// transitions are evaluated in their listed order (first to fire wins; a
// transition fires after its condition held for `cycles` consecutive valid
// cycles) and the new phase acts in the same cycle. Events: contact, edge,
// point (the extractor's contact type), aligned (chosen |Δs| rows, |Δforce|,
// |CoC| below tolerances), contact_lost, force_above, timeout (time in phase).
// While holding (stale/invalid input) transitions are not evaluated.
//
// Real-time: step() and requestPhase() do not allocate, throw, log or block.
// They are not thread-safe: call them from the same thread (in RTT, run the
// requestPhase operation in the component's own thread).
#pragma once

#include <Eigen/Core>
#include <kdl/frames.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

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

/// Li et al. (RSS 2013) constant Jacobian as compared in Sec. 5.2.1: CoP_x,
/// CoP_y, d_z (force), alpha_z; no DZMP rows.
Mat6 baselineJinv();

/// Projection matrix of Eq. 10.
Mat6 projection(double gx, double gy, double gz, double gwx, double gwy, double gwz, double gcom = 0.0);

/// Default motion sign S (see the header comment).
Vec6 defaultMotionSign();

enum class TransitionEvent : uint8_t { Contact, Edge, Point, Aligned, ContactLost, ForceAbove, Timeout };
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
  int cycles = 1;          ///< consecutive cycles the condition must hold (>= 1)
  std::array<double, kNumTol> tolerance;  ///< aligned: per quantity, < 0 = unused
  double timeout_s = 0.0;  ///< timeout: seconds in the phase (> 0)
  double force_n = 0.0;    ///< force_above: threshold (N, > 0)
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
  Vec6 kp = Vec6::Zero();                  ///< per cycle, >= 0
  Vec6 ki = Vec6::Zero();                  ///< 1/s, >= 0
  Vec6 integral_limit = Vec6::Constant(1e-3);  ///< |K_I ∫Δ| per axis (m or rad per cycle), >= 0
  Vec6 u_max = Vec6::Constant(1e9);        ///< per-axis limit of the PI output per cycle, > 0
  Vec6 feedforward = Vec6::Zero();         ///< twist in {s} (m/s, rad/s)
  bool requires_contact = true;            ///< contact-loss recovery applies in this phase
  bool reset_integrator = true;            ///< zero the integrator on entering this phase
  bool terminal = false;                   ///< entering it -> status Done, hold
  std::vector<TransitionParams> transitions;
};

enum class PoseUpdate : uint8_t { Measured = 0, Integrated = 1 };  ///< Eq. 12 / Eq. 15
enum class ControllerMode : uint8_t { Proposed = 0, Baseline = 1 };
enum class ContactLossMode : uint8_t { Hold = 0, Backoff = 1, Search = 2 };

struct SafetyParams {
  double max_trans_step = 0.0005;               ///< m per cycle (norm), > 0
  double max_rot_step = 0.5 * kPi / 180.0;      ///< rad per cycle (norm), > 0
  std::array<double, 3> workspace_min{{-2.0, -2.0, -2.0}};  ///< m, flange position in {g}
  std::array<double, 3> workspace_max{{2.0, 2.0, 2.0}};
  double force_ceiling = 40.0;                  ///< N, > 0
  double ceiling_retreat = 0.01;                ///< m, >= 0
  double stale_timeout = 0.05;                  ///< s, > 0
  ContactLossMode contact_loss = ContactLossMode::Hold;
  double backoff_distance = 0.005;              ///< m, >= 0
  double search_speed = 0.005;                  ///< m/s, >= 0
  double search_max_distance = 0.01;            ///< m, >= 0
};

struct ServoParams {
  KDL::Frame sensor_mount = KDL::Frame::Identity();  ///< {e}T{s}
  Vec6 motion_sign = defaultMotionSign();
  PoseUpdate pose_update = PoseUpdate::Integrated;
  ControllerMode mode = ControllerMode::Proposed;
  double c_z = 1.0 / 1800.0;                          ///< m/N (Eq. 2), > 0
  SafetyParams safety;
  std::vector<PhaseParams> phases;
  std::string initial_phase;                          ///< empty = first phase
  std::string source;                                 ///< file name, for messages
};

struct ServoInput {
  double time_s = 0.0;
  ContactFeatures features;
  /// {g}T{e} measured. kNoPose until a measurement arrived: the servo then
  /// commands nothing (status WaitingForPose).
  Pose flange_measured = kNoPose;
};

struct ServoOutput {
  PoseCommand command;   ///< {g}T{e} desired
  PhaseState phase;
  Vec6 error = Vec6::Zero();       ///< Δs (Eq. 7)
  Vec6 error_task = Vec6::Zero();  ///< Δs_task (Eq. 9)
  Vec6 u_s = Vec6::Zero();         ///< increment applied this cycle, in {s}
  uint8_t beta = 0;                ///< 1 when the edge Jacobian was used
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

  int phaseCount() const { return static_cast<int>(phases_.size()); }
  int phaseIndex() const { return current_; }
  int phaseIndexOf(const char* name) const;  ///< -1 if unknown
  const PhaseParams& phase(int i) const { return params_.phases[static_cast<std::size_t>(i)]; }
  const ServoParams& params() const { return params_; }

  /// Δs for the given phase and features (Eq. 7), without any state change.
  Vec6 featureError(int phase, const ContactFeatures& f, uint8_t* beta_out = nullptr) const;

  /// The J^-1 (Eq. 8) used in `phase` for contact type `c` (baseline mode
  /// included), e.g. for reporting on a port. `phase` must be valid.
  const Mat6& jacobian(int phase, ContactType c, uint8_t* beta_out = nullptr) const;

 private:
  struct Transition {
    TransitionEvent on;
    int to;
    int cycles;
    std::array<double, kNumTol> tol;
    double timeout_s, force_n;
    int count;
  };
  struct Phase {
    std::array<char, kPhaseNameLen> name{};
    Vec6 s_d;
    Mat6 j_point, j_edge;
    bool touch, fixed_edge;
    Mat6 P;
    Vec6 kp, ki, i_lim, u_max, ff;
    bool requires_contact, reset_integrator, terminal, free_motion;
    int first_transition, num_transitions;
  };

  void enterPhase(int idx, double now);
  bool evaluateTransitions(const ContactFeatures& f, const Vec6& err, double now, int& target);
  const Mat6& jacobianFor(const Phase& ph, ContactType c, uint8_t& beta) const;
  bool limitIncrement(Vec6& u) const;
  ServoStatus finish(ServoStatus st, double now, ServoOutput& out);
  ServoStatus applyIncrement(const KDL::Frame& base, Vec6 u_s, ServoStatus st, double now, ServoOutput& out);

  bool configured_ = false;
  ServoParams params_;
  std::vector<Phase> phases_;
  std::vector<Transition> transitions_;
  KDL::Frame T_es_, T_se_;
  int initial_ = 0;
  int current_ = 0;
  int pending_ = -1;
  bool entered_ = false;
  double t_enter_ = 0.0;
  Vec6 integral_ = Vec6::Zero();
  KDL::Frame cmd_;
  bool has_cmd_ = false;
  bool ceiling_latched_ = false;
  double ceiling_moved_ = 0.0;
  double recovery_moved_ = 0.0;
  uint32_t seq_ = 0;
  Mat6 baseline_ = baselineJinv();
};

}  // namespace tactile
