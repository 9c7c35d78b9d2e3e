// Shared by the RTT benchmarks (tests/rtt/bench_rtt_components.cpp,
// tests/ros/bench_ros_streams.cpp): a FeatureComponent on a SlaveActivity fed
// an edge frame through its raw_frame port, its features read back each cycle.
#pragma once

#include <benchmark/benchmark.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/extras/SlaveActivity.hpp>

#include <cmath>
#include <string>

#include "tactile_features_rtt/feature_component.hpp"

namespace bench_rig {

inline const std::string kParamFile = TACTILE_DEPLOYMENTS_DIR "/../params/sensors/wts0614.yaml";

/// An edge across the pad, as raw counts (up to 600 counts: 0.25 N with the file's calibration).
inline tactile::RawTactileFrame edgeFrame() {
  tactile::RawTactileFrame raw;
  for (int r = 0; r < raw.rows; ++r)
    for (int c = 0; c < raw.cols; ++c) {
      const double d = std::fabs((c - 6.5) * 0.3 - (r - 2.5));  // distance (in taxels) from a line
      raw.counts[static_cast<std::size_t>(r * raw.cols + c)] = static_cast<uint16_t>(d < 1.5 ? 400 * (1.5 - d) : 0);
    }
  return raw;
}

struct FeatureRig {
  tactile::FeatureComponent comp{"features"};
  RTT::OutputPort<tactile::RawTactileFrame> raw_out{"raw_out"};
  RTT::InputPort<tactile::ContactFeatures> features_in{"features_in"};

  FeatureRig() {
    comp.setActivity(new RTT::extras::SlaveActivity());
    comp.properties()->getPropertyType<std::string>("param_file")->set(kParamFile);
    raw_out.connectTo(comp.ports()->getPort("raw_frame"));
    comp.ports()->getPort("features")->connectTo(&features_in);
  }

  /// Configures, starts and runs the benchmark loop (one frame in, one
  /// update, the features out per iteration); stops the component after.
  void run(benchmark::State& state) {
    if (!comp.configure() || !comp.start()) {
      state.SkipWithError("configure/start");
      return;
    }
    tactile::RawTactileFrame raw = edgeFrame();
    raw_out.setDataSample(raw);
    tactile::ContactFeatures out;
    for (auto _ : state) {
      ++raw.seq;
      raw_out.write(raw);
      comp.update();
      features_in.read(out, false);
      benchmark::DoNotOptimize(out);
    }
    comp.stop();
  }
};

}  // namespace bench_rig
