// What the project's command-line tools share: option values (the value after
// an option, or a number in a range; a missing or bad value ends the tool with
// exit code 2 (usage) and a message naming the tool, the option and the
// range), printf-style text and JSON strings for their reports.
#pragma once

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace tactile {
namespace config {

class CliArgs {
 public:
  CliArgs(const char* tool, int argc, char** argv) : tool_(tool), argc_(argc), argv_(argv) {}
  /// The value after the option at argv[i]; advances i.
  std::string value(int& i) const {
    if (i + 1 >= argc_) {
      std::fprintf(stderr, "%s: %s needs a value\n", tool_, argv_[i]);
      std::exit(2);
    }
    ++i;
    return argv_[i];
  }
  /// The value after the option at argv[i] as a number in [lo, hi]; advances i.
  double number(int& i, double lo, double hi) const {
    const char* opt = argv_[i];
    const std::string v = value(i);
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !(x >= lo && x <= hi)) {
      std::fprintf(stderr, "%s: %s = '%s': must be a number in [%g, %g]\n", tool_, opt, v.c_str(), lo, hi);
      std::exit(2);
    }
    return x;
  }

 private:
  const char* tool_;
  int argc_;
  char** argv_;
};

/// printf into a std::string (reports; at most 1023 characters).
inline std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
inline std::string fmt(const char* f, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

/// `s` as a JSON string literal (quotes, backslashes and control characters escaped).
inline std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') o += '\\';
    if (u < 0x20) o += fmt("\\u%04x", static_cast<unsigned>(u));
    else o += ch;
  }
  return o + "\"";
}

}  // namespace config
}  // namespace tactile
