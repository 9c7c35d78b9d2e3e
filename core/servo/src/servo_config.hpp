// Internal: the messages of the servo's configuration errors, shared by the
// control law, the phase program and the safety supervisor
// ("<file>: phases.<phase>.<field> = <value>: <requirement>").
#pragma once

#include <string>

#include "tactile_servo/servo_params.hpp"

namespace tactile {
namespace servo_config {

inline std::string where(const ServoParams& p, const std::string& phase, const std::string& field) {
  std::string s = p.source.empty() ? std::string("<memory>") : p.source;
  s += ": ";
  if (!phase.empty()) s += "phases." + phase + ".";
  return s + field;
}

template <typename T>
ConfigResult err(const ServoParams& p, const std::string& phase, const std::string& field, const T& value,
                 const std::string& req) {
  return rangeError(where(p, phase, field), value, req);
}

}  // namespace servo_config
}  // namespace tactile
