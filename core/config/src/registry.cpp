#include "tactile_config/registry.hpp"

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
              "the servo's phase program: the scene's own (DeployGuard refuses another)")
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

std::string registrySchemaMarkdown() { return schema::markdownSection(registryEntrySchema()); }

}  // namespace config
}  // namespace tactile
