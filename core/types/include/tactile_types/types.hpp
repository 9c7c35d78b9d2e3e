// Plain data types shared by the cores, the simulator, the RTT components and
// the typekit. No RTT, no heap: every type here is a fixed-size aggregate, so it
// can travel through an RTT data port without allocation (the typekit in
// rtt/typekit serialises exactly these fields).
// See conventions.hpp for units and frames.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "tactile_types/conventions.hpp"

namespace tactile {

/// Largest array supported without reallocation. The WTS family tops out well
/// below this (WTS0614 = 6 x 14); frames carry their actual size.
constexpr int kMaxRows = 16;
constexpr int kMaxCols = 32;
constexpr int kMaxTaxels = kMaxRows * kMaxCols;

constexpr int kDefaultRows = 6;
constexpr int kDefaultCols = 14;
constexpr double kDefaultPitch = 0.0034;  // m

/// Raw frame as delivered by the sensor: 12-bit counts, row-major, {s} layout.
struct RawTactileFrame {
  double time_s = 0.0;          ///< acquisition time (s), host time base
  uint32_t seq = 0;             ///< acquisition counter
  uint32_t device_time_ms = 0;  ///< the device's own millisecond timestamp
  uint16_t rows = kDefaultRows;
  uint16_t cols = kDefaultCols;
  std::array<uint16_t, kMaxTaxels> counts{};  ///< raw counts, row-major
};

/// Calibrated frame: taxel forces in newtons, row-major, {s} layout.
struct TactileFrame {
  double time_s = 0.0;
  uint32_t seq = 0;
  uint16_t rows = kDefaultRows;
  uint16_t cols = kDefaultCols;
  uint16_t saturated_count = 0;  ///< taxels whose raw value reached full scale
  std::array<double, kMaxTaxels> force{};  ///< N per taxel, row-major

  double& at(int r, int c) { return force[static_cast<std::size_t>(r * cols + c)]; }
  double at(int r, int c) const { return force[static_cast<std::size_t>(r * cols + c)]; }
  int size() const { return static_cast<int>(rows) * static_cast<int>(cols); }
};

/// Contact type (Sec. 3.3, Eq. 5). Multiple: two or more separate contact
/// regions (beyond the paper, which assumes one): their joint moments are not
/// one edge, so no edge Jacobian and no alpha_z (see extractor.hpp).
enum class ContactType : uint8_t { None = 0, Point = 1, Edge = 2, Multiple = 3 };
constexpr ContactType kLastContactType = ContactType::Multiple;

/// Status of one feature extraction. Values < kFeatureStatusInvalid carry
/// usable features (possibly with a warning); the others carry none.
enum class FeatureStatus : uint8_t {
  Ok = 0,
  NoContact = 1,     ///< no taxel above the contact threshold; features zero
  Saturated = 2,     ///< features computed, but >= 1 taxel at full scale
  TareRejected = 3,  ///< features computed; the last tare request was rejected
                     ///< (an offset beyond calibration.max_tare): the previous tare is kept
  InvalidInput = 10, ///< NaN/Inf in the frame; nothing propagated
  BadDimensions = 11,///< frame size differs from the configured one
  NotConfigured = 12,///< step() before a successful configure()
  OutOfRange = 13    ///< a finite taxel value beyond features.max_taxel_force; nothing propagated
};
constexpr FeatureStatus kLastFeatureStatus = FeatureStatus::OutOfRange;
constexpr uint8_t kFeatureStatusInvalid = 10;
inline bool usable(FeatureStatus s) { return static_cast<uint8_t>(s) < kFeatureStatusInvalid; }

/// Tactile features of one frame, all in {s} (Sec. 3, App. B).
struct ContactFeatures {
  double time_s = 0.0;  ///< time of the frame they were extracted from
  uint32_t seq = 0;     ///< seq of that frame
  double cop_x = 0.0, cop_y = 0.0;    ///< centre of pressure (m), Eq. B.2/B.3
  double coc_x = 0.0, coc_y = 0.0;    ///< centre of contact (m), binarised image
  double dzmp_x = 0.0, dzmp_y = 0.0;  ///< Eq. 3 (m)
  double alpha_z = 0.0;               ///< edge angle (rad), Eq. B.5; held when !alpha_defined
  double force = 0.0;                 ///< total normal force f (N)
  double d_z = 0.0;                   ///< C_z * f (m), Eq. 2
  double lambda1 = 0.0, lambda2 = 0.0;///< PCA eigenvalues (m^2), lambda1 >= lambda2
  /// In-plane curvature (1/m) of an edge's contact line along the pad
  /// (tactile_features/edge_line.hpp: edgeLineCurvature; beyond the paper),
  /// positive bending towards +y_s; 0 for other contacts or a line too short.
  double curvature = 0.0;
  double max_taxel = 0.0;             ///< largest taxel force (N)
  uint16_t area = 0;                  ///< taxels above the binarisation threshold
  ContactType contact = ContactType::None;
  FeatureStatus status = FeatureStatus::NotConfigured;
  /// False when the principal direction is not resolved above the noise
  /// (lambda1 - lambda2 within the noise, see extractor.hpp), for a point or
  /// multiple contact and without contact: alpha_z is then the last defined
  /// angle (held), not a measurement, and must not drive a rotation.
  bool alpha_defined = false;
};

/// A pose: position (m) and unit quaternion (x, y, z, w).
struct Pose {
  std::array<double, 3> p{0.0, 0.0, 0.0};
  std::array<double, 4> q{0.0, 0.0, 0.0, 1.0};
};

/// The project's one pose-validity rule, for every pose that comes from
/// outside (ports, packets, files, commands): every entry finite and the
/// quaternion a unit quaternion, | |q| - 1 | <= kUnitQuaternionTol. Users
/// normalise q before use (KDL builds the matrix from q as given).
constexpr double kUnitQuaternionTol = 1e-3;
inline bool validPose(const Pose& pose) noexcept {
  double n2 = 0.0;
  for (double v : pose.p)
    if (!std::isfinite(v)) return false;
  for (double v : pose.q) {
    if (!std::isfinite(v)) return false;
    n2 += v * v;
  }
  const double n = std::sqrt(n2);
  return n >= 1.0 - kUnitQuaternionTol && n <= 1.0 + kUnitQuaternionTol;
}

/// "No pose yet": what an input holds until a measured pose arrived. Not a
/// valid pose (zero quaternion), so nothing can start from it by mistake.
constexpr Pose kNoPose{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}};
inline bool isNoPose(const Pose& pose) noexcept {
  return pose.q[0] == 0.0 && pose.q[1] == 0.0 && pose.q[2] == 0.0 && pose.q[3] == 0.0 && pose.p[0] == 0.0 &&
         pose.p[1] == 0.0 && pose.p[2] == 0.0;
}

/// Servo status, ordered by severity. Every status keeps the command finite.
enum class ServoStatus : uint8_t {
  Ok = 0,
  FreeMotion = 1,      ///< phase with P = 0 following its feed-forward twist
  Holding = 2,         ///< stale or invalid features: holding the last pose
  ContactLost = 3,     ///< contact lost, recovery behaviour active
  Limited = 4,         ///< command clipped by a step limit or the workspace box
  Done = 5,            ///< the phase program reached its final phase
  WaitingForPose = 6,  ///< no valid measured pose has arrived yet: no command at all
  Starting = 7,        ///< first valid measured pose: the command is that pose, unchanged
  WaitingForRobot = 8, ///< the arm cannot be commanded now (RobotState::commandable false: the KRC
                       ///< in monitor mode, quality below OK, drives off, ...): the command is the
                       ///< measured pose; integrators, phase timers and the program are frozen
  ForceCeiling = 10,   ///< force ceiling hit: retreating
  InvalidInput = 11,   ///< NaN/Inf pose or dt < 0: holding
  NotConfigured = 12,
  // Watchdogs (fatal, latched until reset or a phase request; the command is
  // held): a run that reports one of these did not succeed.
  PhaseTimeout = 13,   ///< longer in a phase than its max_duration_s: a phase that never ends
  ArmStalled = 14,     ///< motion commanded for a window but the measured pose did not follow
  ForceMismatch = 15,  ///< tactile force contradicted by the arm's estimated wrench along z_s
  SurfaceTooCurved = 16, ///< the surface curves more tightly than the rigid pad can follow: the image
                         ///< shrank to part of the pad (or vanished) while the arm's wrench carries
                         ///< more than the force set point (the load on the pad's ends or housing)
  // The two sensors checked against each other (watchdog.hpp): each
  // contradiction has its own status.
  PhantomContact = 17,      ///< the taxels read a load the arm's wrench does not carry (a stuck or
                            ///< pressed region, a cable or the cover, a calibration too high)
  UnseenLoad = 18,          ///< the arm's wrench carries a load no taxel sees (the housing, the cable,
                            ///< a wrong load model)
  CorrectionSaturated = 19, ///< the fused force estimate's correction held at its limit: the taxels and
                            ///< the wrench disagree by more than the estimate may bridge
  CorrectionDrift = 20      ///< the fused force estimate's correction kept moving where the load the pad
                            ///< misses is stationary: the sensors drift apart (the wrench, the pad's tare)
};
/// The highest ServoStatus value (tables and parsers that walk every status).
constexpr ServoStatus kLastServoStatus = ServoStatus::CorrectionDrift;

/// A watchdog status (PhaseTimeout, ArmStalled, ForceMismatch, SurfaceTooCurved,
/// PhantomContact, UnseenLoad, CorrectionSaturated, CorrectionDrift): the run failed.
inline bool watchdogStatus(ServoStatus s) noexcept {
  return s == ServoStatus::PhaseTimeout || s == ServoStatus::ArmStalled || s == ServoStatus::ForceMismatch ||
         s == ServoStatus::SurfaceTooCurved || s == ServoStatus::PhantomContact || s == ServoStatus::UnseenLoad ||
         s == ServoStatus::CorrectionSaturated || s == ServoStatus::CorrectionDrift;
}

/// Desired pose for the robot's Cartesian impedance controller, in {g}.
struct PoseCommand {
  double time_s = 0.0;
  uint32_t seq = 0;
  Pose pose;  ///< {g}T{e} desired (flange pose, what FRI commands)
  ServoStatus status = ServoStatus::NotConfigured;
};

constexpr int kPhaseNameLen = 32;

/// Where the phase program is, for ports and logs.
struct PhaseState {
  double time_s = 0.0;
  double t_enter_s = 0.0;  ///< when the current phase was entered
  uint16_t index = 0;      ///< phase index in the program
  std::array<char, kPhaseNameLen> name{};  ///< NUL-terminated phase name
  ServoStatus status = ServoStatus::NotConfigured;
};

/// A wrench [Fx Fy Fz Tx Ty Tz] (N, N m), fixed size (port estimated_wrench
/// of the FRI bridge and of the simulated arm: the KRC's estExtTcpFT, the
/// external wrench at the TCP, {g} orientation).
struct Wrench {
  double time_s = 0.0;
  std::array<double, 6> w{};
};

/// The KRC's FRI interface state (FRI's OFF / MON / CMD).
enum class RobotMode : uint8_t { Off = 0, Monitor = 1, Command = 2 };

constexpr int kArmJoints = 7;  ///< the LWR 4+
/// The LWR 4+'s joint range (rad): |q_i| <= kArmJointLimit[i], +-170 deg for
/// A1, A3, A5, A7 and +-120 deg for A2, A4, A6 (the KRC's software limits may
/// lie inside it; the servo's joint_margin event takes a margin from it).
constexpr std::array<double, kArmJoints> kArmJointLimit{2.967, 2.094, 2.967, 2.094, 2.967, 2.094, 2.967};

/// What the arm's side says each cycle about the arm (port robot_state of the
/// FRI bridge and of the simulated arm, the same meaning on both): the KRC's
/// mode and link quality, whether the arm follows pose commands now, and the
/// measured joint positions.
struct RobotState {
  double time_s = 0.0;              ///< when the state was measured (s), the servo's time base
  RobotMode mode = RobotMode::Off;  ///< the KRC's interface state
  int quality = 0;                  ///< FRI link quality: 0 unacceptable, 1 bad, 2 ok, 3 perfect
  bool power_on = false;            ///< the drives are powered
  bool cartesian_impedance = false; ///< the KRC runs the Cartesian impedance strategy
  /// The KRC agrees with the bridge's configuration (fri.yaml): cycle time,
  /// the KRC's UDP port, control mode. False: the bridge does not command.
  bool config_ok = true;
  /// Bring-up dry run: the bridge holds the arm whatever is asked; the servo
  /// computes and records its commands as if the arm followed.
  bool dry_run = false;
  /// The arm follows pose commands now: Command mode, drives on, quality >= ok,
  /// Cartesian impedance, config_ok, not dry_run.
  bool commandable = false;
  int link_status = 0;              ///< fri::BridgeStatus of the last packet (simulated arm: 0, commanding)
  /// The arm's set point {g}T{e}: where the KRC holds it outside command mode
  /// (FRI's cmdCartPos; the simulator: its held command). In a pressing
  /// contact it lies inside the object by force / stiffness, the measured
  /// pose does not: the servo holds this one, so the force is kept.
  Pose setpoint = kNoPose;
  std::array<double, kArmJoints> q{};  ///< measured joint positions (rad), A1..A7
};

/// Simulator ground truth (port `truth` of the simulated arm; never read by
/// the controller): what an ATI Nano17 under the sensor would measure plus
/// the world state the logs and the summary need.
struct SimTruth {
  double time_s = 0.0;              ///< simulated time of the state (s)
  std::array<double, 6> wrench_s{}; ///< contact wrench on the sensor, {s} about its origin (pressing: fz < 0)
  double layer_force = 0.0;         ///< N carried by the elastic layer
  double housing_force = 0.0;       ///< N carried by the rigid housing
  double tray_pitch = 0.0, tray_roll = 0.0;  ///< rad (scenes with a tray)
  std::array<double, 3> contact_point_g{};   ///< pressure centre of the last acquisition, {g} (m)
  bool in_contact = false;          ///< the last acquisition had layer force > 0
  Pose sensor_pose;                 ///< {g}T{s}
  int sim_status = 0;               ///< tactile::sim::SimStatus of the last step
};

const char* toString(ContactType t);
const char* toString(FeatureStatus s);
const char* toString(ServoStatus s);
const char* toString(RobotMode m);
/// What a servo status means for the operator, in one sentence (for the
/// deployer's state machines and tactile_sim's report; never on a cycle).
const char* explain(ServoStatus s);

}  // namespace tactile
