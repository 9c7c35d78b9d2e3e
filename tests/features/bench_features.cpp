// One 6x14 frame through the extractor vs the OpenCV pipeline of
// opencv_reference.hpp, same run, same frames. Report the ratio
// BM_OpenCvPipeline / BM_Extractor (absolute times on a shared machine are noisy).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "opencv_reference.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"

using namespace tactile;

namespace {
std::vector<TactileFrame> frames() {
  std::vector<TactileFrame> out;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> a(-1.5, 1.5), x(-0.01, 0.01), d(0.002, 0.004);
  sim::PadGeometry g;
  for (int i = 0; i < 256; ++i) {
    TactileFrame f;
    if (i % 2)
      sim::integratePad(g, sim::EdgeIndent{x(rng), x(rng) / 4, a(rng), d(rng)}, f);
    else
      sim::integratePad(g, sim::SphereIndent{x(rng), x(rng) / 4, 0.01, d(rng)}, f);
    out.push_back(f);
  }
  return out;
}
const std::vector<TactileFrame>& data() {
  static const std::vector<TactileFrame> d = frames();
  return d;
}
}  // namespace

static void BM_Extractor(benchmark::State& state) {
  FeatureParams p;
  p.threshold_mode = state.range(0) ? ThresholdMode::Otsu : ThresholdMode::Fixed;
  FeatureExtractor ex;
  ex.configure(p);
  ContactFeatures out;
  std::size_t i = 0;
  for (auto _ : state) {
    ex.step(data()[i++ & 255], out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_Extractor)->Arg(0)->Arg(1)->ArgName("otsu");

static void BM_OpenCvPipeline(benchmark::State& state) {
  std::size_t i = 0;
  for (auto _ : state) {
    auto r = test::referenceFeatures(data()[i++ & 255], kDefaultPitch, 0.2);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_OpenCvPipeline);

BENCHMARK_MAIN();
