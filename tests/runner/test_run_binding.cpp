// The experiment registry binds each scene to the program a run of it takes
// (tactile::config::programForScene): scenes name no program.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "tactile_config/registry.hpp"
#include "tactile_sim_runner/scene.hpp"

namespace fs = std::filesystem;
using tactile::ConfigResult;
using tactile::config::programForScene;

namespace {

const std::string kRoot = TACTILE_SOURCE_DIR;

// A registry of the test's own beside folders of empty files.
struct Fixture {
  fs::path dir = fs::path(testing::TempDir()) / "run_binding";
  Fixture() {
    fs::remove_all(dir);
    fs::create_directories(dir / "scenes" / "family");
    for (const char *f : {"scenes/a.yaml", "scenes/b.yaml",
                          "scenes/family/one.yaml", "scenes/family/two.yaml"})
      std::ofstream(dir / f) << "name: x\n";
  }
  std::string registry(const std::string &body) const {
    const fs::path p = dir / "experiments.yaml";
    std::ofstream(p) << body;
    return p.string();
  }
  std::string at(const std::string &rel) const {
    return fs::weakly_canonical(dir / rel).string();
  }
};

std::string programOf(const std::string &registry, const std::string &scene) {
  std::string program;
  const ConfigResult r = programForScene(registry, scene, program);
  return r ? program : "error: " + r.message();
}

} // namespace

TEST(RunBinding, AnExperimentsSceneTakesItsProgramElseTheNearestScenesEntry) {
  const Fixture f;
  const std::string reg =
      f.registry("experiments:\n"
                 "  first: {scene: scenes/a.yaml, program: p_a.yaml}\n"
                 "  again: {scene: scenes/a.yaml, program: ./p_a.yaml, "
                 "controller: baseline}\n"
                 "scenes:\n"
                 "  scenes/: p_any.yaml\n"
                 "  scenes/family/: p_family.yaml\n"
                 "  scenes/family/two.yaml: p_two.yaml\n"
                 "  scenes/a.yaml: p_not_this.yaml\n");
  EXPECT_EQ(programOf(reg, (f.dir / "scenes/a.yaml").string()),
            f.at("p_a.yaml"))
      << "the experiments' program first";
  EXPECT_EQ(programOf(reg, (f.dir / "scenes/b.yaml").string()),
            f.at("p_any.yaml"));
  EXPECT_EQ(programOf(reg, (f.dir / "scenes/family/one.yaml").string()),
            f.at("p_family.yaml"))
      << "the nearest folder";
  EXPECT_EQ(
      programOf(reg, (f.dir / "scenes/family/../family/two.yaml").string()),
      f.at("p_two.yaml"));
}

TEST(RunBinding,
     DisagreeingExperimentsOrAnUnboundSceneAreErrorsNamingTheRegistry) {
  const Fixture f;
  const std::string reg =
      f.registry("experiments:\n"
                 "  first: {scene: scenes/a.yaml, program: p_a.yaml}\n"
                 "  other: {scene: scenes/a.yaml, program: p_other.yaml}\n"
                 "scenes:\n"
                 "  scenes/family/: p_family.yaml\n");
  const std::string both = programOf(reg, (f.dir / "scenes/a.yaml").string());
  EXPECT_NE(both.find(reg + ": experiments.other.program"), std::string::npos)
      << both;
  EXPECT_NE(both.find("differs from experiments.first.program"),
            std::string::npos)
      << both;
  const std::string none = programOf(reg, (f.dir / "scenes/b.yaml").string());
  EXPECT_NE(none.find(reg + ": no program for the scene"), std::string::npos)
      << none;
  EXPECT_NE(none.find("tactile_sim run SCENE --program FILE"),
            std::string::npos)
      << none;
  const std::string missing = programOf((f.dir / "none.yaml").string(),
                                        (f.dir / "scenes/b.yaml").string());
  EXPECT_NE(missing.find("none.yaml: cannot open file"), std::string::npos)
      << missing;
  const std::string bad =
      programOf(f.registry("experiments: {}\nscenes: [a, b]\n"),
                (f.dir / "scenes/b.yaml").string());
  EXPECT_NE(bad.find("scenes: must map a scene or a folder to a program"),
            std::string::npos)
      << bad;
}

// Every shipped scene is a run: the registry gives it a program that loads
// with it (the metrics name that program's phases), and a scene an
// experiment runs takes that experiment's program.
TEST(RunBinding, EveryShippedSceneHasAProgramThatLoadsWithIt) {
  const std::string reg = kRoot + "/experiments.yaml";
  int scenes = 0;
  for (const auto &e :
       fs::recursive_directory_iterator(kRoot + "/params/scenes")) {
    if (e.path().extension() != ".yaml")
      continue;
    ++scenes;
    tactile::sim::RunFiles files{e.path().string(), "", ""};
    const ConfigResult bound = programForScene(reg, files.scene, files.program);
    ASSERT_TRUE(bound.ok()) << bound.message();
    tactile::sim::Scene sc;
    const ConfigResult loaded = tactile::sim::loadRun(files, sc);
    EXPECT_TRUE(loaded.ok()) << loaded.message();
    EXPECT_FALSE(sc.servo.phases.empty()) << files.scene;
  }
  EXPECT_GE(scenes, 37);
  std::string program;
  ASSERT_TRUE(programForScene(reg, kRoot + "/params/scenes/bent_bar_fused.yaml",
                              program)
                  .ok());
  EXPECT_EQ(program, fs::weakly_canonical(
                         kRoot + "/params/programs/bent_bar_to_end_cap.yaml")
                         .string());
}

// The registry's `scenes:` names files and folders that exist, programs that
// exist, and no scene an experiment runs (that entry would never be read).
TEST(RunBinding, TheRegistrysScenesEntriesAreLive) {
  const YAML::Node root = YAML::LoadFile(kRoot + "/experiments.yaml");
  std::vector<fs::path> experiment_scenes;
  for (const auto &e : root["experiments"])
    experiment_scenes.push_back(fs::weakly_canonical(
        kRoot + "/" + e.second["scene"].as<std::string>()));
  ASSERT_TRUE(root["scenes"].IsMap());
  int entries = 0;
  for (const auto &kv : root["scenes"]) {
    ++entries;
    const std::string key = kv.first.as<std::string>(),
                      program = kv.second.as<std::string>();
    const fs::path at = kRoot + "/" + key;
    EXPECT_TRUE(key.back() == '/' ? fs::is_directory(at)
                                  : fs::is_regular_file(at))
        << key;
    EXPECT_TRUE(fs::is_regular_file(kRoot + "/" + program))
        << key << ": " << program;
    for (const fs::path &s : experiment_scenes)
      EXPECT_NE(fs::weakly_canonical(at), s) << key << " is an experiment's";
  }
  EXPECT_GE(entries, 1);
}
