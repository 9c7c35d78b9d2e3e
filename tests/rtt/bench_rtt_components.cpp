// Cost of the RTT layer: one FeatureComponent cycle (write raw_frame, update(),
// read features) against the same cores called directly, in the same run.
#include <benchmark/benchmark.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>

#include <cmath>
#include <string>

#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_features_rtt/feature_component.hpp"
#include "rtt_benchmark_main.hpp"

namespace {

const std::string kParamFile = TACTILE_DEPLOYMENTS_DIR "/../components/features/params/wts0614.yaml";

// An edge across the pad, as raw counts (up to 600 counts: 0.25 N with the file's calibration).
tactile::RawTactileFrame edgeFrame() {
  tactile::RawTactileFrame raw;
  for (int r = 0; r < raw.rows; ++r)
    for (int c = 0; c < raw.cols; ++c) {
      const double d = std::fabs((c - 6.5) * 0.3 - (r - 2.5));  // distance (in taxels) from a line
      raw.counts[static_cast<std::size_t>(r * raw.cols + c)] = static_cast<uint16_t>(d < 1.5 ? 400 * (1.5 - d) : 0);
    }
  return raw;
}

void BM_CoresDirect(benchmark::State& state) {
  tactile::FeatureParams fp;
  tactile::CalibrationParams cp;
  if (!tactile::loadSensorParamFile(kParamFile, fp, cp).ok()) {
    state.SkipWithError("param file");
    return;
  }
  tactile::Calibration cal;
  tactile::FeatureExtractor ex;
  cal.configure(cp);
  ex.configure(fp);
  tactile::RawTactileFrame raw = edgeFrame();
  tactile::TactileFrame frame;
  tactile::ContactFeatures out;
  for (auto _ : state) {
    ++raw.seq;
    cal.step(raw, frame);
    ex.step(frame, out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_CoresDirect);

void BM_FeatureComponentCycle(benchmark::State& state) {
  tactile::FeatureComponent comp("features");
  comp.setActivity(new RTT::extras::SlaveActivity());
  comp.properties()->getPropertyType<std::string>("param_file")->set(kParamFile);
  RTT::OutputPort<tactile::RawTactileFrame> raw_out("raw_out");
  RTT::InputPort<tactile::ContactFeatures> features_in("features_in");
  raw_out.connectTo(comp.ports()->getPort("raw_frame"));
  comp.ports()->getPort("features")->connectTo(&features_in);
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
BENCHMARK(BM_FeatureComponentCycle);

}  // namespace

int main(int argc, char** argv) { return tactile::test::rttBenchmarkMain(argc, argv); }
