#include "tactile_fri/krl_settings.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

namespace tactile {
namespace fri {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The file's lines without KRL comments, upper-cased; false when unreadable.
bool readKrl(const std::string& path, std::vector<std::string>& lines) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    bool in_str = false;
    std::size_t cut = line.size();
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '"') in_str = !in_str;
      else if (line[i] == ';' && !in_str) {
        cut = i;
        break;
      }
    }
    line.resize(cut);
    std::transform(line.begin(), line.end(), line.begin(), [](unsigned char c) { return std::toupper(c); });
    lines.push_back(line);
  }
  return true;
}

/// The first line (index) matching `re`, or lines.size().
std::size_t firstLine(const std::vector<std::string>& lines, const std::regex& re) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (std::regex_search(lines[i], re)) return i;
  return lines.size();
}

/// The last match of `re` (group 1) before line `end`; false when none.
bool lastBefore(const std::vector<std::string>& lines, const std::regex& re, std::size_t end, std::string& value,
                std::size_t& line) {
  bool found = false;
  std::smatch m;
  for (std::size_t i = 0; i < std::min(end, lines.size()); ++i) {
    if (std::regex_search(lines[i], m, re)) {
      value = m[1].str();
      line = i + 1;
      found = true;
    }
  }
  return found;
}

ConfigResult readLoad(const std::string& dat, const std::string& name, KrlSettings& out) {
  std::vector<std::string> lines;
  if (!readKrl(dat, lines)) return ConfigResult::failure(dat + ": cannot read (the .dat beside the .src)");
  const std::string num = "([-+]?[0-9]+(?:\\.[0-9]*)?(?:E[-+]?[0-9]+)?)";
  const std::regex decl("\\bDECL\\s+LOAD\\s+" + name + "\\s*=\\s*\\{\\s*M\\s+" + num + "\\s*,\\s*CM\\s*\\{\\s*X\\s+" +
                        num + "\\s*,\\s*Y\\s+" + num + "\\s*,\\s*Z\\s+" + num);
  std::smatch m;
  for (const std::string& l : lines) {
    if (!std::regex_search(l, m, decl)) continue;
    out.load_mass_kg = std::stod(m[1].str());
    for (int i = 0; i < 3; ++i) out.load_com_m[static_cast<std::size_t>(i)] = 1e-3 * std::stod(m[i + 2].str());
    return ConfigResult::success();
  }
  return ConfigResult::failure(dat + ": no DECL LOAD " + name +
                               " = {M kg, CM {X mm, Y mm, Z mm, ...}, ...} (the load $LOAD names)");
}

/// "= {X 20.0, Y 20.0, Z 20.0, A 2.0, B 2.0, C 2.0}" -> X Y Z A B C; false with `why`.
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
    if (!(v[static_cast<std::size_t>(i)] > 0.0)) {
      why = std::string("component ") + kAxes[i] + " must be > 0";
      return false;
    }
  }
  return true;
}

/// $STIFFNESS.<key> = {...}, the last assignment before line `end`, into `v`.
ConfigResult readAggregate(const std::string& src, const std::vector<std::string>& lines, std::size_t end,
                           const std::string& key, const char* units, std::array<double, 6>& v) {
  std::string rhs;
  std::size_t ln = 0;
  if (!lastBefore(lines, std::regex("\\$STIFFNESS\\." + key + "\\s*(=.*)"), end, rhs, ln))
    return ConfigResult::failure(src + ": no $STIFFNESS." + key + " assignment before friOpen (the KRC would run " +
                                 "with whatever was set before)");
  std::string why;
  if (!parseAggregate(rhs, v, why))
    return ConfigResult::failure(src + ":" + std::to_string(ln) + ": $STIFFNESS." + key + ": " + why + " (" + units +
                                 ")");
  return ConfigResult::success();
}

ConfigResult readLimits(const std::string& src, const std::vector<std::string>& lines, std::size_t open,
                        KrcStiffnessLimits& out) {
  std::array<double, 6> maxforce{}, cpmaxdelta{};
  if (ConfigResult r = readAggregate(src, lines, open, "MAXFORCE", "N, N m", maxforce); !r) return r;
  if (ConfigResult r = readAggregate(src, lines, open, "CPMAXDELTA", "mm, deg", cpmaxdelta); !r) return r;
  for (std::size_t i = 0; i < 6; ++i) {
    out.max_force[i] = maxforce[i];
    out.cp_max_delta[i] = i < 3 ? 1e-3 * cpmaxdelta[i] : cpmaxdelta[i] * kPi / 180.0;
  }
  return ConfigResult::success();
}

}  // namespace

ConfigResult readKrlSettings(const std::string& src, KrlSettings& out) {
  std::vector<std::string> lines;
  if (!readKrl(src, lines)) return ConfigResult::failure(src + ": cannot read (the KRL program, krc/TactileServo.src)");
  const std::size_t start = firstLine(lines, std::regex("\\bFRISTART\\s*\\("));
  const std::size_t open = firstLine(lines, std::regex("\\bFRIOPEN\\s*\\("));
  if (start == lines.size()) return ConfigResult::failure(src + ": no friStart(...) call");
  KrlSettings s;
  std::string v;
  std::size_t ln = 0;
  if (!lastBefore(lines, std::regex("\\$STIFFNESS\\.FRAMETYPE\\s*=\\s*(\\S+)"), start, v, ln))
    return ConfigResult::failure(src + ": no $STIFFNESS.FRAMETYPE before friStart (line " + std::to_string(start + 1) +
                                 "): the axes of estExtTcpFT would be inherited (valid: #BASE, #TOOL)");
  if (v == "#BASE") s.wrench_frame = WrenchFrame::Base;
  else if (v == "#TOOL") s.wrench_frame = WrenchFrame::Tool;
  else
    return ConfigResult::failure(src + ":" + std::to_string(ln) + ": $STIFFNESS.FRAMETYPE = " + v +
                                 ": the simulated KRC knows #BASE (base axes) and #TOOL (tool axes)");
  if (!lastBefore(lines, std::regex("\\$LOAD\\s*=\\s*(\\w+)"), open, v, ln))
    return ConfigResult::failure(src + ": no $LOAD = NAME before friOpen (line " + std::to_string(open + 1) +
                                 "): the pad's load would be inherited");
  std::string dat = src;
  const std::size_t dot = dat.rfind('.');
  dat = (dot == std::string::npos ? dat : dat.substr(0, dot)) + ".dat";
  if (ConfigResult r = readLimits(src, lines, open, s.limits); !r) return r;
  if (ConfigResult r = readLoad(dat, v, s); !r) return r;
  out = s;
  return ConfigResult::success();
}

}  // namespace fri
}  // namespace tactile
