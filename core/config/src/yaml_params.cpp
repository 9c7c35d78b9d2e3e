#include "tactile_config/yaml_params.hpp"

#include "tactile_config/schema_yaml.hpp"

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

ConfigResult checkNestedKeys(const YAML::Node& node, const Where& where, const std::vector<std::string>& keys,
                             const std::string& prefix) {
  if (!node) return ConfigResult::success();
  if (!node.IsMap()) return ConfigResult::failure(where.str() + ": must be a mapping");
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    const std::string full = prefix + k;
    bool leaf = false, branch = false;
    for (const std::string& key : keys) {
      leaf = leaf || key == full;
      branch = branch || key.rfind(full + ".", 0) == 0;
    }
    if (branch && !leaf) {
      const ConfigResult r = checkNestedKeys(kv.second, where.child(k), keys, full + ".");
      if (!r) return r;
      continue;
    }
    if (leaf) continue;
    std::vector<std::string> here;  // the first components of the keys at this level
    for (const std::string& key : keys) {
      if (key.rfind(prefix, 0) != 0) continue;
      const std::string rest = key.substr(prefix.size());
      const std::string first = rest.substr(0, rest.find('.'));
      bool seen = false;
      for (const std::string& h : here) seen = seen || h == first;
      if (!seen) here.push_back(first);
    }
    std::string list;
    for (const std::string& h : here) list += (list.empty() ? "" : ", ") + h;
    return ConfigResult::failure(where.child(k).str() + ": unknown key (allowed: " + list + ")");
  }
  return ConfigResult::success();
}

YAML::Node nodeAt(const YAML::Node& node, const std::string& dotted) {
  if (!node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  const std::size_t dot = dotted.find('.');
  const YAML::Node child = node[dotted.substr(0, dot)];  // const: never inserts
  if (dot == std::string::npos || !child) return child;
  return nodeAt(child, dotted.substr(dot + 1));
}

namespace detail {

ConfigResult readNumber(const YAML::Node& v, const Where& w, double& out) {
  if (!v.IsScalar()) return ConfigResult::failure(w.str() + ": must be a number");
  return readScalar(v, w, out);
}

ConfigResult readChoiceIndex(const YAML::Node& v, const Where& w, const char* names, int& index) {
  std::string s;  // a null value (`key:` or `~`) is the empty name
  ConfigResult r = v.IsNull() ? ConfigResult::success() : readScalar(v, w, s);
  if (!r) return r;
  const std::string all(names);
  std::string allowed;
  std::size_t start = 0;
  for (int i = 0;; ++i) {
    const std::size_t bar = all.find('|', start);
    const std::string name = all.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
    if (name == s) {
      index = i;
      return r;
    }
    allowed += (i ? ", " : "") + (name.empty() ? std::string("''") : name);
    if (bar == std::string::npos) break;
    start = bar + 1;
  }
  return ConfigResult::failure(w.str() + ": '" + s + "': must be one of " + allowed);
}

ConfigResult readNames(const YAML::Node& v, const Where& w, std::vector<std::string>& out) {
  if (!v.IsSequence()) return ConfigResult::failure(w.str() + ": must be a list of names ([]: none)");
  return readScalar(v, w, out);
}

ConfigResult readTriple(const YAML::Node& v, const Where& w, std::array<double, 3>& out) {
  std::vector<double> x;
  ConfigResult r = readScalar(v, w, x);
  if (!r) return r;
  if (x.size() != 3) return ConfigResult::failure(w.str() + ": must have 3 entries, has " + std::to_string(x.size()));
  out = {x[0], x[1], x[2]};
  return r;
}

ConfigResult readVector(const YAML::Node& v, const Where& w, const char* labels, double* out) {
  const int n = schema::detail::choiceCount(labels);
  if (v.IsSequence()) {
    if (static_cast<int>(v.size()) != n)
      return ConfigResult::failure(w.str() + ": must have " + std::to_string(n) + " entries, has " +
                                   std::to_string(v.size()));
    for (int i = 0; i < n; ++i) {
      ConfigResult r = readNumber(v[static_cast<std::size_t>(i)], w.child(std::to_string(i)), out[i]);
      if (!r) return r;
    }
    return ConfigResult::success();
  }
  if (!v.IsMap()) return ConfigResult::failure(w.str() + ": must be a list of " + std::to_string(n) + " numbers or a mapping");
  for (const auto& kv : v) {
    const std::string k = kv.first.as<std::string>();
    int idx = -1;
    std::string allowed;
    for (int i = 0; i < n; ++i) {
      const std::string name = schema::detail::choiceName(labels, i);
      if (k == name) idx = i;
      allowed += (i ? ", " : "") + (name.empty() ? std::string("''") : name);
    }
    if (idx < 0) return ConfigResult::failure(w.child(k).str() + ": unknown name (allowed: " + allowed + ")");
    ConfigResult r = readNumber(kv.second, w.child(k), out[idx]);
    if (!r) return r;
  }
  return ConfigResult::success();
}

}  // namespace detail

ConfigResult locate(const ConfigResult& r, const Where& where) {
  if (r.ok()) return r;
  return ConfigResult::failure(where.file.empty() ? r.message() : where.file + ": " + r.message());
}

}  // namespace config
}  // namespace tactile
