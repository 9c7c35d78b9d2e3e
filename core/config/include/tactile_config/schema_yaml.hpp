// Reading a declared block (tactile_types/schema.hpp) from YAML: the keys the
// block declares and no other, at every level of its nested mappings; each
// value parsed as its Field's kind says; an absent key keeps the member's
// value (the default, or what a program's base set). The ranges are not
// checked here but by the cores' configure(), from the same declaration.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace config {

/// Rejects keys of `node` that are not among `keys` (dotted paths: "a.b" is
/// key b of the mapping a) at the level `prefix`; names the keys allowed there.
ConfigResult checkNestedKeys(const YAML::Node& node, const Where& where, const std::vector<std::string>& keys,
                             const std::string& prefix = "");

/// The node at a dotted key ("a.b"), or an undefined node.
YAML::Node nodeAt(const YAML::Node& node, const std::string& dotted);

template <class S>
std::vector<std::string> keysOf(const schema::Block<S>& b) {
  std::vector<std::string> k;
  for (const auto& f : b.fields) k.push_back(f.key);
  return k;
}

namespace detail {

ConfigResult readNumber(const YAML::Node& v, const Where& w, double& out);
ConfigResult readChoiceIndex(const YAML::Node& v, const Where& w, const char* names, int& index);
ConfigResult readNames(const YAML::Node& v, const Where& w, std::vector<std::string>& out);
ConfigResult readTriple(const YAML::Node& v, const Where& w, std::array<double, 3>& out);
/// `labels` ("x|y|z") numbers: a list of all of them, or a mapping over some
/// (the others keep their value).
ConfigResult readVector(const YAML::Node& v, const Where& w, const char* labels, double* out);

template <class T>
ConfigResult readScalar(const YAML::Node& v, const Where& w, T& out) {
  try {
    out = v.as<T>();
  } catch (const YAML::Exception&) {
    return ConfigResult::failure(w.str() + ": cannot parse '" + YAML::Dump(v) + "'");
  }
  return ConfigResult::success();
}

template <class S>
ConfigResult readField(const YAML::Node& v, const Where& w, const schema::Field<S>& f, S& s) {
  using schema::Kind;
  switch (f.kind) {
    case Kind::Number: {
      double x = 0.0;
      ConfigResult r = readNumber(v, w, x);
      if (r) f.store(s, x);
      return r;
    }
    case Kind::Integer: return readScalar(v, w, f.integer(s));
    case Kind::Flag: return readScalar(v, w, f.flag(s));
    case Kind::Choice: {
      int i = f.get(s);
      ConfigResult r = readChoiceIndex(v, w, f.range, i);
      if (r) f.set(s, i);
      return r;
    }
    case Kind::Text: return readScalar(v, w, f.text(s));
    case Kind::Names: return readNames(v, w, f.names(s));
    case Kind::Triple: return readTriple(v, w, f.triple(s));
    case Kind::Vector: return readVector(v, w, f.labels, f.vec(s));
    case Kind::Custom: return ConfigResult::success();  // the block's own code reads it
  }
  return ConfigResult::success();
}

/// The variants every field of `key` belongs to ("" if one of them belongs
/// to all).
template <class S>
std::string variantsOf(const schema::Block<S>& b, const std::string& key) {
  std::string all;
  for (const auto& f : b.fields) {
    if (key != f.key) continue;
    if (!*f.when) return "";
    all += (all.empty() ? "" : "|") + std::string(f.when);
  }
  return all;
}

/// A key given for another variant, or a required key absent for this one.
template <class S>
ConfigResult checkPresence(const YAML::Node& node, const Where& where, const schema::Block<S>& b, const S& s) {
  const std::string var = schema::variant(b, s);
  for (const auto& f : b.fields) {
    const bool given = static_cast<bool>(nodeAt(node, f.key));
    const std::string when = variantsOf(b, f.key);
    if (given && !when.empty() && !schema::detail::inList(when.c_str(), var))
      return ConfigResult::failure(where.child(f.key).str() + ": only for " + schema::quotedList(when.c_str()));
    if (!given && f.required && schema::applies(f, var))
      return ConfigResult::failure(where.child(f.key).str() + ": required" + (*f.when ? " for '" + var + "'" : ""));
  }
  return ConfigResult::success();
}

}  // namespace detail

/// Fills `s` from the block `node` at `where` (absent: nothing changes),
/// then rejects a key of another variant and requires the required ones.
/// `also`: the keys of another block read from the same mapping (a block
/// split over two structs, as speed_law's SpeedLawConfig and SpeedLawParams).
template <class S>
ConfigResult readBlock(const YAML::Node& node, const Where& where, const schema::Block<S>& b, S& s,
                       const std::vector<std::string>& also = {}) {
  if (!node) return ConfigResult::success();
  std::vector<std::string> keys = keysOf(b);
  keys.insert(keys.end(), also.begin(), also.end());
  ConfigResult r = checkNestedKeys(node, where, keys);
  if (!r) return r;
  for (const auto& f : b.fields) {
    const YAML::Node v = nodeAt(node, f.key);
    if (v && !(r = detail::readField(v, where.child(f.key), f, s))) return r;
  }
  return detail::checkPresence(node, where, b, s);
}

}  // namespace config
}  // namespace tactile
