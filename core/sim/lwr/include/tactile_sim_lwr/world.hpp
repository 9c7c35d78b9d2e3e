// The simulated world: LWR arm + WTS0614 pad on its flange + the scene's
// objects (table, sphere, bars, tray), at one of two fidelity levels.
//
//   World w;
//   WorldParams p; ...;                       // or from a scene file (runner)
//   ConfigResult r = w.configure(p);          // validates: names the parameter
//   SimState s;
//   for (each sim cycle, dt = 1 / sim_rate)
//     w.step(flange_cmd_g, dt, s);            // physics; s.status
//   on each WTS acquisition (140 Hz):
//     w.acquire(raw, truth);                  // tactile image at the current state
//   Calibration cal; cal.configure(w.calibration());   // as on the robot
//
// Fidelity (Sec. 4, Eq. 11):
//   QuasiStatic: each step the flange settles at the impedance equilibrium
//     K (x_d - x) + W_contact(x) = 0 (damped Newton with the analytic contact
//     stiffness of the elastic foundation, warm-started from the previous
//     equilibrium; the tray's two angles are solved jointly), then the joints
//     follow by damped differential IK from the previous q (joint limits and
//     singularities detected). Fine for servo-rate steps (no inertia).
//   Dynamics: joint-space rigid-body dynamics (KDL::ChainDynParam) under the
//     robot's Cartesian impedance torque (Eq. 11) and J^T W_contact,
//     semi-implicit Euler; the tray angles are integrated too.
//
// Time is passed in: step() advances the world time by dt; acquire() stamps
// the frame with the world time. Nothing reads a clock. step() and acquire()
// do not allocate and do not throw.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tactile_sim_lwr/lwr_arm.hpp"
#include "tactile_sim_lwr/objects.hpp"
#include "tactile_sim_lwr/pad_sensor.hpp"

namespace tactile {
namespace sim {

enum class Fidelity : uint8_t { QuasiStatic = 0, Dynamics = 1 };
const char* toString(Fidelity f);
/// "quasi_static" | "dynamics" -> fidelity; false if unknown.
bool parseFidelity(const std::string& s, Fidelity& out);

struct WorldParams {
  ArmParams arm;
  PadParams pad;
  Fidelity fidelity = Fidelity::QuasiStatic;
  std::vector<ObjectParams> objects;
  uint64_t seed = 1;                ///< noise seed (overrides pad.seed)
  /// If set, the arm starts at this flange pose {g}T{e} (IK from arm.q_init);
  /// otherwise at FK(arm.q_init).
  bool use_initial_flange_pose = false;
  tactile::Pose initial_flange_pose;
  /// Extra constant wrench on the flange, {g} at the flange, [f; m] (tests, pushes).
  std::array<double, 6> external_wrench{};
  double force_ceiling = 150.0;     ///< N, |contact force| above this -> ForceCeiling
  int qs_max_iterations = 40;       ///< quasi-static Newton iterations per step (with friction the steps may be halved)
  double qs_tolerance = 1e-4;       ///< N (and N m) residual to stop the quasi-static solve
  double qs_max_step = 0.005;       ///< m per Newton iteration (rad for rotations: x 10)
  /// Dynamics only: start from the quasi-static equilibrium of the initial
  /// command (arm, contacts and tray angles balanced, all velocities zero)
  /// instead of the configured posture. A scene whose object rests on the
  /// sensor (the tray) then starts without a drop transient; with nothing in
  /// contact the equilibrium is the initial posture itself.
  bool start_in_equilibrium = true;
  /// The physics step the world is stepped with (s; the runner and the RTT
  /// arm set 1 / rates.sim): the unit of the KRC cycle and the FRI delay
  /// below, which must be whole multiples of it. In (0, max_step_s].
  double physics_step_s = 0.001;
  /// Largest dt step() accepts (s): a larger (or non-positive) step is
  /// refused with SimStatus::StepRejected, the state and time unchanged.
  /// In (0, 0.1]; the default 0.01 s is the coarsest step the quasi-static
  /// solve is tested at (dynamics is run at 1 ms).
  double max_step_s = 0.01;

  // ---- Physics and timing effects (each off by default: no work when off) --
  /// Coulomb friction coefficient between the pad and the objects (0 = the
  /// frictionless layer of Sec. 3.2). Elasto-plastic (spring-slider) model:
  /// the tangential force on the sensor is -friction_stiffness * u (u: the
  /// shear of the layer, the sensor's tangential displacement from the
  /// point where the contact stuck), capped at mu N (then the stuck point
  /// slides: Coulomb drag of magnitude mu N opposing the slip). It acts at
  /// the pressure centre on the surface, so its moment about the flange
  /// (lever = the sensor mount) tilts the sensor in the impedance. In [0, 2].
  double friction_mu = 0.0;
  /// Tangential (shear) stiffness of the layer before it slides (N/m), (0, 1e7].
  double friction_stiffness = 5000.0;
  /// FRI transport delay (s): the impedance controller uses the command
  /// given this long before. A whole number of physics steps, in [0, 1].
  double fri_delay_s = 0.0;
  /// KRC set-point sample-and-hold period (s): the (delayed) command is
  /// sampled at t = k * krc_cycle_s and held in between; 0 = every physics
  /// step. A whole number of physics steps, in [0, 1].
  double krc_cycle_s = 0.0;
  /// Per-body fidelity: the tray's two angles are integrated in time (its
  /// inertia, springs and bearing damping; the dynamics' backward Euler)
  /// while the arm stays quasi-static (fidelity QuasiStatic only; in
  /// Dynamics the tray is always integrated).
  bool tray_dynamics = false;
};

struct SimState {
  double time_s = 0.0;
  uint64_t step = 0;
  JointVec q = JointVec::Zero(), qd = JointVec::Zero();
  tactile::Pose flange_g;            ///< {g}T{e}
  tactile::Pose sensor_g;            ///< {g}T{s}
  KDL::Frame T_ge, T_gs;
  tactile::Pose command_g;           ///< the flange command as given (last valid)
  /// The set point the impedance controller used this step: command_g after
  /// the FRI delay and the KRC's sample-and-hold (= command_g when both are off).
  tactile::Pose setpoint_g;
  /// True contact wrench on the sensor from all contacts, {s} about its origin,
  /// [fx fy fz mx my mz] (what an ATI Nano17 under the sensor would read, sign
  /// as a wrench acting on the sensor: pressing gives fz < 0).
  std::array<double, 6> wrench_s{};
  double normal_force = 0.0;         ///< N carried by the elastic layer (>= 0)
  double housing_force = 0.0;        ///< N carried by the rigid housing (>= 0)
  double tray_pitch = 0.0, tray_roll = 0.0;  ///< rad (roll = the tray angle, about the equilibrium axis)
  double manipulability = 0.0;
  int solver_iterations = 0;         ///< quasi-static Newton iterations used
  double solver_residual = 0.0;      ///< N, N m: the quasi-static solve's largest residual at its last evaluated iterate
  bool slipping = false;             ///< friction on: the contact slides (|friction| = mu N)
  SimStatus status = SimStatus::NotConfigured;
};

class World {
 public:
  /// Validates everything (errors name the parameter, the object and its
  /// range; e.g. an object that starts inside the sensor) and places the arm.
  ConfigResult configure(const WorldParams& params);
  bool configured() const { return configured_; }
  const WorldParams& params() const { return params_; }

  /// Physics: advance by dt (s) toward the flange command {g}T{e}.
  /// A NaN/Inf/zero-quaternion command is ignored (the last valid one is held,
  /// status InvalidCommand); dt <= 0 or non-finite leaves the state unchanged.
  SimStatus step(const tactile::Pose& flange_cmd_g, double dt, SimState& out);

  /// WTS acquisition at the current state and world time.
  void acquire(tactile::RawTactileFrame& raw, SensorTruth& truth);
  /// The contact image alone at the current state: the noise-free taxel
  /// forces (N, stamped with the world time) and the ground truth; the
  /// sensor's electronics (tactile::sim::TaxelResponse) turn it into counts.
  /// Consumes no noise. Allocation-free.
  void acquireForces(tactile::TactileFrame& forces, SensorTruth& truth);

  /// Calibration that inverts the simulated taxel response.
  tactile::CalibrationParams calibration() const { return pad_.calibration(); }

  const SimState& state() const { return state_; }
  const LwrArm& arm() const { return arm_; }
  const PadSensor& pad() const { return pad_; }
  const ObjectSet& objects() const { return objects_; }
  double time() const { return state_.time_s; }
  /// Tray moving-mass position in {g} now (for logs); zero without a tray.
  std::array<double, 3> trayMassPosition() const;

  /// Replace the constant external wrench (allocation-free).
  void setExternalWrench(const std::array<double, 6>& w);

 private:
  SimStatus stepQuasiStatic(const KDL::Frame& T_cmd, double dt);
  SimStatus stepDynamics(const KDL::Frame& T_cmd, double dt);
  // The steps of stepQuasiStatic(), in order.
  struct QsResidual;
  /// The previous converged equilibrium holds: same command, nothing moving.
  bool quasiStaticHolds(const KDL::Frame& T_cmd, double dt) const;
  /// Starts the solve at the last contact evaluation (T) when it was taken at T_eq_ and tray angles th.
  bool reuseLastContact(const TrayPose& th, KDL::Frame& T);
  /// The equilibrium residual at flange pose T, tray angles th (Eq. 11 at rest + contact + friction + tray).
  void quasiStaticResidual(const KDL::Frame& T_cmd, const KDL::Frame& T, const TrayPose& th, const Mat6& A,
                           bool tray, QsResidual& r);
  /// The undamped Newton step (de, dth) on the residual's Jacobian.
  void newtonStep(const Mat6& A, bool tray, const QsResidual& r, Vec6& de, Eigen::Vector2d& dth) const;
  /// The arm settles at the solution; contact, friction and the cached equilibrium follow.
  SimStatus settleQuasiStatic(const KDL::Frame& T_cmd, const KDL::Frame& T, const TrayPose& th, double dt,
                              bool converged, bool evaluated, int iterations);
  void placeObjects(const KDL::Frame& T_ge, const TrayPose& tp);
  /// placeObjects() + PadSensor::evaluate() into contact_, remembering where.
  void evaluateContact(const KDL::Frame& T_ge, const TrayPose& tp);
  void fillState(SimStatus s);
  /// The KRC side of the command: FRI delay line, then sample-and-hold.
  const KDL::Frame& setPoint();
  /// Tray angles, one backward-Euler step with the current contact (dynamics
  /// and the dynamic tray on a quasi-static arm).
  void integrateTray(double dt);
  /// Friction at the current contact_ and sensor pose T_gs (the stuck point
  /// anchor_ held): fric_ (force on the sensor in {s}, x and y), fric_mz_,
  /// slip_. With `commit`, the stuck point follows a slip (return mapping)
  /// or is set/reset at the start/end of contact.
  void friction(const KDL::Frame& T_gs, const TrayPose& tp, bool commit);
  /// The friction wrench's torque on the tray about its bearing (x_g, y_g).
  Eigen::Vector2d frictionTrayTorque(const KDL::Frame& T_gs) const;
  /// The friction force and moment added to an acquisition's true wrench.
  void addFriction(SensorTruth& truth) const;
  void fillStatus(SimStatus s);  ///< status and iteration count only

  bool configured_ = false;
  WorldParams params_;
  LwrArm arm_;
  PadSensor pad_;
  ObjectSet objects_;
  ContactEval contact_;
  SimState state_;
  KDL::Frame T_eq_;                 ///< quasi-static equilibrium flange pose (warm start)
  KDL::Frame T_cmd_;                ///< last valid command
  TrayPose tray_;
  Eigen::Vector2d tray_rate_ = Eigen::Vector2d::Zero();
  Vec6 W_ext_ = Vec6::Zero();
  uint32_t acq_seq_ = 0;
  int last_iterations_ = 0;
  double last_residual_ = 0.0;
  // Quasi-static: the equilibrium is a function of the command and the world;
  // when neither changed since a converged solve, step() only advances time.
  bool qs_valid_ = false;
  bool held_ = false;               ///< this step held the previous equilibrium
  tactile::Pose last_cmd_;          ///< last valid command as given (T_cmd_ is its frame)
  bool last_cmd_valid_ = false;
  KDL::Frame contact_T_ge_;         ///< flange pose and tray angles of contact_
  TrayPose contact_tray_;
  // Placement of the last acquisition: an unchanged sensor pose and tray
  // reuse the contact integral (PadSensor::acquireRepeat).
  bool acq_valid_ = false;
  KDL::Frame acq_T_gs_;
  TrayPose acq_tray_;
  KDL::Frame qs_cmd_;
  SimStatus qs_status_ = SimStatus::Ok;
  // KRC cycle and FRI delay (WorldParams::krc_cycle_s, fri_delay_s).
  bool cmd_path_ = false;           ///< either is on
  std::vector<KDL::Frame> cmd_line_;  ///< ring of delay + 1 commands (allocated in configure)
  long delay_steps_ = 0, krc_steps_ = 0;
  KDL::Frame T_set_;                ///< the set point in use
  // Friction (WorldParams::friction_mu).
  bool friction_on_ = false;
  bool stuck_valid_ = false;        ///< a stuck point exists (in contact)
  KDL::Vector anchor_;              ///< stuck point: {g}, or the tray's frame relative to its bearing
  Eigen::Vector2d fric_ = Eigen::Vector2d::Zero();  ///< friction force on the sensor, {s} x, y (N)
  double fric_mz_ = 0.0;            ///< its moment about z_s at the sensor origin (N m)
  double fric_n_ = 0.0;             ///< normal force it was computed with (N)
  Eigen::Vector2d fric_u_ = Eigen::Vector2d::Zero();  ///< the shear u ({s} x, y) it was computed with
  bool slip_ = false;
  bool tray_dynamic_ = false;       ///< quasi-static arm, dynamic tray
};

}  // namespace sim
}  // namespace tactile
