#include "tactile_config/yaml_params.hpp"

#include <cmath>
#include <cstring>
#include <vector>

namespace tactile {
namespace config {

ConfigResult loadFile(const std::string& file, YAML::Node& out) {
  try {
    out = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    return ConfigResult::failure(file + ": cannot open file");
  } catch (const YAML::ParserException& e) {
    return ConfigResult::failure(file + ": YAML error at line " + std::to_string(e.mark.line + 1) + ", column " +
                                 std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (!out || !out.IsMap()) return ConfigResult::failure(file + ": top level must be a mapping");
  return ConfigResult::success();
}

ConfigResult checkKeys(const YAML::Node& node, const Where& where, std::initializer_list<const char*> allowed) {
  if (!node) return ConfigResult::success();
  if (!node.IsMap()) return ConfigResult::failure(where.str() + ": must be a mapping");
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    bool ok = false;
    for (const char* a : allowed) ok = ok || k == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      return ConfigResult::failure(where.child(k).str() + ": unknown key (allowed: " + list + ")");
    }
  }
  return ConfigResult::success();
}

ConfigResult readVec3(const YAML::Node& node, const char* key, std::array<double, 3>& v, const Where& where) {
  if (!node[key]) return ConfigResult::success();
  std::vector<double> x;
  ConfigResult r = read(node, key, x, where);
  if (!r) return r;
  const std::string at = where.child(key).str() + ": ";
  if (x.size() != 3) return ConfigResult::failure(at + "must have 3 entries, has " + std::to_string(x.size()));
  for (double e : x)
    if (!std::isfinite(e)) return ConfigResult::failure(at + "must be finite");
  v = {x[0], x[1], x[2]};
  return ConfigResult::success();
}

ConfigResult locate(const ConfigResult& r, const Where& where) {
  if (r.ok()) return r;
  return ConfigResult::failure(where.file.empty() ? r.message() : where.file + ": " + r.message());
}

}  // namespace config
}  // namespace tactile
