// Added per-cycle cost of the ROS streams (deployments/ros_streams.ops) on the
// real-time side: one FeatureComponent cycle (write raw_frame, update(), read
// features), without (streams = 0) and with (streams = 1) the streams' extra
// connections of its two outputs, calibrated_frame and features: buffered
// (256), lock-free, to the event ports of a reader in its own non-periodic
// thread that drains them, as tactile_ros::RosAdapter does. The ROS side
// (conversion, serialisation, publishing) runs in other threads and is not
// in this cycle.
#include <benchmark/benchmark.h>

#include <rtt/Activity.hpp>
#include <rtt/ConnPolicy.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>

#include <cmath>
#include <string>

#include "feature_bench_rig.hpp"
#include "rtt_benchmark_main.hpp"
#include "tactile_features_rtt/feature_component.hpp"

namespace {

// The adapter's place: drains its buffered event ports in its own thread.
class Drain : public RTT::TaskContext {
 public:
  Drain() : RTT::TaskContext("drain"), frame_in_("calibrated_frame"), features_in_("features") {
    addEventPort(frame_in_);
    addEventPort(features_in_);
  }
  void updateHook() override {
    while (frame_in_.read(frame_, false) == RTT::NewData) {
    }
    while (features_in_.read(features_, false) == RTT::NewData) {
    }
  }
  RTT::InputPort<tactile::TactileFrame> frame_in_;
  RTT::InputPort<tactile::ContactFeatures> features_in_;
  tactile::TactileFrame frame_;
  tactile::ContactFeatures features_;
};

void BM_FeatureCycleStreams(benchmark::State& state) {
  const bool streams = state.range(0) != 0;
  bench_rig::FeatureRig rig;
  Drain drain;
  drain.setActivity(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0));
  if (streams) {
    RTT::ConnPolicy cp = RTT::ConnPolicy::buffer(256);
    cp.lock_policy = RTT::ConnPolicy::LOCK_FREE;
    rig.comp.ports()->getPort("calibrated_frame")->connectTo(&drain.frame_in_, cp);
    rig.comp.ports()->getPort("features")->connectTo(&drain.features_in_, cp);
    drain.start();
  }
  rig.run(state);
  drain.stop();
}
BENCHMARK(BM_FeatureCycleStreams)->Arg(0)->Arg(1);

}  // namespace

int main(int argc, char** argv) { return tactile::test::rttBenchmarkMain(argc, argv); }
