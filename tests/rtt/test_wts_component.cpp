// tactile::WtsComponent in-process against the simulated WTS0614 on a PTY
// (tactile::wts::SimulatedWts) on a FileDescriptorActivity (as deployed),
// including unplug and replug (no spinning while unplugged, the re-opened
// descriptor watched), and packet by packet on a bare PTY for the allocation
// check (no simulator thread whose allocations would count).
#include <gtest/gtest.h>

#include <rtt/Activity.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/FileDescriptorActivity.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/Thread.hpp>
#include <rtt/os/main.h>

#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_wts/sim_device.hpp"
#include "tactile_wts_rtt/wts_component.hpp"
#include "wts_test_util.hpp"
#include "support/rtt_environment.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::RawTactileFrame;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::System));

// counts[i] = (37 i + t) mod 4096 in {s} order: every frame checkable exactly.
void pattern(uint32_t t, RawTactileFrame& f) {
  for (int i = 0; i < 84; ++i) f.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>((37 * i + t) % 4096);
}
bool matchesPattern(const RawTactileFrame& f) {
  if (f.rows != 6 || f.cols != 14) return false;
  for (int i = 0; i < 84; ++i)
    if (f.counts[static_cast<std::size_t>(i)] != (37 * i + f.device_time_ms) % 4096) return false;
  return true;
}

// Counts updateHook calls (the component's cycles).
struct CountingWts : tactile::WtsComponent {
  using tactile::WtsComponent::WtsComponent;
  std::atomic<int> updates{0};
  void updateHook() override {
    updates.fetch_add(1, std::memory_order_relaxed);
    tactile::WtsComponent::updateHook();
  }
};

struct Rig {
  CountingWts comp{"wts"};
  RTT::InputPort<RawTactileFrame> raw_in{"raw_in"};
  RTT::TaskContext io{"io"};
  Rig(RTT::base::ActivityInterface* a, const std::string& device) {
    comp.setActivity(a);
    io.ports()->addPort(raw_in);
    comp.properties()->getPropertyType<std::string>("device")->set(device);
    EXPECT_TRUE(comp.ports()->getPort("raw_frame")->connectTo(&raw_in));
  }
  ~Rig() { comp.stop(); }  // before CountingWts is destroyed: its updateHook may be running
  int attr(const char* n) { return tactile::readAttribute<int>(*comp.provides(), n); }
  bool flag(const char* n) { return tactile::readAttribute<bool>(*comp.provides(), n); }
};

// Polls `pred` every 1 ms for up to `limit_s` (this thread); true when it held.
template <class Pred>
bool waitFor(Pred pred, double limit_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  while (!pred()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

struct TempDir {
  std::string path;
  TempDir() {
    char t[] = "/tmp/wts_rtt_XXXXXX";
    path = mkdtemp(t);
  }
  ~TempDir() { std::system(("rm -rf " + path).c_str()); }
};

TEST(WtsComponent, InterfaceAndConfigureErrors) {
  tactile::WtsComponent c("w");
  ASSERT_NE(c.ports()->getPort("raw_frame"), nullptr);
  EXPECT_FALSE(c.ports()->getPort("raw_frame")->getDescription().empty());
  for (const char* p : {"param_file", "device", "poll_timeout", "stop_timeout"}) EXPECT_NE(c.properties()->getProperty(p), nullptr) << p;
  for (const char* a : {"read_status", "frames", "timeouts", "fd_activity"})
    EXPECT_NE(c.provides()->getAttribute(a), nullptr) << a;
  c.properties()->getPropertyType<double>("poll_timeout")->set(5.0);
  EXPECT_FALSE(c.configure());
  EXPECT_NE(c.lastError().find("poll_timeout"), std::string::npos) << c.lastError();
  c.properties()->getPropertyType<double>("poll_timeout")->set(0.05);
  c.properties()->getPropertyType<double>("stop_timeout")->set(0.5);
  EXPECT_FALSE(c.configure());
  EXPECT_NE(c.lastError().find("stop_timeout"), std::string::npos) << c.lastError();
  tactile::WtsComponent d("w2");
  d.setActivity(new RTT::extras::SlaveActivity());
  d.properties()->getPropertyType<std::string>("device")->set("/nonexistent/ttyACM9");
  ASSERT_TRUE(d.configure());
  EXPECT_FALSE(d.start());  // the port cannot be opened: start() fails and says why
  EXPECT_NE(d.lastError().find("/nonexistent/ttyACM9"), std::string::npos) << d.lastError();
}

// A plain non-periodic activity (the TaskContext's default) would either spin
// (the hook never waits) or never read: start() refuses it and says what to use.
TEST(WtsComponent, NonPeriodicPlainActivityIsRefused) {
  tactile::wts::SimulatedWts sim;
  tactile::wts::SimulatedWts::Params sp;
  sim.setSource(pattern);
  std::string why;
  ASSERT_TRUE(sim.start(sp, &why)) << why;
  {
    Rig rig(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0), sim.path());
    ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
    EXPECT_FALSE(rig.comp.start());
    EXPECT_NE(rig.comp.lastError().find("FileDescriptorActivity"), std::string::npos) << rig.comp.lastError();
  }
  sim.stop();
}

// As deployed: a FileDescriptorActivity watching the serial port, paced by the
// simulated device.
TEST(WtsComponent, StreamsFramesFromTheSimulatedDevice) {
  tactile::wts::SimulatedWts sim;
  tactile::wts::SimulatedWts::Params sp;
  sim.setSource(pattern);
  std::string why;
  ASSERT_TRUE(sim.start(sp, &why)) << why;
  {
    Rig rig(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, 0), sim.path());
    ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
    ASSERT_TRUE(rig.comp.start()) << rig.comp.lastError();
    EXPECT_TRUE(rig.flag("fd_activity"));
    int got = 0, bad = 0;
    RawTactileFrame f;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (got < 30 && std::chrono::steady_clock::now() < end) {
      if (rig.raw_in.read(f) == RTT::NewData) {
        ++got;
        if (!matchesPattern(f)) ++bad;
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    }
    ASSERT_TRUE(rig.comp.stop());
    EXPECT_GE(got, 30);
    EXPECT_EQ(bad, 0);
    EXPECT_GE(rig.attr("frames"), got);
  }
  sim.stop();
}

// poll through the component over a bare PTY, this thread writing the frames.
TEST(WtsComponent, UpdateDoesNotAllocate) {
  std::string slave;
  const int m = wtstest::openBarePty(slave);
  ASSERT_GE(m, 0);
  const char* name = slave.c_str();
  const std::string params = ::testing::TempDir() + "wts_rtt.yaml";
  {
    FILE* f = std::fopen(params.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fprintf(f, "wts:\n  periodic_ms: 0\n  check_matrix_info: false\n");
    std::fclose(f);
  }
  {
    Rig rig(new RTT::extras::SlaveActivity(), name);
    rig.comp.properties()->getPropertyType<std::string>("param_file")->set(params);
    ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
    ASSERT_TRUE(rig.comp.start()) << rig.comp.lastError();
    tactile::wts::CellMap map;
    ASSERT_TRUE(map.configure(tactile::wts::CellMapParams{}).ok());
    std::vector<std::vector<uint8_t>> pkts;
    for (int k = 0; k < 20; ++k) {
      RawTactileFrame f;
      pattern(static_cast<uint32_t>(k * 10), f);
      pkts.push_back(wtstest::framePacket(map, f.counts.data(), static_cast<uint32_t>(k * 10), k % 2 == 0, 0x20));
    }
    uint8_t sink[512];
    RawTactileFrame f;
    int frames = 0, wrong = 0;
    std::size_t allocs = 0;
    {
      tactile::test::AllocationScope scope;
      for (int it = 0; it < 200; ++it) {
        const auto& pkt = pkts[static_cast<std::size_t>(it) % pkts.size()];
        if (::write(m, pkt.data(), pkt.size()) != static_cast<ssize_t>(pkt.size())) break;
        // PTY delivery is asynchronous and may come in pieces; update() never
        // waits: this thread does, between updates, until the frame is out.
        for (int tries = 0; tries < 2000; ++tries) {
          rig.comp.update();
          if (rig.raw_in.read(f) == RTT::NewData) {
            ++frames;
            if (!matchesPattern(f)) ++wrong;
            break;
          }
          std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        while (::read(m, sink, sizeof(sink)) > 0) {
        }
      }
      allocs = scope.count();
    }
    EXPECT_EQ(allocs, 0u);
    EXPECT_EQ(frames, 200);
    EXPECT_EQ(wrong, 0);
    rig.comp.stop();
  }
  ::close(m);
}

// Unplugged at full rate on the deployed activity: Disconnected, the hook runs
// once per poll_timeout (no spinning on a closed descriptor), then Reconnected
// and frames again from the re-opened, watched descriptor.
TEST(WtsComponent, UnplugAndReplugOnTheFileDescriptorActivity) {
  TempDir dir;
  tactile::wts::SimulatedWts sim;
  tactile::wts::SimulatedWts::Params sp;
  sp.link = dir.path + "/wts0";  // stable path across replug
  sim.setSource(pattern);
  std::string why;
  ASSERT_TRUE(sim.start(sp, &why)) << why;
  const std::string params = dir.path + "/wts.yaml";
  {
    FILE* f = std::fopen(params.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fprintf(f, "wts:\n  periodic_ms: 2\n  reconnect_period_s: 0.05\n");
    std::fclose(f);
  }
  {
    constexpr double kPollTimeout = 0.02;
    Rig rig(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, 0), sim.path());
    rig.comp.properties()->getPropertyType<std::string>("param_file")->set(params);
    rig.comp.properties()->getPropertyType<double>("poll_timeout")->set(kPollTimeout);
    ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
    ASSERT_TRUE(rig.comp.start()) << rig.comp.lastError();
    // stop() waits up to stop_timeout (default 5 s, not RTT's 1 s) for the thread to leave select().
    const auto* thread = dynamic_cast<RTT::os::Thread*>(rig.comp.getActivity());
    ASSERT_NE(thread, nullptr);
    EXPECT_DOUBLE_EQ(thread->getStopTimeout(), 5.0);
    ASSERT_TRUE(waitFor([&] { return rig.attr("frames") >= 20; }, 5.0));
    const int status_disconnected = static_cast<int>(tactile::wts::ReadStatus::Disconnected);
    sim.unplug();
    ASSERT_TRUE(waitFor([&] { return rig.attr("read_status") == status_disconnected; }, 5.0));
    EXPECT_EQ(rig.comp.statusName(), "Disconnected");
    // Unplugged for 0.5 s: woken by the activity's timeout only, about 25 times
    // (a spinning hook would run thousands of times).
    const int u0 = rig.comp.updates.load(), t0 = rig.attr("timeouts"), f0 = rig.attr("frames");
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const int cycles = rig.comp.updates.load() - u0;
    EXPECT_LE(cycles, 0.5 / kPollTimeout + 10);
    EXPECT_GE(cycles, 3);
    EXPECT_NEAR(rig.attr("timeouts") - t0, cycles, 2);  // every one a timeout
    EXPECT_EQ(rig.attr("frames"), f0);
    EXPECT_EQ(rig.attr("read_status"), status_disconnected);
    ASSERT_TRUE(sim.replug());
    EXPECT_TRUE(waitFor([&] { return rig.attr("frames") >= f0 + 20; }, 5.0)) << rig.comp.statusName();
    RawTactileFrame f;
    ASSERT_EQ(rig.raw_in.read(f), RTT::NewData);
    EXPECT_TRUE(matchesPattern(f));
    ASSERT_TRUE(rig.comp.stop());
  }
  sim.stop();
}

}  // namespace
