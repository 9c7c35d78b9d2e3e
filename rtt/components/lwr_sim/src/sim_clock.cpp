#include "tactile_sim_rtt/sim_clock.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Activity.hpp>
#include <rtt/Logger.hpp>
#include <rtt/base/DisposableInterface.hpp>
#include <rtt/base/AttributeBase.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/fosi.h>

#include <algorithm>
#include <cmath>

#include "tactile_sim_runner/scene.hpp"

namespace tactile {

SimClock::SimClock(const std::string& name) : Component(name, PreOperational) {
  addProperty("scene_file", scene_file_)
      .doc("Scene YAML (params/scenes/*.yaml): rates (Table 2) and duration of the run; the stages load the same file.");
  addProperty("realtime_factor", realtime_factor_)
      .doc("Simulated seconds per wall-clock second: 0 = as fast as possible (default), else in (0, 100].");
  addProperty("robot", robot_name_).doc("Peer name of the simulated arm (tactile::LwrSimComponent), a slave of this clock.");
  addProperty("sensor", sensor_name_).doc("Peer name of the simulated sensor (tactile::WtsSimComponent), a slave.");
  addProperty("features", features_name_).doc("Peer name of tactile::FeatureComponent, a slave.");
  addProperty("servo", servo_name_).doc("Peer name of tactile::ServoComponent, a slave.");
  addProperty("reporter", reporter_name_)
      .doc("Optional peer executed right after each servo cycle (a logger, e.g. OCL::FileReporting, a slave of "
           "this clock), so that it samples every cycle at simulated time; '' = none.");
  addAtomicAttribute(*provides(), "sim_time", sim_time_);
  addAtomicAttribute(*provides(), "ticks", ticks_);
  addAtomicAttribute(*provides(), "finished", finished_);
  addAttribute("status", status_);
  addAtomicAttribute(*provides(), "exit_code", exit_code_);
  addOperation("lastError", &SimClock::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
}

namespace {
RTT::internal::DataSource<int>::shared_ptr intAttribute(RTT::TaskContext* tc, const std::string& name) {
  RTT::base::AttributeBase* a = tc->provides()->getAttribute(name);
  if (!a) return {};
  return RTT::internal::DataSource<int>::narrow(a->getDataSource().get());
}
}  // namespace

bool SimClock::configureHook() {
  if (detached_ != nullptr) {  // after cleanup(): the thread back on the engine
    detached_->run(engine());
    detached_->start();
    detached_ = nullptr;
  }
  sim::Scene scene;
  ConfigResult r = scene_file_.empty() ? ConfigResult::failure("scene_file is empty: set it to a scene YAML (params/scenes/*.yaml)")
                                       : sim::loadScene(scene_file_, scene);
  if (r) {
    r = schedule_.configure(scene.rates, scene.duration);
    if (!r) r = ConfigResult::failure(scene_file_ + ": " + r.message());
  }
  if (r && !(realtime_factor_ >= 0.0 && realtime_factor_ <= 100.0))
    r = rangeError("realtime_factor", realtime_factor_, "must be in [0, 100] (0: as fast as possible)");
  struct Stage {
    const std::string& name;
    RTT::TaskContext** tc;
  };
  for (const Stage& s : {Stage{robot_name_, &robot_}, Stage{sensor_name_, &sensor_}, Stage{features_name_, &features_},
                         Stage{servo_name_, &servo_}}) {
    if (!r) break;
    *s.tc = getPeer(s.name);
    if (!*s.tc) {
      r = ConfigResult::failure("no peer '" + s.name + "': make it a slave of " + getName() +
                                " (setMasterSlaveActivity(\"" + getName() + "\", \"" + s.name + "\"))");
    } else if (!dynamic_cast<RTT::extras::SlaveActivity*>((*s.tc)->getActivity())) {
      r = ConfigResult::failure("peer '" + s.name + "' must run on a SlaveActivity of " + getName() +
                                " (setMasterSlaveActivity): the clock executes it");
    }
  }
  reporter_ = nullptr;
  if (r && !reporter_name_.empty()) {
    reporter_ = getPeer(reporter_name_);
    if (!reporter_ || !dynamic_cast<RTT::extras::SlaveActivity*>(reporter_->getActivity()))
      r = ConfigResult::failure("reporter '" + reporter_name_ + "' must be a peer on a SlaveActivity of " + getName() +
                                " (setMasterSlaveActivity(\"" + getName() + "\", \"" + reporter_name_ + "\"))");
  }
  if (r) {
    servo_status_ = intAttribute(servo_, "last_status");
    sim_status_ = intAttribute(robot_, "sim_status");
    if (!servo_status_) r = ConfigResult::failure("peer '" + servo_name_ + "' has no int attribute last_status (tactile::ServoComponent)");
    else if (!sim_status_) r = ConfigResult::failure("peer '" + robot_name_ + "' has no int attribute sim_status (tactile::LwrSimComponent)");
  }
  if (!verdict(r, last_error_)) return false;
  end_.configure(scene.rates);
  // With a WTS transfer delay the sensor delivers frames between acquisitions:
  // it runs every tick (it acquires only on new taxel forces).
  sensor_every_tick_ = scene.sensor_effects.wts_transfer_delay_s > 0.0;
  return true;
}

void SimClock::setTime(int64_t t_ns) {
  // Simulated time: the TimeService reads t_i = i * period_ns (its seconds are double(ns) / 1e9).
  RTT::os::TimeService* ts = RTT::os::TimeService::Instance();
  ts->ticksChange(RTT::os::TimeService::nsecs2ticks(t_ns) - ts->getTicks());
}

bool SimClock::startHook() {
  schedule_.reset();
  end_.reset();
  record(ticks_, 0);
  record(finished_, false);
  status_ = "running";
  record(exit_code_, 0);
  RTT::os::TimeService::Instance()->enableSystemClock(false);
  setTime(0);
  record(sim_time_, schedule_.time());
  wall_start_ns_ = rtos_get_time_ns();
  return true;
}

void SimClock::finish(sim::EndReason reason, sim::SimStatus st) {
  sim::Summary s;
  sim::applyEnd(reason, st, s);
  status_ = s.status;
  record(exit_code_, s.exit_code);
  record(finished_, true);  // after status_ (release)
}

bool SimClock::tick() {
  if (schedule_.finished()) {
    record(sim_time_, schedule_.time());  // the runner's end time: after the last physics step
    finish(sim::EndReason::Duration, sim::SimStatus::Ok);
    return false;
  }
  const double t = schedule_.time();
  setTime(static_cast<int64_t>(schedule_.tick()) * schedule_.periodNs());
  record(sim_time_, t);
  const sim::StageFires f = schedule_.fires();
  if (f.wts || sensor_every_tick_) sensor_->update();
  if (f.features) features_->update();
  if (f.servo) {
    servo_->update();
    if (reporter_) reporter_->update();  // samples this cycle's ports
    const ServoStatus st = static_cast<ServoStatus>(servo_status_->get());
    const sim::EndReason e = end_.afterServo(st);
    if (e != sim::EndReason::None) {
      // A latched stop (a watchdog, the force ceiling): one more servo cycle,
      // one servo period later, as the servo's own activity would run on the
      // arm, so that the experiment's state machine (it runs before the
      // servo's updateHook) sees the latched status and reports it. The arm,
      // the sensor and the reporter do not step: the record ends where the
      // runner's does.
      if (st != ServoStatus::Done) {
        setTime(static_cast<int64_t>(schedule_.tick()) * schedule_.periodNs() +
                static_cast<int64_t>(std::llround(1e9 / schedule_.rates().servo)));
        servo_->update();
      }
      finish(e, sim::SimStatus::Ok);
      return false;
    }
  }
  robot_->update();
  schedule_.advance();
  bump(ticks_);
  const sim::SimStatus ss = static_cast<sim::SimStatus>(sim_status_->get());
  const sim::EndReason e = end_.afterPhysics(ss);
  if (e != sim::EndReason::None) {
    record(sim_time_, schedule_.time());  // after the fatal physics step, as the runner's
    finish(e, ss);
    return false;
  }
  return true;
}

namespace {
/// A message that only marks that the engine's queue was run up to it.
class QueueMarker : public RTT::base::DisposableInterface {
 public:
  void executeAndDispose() override { done_.store(true, std::memory_order_release); }
  void dispose() override {}
  bool done() const { return done_.load(std::memory_order_acquire); }

 private:
  std::atomic<bool> done_{false};
};

/// Returns when the engine's thread has run the messages queued before the
/// call (true); false when the queue is full or after 2 s (then the marker
/// is left to the engine, whose dispose() of it does nothing).
bool runQueued(RTT::ExecutionEngine& ee) {
  auto* marker = new QueueMarker;  // cleanup only, not a per-tick path
  if (!ee.process(marker)) {  // not queued (the queue is full)
    delete marker;
    return false;
  }
  TIME_SPEC ms = ticks2timespec(nano2ticks(1000000LL));
  for (int i = 0; i < 2000 && !marker->done(); ++i) rtos_nanosleep(&ms, nullptr);
  if (!marker->done()) return false;
  delete marker;
  return true;
}
}  // namespace

void SimClock::cleanupHook() {
  RTT::base::ActivityInterface* a = getActivity();
  if (dynamic_cast<RTT::Activity*>(a) == nullptr || !a->isActive() || a->thread()->isSelf()) return;
  if (!runQueued(*engine()))  // what the slaves queued, run while they all exist
    RTT::log(RTT::Warning) << getName() << ": its thread did not run its queued messages (queue full, or not within 2 s)" << RTT::endlog();
  a->stop();
  a->run(nullptr);  // the engine without an activity: nothing more is queued (SlaveActivity::trigger)
  detached_ = a;
}

void SimClock::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  if (finished_.load(std::memory_order_acquire)) return;
  for (int k = 0; k < kTicksPerUpdate; ++k) {
    if (realtime_factor_ > 0.0) {
      // Not ahead of the wall clock: t_i <= r * elapsed.
      const double elapsed = 1e-9 * static_cast<double>(rtos_get_time_ns() - wall_start_ns_);
      const double ahead = schedule_.time() / realtime_factor_ - elapsed;
      if (ahead > 0.0) {
        TIME_SPEC ts = ticks2timespec(nano2ticks(static_cast<long long>(std::min(ahead, 0.01) * 1e9)));
        rtos_nanosleep(&ts, nullptr);
        break;  // re-check after the trigger
      }
    }
    if (!tick()) return;
  }
  this->trigger();
}

}  // namespace tactile
