// tactile::Component (tactile_types_rtt/component.hpp): what configureHook()
// and startHook() write in the calling thread is seen by updateHook() in the
// activity's own thread, and what updateHook() writes is seen by the caller
// after stop(). The data here are plain (non-atomic) members, as in the real
// components (a configured core, a loaded scene).
//
// In a plain build this checks the values. Under ThreadSanitizer
// (scripts/realtime/sanitize.sh tsan) it also checks the ordering: without the edge
// that tactile::Component adds, RTT 2.10 publishes the task state through a
// plain enum and every cycle below is a reported data race, which fails the
// test (TSAN_OPTIONS exitcode). Checked by hand: with Component's acquire()
// and release() emptied, this test failed under TSan (exit 66: a race on
// `value`, read by updateHook()); with them, 0 reports.
#include <gtest/gtest.h>

#include <rtt/Activity.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

#include "tactile_types_rtt/component.hpp"

namespace {

class Probe : public tactile::Component {
 public:
  Probe() : tactile::Component("probe", PreOperational) {}

  int value = 0;                   // set by the test before configure()
  std::array<double, 32> table{};  // written by configureHook(), read by updateHook()
  double offset = 0.0;             // written by startHook()
  long updates = 0;                // written by updateHook(), read after stop()
  long wrong = 0;                  // updates that saw another table or offset
  std::atomic<long> progress{0};   // for the test's wait only

 protected:
  bool configureHook() override {
    for (std::size_t k = 0; k < table.size(); ++k) table[k] = value + 0.5 * static_cast<double>(k);
    return true;
  }
  bool startHook() override {
    offset = 2.0 * value;
    updates = 0;
    wrong = 0;
    return true;
  }
  void updateHook() override {
    const HookScope hook(*this);
    for (std::size_t k = 0; k < table.size(); ++k)
      if (table[k] != value + 0.5 * static_cast<double>(k) || offset != 2.0 * value) {
        ++wrong;
        break;
      }
    ++updates;
    progress.fetch_add(1, std::memory_order_relaxed);
  }
};

TEST(ComponentOrder, HooksInTheCallersThreadAndUpdatesInTheActivitysSeeEachOther) {
  Probe p;
  // A periodic activity: its own thread, running from here on (RTT runs the
  // engine whatever the task state; updateHook() only when Running).
  ASSERT_TRUE(p.setActivity(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.001, nullptr, "probe")));
  for (int cycle = 1; cycle <= 10; ++cycle) {
    p.value = cycle;
    ASSERT_TRUE(p.configure());
    const long before = p.progress.load();
    ASSERT_TRUE(p.start());
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (p.progress.load() < before + 5 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(p.stop());
    ASSERT_TRUE(p.cleanup());
    EXPECT_GE(p.updates, 5) << "cycle " << cycle;  // read after stop(): the activity's writes
    EXPECT_EQ(p.wrong, 0) << "cycle " << cycle << ": an update saw another cycle's configuration";
  }
}

}  // namespace
