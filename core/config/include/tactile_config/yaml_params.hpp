// Reading parameter files (YAML) with errors that name the file, the key path
// and the valid range. The deployer (through the RTT components' properties
// "param_file") and the headless runner load the same files through these
// functions, so one set of files serves both hosts.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <initializer_list>
#include <string>

#include "tactile_types/config_result.hpp"

namespace tactile {
namespace config {

/// Where a node lives, for messages: "file.yaml: features.threshold".
struct Where {
  std::string file;
  std::string path;
  Where child(const std::string& key) const { return {file, path.empty() ? key : path + "." + key}; }
  std::string str() const { return (file.empty() ? std::string("<memory>") : file) + ": " + path; }
};

/// Load a YAML file; failure names the file and the parser's line/column.
ConfigResult loadFile(const std::string& file, YAML::Node& out);

/// Reject keys of `node` not in `allowed` (catches typos in parameter files).
ConfigResult checkKeys(const YAML::Node& node, const Where& where, std::initializer_list<const char*> allowed);

/// Read an optional scalar: absent keeps `value`; present but unparsable fails.
template <typename T>
ConfigResult read(const YAML::Node& node, const char* key, T& value, const Where& where) {
  const YAML::Node n = node[key];
  if (!n) return ConfigResult::success();
  try {
    value = n.as<T>();
  } catch (const YAML::Exception& e) {
    return ConfigResult::failure(where.child(key).str() + ": cannot parse '" + YAML::Dump(n) + "'");
  }
  return ConfigResult::success();
}

/// Read an optional [x, y, z] of finite numbers: absent keeps `v`; another
/// length or a non-finite entry fails naming the key.
ConfigResult readVec3(const YAML::Node& node, const char* key, std::array<double, 3>& v, const Where& where);

/// Prefix a failure with the file/path it came from.
ConfigResult locate(const ConfigResult& r, const Where& where);

}  // namespace config
}  // namespace tactile
