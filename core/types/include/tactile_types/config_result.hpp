// Result of a configure() call. Configuration happens outside the real-time
// path, so the message may allocate. A failed result names the parameter, the
// value given and its valid range, e.g.
//   "features.pitch = -0.001: must be > 0 (m)".
#pragma once

#include <sstream>
#include <string>
#include <utility>

namespace tactile {

class ConfigResult {
 public:
  ConfigResult() = default;
  static ConfigResult success() { return ConfigResult(); }
  static ConfigResult failure(std::string message) {
    ConfigResult r;
    r.ok_ = false;
    r.message_ = std::move(message);
    return r;
  }
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const std::string& message() const { return message_; }

 private:
  bool ok_ = true;
  std::string message_;
};

/// "name = value: requirement" failure helper.
template <typename T>
ConfigResult rangeError(const std::string& name, const T& value, const std::string& requirement) {
  std::ostringstream os;
  os << name << " = " << value << ": " << requirement;
  return ConfigResult::failure(os.str());
}

}  // namespace tactile
