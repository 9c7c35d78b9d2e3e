// tactile_calibrate: fit the WTS0614's calibration polynomial (App. A) from a
// recording of the sensor under known loads (calibration_fit.hpp,
// docs/calibration.md).
//
//   tactile_calibrate --recording REC.csv [--params FILE.yaml] [--model border|per_taxel|shared]
//                     [--degree 1..3] [--ridge R] [--unloaded-max N] [--max-rms-pct P]
//                     [--unconstrained] --out CALIB.yaml
//
// --params: the sensor's parameter file (features.rows/cols, calibration.
// full_scale, max_tare, noise_counts; default params/sensors/
// wts0614.yaml of the source tree, else the installed copy). The output is that
// file with its `calibration:` section replaced by the fitted one (features and
// comments kept as written), so it serves wherever the input did: the feature
// component's param_file (deployments/features.cpf) and a scene's
// features_file (the simulated sensor inverts the same block).
//
// Prints the frames used, the coefficients, the residual (RMS and max in N,
// RMS in % of the load range), the condition number, the per-taxel residual
// as a rows x cols grid (mN; '-' never loaded; '*' above 3x the median), and
// PASS or FAIL with what to do next. PASS needs the residual RMS within
// --max-rms-pct (default 2 %) of the load range and the fitted curves'
// standard error at the largest count used within --max-se-pct (default
// 0.5 %) of it (loads that leave coefficients undetermined, e.g. a plate
// loading the interior and the border alike); the file is written only on
// PASS, then read back through the project's loader (params_io) and checked.
// Exit: 0 pass, 1 fit failed or bad recording (nothing written), 2 usage or
// parameter-file error.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "tactile_config/cli_args.hpp"
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/calibration_fit.hpp"
#include "tactile_features/params_io.hpp"

#ifndef TACTILE_CALIBRATE_DEFAULT_PARAMS
#define TACTILE_CALIBRATE_DEFAULT_PARAMS ""
#endif
#ifndef TACTILE_CALIBRATE_INSTALLED_PARAMS
#define TACTILE_CALIBRATE_INSTALLED_PARAMS ""
#endif

namespace {

using namespace tactile;

void usage() {
  std::fprintf(stderr,
               "usage: tactile_calibrate --recording REC.csv [--params FILE.yaml] [--model border|per_taxel|shared]\n"
               "                         [--degree 1..3] [--ridge R=0.001] [--unloaded-max N=0.05]\n"
               "                         [--max-rms-pct P=2] [--max-se-pct P=0.5] [--unconstrained] --out CALIB.yaml\n"
               "Fits f_i = c1 n + c2 n^2 + c3 n^3 (tared counts n) so that the taxels add up to f_ref_n per frame.\n"
               "REC.csv: header, then time_s, f_ref_n, raw_0..raw_{rows*cols-1} per frame (docs/calibration.md).\n"
               "Writes the parameter file with its calibration: section replaced. Exit 0 pass, 1 fail, 2 usage.\n");
}

std::string fmt(const char* f, double v) {
  char b[96];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

bool readText(const std::string& file, std::string& out) {
  std::ifstream in(file);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return true;
}

bool fileExists(const std::string& f) { return !f.empty() && std::ifstream(f).good(); }

std::string poly(const std::array<double, 4>& c, int degree) {
  std::string s;
  for (int k = 1; k <= degree; ++k)
    s += fmt(k == 1 ? "%.6g n" : (k == 2 ? " + %.6g n^2" : " + %.6g n^3"), c[static_cast<std::size_t>(k)]);
  return s;
}

int fail(const std::string& why, const std::vector<std::string>& next) {
  std::printf("FAIL: %s\n", why.c_str());
  for (const std::string& n : next) std::printf("  next: %s\n", n.c_str());
  return 1;
}

// The command line: the options, or false with the exit code (help: 0; a
// usage error: 2, after its message).
struct Options {
  std::string recording, params_file, out_file;
  CalibrationFitOptions opt;
  double max_rms_pct = 2.0, max_se_pct = 0.5;
};

bool parseArgs(int argc, char** argv, Options& o, int& code) {
  const config::CliArgs args("tactile_calibrate", argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() { return args.value(i); };
    auto number = [&](double lo, double hi) { return args.number(i, lo, hi); };
    if (a == "--recording") {
      o.recording = value();
    } else if (a == "--params") {
      o.params_file = value();
    } else if (a == "--out") {
      o.out_file = value();
    } else if (a == "--model") {
      const std::string m = value();
      if (!parseCalibrationModel(m, o.opt.model)) {
        std::fprintf(stderr, "tactile_calibrate: --model '%s': must be border, per_taxel or shared\n", m.c_str());
        code = 2;
        return false;
      }
    } else if (a == "--degree") {
      const double dg = number(1, 3);
      if (dg != std::floor(dg)) {
        std::fprintf(stderr, "tactile_calibrate: --degree must be 1, 2 or 3\n");
        code = 2;
        return false;
      }
      o.opt.degree = static_cast<int>(dg);
    } else if (a == "--ridge") {
      o.opt.ridge = number(0, 1e6);
    } else if (a == "--unloaded-max") {
      o.opt.unloaded_max_n = number(1e-9, 1e3);
    } else if (a == "--max-rms-pct") {
      o.max_rms_pct = number(0, 100);
    } else if (a == "--max-se-pct") {
      o.max_se_pct = number(0, 100);
    } else if (a == "--unconstrained") {
      o.opt.nonnegative = false;
    } else if (a == "-h" || a == "--help") {
      usage();
      code = 0;
      return false;
    } else {
      std::fprintf(stderr, "tactile_calibrate: unknown argument %s\n", a.c_str());
      usage();
      code = 2;
      return false;
    }
  }
  if (o.recording.empty() || o.out_file.empty()) {
    std::fprintf(stderr, "tactile_calibrate: --recording and --out are required\n");
    usage();
    code = 2;
    return false;
  }
  if (o.params_file.empty()) {
    o.params_file = fileExists(TACTILE_CALIBRATE_DEFAULT_PARAMS) ? TACTILE_CALIBRATE_DEFAULT_PARAMS
                                                                : TACTILE_CALIBRATE_INSTALLED_PARAMS;
    if (!fileExists(o.params_file)) {
      std::fprintf(stderr, "tactile_calibrate: no --params given and the default wts0614.yaml is not found\n");
      code = 2;
      return false;
    }
  }
  return true;
}

// The fit's summary: frames, loads, model, coefficients, residual, condition,
// notes. Returns the largest curve standard error at the largest count used.
double printFit(const CalibrationFit& fit, const CalibrationFitOptions& opt, double fit_ms, int n) {
  std::printf("frames: %zu in the file, %zu unloaded (tare and noise), %zu loaded: %zu used", fit.frames_total,
              fit.frames_unloaded, fit.frames_loaded, fit.frames_used);
  if (fit.frames_saturated) std::printf(", %zu saturated dropped", fit.frames_saturated);
  if (fit.frames_silent) std::printf(", %zu silent dropped", fit.frames_silent);
  std::printf("\nloads: %d distinct, up to %.4g N\n", fit.distinct_loads, fit.load_max);
  std::printf("model: %s, degree %d, %d unknowns%s; fitted in %.1f ms\n", toString(fit.model), fit.degree,
              fit.unknowns, opt.nonnegative ? " (c_k >= 0)" : "", fit_ms);
  if (fit.model == CalibrationModel::PerTaxel) {
    double lo = 1e300, hi = -1e300;
    for (const auto& c : fit.params.taxels) {
      lo = std::min(lo, c[1]);
      hi = std::max(hi, c[1]);
    }
    std::printf("  per taxel: c1 from %.6g to %.6g N/count (ridge %g toward the prior below)\n", lo, hi, opt.ridge);
  }
  std::printf("  %s: f = %s\n", fit.params.use_border ? "interior" : "all taxels", poly(fit.params.coeffs, fit.degree).c_str());
  if (fit.params.use_border) std::printf("  border:   f = %s\n", poly(fit.params.border_coeffs, fit.degree).c_str());
  if (fit.constrained) std::printf("  %d coefficient(s) held at 0 by the c_k >= 0 constraint\n", fit.constrained);
  std::printf("residual: RMS %.4g N = %.3g %% of the %.4g N load range, max %.4g N (line %ld), sigma %.4g N\n",
              fit.rms_n, fit.rms_pct, fit.load_max, fit.max_abs_n, fit.max_abs_line, fit.sigma_n);
  std::printf("condition: %.3g (column-scaled design)", fit.condition);
  if (fit.model == CalibrationModel::PerTaxel) std::printf(", %.3g with the ridge", fit.condition_regularised);
  std::printf("\n");
  double se_max = 0.0;
  for (int i = 0; i < n; ++i)
    if (fit.taxel_frames[static_cast<std::size_t>(i)] > 0)
      se_max = std::max(se_max, fit.curveStdError(i, fit.count_max[static_cast<std::size_t>(i)]));
  std::printf("curve standard error at the largest count used: up to %.3g mN\n", 1000.0 * se_max);
  for (const std::string& note : fit.notes) std::printf("note: %s\n", note.c_str());
  return se_max;
}

// Per-taxel residual grid (mN). Returns the number of taxels marked '*'.
int printResidualGrid(const CalibrationFit& fit, int rows, int cols) {
  const int n = rows * cols;
  std::vector<double> v;
  for (int i = 0; i < n; ++i)
    if (fit.taxel_frames[static_cast<std::size_t>(i)] > 0) v.push_back(fit.taxel_residual[static_cast<std::size_t>(i)]);
  std::sort(v.begin(), v.end());
  const double median = v.empty() ? 0.0 : v[v.size() / 2];
  std::printf("per-taxel residual (mN; each frame's residual shared by the taxels' parts of the predicted force, RMS "
              "over the frames that loaded the taxel; '-' never loaded, '*' above 3x the median %.3g mN):\n",
              1000.0 * median);
  std::printf("       ");
  for (int c = 0; c < cols; ++c) std::printf("%6s ", ("c" + std::to_string(c)).c_str());
  std::printf("\n");
  int flagged = 0;
  for (int rr = 0; rr < rows; ++rr) {
    std::printf("  r%-3d ", rr);
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = static_cast<std::size_t>(rr * cols + c);
      if (fit.taxel_frames[i] == 0) {
        std::printf("%6s ", "-");
      } else {
        const bool big = fit.taxel_residual[i] > 3.0 * median && median > 0.0;
        flagged += big;
        std::printf("%6.1f%c", 1000.0 * fit.taxel_residual[i], big ? '*' : ' ');
      }
    }
    std::printf("\n");
  }
  return flagged;
}

// The written file read back through the project's loader: the same
// calibration as the fit (`base`: the input's full scale for the probes).
ConfigResult checkReadBack(const std::string& out_file, const CalibrationFit& fit, int rows, int cols,
                           const CalibrationParams& base) {
  const int n = rows * cols;
  FeatureParams fp2;
  CalibrationParams cp2;
  ConfigResult r = loadSensorParamFile(out_file, fp2, cp2);
  if (r) {
    bool same = fp2.rows == rows && fp2.cols == cols && cp2.use_border == fit.params.use_border &&
                cp2.taxels.size() == fit.params.taxels.size();
    CalibrationFit readBack;  // its force(): the coefficient rule of tactile::Calibration
    readBack.params = cp2;
    for (int i = 0; i < n && same; ++i)
      for (double cnt : {0.25 * base.full_scale, 0.5 * base.full_scale, 1.0 * base.full_scale}) {
        const double fb = fit.force(i, cnt);
        same = same && std::fabs(readBack.force(i, cnt) - fb) <= 1e-7 * std::max(1.0, std::fabs(fb));
      }
    if (!same) r = ConfigResult::failure(out_file + ": read back, the calibration differs from the fit");
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  Options cli;
  if (int code = 0; !parseArgs(argc, argv, cli, code)) return code;
  const std::string &recording = cli.recording, &params_file = cli.params_file, &out_file = cli.out_file;
  const CalibrationFitOptions& opt = cli.opt;
  const double max_rms_pct = cli.max_rms_pct, max_se_pct = cli.max_se_pct;

  // The sensor's parameters (size, full scale, max_tare, noise_counts).
  FeatureParams fp;
  CalibrationParams base;
  std::string params_text;
  ConfigResult r = loadSensorParamFile(params_file, fp, base);
  if (r && !readText(params_file, params_text)) r = ConfigResult::failure(params_file + ": cannot read");
  if (!r) {
    std::fprintf(stderr, "tactile_calibrate: %s\n", r.message().c_str());
    return 2;
  }
  if (!std::ifstream(recording).good()) {
    std::fprintf(stderr, "tactile_calibrate: %s: cannot open the recording\n", recording.c_str());
    return 2;
  }
  std::printf("tactile_calibrate: %s (sensor %d x %d, full scale %u, from %s)\n", recording.c_str(), fp.rows, fp.cols,
              static_cast<unsigned>(base.full_scale), params_file.c_str());

  CalibrationRecording rec;
  r = readCalibrationRecording(recording, fp.rows, fp.cols, rec);
  if (!r)
    return fail(r.message(), {"the format: a header line, then time_s, f_ref_n, raw_0..raw_" +
                                  std::to_string(fp.rows * fp.cols - 1) + " per frame (docs/calibration.md)"});
  CalibrationFit fit;
  const auto t0 = std::chrono::steady_clock::now();
  r = fitCalibration(rec, base, opt, fit);
  const double fit_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!r) return fail(r.message(), {"fix the recording (docs/calibration.md: how to record) and run again"});

  const int rows = fp.rows, cols = fp.cols;
  const double se_max = printFit(fit, opt, fit_ms, rows * cols);
  const int flagged = printResidualGrid(fit, rows, cols);

  if (!(fit.rms_pct <= max_rms_pct))
    return fail(fmt("residual RMS %.3g %% of the load range", fit.rms_pct) + fmt(" above --max-rms-pct %g %%", max_rms_pct),
                {fit.degree < 3 ? "the curve may need a higher degree: --degree " + std::to_string(fit.degree + 1)
                                : "a per-taxel model may fit: --model per_taxel (needs loads on every taxel)",
                 "check the reference: its zero (f_ref_n = 0 with nothing on the pad) and its sign, and that each "
                 "f_ref_n belongs to its frame (no lag between the reference and the WTS)",
                 "a probe wider than a taxel loses the load its rim puts on taxels below the firing threshold "
                 "(docs/calibration.md): use a probe within one taxel"});

  if (!(100.0 * se_max / fit.load_max <= max_se_pct))
    return fail(fmt("the fitted curves are poorly determined: standard error up to %.3g mN", 1000.0 * se_max) +
                    fmt(" = %.3g %% of the load range", 100.0 * se_max / fit.load_max) +
                    fmt(" at the largest counts, above --max-se-pct %g %%", max_se_pct),
                {"the loads do not separate the coefficients: record more load levels, loads on single taxels "
                 "(a probe within one taxel) and on the border taxels",
                 "or a simpler model: --model shared, a lower --degree"});

  // Write: the input file with the calibration section replaced.
  std::vector<std::string> comment = {
      "fitted by tactile_calibrate from " + recording + " (model " + toString(fit.model) + ", degree " +
          std::to_string(fit.degree) + ")",
      std::to_string(fit.frames_used) + " loaded frames, " + std::to_string(fit.frames_unloaded) + " unloaded, " +
          std::to_string(fit.distinct_loads) + " distinct loads up to " + fmt("%.4g N", fit.load_max),
      "residual RMS " + fmt("%.4g N", fit.rms_n) + fmt(" (%.3g %% of the load range)", fit.rms_pct) +
          fmt(", max %.4g N", fit.max_abs_n) + fmt("; condition %.3g", fit.condition)};
  const std::string text = replaceCalibrationBlock(params_text, calibrationYaml(fit.params, comment));
  {
    std::ofstream o(out_file);
    if (!(o << text) || !(o.flush()))
      return fail(out_file + ": cannot write", {"check the directory and its permissions"});
  }
  // Read it back through the project's loader: the same calibration.
  r = checkReadBack(out_file, fit, rows, cols, base);
  if (!r) return fail(r.message(), {"a bug in the writer: keep the recording and report it"});

  std::printf("PASS: wrote %s (the parameter file with its calibration: section replaced%s)\n", out_file.c_str(),
              flagged ? fmt("; %.0f taxel(s) marked *", flagged).c_str() : "");
  std::printf("  next: set deployments/features.cpf's param_file (the FeatureComponent) to %s\n", out_file.c_str());
  std::printf("  next: for the simulator, a scene's features_file: %s (its sensor inverts the same calibration)\n",
              out_file.c_str());
  std::printf("  next: check it: `wts_check --params %s` (noise against noise_counts), then a known weight on the "
              "pad: the features' force should read its m g\n",
              out_file.c_str());
  return 0;
}
