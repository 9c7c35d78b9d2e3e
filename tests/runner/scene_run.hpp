// Shared by the runner tests: load a shipped scene (params/scenes/) as a run,
// with the program the registry binds to it (experiments.yaml,
// tactile::config::programForScene) and `--set`-style overrides, and run it
// through tactile::sim::Runner, failing the calling test (EXPECT) on a load
// or configure error.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "tactile_config/registry.hpp"
#include "tactile_sim_runner/runner.hpp"

namespace tactile {
namespace sim {
namespace test {

inline const std::string kScenes = std::string(TACTILE_SOURCE_DIR) + "/params/scenes/";

inline const std::string kRegistry = std::string(TACTILE_SOURCE_DIR) + "/experiments.yaml";

/// The run of a shipped scene: the scene with the program the registry binds to it.
inline RunFiles shippedRun(const std::string& name) {
  RunFiles files{kScenes + name, "", ""};
  const ConfigResult r = config::programForScene(kRegistry, files.scene, files.program);
  EXPECT_TRUE(r.ok()) << r.message();
  return files;
}

inline Scene loadRunOf(const RunFiles& files, const std::vector<std::string>& overrides = {}) {
  Scene sc;
  const ConfigResult r = loadRun(files, sc, overrides);
  EXPECT_TRUE(r.ok()) << r.message();
  return sc;
}

inline Scene loadShipped(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return loadRunOf(shippedRun(name), overrides);
}

inline const std::string kPrograms = std::string(TACTILE_SOURCE_DIR) + "/params/programs/";

/// A shipped scene with another program (a path).
inline Scene loadShippedWith(const std::string& name, const std::string& program,
                             const std::vector<std::string>& overrides = {}) {
  return loadRunOf(RunFiles{kScenes + name, program, ""}, overrides);
}

/// A shipped scene with the paper's program in place of the shipped one: the
/// `*_paper.yaml` beside it (Eq. 2's force alone, CoP_y at 0), for the tests
/// of the paper's own comparisons; the scene's program when it has none.
inline Scene loadPaper(const std::string& name, const std::vector<std::string>& overrides = {}) {
  RunFiles files = shippedRun(name);
  const std::string ext = ".yaml";
  const std::string paper = files.program.substr(0, files.program.size() - ext.size()) + "_paper.yaml";
  if (std::ifstream(paper).good()) files.program = paper;
  return loadRunOf(files, overrides);
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
