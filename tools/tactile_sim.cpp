// tactile_sim: the headless experiment runner.
//
//   tactile_sim summarize SCENE REPORT --out DIR [--program FILE] [--controller proposed|baseline|no_rotation]
//                         [--status S --exit-code N --sim-time T] [--no-plots]
//   tactile_sim run SCENE [--program FILE] [--controller proposed|baseline|no_rotation] [--out DIR] [--seed N]
//                         [--duration S] [--servo-rate HZ] [--sim-rate HZ]
//                         [--wts-rate HZ] [--features-rate HZ] [--subsamples K]
//                         [--fidelity quasi_static|dynamics] [--through-fri] [--no-plots]
//                         [--set KEY.PATH=VALUE ...]
//   tactile_sim program FILE [--check]   the phase program with its `base:` merged (YAML)
//   tactile_sim scene FILE [--program FILE] [--set KEY.PATH=VALUE ...]   the scene and its program as read (YAML)
//   tactile_sim schema [program|scene|faults|sensor|registry]   the key tables of the declared blocks (Markdown)
//   tactile_sim binding SCENE [--registry FILE]   the path of the program the registry binds to the scene
//
// A run is a scene with a phase program (tactile::sim::RunFiles): --program
// names it; without it, the experiment registry (--registry FILE, default
// this tree's experiments.yaml) gives the program of the experiments that run
// the scene, or of its `scenes:` entry (tactile::config::programForScene).
// The controller is the program's controller.mode unless --controller names one.
//
// --set overrides a scene key before the scene is read (repeatable):
// `--set sensor.noise_counts=30 --set rates.servo=1000`; a key under
// `program.` is one of the run's program (`--set program.speed_law.v_max=0.08`,
// `--set program.phases.explore.kp_per_s.x=4.8`); errors as for the file.
//
// `program` prints the program document as the servo reads it, its `base:`
// chain merged (exit 2 with the error of a missing file, a key the base lacks,
// a cycle): the scripts that read or derive programs take it rather than
// merging `base:` themselves. --check reads it in full as the servo does
// first (keys, ranges, phases). `scene` prints the scene with its overrides
// and then, as a second YAML document, its program as `program` prints it
// with the `program.` overrides: what `run` would read, checked in full. `schema` prints what
// docs/formats.md shows for each declared block of a program
// (tactile_servo/servo_schema.hpp), of a scene (tactile_sim_runner/scene_schema.hpp), of a
// sensor's parameter file (tactile_features/features_schema.hpp) or of the
// experiment registry (tactile_config/registry.hpp).
//
// --through-fri sends every 1 kHz command through the FRI protocol: the world
// state is encoded as a KRC measurement packet, tactile::fri::FriBridge (rate
// limiter, sequence and state handling) answers with a command packet, and the
// decoded pose is what the simulated robot applies.
//
// `summarize` turns the reporter's table of a simulated deployment
// (scripts/run_deployment.sh; deployments/sim_loop.ops) into the same run
// directory, with the runner's own rows and metrics (tactile/sim/report_table.hpp);
// --status/--exit-code/--sim-time carry the deployment's end (tactile::SimClock's
// status, exit_code, sim_time).
//
// Writes DIR/timeseries.csv, summary.json, snapshots.csv, contacts.csv and the
// PNG plots (scripts/tools/plot_run.py, Debian's /usr/bin/python3). A progress bar is
// drawn on a terminal, nothing otherwise. Exit code: 0 ok, 2 bad scene or
// arguments, 3 the simulation went unstable (NaN, joint limit, singularity,
// force limit) or refused its steps or commands (sim_step_rejected,
// sim_invalid_command), 4 the servo's force ceiling tripped, 5/6/7 a servo
// watchdog (phase_timeout, arm_stalled, force_mismatch), 8 the surface curves
// more tightly than the pad can follow (surface_too_curved); the status is in summary.json.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "tactile_servo/program_io.hpp"
#include "tactile_config/registry.hpp"
#include "tactile_features/features_schema.hpp"
#include "tactile_servo/servo_schema.hpp"
#include "tactile_sim_runner/report_table.hpp"
#include "tactile_sim_runner/scene_schema.hpp"
#include "tactile_sim_faults/fault_schema.hpp"
#include "tactile_sim_runner/runner.hpp"

#ifndef TACTILE_SOURCE_DIR
#define TACTILE_SOURCE_DIR "."
#endif

using namespace tactile;
using namespace tactile::sim;

namespace {

void usage() {
  std::cerr << "usage: tactile_sim summarize SCENE REPORT --out DIR [--program FILE | --registry FILE]\n"
               "                         [--controller proposed|baseline|no_rotation]\n"
               "                         [--status S --exit-code N --sim-time T] [--no-plots]\n"
               "       tactile_sim run SCENE [--program FILE | --registry FILE]\n"
               "                         [--controller proposed|baseline|no_rotation] [--out DIR] [--seed N]\n"
               "                         [--duration S] [--servo-rate HZ] [--sim-rate HZ] [--wts-rate HZ]\n"
               "                         [--features-rate HZ] [--subsamples K] [--fidelity quasi_static|dynamics]\n"
               "                         [--through-fri] [--no-plots] [--set KEY.PATH=VALUE ...]\n"
               "       tactile_sim program FILE [--check]\n"
               "       tactile_sim scene FILE [--program FILE | --registry FILE] [--set KEY.PATH=VALUE ...]\n"
               "       tactile_sim schema [program|scene|faults|sensor|registry]\n"
               "       tactile_sim binding SCENE [--registry FILE]\n";
}

bool number(const char* s, double& v) {
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end != s && *end == '\0';
}

bool parseController(const std::string& m, ControllerMode& mode) {
  if (parseControllerMode(m, mode)) return true;
  std::cerr << "tactile_sim: --controller '" << m << "' must be " << kControllerModeNames << "\n";
  return false;
}

// The run's files: the scene argv[2]; the program from --program, or from
// the registry (--registry, default this tree's experiments.yaml). false
// (after the error) when neither gives one.
bool runFiles(int argc, char** argv, RunFiles& files) {
  files.scene = argv[2];
  std::string registry = std::string(TACTILE_SOURCE_DIR) + "/experiments.yaml";
  for (int i = 3; i + 1 < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--program") files.program = argv[++i];
    else if (a == "--registry") registry = argv[++i];
  }
  if (!files.program.empty()) return true;
  const ConfigResult r = config::programForScene(registry, files.scene, files.program);
  if (!r) std::cerr << "tactile_sim: " << r.message() << "\n";
  return r.ok();
}

// An option the run's files took (runFiles); skipped by the other parsers.
bool isFileOption(const std::string& a) { return a == "--program" || a == "--registry"; }

void printCriteria(const Summary& s) {
  if (s.criteria_failed.empty()) {
    std::printf("criteria: passed\n");
    return;
  }
  std::printf("criteria: FAILED\n");
  for (const auto& f : s.criteria_failed) std::printf("  %s\n", f.c_str());
}

int mkdirs(const std::string& dir) {
  std::string cur;
  for (std::size_t i = 0; i <= dir.size(); ++i) {
    if (i == dir.size() || dir[i] == '/') {
      if (!cur.empty() && ::mkdir(cur.c_str(), 0755) != 0 && errno != EEXIST) return -1;
    }
    if (i < dir.size()) cur += dir[i];
  }
  return 0;
}

// A servo stop (the force ceiling, a watchdog): what it means, for the user.
void printServoStop(const Summary& s) {
  for (int k = static_cast<int>(ServoStatus::ForceCeiling); k <= static_cast<int>(kLastServoStatus); ++k) {
    const ServoStatus st = static_cast<ServoStatus>(k);
    if (s.status == std::string("servo_") + toString(st)) std::printf("  %s: %s\n", toString(st), explain(st));
  }
}

}  // namespace

int plot(const std::string& out_dir) {
  const char* script_env = std::getenv("TACTILE_PLOT_SCRIPT");
  const std::string script = script_env ? script_env : std::string(TACTILE_SOURCE_DIR) + "/scripts/tools/plot_run.py";
  const std::string cmd = "/usr/bin/python3 '" + script + "' '" + out_dir + "'";
  const int rc = std::system(cmd.c_str());
  if (rc != 0) std::cerr << "tactile_sim: plotting failed (" << cmd << ")\n";
  return rc;
}

int summarize(int argc, char** argv) {
  if (argc < 4) {
    usage();
    return 2;
  }
  RunFiles files;
  if (!runFiles(argc, argv, files)) return 2;
  Scene scene;
  ConfigResult r = loadRun(files, scene);
  if (!r) {
    std::cerr << "tactile_sim: " << r.message() << "\n";
    return 2;
  }
  const std::string report = argv[3];
  std::string out_dir, status = "ok";
  int exit_code = 0;
  double sim_time = -1.0;
  bool plots = true;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) {
      out_dir = argv[++i];
    } else if (a == "--controller" && i + 1 < argc) {
      if (!parseController(argv[++i], scene.controller)) return 2;
    } else if (a == "--status" && i + 1 < argc) {
      status = argv[++i];
    } else if (a == "--exit-code" && i + 1 < argc) {
      double v = 0;
      if (!number(argv[++i], v)) {
        std::cerr << "tactile_sim: --exit-code needs a number\n";
        return 2;
      }
      exit_code = static_cast<int>(v);
    } else if (a == "--sim-time" && i + 1 < argc) {
      if (!number(argv[++i], sim_time) || !(sim_time >= 0.0)) {
        std::cerr << "tactile_sim: --sim-time needs a time >= 0 (s)\n";
        return 2;
      }
    } else if (a == "--no-plots") {
      plots = false;
    } else if ((a == "--set" || isFileOption(a)) && i + 1 < argc) {
      ++i;  // applied when the run was read
    } else {
      std::cerr << "tactile_sim: unknown argument " << a << "\n";
      usage();
      return 2;
    }
  }
  if (out_dir.empty()) {
    std::cerr << "tactile_sim: summarize needs --out DIR\n";
    return 2;
  }
  RunResult result;
  if (!(r = readReportTable(report, scene, result))) {
    std::cerr << "tactile_sim: " << r.message() << "\n";
    return 2;
  }
  Summary& s = result.summary;
  s.scene = scene.name;
  s.controller = toString(scene.controller);
  s.seed = scene.seed;
  s.fidelity = toString(scene.world.fidelity);
  s.status = status;
  s.exit_code = exit_code;
  s.sim_time_s = sim_time >= 0.0 ? sim_time : result.rows.back().t;
  computeSummary(scene, result);
  std::string err;
  if (mkdirs(out_dir) != 0 || !writeRun(out_dir, scene, result, err)) {
    std::cerr << "tactile_sim: cannot write " << out_dir << " " << err << "\n";
    return 2;
  }
  std::printf("%s (%s, deployment): status %s, %zu servo cycles, %.1f s simulated\n", s.scene.c_str(),
              s.controller.c_str(), s.status.c_str(), result.rows.size(), s.sim_time_s);
  printServoStop(s);
  printCriteria(s);
  if (plots) plot(out_dir);
  std::printf("results: %s\n", out_dir.c_str());
  return s.exit_code;
}

// `run`'s options after the scene (argv[3..]) over the scene; the output
// folder (default runs/<scene>[_<controller>]) and whether to plot. -1, or
// the exit code (2).
int runOptions(int argc, char** argv, Scene& scene, std::string& out_dir, bool& plots) {
  out_dir = "runs/" + scene.name;
  plots = true;
  bool out_given = false;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](double& v) {
      if (i + 1 >= argc || !number(argv[i + 1], v)) {
        std::cerr << "tactile_sim: " << a << " needs a number\n";
        std::exit(2);
      }
      ++i;
    };
    double v = 0;
    if (a == "--controller" && i + 1 < argc) {
      if (!parseController(argv[++i], scene.controller)) return 2;
    } else if (a == "--out" && i + 1 < argc) {
      out_dir = argv[++i];
      out_given = true;
    } else if (a == "--seed") {
      value(v);
      scene.seed = static_cast<uint64_t>(v);
    } else if (a == "--duration") {
      value(scene.duration);
    } else if (a == "--servo-rate") {
      value(scene.rates.servo);
    } else if (a == "--sim-rate") {
      value(scene.rates.sim);
    } else if (a == "--wts-rate") {
      value(scene.rates.wts);
    } else if (a == "--features-rate") {
      value(scene.rates.features);
    } else if (a == "--subsamples") {
      value(v);
      scene.world.pad.subsamples = static_cast<int>(v);
    } else if (a == "--fidelity" && i + 1 < argc) {
      if (!parseFidelity(argv[++i], scene.world.fidelity)) {
        std::cerr << "tactile_sim: --fidelity must be quasi_static | dynamics\n";
        return 2;
      }
      // A dynamic arm integrates a tray anyway: a scene's dynamic tray
      // (objects[].fidelity) is then no body of its own fidelity.
      if (scene.world.fidelity == Fidelity::Dynamics) scene.world.tray_dynamics = false;
    } else if (a == "--through-fri") {
      scene.through_fri = true;
      if (scene.fri_file.empty()) scene.fri_file = std::string(TACTILE_SOURCE_DIR) + "/params/sensors/fri.yaml";
    } else if (a == "--no-plots") {
      plots = false;
    } else if ((a == "--set" || isFileOption(a)) && i + 1 < argc) {
      ++i;  // applied when the run was read
    } else {
      std::cerr << "tactile_sim: unknown argument " << a << "\n";
      usage();
      return 2;
    }
  }
  if (!out_given && scene.controller != ControllerMode::Proposed) out_dir += std::string("_") + toString(scene.controller);
  if (!(scene.duration > 0)) {
    std::cerr << "tactile_sim: --duration must be > 0 (s)\n";
    return 2;
  }
  return -1;
}

/// `program FILE [--check]`: the merged program as YAML on stdout.
int printProgram(const std::string& file, bool check) {
  ServoParams p;
  YAML::Node doc;
  ConfigResult r = check ? loadServoProgram(file, p) : ConfigResult::success();
  if (r) r = loadProgramDocument(file, doc);
  if (!r) {
    std::cerr << "tactile_sim: " << r.message() << "\n";
    return 2;
  }
  std::cout << YAML::Dump(doc) << "\n";
  return 0;
}

/// `scene FILE [--program FILE] [--set ...]`: the scene and its run's program
/// as read, two YAML documents.
int printScene(int argc, char** argv) {
  std::vector<std::string> overrides;
  for (int i = 3; i < argc; i += 2) {
    const std::string a = argv[i];
    if ((a != "--set" && !isFileOption(a)) || i + 1 >= argc) {
      usage();
      return 2;
    }
    if (a == "--set") overrides.push_back(argv[i + 1]);
  }
  RunFiles files;
  if (!runFiles(argc, argv, files)) return 2;
  YAML::Node scene, program;
  const ConfigResult r = runDocuments(files, overrides, scene, program);
  if (!r) {
    std::cerr << "tactile_sim: " << r.message() << "\n";
    return 2;
  }
  std::cout << YAML::Dump(scene) << "\n---\n" << YAML::Dump(program) << "\n";
  return 0;
}

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "summarize") return summarize(argc, argv);
  if ((argc == 3 || (argc == 4 && std::string(argv[3]) == "--check")) && std::string(argv[1]) == "program")
    return printProgram(argv[2], argc == 4);
  if (argc >= 3 && std::string(argv[1]) == "scene") return printScene(argc, argv);
  if ((argc == 3 || (argc == 5 && std::string(argv[3]) == "--registry")) && std::string(argv[1]) == "binding") {
    RunFiles files;
    if (!runFiles(argc, argv, files)) return 2;
    std::cout << files.program << "\n";
    return 0;
  }
  if ((argc == 2 || argc == 3) && std::string(argv[1]) == "schema") {
    const std::string which = argc == 3 ? argv[2] : "program";
    if (which != "program" && which != "scene" && which != "faults" && which != "sensor" && which != "registry") {
      usage();
      return 2;
    }
    std::cout << (which == "program"    ? programSchemaMarkdown()
                  : which == "scene"    ? sceneFileSchemaMarkdown()
                  : which == "faults"   ? schema::markdownSection(faultSchema())
                  : which == "registry" ? config::registrySchemaMarkdown()
                                        : sensorSchemaMarkdown());
    return 0;
  }
  if (argc < 3 || std::string(argv[1]) != "run") {
    usage();
    return 2;
  }
  std::vector<std::string> overrides;  // --set, applied to the scene file before it is read
  for (int i = 3; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--set") overrides.push_back(argv[++i]);
  RunFiles files;
  if (!runFiles(argc, argv, files)) return 2;
  Scene scene;
  ConfigResult r = loadRun(files, scene, overrides);
  if (!r) {
    std::cerr << "tactile_sim: " << r.message() << "\n";
    return 2;
  }
  std::string out_dir;
  bool plots = true;
  if (int code = runOptions(argc, argv, scene, out_dir, plots); code >= 0) return code;
  Runner runner;
  if (!(r = runner.configure(scene))) {
    std::cerr << "tactile_sim: " << r.message() << "\n";
    return 2;
  }
  if (mkdirs(out_dir) != 0) {
    std::cerr << "tactile_sim: cannot create " << out_dir << "\n";
    return 2;
  }
  const bool tty = ::isatty(2);
  RunResult result;
  runner.run(result, [&](double t, double T) {
    if (!tty) return;
    const int w = 40;
    const int k = static_cast<int>(w * t / T + 0.5);
    std::fprintf(stderr, "\r%-18s [%.*s%*s] %5.1f / %.1f s", scene.name.c_str(), k,
                 "########################################", w - k, "", t, T);
    std::fflush(stderr);
  });
  if (tty) std::fprintf(stderr, "\n");
  std::string err;
  if (!writeRun(out_dir, scene, result, err)) {
    std::cerr << "tactile_sim: " << err << "\n";
    return 2;
  }
  const Summary& s = result.summary;
  std::printf("%s (%s): status %s, %.1f s simulated in %.2f s (%.0fx real time)\n", s.scene.c_str(),
              s.controller.c_str(), s.status.c_str(), s.sim_time_s, s.wall_time_s, s.real_time_factor);
  printServoStop(s);
  printCriteria(s);
  if (plots) plot(out_dir);
  std::printf("results: %s\n", out_dir.c_str());
  return s.exit_code;
}
