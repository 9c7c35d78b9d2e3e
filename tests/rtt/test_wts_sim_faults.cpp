// tactile::WtsSimComponent's fault schedule (tests only; tactile_sim_faults/sensor_faults.hpp),
// in-process on a SlaveActivity with RTT's TimeService set by the test: off
// by default and then the same frames as without it, each fault does what
// the deployed fault tests (tests/rtt/faults) rely on, configuration errors
// name the property and the valid range, no allocation per update.
#include <gtest/gtest.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "alloc_counter.hpp"
#include "support/rtt_environment.hpp"
#include "tactile_sim_rtt/wts_sim_component.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::RawTactileFrame;
using tactile::TactileFrame;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::Manual));

const std::string kScene = TACTILE_SCENE_DIR "/bent_bar.yaml";

void setTime(double t) {
  RTT::os::TimeService* ts = RTT::os::TimeService::Instance();
  ts->ticksChange(RTT::os::TimeService::nsecs2ticks(static_cast<int64_t>(std::llround(t * 1e9))) - ts->getTicks());
}

struct Rig {
  tactile::WtsSimComponent sensor{"sensor"};
  RTT::OutputPort<TactileFrame> forces_out{"forces_out"};
  RTT::InputPort<RawTactileFrame> raw_in{"raw_in"};
  RTT::InputPort<TactileFrame> fault_in{"fault_in"};
  RTT::TaskContext io{"io"};  // declared last: destroyed before the ports it holds
  TactileFrame forces;

  Rig(const std::string& fault, double start, double duration, const std::string& scene = kScene) {
    sensor.setActivity(new RTT::extras::SlaveActivity(0.0));
    io.ports()->addPort(forces_out);
    io.ports()->addPort(raw_in);
    io.ports()->addPort(fault_in);
    sensor.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    sensor.properties()->getPropertyType<std::string>("fault")->set(fault);
    sensor.properties()->getPropertyType<double>("fault_start")->set(start);
    sensor.properties()->getPropertyType<double>("fault_duration")->set(duration);
    EXPECT_TRUE(forces_out.connectTo(sensor.ports()->getPort("taxel_forces")));
    EXPECT_TRUE(sensor.ports()->getPort("raw_frame")->connectTo(&raw_in, RTT::ConnPolicy::buffer(4)));
    EXPECT_TRUE(sensor.ports()->getPort("fault_frame")->connectTo(&fault_in, RTT::ConnPolicy::buffer(4)));
    for (int i = 0; i < forces.size(); ++i) forces.force[static_cast<std::size_t>(i)] = 0.05 * (i % 7);  // a press
    forces_out.setDataSample(forces);
  }
  template <typename T>
  T attr(const char* name) {
    return tactile::readAttribute<T>(*sensor.provides(), name);
  }
};

struct Out {
  double t;
  bool raw, nan;
  RawTactileFrame frame;
  int link;
};

// Acquisitions at 140 Hz from t = 0 for `n` frames; what came out of each.
std::vector<Out> run(Rig& rig, int n) {
  std::vector<Out> out;
  for (int k = 0; k < n; ++k) {
    const double t = k / 140.0;
    setTime(t);
    rig.forces.time_s = t;
    rig.forces_out.write(rig.forces);
    rig.sensor.update();
    Out o{t, false, false, RawTactileFrame(), rig.attr<int>("link_status")};
    o.raw = rig.raw_in.read(o.frame, false) == RTT::NewData;
    TactileFrame f;
    if (rig.fault_in.read(f, false) == RTT::NewData) {
      int nans = 0;
      for (int i = 0; i < f.size(); ++i) nans += std::isnan(f.force[static_cast<std::size_t>(i)]) ? 1 : 0;
      o.nan = nans == 1;
      EXPECT_EQ(nans, 1) << "t " << t;
    }
    out.push_back(o);
  }
  return out;
}

TEST(WtsSimFaults, OffByDefaultAndTheSameFramesOutsideTheFault) {
  tactile::WtsSimComponent plain("plain");
  EXPECT_EQ(plain.properties()->getPropertyType<std::string>("fault")->get(), "");
  for (const char* p : {"fault", "fault_start", "fault_duration"})
    EXPECT_FALSE(plain.properties()->getProperty(p)->getDescription().empty()) << p;
  EXPECT_FALSE(plain.ports()->getPort("fault_frame")->getDescription().empty());
  EXPECT_TRUE(plain.provides()->hasOperation("statusName"));

  Rig off("", 0.0, 0.0), stale("stale", 1.0, 0.1);
  for (Rig* r : {&off, &stale}) {
    ASSERT_TRUE(r->sensor.configure()) << r->sensor.lastError();
    ASSERT_TRUE(r->sensor.start());
  }
  const std::vector<Out> a = run(off, 280);
  const std::vector<Out> b = run(stale, 280);
  int withheld = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(a[k].raw && !a[k].nan && a[k].link == 0) << "no fault: every acquisition delivered, t " << a[k].t;
    const bool inside = a[k].t >= 1.0 && a[k].t < 1.1;
    EXPECT_EQ(b[k].raw, !inside) << "t " << a[k].t;
    if (!b[k].raw) {
      ++withheld;
      continue;
    }
    // Same noise stream (acquired, then withheld): equal counts and times.
    EXPECT_EQ(a[k].frame.counts, b[k].frame.counts) << "t " << a[k].t;
    EXPECT_EQ(a[k].frame.time_s, b[k].frame.time_s);
  }
  EXPECT_EQ(withheld, 14);  // 100 ms at 140 Hz
  EXPECT_EQ(off.attr<int>("fault_seq"), -1);
  EXPECT_EQ(stale.attr<int>("fault_seq"), 140);  // the first frame after the window
}

TEST(WtsSimFaults, DisconnectNamesTheLinkAsTheReaderDoes) {
  Rig rig("disconnect", 1.0, 0.5);
  ASSERT_TRUE(rig.sensor.configure()) << rig.sensor.lastError();
  ASSERT_TRUE(rig.sensor.start());
  const std::vector<Out> o = run(rig, 280);
  bool reconnected = false;
  for (const Out& x : o) {
    if (x.t >= 1.0 && x.t < 1.5) {
      EXPECT_FALSE(x.raw);
      EXPECT_EQ(x.link, 5) << "Disconnected, t " << x.t;
    } else if (x.t >= 1.5 && !reconnected) {
      EXPECT_TRUE(x.raw);
      EXPECT_EQ(x.link, 4) << "Reconnected at the first frame after, t " << x.t;
      reconnected = true;
    } else {
      EXPECT_EQ(x.link, 0) << "NewFrame, t " << x.t;
    }
  }
  EXPECT_TRUE(reconnected);
  EXPECT_EQ(rig.sensor.statusName(), "NewFrame");
}

TEST(WtsSimFaults, OneNanFrameAndOneSaturatedFrame) {
  Rig nan("nan", 1.0, 0.0), sat("saturated", 1.0, 0.0);
  for (Rig* r : {&nan, &sat}) {
    ASSERT_TRUE(r->sensor.configure()) << r->sensor.lastError();
    ASSERT_TRUE(r->sensor.start());
  }
  const std::vector<Out> a = run(nan, 280);
  const std::vector<Out> b = run(sat, 280);
  int nans = 0, saturated = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const bool hit = a[k].t >= 1.0 && a[k].t < 1.0 + 0.5 / 140.0;  // the first acquisition at or after 1.0 s
    EXPECT_EQ(a[k].nan, hit) << "t " << a[k].t;
    EXPECT_EQ(a[k].raw, !hit) << "the NaN frame replaces that raw frame, t " << a[k].t;
    nans += a[k].nan ? 1 : 0;
    bool full = true;
    for (int i = 0; i < 84; ++i) full = full && b[k].frame.counts[static_cast<std::size_t>(i)] == 4095;
    EXPECT_EQ(full, hit) << "t " << b[k].t;
    saturated += full ? 1 : 0;
  }
  EXPECT_EQ(nans, 1);
  EXPECT_EQ(saturated, 1);
  EXPECT_EQ(nan.attr<int>("fault_seq"), 140);
  EXPECT_EQ(sat.attr<int>("fault_seq"), 140);
}

// The scene's `faults:` list reaches the simulated sensor: the phantom
// press's 16 taxels read constant counts from the first frame, the other
// taxels what the same scene without the fault gives (same noise stream);
// the property's fault comes on top of the scene's.
TEST(WtsSimFaults, TheScenesFaultsAndThePropertysTogether) {
  const std::string phantom = TACTILE_SCENE_DIR "/faults/phantom_contact.yaml";
  const std::string plain = TACTILE_SCENE_DIR "/edge_exploration.yaml";  // the same calibration, noise and seed
  Rig a("", 0.0, 0.0, plain), b("stale", 1.0, 0.1, phantom);
  for (Rig* r : {&a, &b}) {
    ASSERT_TRUE(r->sensor.configure()) << r->sensor.lastError();
    ASSERT_TRUE(r->sensor.start());
  }
  const std::vector<Out> x = run(a, 280), y = run(b, 280);
  int withheld = 0;
  uint16_t stuck = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!y[k].raw) {
      ++withheld;
      continue;
    }
    for (int i = 0; i < 84; ++i) {
      const int r = i / 14, c = i % 14;
      const uint16_t v = y[k].frame.counts[static_cast<std::size_t>(i)];
      if (r >= 1 && r <= 4 && c >= 5 && c <= 8) {
        if (stuck == 0) stuck = v;
        EXPECT_EQ(v, stuck) << "a stuck taxel, t " << y[k].t;
      } else {
        EXPECT_EQ(v, x[k].frame.counts[static_cast<std::size_t>(i)]) << "taxel " << i << ", t " << y[k].t;
      }
    }
  }
  EXPECT_GT(stuck, 0) << "0.5 N per taxel, above the threshold";
  EXPECT_EQ(withheld, 14) << "the property's stale window on top";
}

TEST(WtsSimFaults, ConfigureErrorsNameThePropertyAndTheRange) {
  struct Case {
    const char* fault;
    double start, duration;
    const char* key;
  };
  for (const Case& c : {Case{"stall", 1.0, 0.1, "fault = 'stall'"}, Case{"stale", -1.0, 0.1, "fault_start"},
                        Case{"stale", 1.0, 0.0, "fault_duration"}, Case{"disconnect", 1.0, 61.0, "(0, 60]"}}) {
    Rig rig(c.fault, c.start, c.duration);
    EXPECT_FALSE(rig.sensor.configure()) << c.fault;
    EXPECT_NE(rig.sensor.lastError().find(c.key), std::string::npos) << rig.sensor.lastError();
    EXPECT_NE(rig.sensor.lastError().find("sensor"), std::string::npos) << "names the component";
  }
}

TEST(WtsSimFaults, UpdateWithAFaultDoesNotAllocate) {
  for (const char* fault : {"stale", "disconnect", "nan", "saturated"}) {
    Rig rig(fault, 0.3, 0.2);
    ASSERT_TRUE(rig.sensor.configure());
    ASSERT_TRUE(rig.sensor.start());
    run(rig, 20);  // warm-up: every port carried a sample once
    tactile::test::AllocationScope scope;
    RawTactileFrame raw;
    TactileFrame f;
    for (int k = 20; k < 140; ++k) {
      setTime(k / 140.0);
      rig.forces_out.write(rig.forces);
      rig.sensor.update();
      rig.raw_in.read(raw, false);
      rig.fault_in.read(f, false);
    }
    EXPECT_EQ(scope.count(), 0u) << fault;
    EXPECT_GE(rig.attr<int>("fault_seq"), 0) << fault;
  }
}

}  // namespace
