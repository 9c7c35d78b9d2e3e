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
#include "feature_bench_rig.hpp"
#include "rtt_benchmark_main.hpp"

namespace {

using bench_rig::edgeFrame;
using bench_rig::kParamFile;

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
  bench_rig::FeatureRig rig;
  rig.run(state);
}
BENCHMARK(BM_FeatureComponentCycle);

}  // namespace

int main(int argc, char** argv) { return tactile::test::rttBenchmarkMain(argc, argv); }
