#include "tactile_lab/krl_stiffness.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace tactile {
namespace lab {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

/// "{X 20.0, Y 20.0, Z 20.0, A 2.0, B 2.0, C 2.0}" -> X Y Z A B C; false with `why`.
bool parseAggregate(const std::string& text, std::array<double, 6>& v, std::string& why) {
  static const char kAxes[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};
  const std::size_t open = text.find('{'), close = text.find('}');
  if (open == std::string::npos || close == std::string::npos || close < open) {
    why = "expected {X .., Y .., Z .., A .., B .., C ..}";
    return false;
  }
  std::array<bool, 6> seen{};
  std::istringstream items(text.substr(open + 1, close - open - 1));
  std::string item;
  while (std::getline(items, item, ',')) {
    std::istringstream is(item);
    std::string axis, value;
    if (!(is >> axis >> value)) continue;
    int k = -1;
    for (int i = 0; i < 6; ++i)
      if (axis.size() == 1 && axis[0] == kAxes[i]) k = i;
    char* end = nullptr;
    const double x = std::strtod(value.c_str(), &end);
    if (k < 0 || *end != '\0' || !std::isfinite(x)) {
      why = "'" + item + "' is not one of X, Y, Z, A, B, C with a number";
      return false;
    }
    v[static_cast<std::size_t>(k)] = x;
    seen[static_cast<std::size_t>(k)] = true;
  }
  for (int i = 0; i < 6; ++i) {
    if (!seen[static_cast<std::size_t>(i)]) {
      why = std::string("component ") + kAxes[i] + " missing";
      return false;
    }
  }
  return true;
}

}  // namespace

ConfigResult readKrlStiffnessLimits(const std::string& path, fri::KrcStiffnessLimits& out) {
  std::ifstream in(path);
  if (!in) return ConfigResult::failure(path + ": cannot read the KRL program");
  std::array<double, 6> maxforce{}, cpmaxdelta{};
  int line_force = 0, line_delta = 0, ln = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++ln;
    const std::string code = upper(line.substr(0, line.find(';')));
    if (code.find("FRIOPEN") != std::string::npos) break;  // the values in force at friOpen
    for (int which = 0; which < 2; ++which) {
      const char* key = which == 0 ? "$STIFFNESS.MAXFORCE" : "$STIFFNESS.CPMAXDELTA";
      const std::size_t at = code.find(key);
      if (at == std::string::npos || code.find('=', at) == std::string::npos) continue;
      std::string why;
      if (!parseAggregate(code.substr(code.find('=', at)), which == 0 ? maxforce : cpmaxdelta, why))
        return ConfigResult::failure(path + ":" + std::to_string(ln) + ": " + key + ": " + why);
      (which == 0 ? line_force : line_delta) = ln;
    }
  }
  if (line_force == 0 || line_delta == 0)
    return ConfigResult::failure(path + ": no $STIFFNESS." + (line_force == 0 ? "MAXFORCE" : "CPMAXDELTA") +
                                 " assignment before friOpen (the KRC would run with whatever was set before)");
  for (std::size_t i = 0; i < 6; ++i) {
    if (!(maxforce[i] > 0.0))
      return ConfigResult::failure(path + ":" + std::to_string(line_force) +
                                   ": $STIFFNESS.MAXFORCE: every component must be > 0 (N, N m)");
    if (!(cpmaxdelta[i] > 0.0))
      return ConfigResult::failure(path + ":" + std::to_string(line_delta) +
                                   ": $STIFFNESS.CPMAXDELTA: every component must be > 0 (mm, deg)");
    out.max_force[i] = maxforce[i];
    out.cp_max_delta[i] = i < 3 ? 1e-3 * cpmaxdelta[i] : cpmaxdelta[i] * kPi / 180.0;
  }
  return ConfigResult::success();
}

}  // namespace lab
}  // namespace tactile
