// tactile::RealtimeCheck: the real-time set-up of a deployment, checked and
// reported before its loops start.
//
//  * configure(): locks the process's memory (mlockall(MCL_CURRENT |
//    MCL_FUTURE)) when lock_memory is set, so no page fault delays a cycle
//    later. Refused (no CAP_IPC_LOCK and a small `ulimit -l`): a warning
//    naming the limit, memory_locked false; the deployment goes on.
//  * check(), and start() (XML deployments: listed after the components, it
//    starts once every activity is attached): for each "Name:priority" of
//    `expected`, the scheduler and priority the peer's activity thread really
//    runs with. RTT lowers a refused ORO_SCHED_RT to SCHED_OTHER priority 0
//    (its log: "Lowering scheduler type to SCHED_OTHER for non-privileged
//    users"); this check then logs, per activity, one warning saying so and
//    how to grant the rights, and counts it in `fallbacks`. The deployment
//    goes on (best effort) unless require_realtime is set.
//  * check() also reads kernel.sched_autogroup_enabled. The sensor's bytes
//    (USB-serial or PTY) reach the Sensor thread through a SCHED_OTHER kernel
//    worker (the tty's flip-buffer work); with autogroup on, a CPU-bound load
//    held that worker off its CPU for seconds (docs/realtime.md, "The
//    sensor's tty under CPU load"). On: one warning naming the setting and
//    scripts/setup/realtime_host.sh; a failure with require_realtime.
//
// Interface (documented with .doc() in the constructor):
//   property lock_memory (bool)      mlockall at configure (default true)
//   property scheduler (string)      ORO_SCHED_RT or ORO_SCHED_OTHER: what every expected activity asked for
//   property expected (string)       "Robot:90 Servo:80 ...": peers and the priorities they asked for
//   property require_realtime (bool) a fallback or autogroup on fails check() (default false: warn and go on)
//   property autogroup_path (string) where the autogroup setting is read (default /proc/sys/kernel/sched_autogroup_enabled)
//   attr memory_locked (bool), memory_lock_skipped (bool: sanitizer build), realtime (bool: every activity as asked), rt_permitted (bool: RTT's
//        own verdict on the scheduler for this process), fallbacks (int), report (string),
//        autogroup (int: 1 on, 0 off, -1 unreadable)
//   op   bool check(), string actual(string name) ("SCHED_FIFO 90", "SCHED_OTHER 0", "none")
//
// Not on any real-time path: the deployer's thread calls it while setting up.
#include <rtt/Activity.hpp>
#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/base/ActivityInterface.hpp>
#include <rtt/os/ThreadInterface.hpp>
#include <rtt/os/threads.hpp>

#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TACTILE_SANITIZED_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TACTILE_SANITIZED_BUILD 1
#endif
#endif

namespace tactile {

class RealtimeCheck : public RTT::TaskContext {
 public:
  explicit RealtimeCheck(const std::string& name) : RTT::TaskContext(name) {
    addProperty("lock_memory", lock_memory_)
        .doc("Lock the process's memory (mlockall MCL_CURRENT | MCL_FUTURE) in configure(), before the loops start.");
    addProperty("scheduler", scheduler_)
        .doc("Scheduler every expected activity asked for: ORO_SCHED_RT (SCHED_FIFO) or ORO_SCHED_OTHER.");
    addProperty("expected", expected_)
        .doc("Space-separated Name:priority of the peers to check, e.g. \"Robot:90 Servo:80 Features:70 Sensor:60\".");
    addProperty("require_realtime", require_realtime_)
        .doc("When true, an activity that runs below what it asked for fails check() (and start()); "
             "when false (default) it is a warning and the deployment goes on best effort. The same "
             "for kernel.sched_autogroup_enabled = 1.");
    addProperty("autogroup_path", autogroup_path_)
        .doc("File holding kernel.sched_autogroup_enabled, read by check(); 1 is a warning (the sensor's tty "
             "worker can be starved by a CPU-bound load).");
    addAttribute("memory_locked", memory_locked_);
    addAttribute("memory_lock_skipped", memory_lock_skipped_);
    addAttribute("realtime", realtime_);
    addAttribute("rt_permitted", rt_permitted_);
    addAttribute("fallbacks", fallbacks_);
    addAttribute("report", report_);
    addAttribute("autogroup", autogroup_);
    addOperation("check", &RealtimeCheck::check, this, RTT::ClientThread)
        .doc("Checks each expected peer's activity (scheduler, priority, CPU affinity), logs one line each "
             "(a warning for a fallback) and fills realtime, fallbacks, report; reads autogroup (a warning "
             "when on). False when a peer or its thread is missing, or on a fallback or autogroup on with "
             "require_realtime.");
    addOperation("actual", &RealtimeCheck::actual, this, RTT::ClientThread)
        .doc("Scheduler and priority the peer's activity thread runs with: \"SCHED_FIFO 90\", "
             "\"SCHED_OTHER 0\", or \"none\" (no such peer, or no thread).")
        .arg("name", "Peer name.");
  }

  bool configureHook() override {
    memory_locked_ = false;
    if (!lock_memory_) return true;
#ifdef TACTILE_SANITIZED_BUILD
    // ASan/TSan reserve terabytes of shadow memory: locking it all would
    // exhaust RAM. Sanitizer builds test correctness, not timing.
    memory_lock_skipped_ = true;
    RTT::log(RTT::Info) << getName() << ": memory not locked: sanitizer build (mlockall skipped)" << RTT::endlog();
#else
    if (::mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      memory_locked_ = true;
      RTT::log(RTT::Info) << getName() << ": memory locked (mlockall MCL_CURRENT | MCL_FUTURE)" << RTT::endlog();
    } else {
      const int err = errno;
      rlimit r{};
      ::getrlimit(RLIMIT_MEMLOCK, &r);
      RTT::log(RTT::Warning) << getName() << ": memory NOT locked: mlockall failed: " << std::strerror(err)
                             << " (RLIMIT_MEMLOCK " << static_cast<long long>(r.rlim_cur)
                             << " bytes; grant CAP_IPC_LOCK or `ulimit -l unlimited`): page faults may delay cycles"
                             << RTT::endlog();
    }
#endif
    return true;
  }

  bool startHook() override { return check(); }

  std::string actual(const std::string& name) {
    RTT::os::ThreadInterface* t = threadOf(name);
    if (!t) return "none";
    return schedName(t->getScheduler()) + " " + std::to_string(t->getPriority());
  }

  bool check() {
    int want = 0;
    if (scheduler_ == "ORO_SCHED_RT") {
      want = ORO_SCHED_RT;
    } else if (scheduler_ == "ORO_SCHED_OTHER") {
      want = ORO_SCHED_OTHER;
    } else {
      RTT::log(RTT::Error) << getName() << ": scheduler = '" << scheduler_
                           << "': must be ORO_SCHED_RT or ORO_SCHED_OTHER" << RTT::endlog();
      return false;
    }
    int probe = want;
    rt_permitted_ = RTT::os::CheckScheduler(probe);  // RTT's own rule (root, CAP_SYS_NICE or rtprio limit)
    fallbacks_ = 0;
    realtime_ = true;
    bool ok = true;
    std::ostringstream rep;
    std::istringstream in(expected_);
    std::string item;
    int n = 0;
    while (in >> item) {
      ++n;
      const std::size_t colon = item.find(':');
      const std::string name = item.substr(0, colon);
      int prio = 0;
      if (colon == std::string::npos || !parseInt(item.substr(colon + 1), prio)) {
        RTT::log(RTT::Error) << getName() << ": expected entry '" << item << "': must be Name:priority"
                             << RTT::endlog();
        ok = false;
        continue;
      }
      RTT::os::ThreadInterface* t = threadOf(name);
      if (!t) {
        RTT::log(RTT::Error) << getName() << ": " << name << ": no such peer, or its activity has no thread"
                             << RTT::endlog();
        rep << name << " none; ";
        ok = false;
        realtime_ = false;
        continue;
      }
      const int sched = t->getScheduler();
      const int got = t->getPriority();
      const unsigned cpus = t->getCpuAffinity();
      rep << name << " " << schedName(sched) << " " << got << "; ";
      if (sched == want && (want == ORO_SCHED_OTHER || got == prio)) {
        RTT::log(RTT::Info) << getName() << ": " << name << ": " << schedName(sched) << " priority " << got
                            << " (asked " << scheduler_ << " " << prio << "), CPU mask 0x" << std::hex << cpus
                            << std::dec << RTT::endlog();
        continue;
      }
      realtime_ = false;
      ++fallbacks_;
      if (sched == want) {  // the scheduler as asked, another priority: set elsewhere (not RTT's fallback)
        RTT::log(RTT::Warning) << getName() << ": " << name << ": expected priority " << prio << ", runs "
                               << schedName(sched) << " priority " << got << ": the deployment sets another one"
                               << RTT::endlog();
        if (require_realtime_) ok = false;
        continue;
      }
      RTT::log(RTT::Warning) << getName() << ": " << name << ": asked " << scheduler_ << " priority " << prio
                             << ", runs " << schedName(sched) << " priority " << got
                             << ": no real-time rights for this process (run as root, grant CAP_SYS_NICE, or "
                                "an rtprio limit: `ulimit -r 99`, /etc/security/limits.conf); its cycles are "
                                "best effort, not time-guaranteed"
                             << RTT::endlog();
      if (require_realtime_) ok = false;
    }
    if (n == 0) {
      RTT::log(RTT::Error) << getName() << ": expected is empty: nothing to check" << RTT::endlog();
      ok = false;
    }
    report_ = rep.str();
    return checkAutogroup() && ok;
  }

 private:
  /// kernel.sched_autogroup_enabled into autogroup_; false when on and require_realtime.
  bool checkAutogroup() {
    std::ifstream f(autogroup_path_);
    int v = -1;
    if (!(f >> v) || (v != 0 && v != 1)) v = -1;
    autogroup_ = v;
    if (v == -1) {
      RTT::log(RTT::Info) << getName() << ": " << autogroup_path_ << ": unreadable (a kernel without autogroup)"
                          << RTT::endlog();
      return true;
    }
    if (v == 0) return true;
    RTT::log(RTT::Warning) << getName() << ": kernel.sched_autogroup_enabled = 1 (" << autogroup_path_
                           << "): the sensor's bytes reach the Sensor thread through a SCHED_OTHER kernel "
                              "worker, which a CPU-bound load can hold off for seconds while autogroup is on; set it "
                              "to 0 (scripts/setup/realtime_host.sh, or `sysctl kernel.sched_autogroup_enabled=0`)"
                           << RTT::endlog();
    return !require_realtime_;
  }
  static bool parseInt(const std::string& s, int& v) {
    if (s.empty() || s.size() > 3) return false;
    v = 0;
    for (char c : s) {
      if (c < '0' || c > '9') return false;
      v = 10 * v + (c - '0');
    }
    return true;
  }
  static std::string schedName(int s) {
    if (s == SCHED_FIFO) return "SCHED_FIFO";
    if (s == SCHED_RR) return "SCHED_RR";
    if (s == SCHED_OTHER) return "SCHED_OTHER";
    return "scheduler" + std::to_string(s);
  }
  RTT::os::ThreadInterface* threadOf(const std::string& name) {
    RTT::TaskContext* peer = getPeer(name);
    if (!peer || !peer->getActivity()) return nullptr;
    return peer->getActivity()->thread();
  }

  bool lock_memory_ = true;
  std::string scheduler_ = "ORO_SCHED_RT";
  std::string expected_;
  bool require_realtime_ = false;
  bool memory_locked_ = false;
  bool memory_lock_skipped_ = false;  // sanitizer build: mlockall deliberately not called
  bool realtime_ = false;
  bool rt_permitted_ = false;
  int fallbacks_ = 0;
  std::string report_;
  std::string autogroup_path_ = "/proc/sys/kernel/sched_autogroup_enabled";
  int autogroup_ = -1;
};

}  // namespace tactile

ORO_LIST_COMPONENT_TYPE(tactile::RealtimeCheck)
