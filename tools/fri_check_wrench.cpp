#include "fri_check_wrench.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/params_io.hpp"
#include "tactile_fri/wrench_checks.hpp"

namespace tactile {
namespace fri {

namespace {

int usage(const std::string& msg) {
  std::fprintf(stderr,
               "fri_check: %s\nusage: fri_check --wrench-check --mass KG --tare FILE --loaded FILE [--params FILE] "
               "[--direction base:X,Y,Z|tool:X,Y,Z]\n"
               "       fri_check --load-data --sensor-params FILE [--params FILE] [--mass-tol KG] [--com-tol M] "
               "REST1 REST2 REST3 [...]\n",
               msg.c_str());
  return 1;
}

bool number(const char* s, double& v) {
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(v);
}

/// fri.yaml's wrench_frame (default base without --params); false on an error (printed).
bool configuredFrame(const std::string& params, WrenchFrame& frame) {
  BridgeParams bp;
  UdpParams up;
  if (!params.empty()) {
    if (ConfigResult r = loadBridgeParamsFile(params, bp, up); !r) {
      std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
      return false;
    }
  }
  frame = bp.wrench_frame;
  return true;
}

/// A recording's mean at rest; false on an error (printed).
bool loadRest(const std::string& file, RestMean& m) {
  std::vector<WrenchSample> s;
  ConfigResult r = readRecording(file, s);
  if (r) r = restMean(file, s, m);
  if (!r) std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
  return static_cast<bool>(r);
}

bool parseDirection(const std::string& s, KnownWeight& kw) {
  const std::size_t colon = s.find(':');
  if (colon == std::string::npos) return false;
  const std::string axes = s.substr(0, colon);
  if (axes != "base" && axes != "tool") return false;
  double v[3];
  char tail = 0;
  if (std::sscanf(s.c_str() + colon + 1, "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3) return false;
  const KDL::Vector d(v[0], v[1], v[2]);
  if (!(d.Norm() > 1e-6) || !std::isfinite(d.Norm())) return false;
  kw.dir = d / d.Norm();
  kw.dir_in_tool = axes == "tool";
  return true;
}

}  // namespace

int runWrenchCheck(int argc, char** argv) {
  KnownWeight kw;
  kw.mass_kg = 0.0;
  std::string tare, loaded, params;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--wrench-check") continue;
    if (a == "--mass" && has) {
      if (!number(argv[++i], kw.mass_kg) || kw.mass_kg <= 0.0 || kw.mass_kg > 50.0)
        return usage("--mass must be in (0, 50] kg");
    } else if (a == "--tare" && has) {
      tare = argv[++i];
    } else if (a == "--loaded" && has) {
      loaded = argv[++i];
    } else if (a == "--params" && has) {
      params = argv[++i];
    } else if (a == "--direction" && has) {
      if (!parseDirection(argv[++i], kw)) return usage("--direction must be base:X,Y,Z or tool:X,Y,Z (not all 0)");
    } else {
      return usage("unknown or incomplete argument '" + a + "'");
    }
  }
  if (kw.mass_kg <= 0.0 || tare.empty() || loaded.empty()) return usage("--mass, --tare and --loaded are required");
  WrenchFrame frame = WrenchFrame::Base;
  RestMean t, l;
  if (!configuredFrame(params, frame) || !loadRest(tare, t) || !loadRest(loaded, l)) return 1;
  std::printf("fri_check: known weight; the bridge reads estExtTcpFT in %s axes (%s fri.wrench_frame)\n",
              toString(frame), params.empty() ? "the default" : (params + ":").c_str());
  const WeightResult r = checkKnownWeight(t, l, kw, frame);
  for (const std::string& line : r.lines) std::printf("%s\n", line.c_str());
  return r.verdict == WeightVerdict::Correct ? 0 : 3;
}

int runLoadData(int argc, char** argv) {
  std::string params, sensor;
  std::vector<std::string> files;
  double mass_tol = kMassTolKg, com_tol = kComTolM;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    if (a == "--load-data") continue;
    if (a == "--params" && has) {
      params = argv[++i];
    } else if (a == "--sensor-params" && has) {
      sensor = argv[++i];
    } else if (a == "--mass-tol" && has) {
      if (!number(argv[++i], mass_tol) || mass_tol <= 0.0 || mass_tol > 5.0) return usage("--mass-tol must be in (0, 5] kg");
    } else if (a == "--com-tol" && has) {
      if (!number(argv[++i], com_tol) || com_tol <= 0.0 || com_tol > 0.5) return usage("--com-tol must be in (0, 0.5] m");
    } else if (a.rfind("--", 0) == 0) {
      return usage("unknown or incomplete argument '" + a + "'");
    } else {
      files.push_back(a);
    }
  }
  if (sensor.empty()) return usage("--sensor-params FILE (with pad: pad_mass_kg, pad_com_m) is required");
  if (files.size() < 3) return usage("at least 3 recordings at rest, in different orientations");
  YAML::Node root;
  ConfigResult r = config::loadFile(sensor, root);
  LoadModel model;
  std::array<double, 3> com{};
  const config::Where where{sensor, "pad"};
  if (r && !root["pad"]) r = ConfigResult::failure(sensor + ": no pad: (pad_mass_kg, pad_com_m)");
  if (r && !root["pad"]["pad_mass_kg"]) r = ConfigResult::failure(where.child("pad_mass_kg").str() + ": missing");
  if (r) r = config::read(root["pad"], "pad_mass_kg", model.mass_kg, where);
  if (r) r = config::readVec3(root["pad"], "pad_com_m", com, where);
  if (r && !(model.mass_kg >= 0.0 && model.mass_kg <= 20.0))
    r = rangeError(where.child("pad_mass_kg").str(), model.mass_kg, "must be in [0, 20] kg");
  if (!r) {
    std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
    return 1;
  }
  model.com_m = KDL::Vector(com[0], com[1], com[2]);
  WrenchFrame frame = WrenchFrame::Base;
  if (!configuredFrame(params, frame)) return 1;
  std::vector<RestMean> rests(files.size());
  for (std::size_t i = 0; i < files.size(); ++i)
    if (!loadRest(files[i], rests[i])) return 1;
  std::printf("fri_check: load data from %zu orientations at rest; estExtTcpFT in %s axes (%s fri.wrench_frame); "
              "modelled pad %.3f kg at [%.1f, %.1f, %.1f] mm (%s pad:)\n",
              files.size(), toString(frame), params.empty() ? "the default" : (params + ":").c_str(), model.mass_kg,
              1e3 * com[0], 1e3 * com[1], 1e3 * com[2], sensor.c_str());
  const LoadResult lr = fitLoad(rests, frame, model, mass_tol, com_tol);
  for (const std::string& line : lr.lines) std::printf("%s\n", line.c_str());
  return lr.verdict == LoadVerdict::Ok ? 0 : 3;
}

}  // namespace fri
}  // namespace tactile
