// tactile::Component: RTT::TaskContext with a happens-before edge between the
// hooks that run in the caller's thread and updateHook() in the activity's.
//
// Why (RTT 2.10's task state is a plain enum; nothing orders the hooks'
// writes in the caller's thread before updateHook()'s reads): docs/design.md.
//
// What: configure(), start(), stop() and cleanup() acquire before and release
// after RTT's own; a component's updateHook() opens with `const HookScope
// hook(*this);`, which acquires on entry and releases on exit. The edge is one
// atomic counter per component: an uncontended load and add per update, no
// lock, no allocation (real-time safe). It adds an ordering, never a wait: a
// hook cannot block another through it.
#pragma once

#include <atomic>
#include <string>

#include <rtt/TaskContext.hpp>
#include <rtt/base/ActivityInterface.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/MainThread.hpp>

#include "tactile_types/config_result.hpp"

namespace tactile {

class Component : public RTT::TaskContext {
 public:
  explicit Component(const std::string& name, TaskState initial_state = Stopped)
      : RTT::TaskContext(name, initial_state) {}

  bool configure() override { return ordered([this] { return RTT::TaskContext::configure(); }); }
  bool start() override {
    executed_by_master_.store(hasMaster(), std::memory_order_relaxed);
    return ordered([this] { return RTT::TaskContext::start(); });
  }
  bool stop() override { return ordered([this] { return RTT::TaskContext::stop(); }); }
  bool cleanup() override { return ordered([this] { return RTT::TaskContext::cleanup(); }); }

 protected:
  /// A configuring hook's verdict on `r`: a failure's message goes to
  /// `last_error` (the component's lastError()) and to the log, and it is
  /// false; a success clears `last_error`. Hooks outside updateHook() only
  /// (it logs).
  bool verdict(const ConfigResult& r, std::string& last_error) const {
    if (r) {
      last_error.clear();
      return true;
    }
    last_error = r.message();
    RTT::log(RTT::Error) << getName() << ": " << last_error << RTT::endlog();
    return false;
  }

  /// Every derived destructor's first statement (after its own stop(), if any):
  /// stops the activity while the derived members (ports, cores)
  /// still exist. RTT stops a component's activity only in ~TaskContext,
  /// after the derived destructors ("Ports are probably already destructed
  /// by user code"), so a port callback queued at unload (a writer
  /// disconnecting from an event port) could otherwise run on destroyed ports.
  void haltActivity() noexcept {
    if (RTT::base::ActivityInterface* a = getActivity()) a->stop();
  }

  /// New data on an event port triggers a running component, except one that
  /// a master executes (a slave of tactile::SimClock, which runs it on the
  /// scene's schedule): there RTT's SlaveActivity::trigger would queue one
  /// message per write on the master's engine, more than its queue holds
  /// (100) within one of the clock's updates, for nothing the master needs.
  /// Runs in the writer's thread: one atomic load.
  bool dataOnPortHook(RTT::base::PortInterface* port) override {
    return !executed_by_master_.load(std::memory_order_relaxed) && RTT::TaskContext::dataOnPortHook(port);
  }

  /// updateHook()'s first statement: sees what the other hooks wrote; what
  /// this update writes is seen by the next stop()/cleanup()/configure().
  class HookScope {
   public:
    explicit HookScope(const Component& c) noexcept : c_(c) { c_.acquire(); }
    ~HookScope() { c_.release(); }
    HookScope(const HookScope&) = delete;
    HookScope& operator=(const HookScope&) = delete;

   private:
    const Component& c_;
  };

 private:
  void acquire() const noexcept { (void)gen_.load(std::memory_order_acquire); }
  void release() const noexcept { gen_.fetch_add(1, std::memory_order_release); }
  template <class F>
  bool ordered(F&& f) {
    acquire();
    const bool ok = f();
    release();
    return ok;
  }

  /// A SlaveActivity with a master (its thread is the master's, not the main thread).
  bool hasMaster() {
    auto* slave = dynamic_cast<RTT::extras::SlaveActivity*>(getActivity());
    return slave != nullptr && slave->thread() != RTT::os::MainThread::Instance();
  }

  mutable std::atomic<unsigned> gen_{0};
  std::atomic<bool> executed_by_master_{false};  ///< set by start()
};

}  // namespace tactile
