// The loop's shared rules, used unchanged by the headless runner
// (tactile_sim run) and by the RTT sim deployment (tactile::SimClock and the
// simulated arm), so that both ARE the same loop:
//
//  * Schedule: which stages fire on physics tick i, from the scene's rates
//    (Table 2: physics 1 kHz, WTS 140 Hz, features 200 Hz, servo 100 Hz).
//    Per tick, in pipeline order: WTS acquisition (sensor), feature
//    extraction on the latest raw frame, servo on the latest features, then
//    one physics step of the arm toward the latest command. A stage fires
//    when t_i + dt/4 >= its next event time, which then advances by its
//    period (no drift; exact rates when they divide the physics rate,
//    otherwise the nearest tick). Time is an integer count of nanoseconds,
//    t_i = i * round(1e9 / rates.sim) ns, converted to seconds exactly as
//    RTT's TimeService does (double(ns) / 1e9): the clock component sets the
//    TimeService to it, the runner uses the same numbers.
//  * EndRule: a run ends at the servo's force ceiling (after that cycle,
//    before the physics step), one second (rates.servo cycles) after the
//    servo reports Done, at a fatal simulator status (after the physics
//    step), at a step the world refuses (SimStatus::StepRejected: its time
//    stands still, the arm would never move) or at commands it has refused
//    for 0.1 s running (InvalidCommand), or at the scene's duration. The
//    last three end with status "sim_<status>" and exit code 3, never "ok".
//  * Rows and the summary: makeRow() builds one servo-rate log row from what
//    the ports carry (features, pose command, phase, the simulator's
//    ground truth); computeSummary() computes summary.json's metrics from
//    the rows alone.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tactile_sim_runner/run_log.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

struct StageFires {
  bool wts = false;       ///< WTS acquisition (the sensor)
  bool features = false;  ///< feature extraction on the latest raw frame
  bool servo = false;     ///< tactile servo on the latest features
};

class Schedule {
 public:
  /// Validates the rates (> 0, <= rates.sim) and the duration (> 0 s).
  ConfigResult configure(const Rates& rates, double duration_s);
  /// Back to tick 0 (every stage fires on tick 0).
  void reset();

  long tick() const { return i_; }
  long ticks() const { return steps_; }           ///< round(duration * rates.sim)
  bool finished() const { return i_ >= steps_; }
  int64_t periodNs() const { return period_ns_; }
  double dt() const { return dt_; }               ///< physics step (s), 1 / rates.sim
  double time() const { return timeOf(i_); }      ///< t of the current tick (s)
  double timeOf(long i) const { return static_cast<double>(static_cast<int64_t>(i) * period_ns_) / 1e9; }
  const Rates& rates() const { return rates_; }

  /// The stages firing on the current tick (the physics step always does).
  StageFires fires() const;
  /// Commits the current tick's events and moves to the next tick.
  void advance();

 private:
  Rates rates_;
  long steps_ = 0;
  int64_t period_ns_ = 1000000;
  double dt_ = 0.001;
  long i_ = 0;
  double next_wts_ = 0, next_feat_ = 0, next_servo_ = 0;
};

enum class EndReason : uint8_t {
  None = 0,
  Duration,
  ServoForceCeiling,
  DoneHeld,
  SimFatal,
  SimRejected,         ///< the world refused its steps or commands
  ServoPhaseTimeout,   ///< the servo's watchdogs (tactile::watchdogStatus): never `ok`
  ServoArmStalled,
  ServoForceMismatch,
  ServoSurfaceTooCurved,    ///< the surface curves more tightly than the pad can follow (exit code 8)
  ServoPhantomContact,      ///< the taxels read a load the wrench does not carry (exit code 9)
  ServoUnseenLoad,          ///< the wrench carries a load no taxel sees (exit code 10)
  ServoCorrectionSaturated, ///< the force estimate's correction held at its limit (exit code 11)
  ServoCorrectionDrift      ///< the force estimate's correction kept moving: the wrench drifts (exit code 12)
};

class EndRule {
 public:
  void configure(const Rates& rates) {
    done_limit_ = static_cast<int>(rates.servo);
    invalid_limit_ = std::max(1, static_cast<int>(std::lround(0.1 * rates.sim)));
    unconverged_limit_ = invalid_limit_;
  }
  void reset() { done_cycles_ = invalid_cycles_ = unconverged_cycles_ = unconverged_total_ = 0; }
  /// After a servo cycle: ForceCeiling and the watchdog statuses
  /// (tactile::watchdogStatus) end the run at once; Done
  /// ends it after one more second (rates.servo cycles) of holding.
  EndReason afterServo(ServoStatus st);
  /// After a physics step: a fatal simulator status ends the run (SimFatal);
  /// so does a refused step (SimRejected: the world's time did not advance)
  /// and an invalid command refused on every step for 0.1 s (SimRejected);
  /// so does a quasi-static world that has not found its equilibrium
  /// (NotConverged) on every step for 0.1 s (SimFatal, status
  /// sim_not_converged): its state is then not the physics.
  EndReason afterPhysics(SimStatus st);
  /// Physics steps whose quasi-static solve did not converge, since reset().
  int unconvergedSteps() const { return unconverged_total_; }

 private:
  int done_limit_ = 100;
  int done_cycles_ = 0;
  int invalid_limit_ = 100;  ///< physics steps: 0.1 s
  int invalid_cycles_ = 0;
  int unconverged_limit_ = 100;  ///< physics steps: 0.1 s
  int unconverged_cycles_ = 0;
  int unconverged_total_ = 0;
};

/// summary.json's status and exit code for an end reason (sim_status: the
/// simulator's status when reason == SimFatal).
void applyEnd(EndReason reason, SimStatus sim_status, Summary& s);

/// The arm's estimated external wrench (port estimated_wrench of the
/// simulated arm, the servo's force-mismatch input): the contact wrench on
/// the sensor moved to the flange origin, {g} axes, stamped with the state's time.
void fillEstimatedWrench(const SimState& state, Wrench& out);

/// The arm's estimated external wrench with the scene's estimation error
/// (effects.wrench_error, scene.hpp): force (1 + scale) F + bias + drift
/// |p_flange - p_flange(0)| + noise, moments exact; then the scene's wrench
/// faults active at the state's time (`faults:`, tactile_sim_faults/sensor_faults.hpp:
/// wrench_bias, wrench_drift and pad_mass added in {g}, then wrench_frame's
/// axes and wrench_sign's sign on the whole wrench). The noise is a function
/// of (seed, the state's time) only and the faults of the time, so the
/// runner (servo rate) and the RTT arm (every physics step) publish the same
/// value at the same time. Without an error or a fault it is
/// fillEstimatedWrench(). fill() does not allocate.
class EstimatedWrench {
 public:
  /// `faults`: the scene's list (the pad's are ignored); errors as SensorFaultSchedule::configure's.
  ConfigResult configure(const WrenchErrorParams& p, uint64_t seed, const std::vector<FaultSpec>& faults = {});
  /// The flange's start position p_flange(0) (the drift's origin).
  void start(const SimState& initial);
  void fill(const SimState& state, Wrench& out) const;

 private:
  /// The wrench faults active at the state's time on out (its force and moment at the flange, {g}).
  void applyFaults(const SimState& st, Wrench& out) const;

  WrenchErrorParams p_;
  uint64_t seed_ = 0;
  KDL::Vector p0_ = KDL::Vector::Zero();
  SensorFaultSchedule faults_;
};

/// The simulator's ground truth port value: the state after a physics step
/// and the last acquisition's contact point.
void fillTruth(const SimState& state, const SensorTruth& last_acquisition, SimTruth& out);

/// One servo-rate row from the loop's signals. `u_s`/`beta` are for the
/// timeseries only (zero when not known).
LogRow makeRow(const Scene& scene, double t, int phase, ServoStatus status, const ContactFeatures& f,
               const Pose& command_flange, const SimTruth& truth, const Vec6& u_s = Vec6::Zero(), int beta = 0);

/// Phase entries (first row of each phase run) from the rows.
std::vector<PhaseEntry> phaseEntries(const Scene& scene, const std::vector<LogRow>& rows);

/// summary.json's metrics from out.rows and out.phases (and the scene): force
/// metrics, contact losses, alignment time, path, DZMP, tray. Leaves status,
/// exit code, times and FRI counters alone.
void computeSummary(const Scene& scene, RunResult& out);

/// summary.criteria_failed from the scene's metrics.criteria (computeSummary
/// calls it last; call again after changing the status or exit code).
void checkCriteria(const Scene& scene, Summary& summary);

}  // namespace sim
}  // namespace tactile
