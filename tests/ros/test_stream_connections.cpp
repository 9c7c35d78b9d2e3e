// The real-time side of deployments/ros_streams.ops: each streamed port gets
// one more connection, buffered and lock-free (type BUFFER, size 256,
// LOCK_FREE, as ros_cp there) to an event port of a component in its own
// non-real-time thread (tactile_ros::RosAdapter's place). Writing a sample
// must then neither allocate nor block, for every port type the adapter reads,
// with the reader running and with its buffer full (a full buffer drops).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <rtt/Activity.hpp>
#include <rtt/ConnPolicy.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/os/main.h>

#include "alloc_counter.hpp"
#include "tactile_types/types.hpp"

namespace {

RTT::ConnPolicy rosCp() {
  RTT::ConnPolicy cp = RTT::ConnPolicy::buffer(256);
  cp.lock_policy = RTT::ConnPolicy::LOCK_FREE;
  return cp;
}

template <class T>
class Reader : public RTT::TaskContext {
 public:
  Reader() : RTT::TaskContext("reader"), in_("in") { addEventPort(in_); }
  void updateHook() override {
    while (in_.read(sample_, false) == RTT::NewData) ++reads;
  }
  RTT::InputPort<T> in_;
  T sample_;
  std::atomic<int> reads{0};
};

template <class T>
void expectNoAllocation(bool reader_running) {
  RTT::OutputPort<T> out("out");
  RTT::InputPort<T> rt_in("rt_in");  // the real-time consumer (data connection, as cp in sim_loop.ops)
  Reader<T> reader;
  reader.setActivity(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0));
  T sample{};
  out.setDataSample(sample);
  ASSERT_TRUE(out.connectTo(&rt_in, RTT::ConnPolicy()));
  ASSERT_TRUE(out.connectTo(&reader.in_, rosCp()));
  if (reader_running) {
    ASSERT_TRUE(reader.start());
  }
  out.write(sample);  // warm-up
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const int n = 1000;
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t allocations = 0;
  {
    tactile::test::AllocationScope scope;
    for (int k = 0; k < n; ++k) {
      sample.time_s = 0.001 * k;
      out.write(sample);
      rt_in.read(sample, false);
    }
    allocations = scope.count();
  }
  const double per_write_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / n;
  EXPECT_EQ(allocations, 0u) << n << " writes, reader " << (reader_running ? "running" : "stopped (buffer full)");
  // Not a timing test: a bound far above any write, only to catch a write that waits on the reader.
  EXPECT_LT(per_write_us, 1000.0);
  if (reader_running) {
    for (int i = 0; i < 40 && reader.reads < n; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_GT(reader.reads.load(), 0);
    reader.stop();
  }
}

TEST(RosStreamConnections, WritesDoNotAllocateWithTheReaderRunning) {
  expectNoAllocation<tactile::TactileFrame>(true);
  expectNoAllocation<tactile::ContactFeatures>(true);
  expectNoAllocation<tactile::PoseCommand>(true);
  expectNoAllocation<tactile::Wrench>(true);
  expectNoAllocation<tactile::PhaseState>(true);
  expectNoAllocation<tactile::RobotState>(true);
}

TEST(RosStreamConnections, WritesDoNotAllocateNorBlockWithTheBufferFull) {
  expectNoAllocation<tactile::TactileFrame>(false);
  expectNoAllocation<tactile::ContactFeatures>(false);
  expectNoAllocation<tactile::Wrench>(false);
  expectNoAllocation<tactile::PhaseState>(false);
  expectNoAllocation<tactile::RobotState>(false);
}

}  // namespace
