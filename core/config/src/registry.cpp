#include "tactile_config/registry.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "tactile_config/schema_yaml.hpp"

namespace tactile {
namespace config {

namespace {

constexpr const char* kControllers = "|proposed|baseline|no_rotation";  // '' first: the program's mode

}  // namespace

const schema::Block<ExperimentEntry>& registryEntrySchema() {
  using S = ExperimentEntry;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "experiments.<name>",
      "one experiment of the registry (experiments.yaml; tactile::DeployGuard, the run scripts); paths relative "
      "to the registry's directory",
      {F::str("title", TACTILE_SCHEMA_REF(S, title), "what it is, with the paper's section and figure").form("text"),
       F::str("scene", TACTILE_SCHEMA_REF(S, scene), "the simulated world (params/scenes/*.yaml)").form("a path").needed(),
       F::str("program", TACTILE_SCHEMA_REF(S, program),
              "the servo's phase program (a scene names none)")
           .form("a path")
           .needed(),
       F::choice(
           "controller", kControllers,
           [](const S& s) {
             for (int i = 0; i < schema::detail::choiceCount(kControllers); ++i)
               if (schema::detail::choiceName(kControllers, i) == s.controller) return i;
             return -1;
           },
           [](S& s, int i) { s.controller = schema::detail::choiceName(kControllers, i); },
           "'': the program's controller.mode; else the mode the run uses")
           .needed(),
       F::str("state_machine.file", TACTILE_SCHEMA_REF(S, sm_file), "the experiment's state machines (.osd)")
           .form("a path")
           .needed(),
       F::str("state_machine.name", TACTILE_SCHEMA_REF(S, sm_name), "its RootMachine instance").needed(),
       F::custom("state_machine.params", "", "the machine's `param`s, each of its declared type", "{}",
                 "set after activate(), before start() (DeployGuard checks them against the .osd)"),
       F::num("timeout_s", "s", "> 0", TACTILE_SCHEMA_REF(S, timeout_s),
              "the longest wall-clock wait of the run scripts for the machine")
           .needed(),
       F::yesNo("robot", TACTILE_SCHEMA_REF(S, robot), "it also runs on the real arm (the robot entry scripts)"),
       F::list("metrics", TACTILE_SCHEMA_REF(S, metrics), "the summary.json keys its report shows")}};
  return b;
}

ConfigResult readExperimentEntry(const YAML::Node& node, const Where& where, ExperimentEntry& out) {
  if (!node.IsMap()) return ConfigResult::failure(where.str() + ": must be a mapping");
  ExperimentEntry e;
  ConfigResult r = readBlock(node, where, registryEntrySchema(), e);
  if (!r) return r;
  if (!(r = schema::checkRanges(registryEntrySchema(), e, where.str()))) return r;
  out = e;
  return r;
}

namespace {

namespace fs = std::filesystem;

// The path made absolute and canonical as far as it exists (lexically
// normal where the file system cannot answer: no exception escapes).
fs::path normal(const fs::path& p) {
  std::error_code ec;
  fs::path abs = fs::absolute(p, ec);
  if (ec) abs = p;
  const fs::path c = fs::weakly_canonical(abs, ec);
  return ec ? abs.lexically_normal() : c;
}

// The program of the experiments whose scene is `scene`; an error when two differ.
ConfigResult programOfExperiments(const YAML::Node& all, const std::string& registry, const fs::path& dir,
                                  const fs::path& scene, std::optional<fs::path>& found) {
  if (!all || !all.IsMap()) return ConfigResult::failure(registry + ": no `experiments:` mapping");
  std::string first;
  for (const auto& kv : all) {
    const YAML::Node e = kv.second;
    if (!e.IsMap() || !e["scene"] || !e["program"] || normal(dir / e["scene"].as<std::string>()) != scene) continue;
    const fs::path program = normal(dir / e["program"].as<std::string>());
    if (found && *found != program)
      return ConfigResult::failure(registry + ": experiments." + kv.first.as<std::string>() + ".program (" +
                                   program.string() + ") differs from experiments." + first +
                                   ".program for the same scene: give the run its program");
    if (!found) first = kv.first.as<std::string>();
    found = program;
  }
  return ConfigResult::success();
}

// The `scenes:` entry of the scene, or of the nearest folder holding it.
ConfigResult programOfScenes(const YAML::Node& map, const std::string& registry, const fs::path& dir,
                             const fs::path& scene, std::optional<fs::path>& found) {
  if (!map) return ConfigResult::success();
  if (!map.IsMap()) return ConfigResult::failure(registry + ": scenes: must map a scene or a folder to a program");
  std::size_t best = 0;
  for (const auto& kv : map) {
    const fs::path key = normal(dir / kv.first.as<std::string>());
    const auto [end, unused] = std::mismatch(key.begin(), key.end(), scene.begin(), scene.end());
    const std::size_t depth = static_cast<std::size_t>(std::distance(key.begin(), key.end()));
    if (end != key.end() || depth <= best) continue;
    if (!kv.second.IsScalar())
      return ConfigResult::failure(registry + ": scenes." + kv.first.as<std::string>() + ": must be a program's path");
    best = depth;
    found = normal(dir / kv.second.as<std::string>());
  }
  return ConfigResult::success();
}

}  // namespace

ConfigResult programForScene(const std::string& registry_file, const std::string& scene_file, std::string& program) {
  YAML::Node root;
  ConfigResult r = loadFile(registry_file, root);
  if (!r) return r;
  std::error_code ec;
  const fs::path dir = fs::absolute(fs::path(registry_file), ec).parent_path();
  const fs::path scene = normal(scene_file);
  std::optional<fs::path> found;
  try {
    if (!(r = programOfExperiments(root["experiments"], registry_file, dir, scene, found))) return r;
    if (!found && !(r = programOfScenes(root["scenes"], registry_file, dir, scene, found))) return r;
  } catch (const YAML::Exception& e) {
    return ConfigResult::failure(registry_file + ": " + e.what() + " (scene, program and scenes: entries are paths)");
  }
  if (!found)
    return ConfigResult::failure(registry_file + ": no program for the scene " + scene_file +
                                 ": no experiment runs it and `scenes:` lists neither it nor a folder holding it; "
                                 "give the run its program (tactile_sim run SCENE --program FILE)");
  program = found->string();
  return ConfigResult::success();
}

std::string registrySchemaMarkdown() { return schema::markdownSection(registryEntrySchema()); }

}  // namespace config
}  // namespace tactile
