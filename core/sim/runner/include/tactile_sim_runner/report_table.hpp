// The time series of a simulated deployment, as OCL::FileReporting writes it
// (deployments/sim_loop.ops + experiment_start.ops: the reporter runs right
// after each servo cycle, executed by tactile::SimClock), read back into the
// runner's rows, so that `tactile_sim summarize` computes summary.json and the
// time series with the runner's own makeRow() and computeSummary(): one
// implementation of the metrics for both hosts.
//
// The table: a header line of leaf names ("TimeStamp Servo.phase.index ...
// Robot.truth.wrench_s.Element2 ..."), then one whitespace-separated line per
// sample; enums by name (the typekit's), char arrays one column per char
// (NULs included). FileReporting streams numbers with 6 significant digits, so
// the rows (and the metrics) equal the runner's to that precision; the exact
// per-cycle equality of the deployed loop is tests/rtt/test_sim_loop.cpp's.
#pragma once

#include <string>
#include <vector>

#include "tactile_sim_runner/runner.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace sim {

/// Reads REPORT (the columns named above; a missing column is an error that
/// names it) into `out.rows` and `out.phases` for `scene`. Not real-time.
ConfigResult readReportTable(const std::string& path, const Scene& scene, RunResult& out);

}  // namespace sim
}  // namespace tactile
