// tactile::SimClock: the deterministic scheduler of the RTT sim deployment.
// Its activity executes the loop's components, which run as its slaves
// (deployer: setMasterSlaveActivity("Clock", name)), tick by tick in pipeline
// order at the scene's rates, with the headless runner's schedule and end
// rule (tactile::sim::Schedule, tactile::sim::EndRule): on physics tick i
//   RTT's TimeService := t_i (simulated time; the system clock is disabled)
//   Sensor.update()    if the WTS acquisition fires (every tick with the scene's
//                      effects.wts_transfer_delay_s > 0: frames arrive between acquisitions)
//   Features.update()  if feature extraction fires
//   Servo.update()     if the servo fires; end at its force ceiling or a
//                      watchdog / 1 s after Done
//   Robot.update()     every tick (physics); end at a fatal simulator status
// until the scene's duration or the end rule. After a latched stop (the force
// ceiling, a watchdog) the servo runs one more cycle, a servo period later
// and unrecorded (the arm, the sensor and the reporter do not step): on the
// arm its activity keeps running, and the experiment's state machine, which
// runs before the servo's updateHook, sees the latched status only then. So the deployment runs the same
// loop as `tactile_sim run` (same stages, same schedule, same seed): the same
// pose command on every servo cycle.
//
// Interface (documented with .doc() in the constructor):
//   property scene_file (string)        the scene (rates, duration); the components load the same file
//   property realtime_factor (double)   0 = as fast as possible; r > 0: r x wall-clock speed
//   property robot, sensor, features, servo (string)  peer names of the stages
//                                       (defaults Robot, Sensor, Features, Servo)
//   property reporter (string)          optional peer executed right after each servo cycle
//                                       (a logger such as OCL::FileReporting, a slave too); '' = none
//   attr sim_time (double)   simulated time of the current tick (s); at the end, the
//                            runner's end time (summary.json sim_time_s)
//   attr ticks (int)         physics ticks executed since start
//   attr finished (bool)     the run ended (duration or end rule); the clock then idles
//   attr status (string)     "running", then summary.json's status ("ok", "servo_force_ceiling", "sim_...")
//   attr exit_code (int)     tactile_sim's exit code for that status (0, 3-8)
//   op   string lastError()
//
// Execution: a non-periodic activity (setActivity("Clock", 0, ...)); each
// update runs up to kTicksPerUpdate ticks and triggers the next one. Between
// two updates the clock's engine runs its queued messages, and a slave with
// event ports (the reporter, OCL::FileReporting) queues one trigger message
// there per sample written to it (RTT's SlaveActivity::trigger): about two
// per tick. RTT's engine queue holds 100; an update that overfills it left
// messages that the engine never ran again, and the deployer crashed when it
// unloaded the slaves. 10 ticks stay far below (test_sim_loop.cpp). The slaves must be
// started before the clock. start() resets the schedule, disables the
// system clock of RTT's TimeService and sets it to t = 0. Per tick: no heap
// allocation.
//
// Teardown: the slaves reach this clock's thread through RTT's SlaveActivity
// (a trigger queues a message that points into the slave's activity on the
// clock's engine; a timeout wakes the clock's thread, which then runs the
// slaves' queued messages). The deployer unloads the slaves before the clock,
// and unloading the servo's state machine runs it once more, so the clock's
// thread could still be at work in a slave being destroyed, or a message
// could outlive its slave. cleanup() therefore waits until the clock's
// thread has run what is queued (the slaves all still exist; a marker
// message, up to 2 s), stops that thread and detaches it from the clock's
// engine: a slave's trigger then queues nothing and wakes nobody.
// configure() attaches it again.
#pragma once

#include <rtt/TaskContext.hpp>

#include "tactile_types_rtt/component.hpp"
#include <rtt/internal/DataSource.hpp>

#include <atomic>
#include <string>

#include "tactile_sim_runner/loop.hpp"

namespace tactile {

class SimClock : public Component {
 public:
  /// Physics ticks per update (see "Execution" above).
  static constexpr int kTicksPerUpdate = 10;

  explicit SimClock(const std::string& name);
  ~SimClock() override { haltActivity(); }  // stops its thread while its ports exist (component.hpp)

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;
  void cleanupHook() override;

  std::string lastError() const { return last_error_; }

 private:
  /// One physics tick; false when the run ended.
  bool tick();
  void finish(sim::EndReason reason, sim::SimStatus st);
  void setTime(int64_t t_ns);

  std::string scene_file_;
  double realtime_factor_ = 0.0;
  std::string robot_name_ = "Robot", sensor_name_ = "Sensor", features_name_ = "Features", servo_name_ = "Servo";
  std::string reporter_name_;
  // The run's record, read by any thread (atomic_attribute.hpp). `status_`
  // is written by startHook() (before the activity runs) and by finish()
  // before `finished_` is stored (release): a reader that saw `finished`
  // true (acquire) reads the final status; the deployment scripts read it
  // only then.
  std::atomic<double> sim_time_{0.0};
  std::atomic<int> ticks_{0};
  std::atomic<bool> finished_{false};
  std::string status_ = "running";
  std::atomic<int> exit_code_{0};
  std::string last_error_;

  sim::Schedule schedule_;
  sim::EndRule end_;
  RTT::TaskContext* robot_ = nullptr;
  RTT::TaskContext* sensor_ = nullptr;
  bool sensor_every_tick_ = false;  ///< the scene's WTS transfer delay > 0
  RTT::TaskContext* features_ = nullptr;
  RTT::TaskContext* servo_ = nullptr;
  RTT::TaskContext* reporter_ = nullptr;
  RTT::internal::DataSource<int>::shared_ptr servo_status_, sim_status_;
  int64_t wall_start_ns_ = 0;
  /// The clock's own thread while cleanup() has detached it from the engine
  /// (owned by the TaskContext all along); configure() attaches it again.
  RTT::base::ActivityInterface* detached_ = nullptr;
};

}  // namespace tactile
