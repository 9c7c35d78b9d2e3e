// main() of the RTT Google Benchmark binaries: the RTT OS layer (__os_init /
// __os_exit) around the registered benchmarks.
#pragma once

#include <benchmark/benchmark.h>
#include <rtt/os/main.h>

namespace tactile {
namespace test {

inline int rttBenchmarkMain(int argc, char** argv) {
  __os_init(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  __os_exit();
  return 0;
}

}  // namespace test
}  // namespace tactile
