// One entry of the experiment registry (experiments.yaml), declared once
// (tactile_types/schema.hpp): the reader with its unknown-key and
// required-key errors, its range checks and docs/formats.md's table
// (`tactile_sim schema registry`). tactile::DeployGuard reads entries with
// it; the entry's files and its state machine's params are checked there
// (they need the .osd and the scene).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace config {

struct ExperimentEntry {
  std::string title;
  std::string scene;    ///< relative to the registry's directory
  std::string program;  ///< relative to the registry's directory
  /// '' (the program's controller.mode) or a ControllerMode's name.
  std::string controller;
  std::string sm_file;  ///< state_machine.file (.osd)
  std::string sm_name;  ///< state_machine.name (its RootMachine instance)
  double timeout_s = 60.0;
  bool robot = false;
  std::vector<std::string> metrics;
};

const schema::Block<ExperimentEntry>& registryEntrySchema();

/// Entry `name` of the registry's `experiments:` mapping `node` (at `where`,
/// "<file>: experiments.<name>"), read and range-checked; its
/// state_machine.params are left to the caller.
ConfigResult readExperimentEntry(const YAML::Node& node, const Where& where, ExperimentEntry& out);

/// The phase program a run of `scene_file` takes when it is not given one
/// (`tactile_sim run SCENE`, the tests): the program of the registry's
/// experiments whose scene it is (they must agree), else the registry's
/// `scenes:` entry for the file or for the nearest folder holding it
/// ("params/scenes/curved/"). Registry paths are relative to its directory;
/// `program` is returned absolute. An error names the registry and the scene.
ConfigResult programForScene(const std::string& registry_file, const std::string& scene_file, std::string& program);

/// The registry's key table (Markdown).
std::string registrySchemaMarkdown();

}  // namespace config
}  // namespace tactile
