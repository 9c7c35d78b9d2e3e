// tactile_features: run the feature extractor on recorded frames.
//
//   tactile_features [--rows 6 --cols 14 --pitch 0.0034 --threshold N|otsu
//                     --edge-ratio R --c-z M_PER_N] FILE|-
//
// Input: CSV, one frame per line, rows*cols values in newtons, row-major (row 0
// first) in the {s} layout. Blank lines and lines starting with '#' are skipped.
// Output: one JSON object per frame on stdout. A malformed line produces an
// error on stderr naming the line, and processing continues; the exit code is
// 0 when every line was processed, 1 when any line failed, 2 on usage errors.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "tactile_features/extractor.hpp"

namespace {

void usage() {
  std::cerr << "usage: tactile_features [--rows N] [--cols N] [--pitch M] [--threshold N|otsu]\n"
               "                        [--edge-ratio R] [--c-z M_PER_N] FILE|-\n"
               "Reads CSV frames (rows*cols newtons per line, row-major) and prints one JSON object per frame.\n";
}

bool parseDouble(const char* s, double& v) {
  char* end = nullptr;
  errno = 0;
  v = std::strtod(s, &end);
  return end != s && *end == '\0' && errno == 0;
}

// Parses one CSV line into `frame`; on failure fills `why`.
bool parseLine(const std::string& line, tactile::TactileFrame& frame, int expected, std::string& why) {
  int count = 0;
  const char* p = line.c_str();
  while (true) {
    while (*p == ' ' || *p == '\t') ++p;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p) {
      why = "value " + std::to_string(count + 1) + " is not a number";
      return false;
    }
    if (count < expected) frame.force[static_cast<std::size_t>(count)] = v;
    ++count;
    p = end;
    while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
    if (*p == '\0') break;
    if (*p != ',') {
      why = "unexpected character '" + std::string(1, *p) + "' after value " + std::to_string(count);
      return false;
    }
    ++p;
  }
  if (count != expected) {
    why = "expected " + std::to_string(expected) + " values, got " + std::to_string(count);
    return false;
  }
  return true;
}

void printJson(const tactile::ContactFeatures& f) {
  std::printf(
      "{\"cop_x\":%.9g,\"cop_y\":%.9g,\"coc_x\":%.9g,\"coc_y\":%.9g,\"dzmp_x\":%.9g,\"dzmp_y\":%.9g,"
      "\"alpha_z\":%.9g,\"alpha_defined\":%s,\"force\":%.9g,\"d_z\":%.9g,\"lambda1\":%.9g,\"lambda2\":%.9g,\"area\":%u,"
      "\"max_taxel\":%.9g,\"contact\":\"%s\",\"status\":\"%s\"}\n",
      f.cop_x, f.cop_y, f.coc_x, f.coc_y, f.dzmp_x, f.dzmp_y, f.alpha_z, f.alpha_defined ? "true" : "false", f.force, f.d_z, f.lambda1, f.lambda2,
      static_cast<unsigned>(f.area), f.max_taxel, tactile::toString(f.contact), tactile::toString(f.status));
}

}  // namespace

int main(int argc, char** argv) {
  tactile::FeatureParams params;
  std::string file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&](double& v) {
      if (i + 1 >= argc || !parseDouble(argv[i + 1], v)) {
        std::cerr << "tactile_features: " << a << " needs a numeric value\n";
        std::exit(2);
      }
      ++i;
    };
    double v = 0;
    if (a == "--rows") {
      next(v);
      params.rows = static_cast<int>(v);
    } else if (a == "--cols") {
      next(v);
      params.cols = static_cast<int>(v);
    } else if (a == "--pitch") {
      next(params.pitch);
    } else if (a == "--edge-ratio") {
      next(params.edge_ratio);
      params.edge_ratio_exit = params.edge_ratio >= 1.25 ? 0.8 * params.edge_ratio : 1.0;
    } else if (a == "--c-z") {
      next(params.c_z);
    } else if (a == "--threshold") {
      if (i + 1 < argc && std::string(argv[i + 1]) == "otsu") {
        params.threshold_mode = tactile::ThresholdMode::Otsu;
        ++i;
      } else {
        next(params.threshold);
        params.contact_threshold = params.threshold;
      }
    } else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else if (a == "-" || a[0] != '-') {
      if (!file.empty()) {
        std::cerr << "tactile_features: more than one input given\n";
        return 2;
      }
      file = a;
    } else {
      std::cerr << "tactile_features: unknown option " << a << "\n";
      usage();
      return 2;
    }
  }
  if (file.empty()) {
    usage();
    return 2;
  }
  tactile::FeatureExtractor ex;
  const tactile::ConfigResult cr = ex.configure(params);
  if (!cr) {
    std::cerr << "tactile_features: " << cr.message() << "\n";
    return 2;
  }
  std::ifstream fin;
  std::istream* in = &std::cin;
  if (file != "-") {
    fin.open(file);
    if (!fin) {
      std::cerr << "tactile_features: cannot open " << file << "\n";
      return 2;
    }
    in = &fin;
  }
  tactile::TactileFrame frame;
  frame.rows = static_cast<uint16_t>(params.rows);
  frame.cols = static_cast<uint16_t>(params.cols);
  const int expected = params.rows * params.cols;
  std::string line, why;
  long lineno = 0, failed = 0, frames = 0;
  tactile::ContactFeatures feat;
  while (std::getline(*in, line)) {
    ++lineno;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    if (!parseLine(line, frame, expected, why)) {
      std::cerr << "tactile_features: " << (file == "-" ? "<stdin>" : file) << ":" << lineno << ": " << why << "\n";
      ++failed;
      continue;
    }
    frame.seq = static_cast<uint32_t>(frames++);
    const tactile::FeatureStatus st = ex.step(frame, feat);
    if (!tactile::usable(st)) {
      std::cerr << "tactile_features: " << (file == "-" ? "<stdin>" : file) << ":" << lineno
                << ": frame rejected: " << tactile::toString(st) << "\n";
      ++failed;
      continue;
    }
    printJson(feat);
  }
  return failed ? 1 : 0;
}
