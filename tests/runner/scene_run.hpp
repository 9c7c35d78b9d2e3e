// Shared by the runner tests: load a shipped scene (params/scenes/) with
// `--set`-style overrides and run it through tactile::sim::Runner, failing the
// calling test (EXPECT) on a load or configure error.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "tactile_sim/runner.hpp"

namespace tactile {
namespace sim {
namespace test {

inline const std::string kScenes = std::string(TACTILE_SOURCE_DIR) + "/params/scenes/";

inline Scene loadShipped(const std::string& name, const std::vector<std::string>& overrides = {}) {
  Scene sc;
  const ConfigResult r = loadScene(kScenes + name, sc, overrides);
  EXPECT_TRUE(r.ok()) << r.message();
  return sc;
}

/// A shipped scene with the paper's program in place of the shipped one: the
/// `*_paper.yaml` beside it (Eq. 2's force alone, CoP_y at 0), for the tests
/// of the paper's own comparisons; the scene's program when it has none.
inline Scene loadPaper(const std::string& name, std::vector<std::string> overrides = {}) {
  const Scene shipped = loadShipped(name);
  std::string program = shipped.program_file;
  const std::string ext = ".yaml";
  if (program.size() > ext.size()) program = program.substr(0, program.size() - ext.size()) + "_paper.yaml";
  if (std::ifstream(program).good()) overrides.insert(overrides.begin(), "program=" + program);
  return loadShipped(name, overrides);
}

inline RunResult runFull(const Scene& sc) {
  Runner runner;
  const ConfigResult c = runner.configure(sc);
  EXPECT_TRUE(c.ok()) << c.message();
  RunResult res;
  runner.run(res);
  return res;
}

inline Summary run(const Scene& sc) { return runFull(sc).summary; }

}  // namespace test
}  // namespace sim
}  // namespace tactile
