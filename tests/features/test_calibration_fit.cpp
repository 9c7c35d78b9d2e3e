// Calibration fit (calibration_fit.hpp, tactile_calibrate) against the
// simulator's ground truth (tactile_calibration_record): the recovered
// force-vs-count curves within their noise-derived tolerance, controls that
// must fail that tolerance, the written parameter file read back through
// params_io (and by the simulated sensor), and bad recordings named with
// exit code 1.
//
// TOLERANCE. Frames come from a probe within one taxel, so a frame's force
// noise is one taxel's: sigma_frame = noise_counts x the steepest slope of the
// true curves (dF/dn at full scale), with the reference's noise and the
// 12-bit rounding (1/sqrt(12) count) added in quadrature: an upper bound over
// the count range. The fitted curve's standard error at n is
// sigma_frame sqrt(phi(n)^T (A^T A)^-1 phi(n)) (A: the design; the frames'
// number and spread enter here) = CalibrationFit::curveStdError(i, n) x
// sigma_frame / sigma_fit. The recovered curve must lie within 5 of those
// standard errors of the truth at every count of the range the fit used
// (41 points per taxel over [count_min, count_max]): 5 sigma, because the
// check is the maximum over ~3400 correlated points. The fit's own residual
// sigma must be at most sigma_frame (nothing but noise left).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/calibration_fit.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"
#include "temp_file.hpp"

using namespace tactile;

namespace {

struct ToolRun {
  int code = -1;
  std::string out, err;
};

std::string readAll(const std::string& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

ToolRun run(const std::string& cmd) {
  const std::string errFile = test::writeTempFile("stderr.txt", "");
  ToolRun r;
  FILE* p = popen((cmd + " 2>" + errFile).c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.err = readAll(errFile);
  return r;
}

/// Records the simulated sensor with the calibration of `params`; returns the CSV path.
std::string record(const std::string& params, const std::string& args) {
  const std::string csv = test::writeTempFile("rec.csv", "");
  const ToolRun r = run(std::string(TACTILE_RECORD_BIN) + " --params " + params + " --out " + csv + " " + args);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  return csv;
}

ToolRun calibrate(const std::string& args) { return run(std::string(TACTILE_CALIBRATE_BIN) + " " + args); }

ConfigResult loadParams(const std::string& file, FeatureParams& fp, CalibrationParams& cp) {
  YAML::Node root;
  ConfigResult r = config::loadFile(file, root);
  if (r) r = loadFeatureParams(root["features"], config::Where{file, "features"}, fp);
  if (r) r = loadCalibrationParams(root["calibration"], config::Where{file, "calibration"}, fp.rows, fp.cols, cp);
  return r;
}

bool isBorder(int i, int rows, int cols) {
  const int r = i / cols, c = i % cols;
  return r == 0 || c == 0 || r == rows - 1 || c == cols - 1;
}

const std::array<double, 4>& truthCoeffs(const CalibrationParams& p, int i) {
  if (!p.taxels.empty()) return p.taxels[static_cast<std::size_t>(i)];
  return p.use_border && isBorder(i, p.rows, p.cols) ? p.border_coeffs : p.coeffs;
}

double poly(const std::array<double, 4>& c, double n) { return c[0] + n * (c[1] + n * (c[2] + n * c[3])); }

/// The per-frame force noise bound of the tolerance (see the top comment).
double sigmaFrame(const CalibrationParams& truth, double noise_counts, double ref_noise) {
  double slope = 0.0;
  for (int i = 0; i < truth.rows * truth.cols; ++i) {
    const auto& c = truthCoeffs(truth, i);
    const double n = truth.full_scale;
    slope = std::max(slope, c[1] + n * (2.0 * c[2] + 3.0 * n * c[3]));
  }
  const double q = 1.0 / std::sqrt(12.0);
  return std::sqrt(std::pow(noise_counts * slope, 2) + std::pow(q * slope, 2) + ref_noise * ref_noise);
}

struct Recovery {
  double max_err = 0.0;    ///< N: largest |fitted - true| over the used range
  double max_ratio = 0.0;  ///< largest |fitted - true| / tolerance
  double max_tol = 0.0;    ///< N: largest tolerance
  double max_rel = 0.0;    ///< largest |fitted - true| / the true force at full scale
  int worst = -1;
  double worst_n = 0.0;
  int taxels = 0;
};

Recovery compare(const CalibrationFit& fit, const CalibrationParams& truth, double sigma_frame) {
  Recovery r;
  const double scale = sigma_frame / fit.sigma_n;
  for (int i = 0; i < truth.rows * truth.cols; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (fit.taxel_frames[k] == 0) continue;
    ++r.taxels;
    const double full = poly(truthCoeffs(truth, i), truth.full_scale);
    for (int s = 0; s <= 40; ++s) {
      const double n = fit.count_min[k] + (fit.count_max[k] - fit.count_min[k]) * s / 40.0;
      const double err = std::fabs(fit.force(i, n) - poly(truthCoeffs(truth, i), n));
      const double tol = 5.0 * std::max(fit.curveStdError(i, n) * scale, 1e-6);
      r.max_tol = std::max(r.max_tol, tol);
      r.max_rel = std::max(r.max_rel, err / full);
      if (err > r.max_err) r.max_err = err;
      if (err / tol > r.max_ratio) {
        r.max_ratio = err / tol;
        r.worst = i;
        r.worst_n = n;
      }
    }
  }
  return r;
}

std::string describe(const Recovery& r) {
  char b[256];
  std::snprintf(b, sizeof b, "%d taxels: max error %.3g mN (%.3g %% of full scale), max tolerance %.3g mN, worst "
                "error/tolerance %.3g at taxel %d, n = %.0f", r.taxels, 1000 * r.max_err, 100 * r.max_rel,
                1000 * r.max_tol, r.max_ratio, r.worst, r.worst_n);
  return b;
}

std::vector<std::string> lines(const std::string& file) {
  std::vector<std::string> v;
  std::ifstream in(file);
  std::string l;
  while (std::getline(in, l)) v.push_back(l);
  return v;
}

std::string writeLines(const std::string& name, const std::vector<std::string>& v) {
  std::string t;
  for (const auto& l : v) t += l + "\n";
  return test::writeTempFile(name, t);
}

std::vector<std::string> split(const std::string& l) {
  std::vector<std::string> v;
  std::stringstream ss(l);
  std::string x;
  while (std::getline(ss, x, ',')) v.push_back(x);
  return v;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? "," : "") + v[k];
  return s;
}

constexpr double kRefNoise = 0.005;  // N: a Nano17-class reference (its resolution ~3 mN)

}  // namespace

// The border model (App. A: an interior and a stiffer border polynomial) on a
// recording of every taxel: both curves recovered within tolerance; the
// controls (degree 1 on the cubic truth; a truth with the border slope 1 %
// off) exceed it.
TEST(CalibrationFit, RecoversANonlinearBorderCalibrationAndTheCheckCanFail) {
  const std::string csv = record(TACTILE_CALIB_TRUTH, "--ref-noise " + std::to_string(kRefNoise));
  FeatureParams fp;
  CalibrationParams truth;
  ASSERT_TRUE(loadParams(TACTILE_CALIB_TRUTH, fp, truth).ok());
  CalibrationRecording rec;
  ASSERT_TRUE(readCalibrationRecording(csv, fp.rows, fp.cols, rec).ok());
  CalibrationParams base = truth;  // the fit keeps full_scale, max_tare, noise_counts of the base
  base.coeffs = {0, 1e-3, 0, 0};
  base.use_border = false;

  CalibrationFitOptions opt;
  opt.model = CalibrationModel::Border;
  opt.degree = 3;
  CalibrationFit fit;
  ConfigResult r = fitCalibration(rec, base, opt, fit);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(fit.frames_used, 84u * 8u * 3u);  // every spot x load x repeat
  EXPECT_EQ(fit.frames_saturated, 0u);
  EXPECT_EQ(fit.frames_silent, 0u);
  EXPECT_TRUE(fit.params.use_border);
  const double sigma = sigmaFrame(truth, truth.noise_counts, kRefNoise);
  EXPECT_LE(fit.sigma_n, sigma) << "residual above the sensor's noise: a model error";
  const Recovery rb = compare(fit, truth, sigma);
  EXPECT_EQ(rb.taxels, 84);
  EXPECT_LT(rb.max_ratio, 1.0) << describe(rb);
  std::printf("[ border model ] sigma_frame %.3g mN, fit sigma %.3g mN, RMS %.3g %% of %.3g N; %s\n", 1000 * sigma,
              1000 * fit.sigma_n, fit.rms_pct, fit.load_max, describe(rb).c_str());

  // Control: a straight line through the cubic truth.
  CalibrationFitOptions lin = opt;
  lin.degree = 1;
  CalibrationFit fit1;
  ASSERT_TRUE(fitCalibration(rec, base, lin, fit1).ok());
  const Recovery r1 = compare(fit1, truth, sigma);
  EXPECT_GT(r1.max_ratio, 1.0) << describe(r1);
  std::printf("[ degree 1    ] %s\n", describe(r1).c_str());

  // Control: the right fit against a truth whose border slope is 1 % off.
  CalibrationParams off = truth;
  off.border_coeffs[1] *= 1.01;
  const Recovery ro = compare(fit, off, sigma);
  EXPECT_GT(ro.max_ratio, 1.0) << describe(ro);
  std::printf("[ border c1+1%% ] %s\n", describe(ro).c_str());
}

// Per-taxel coefficients (a seeded 10 % sensitivity spread over the taxels):
// every taxel's curve recovered; the border model cannot follow the spread.
TEST(CalibrationFit, RecoversPerTaxelCoefficients) {
  FeatureParams fp;
  CalibrationParams base;
  ASSERT_TRUE(loadParams(TACTILE_CALIB_TRUTH, fp, base).ok());
  CalibrationParams truth = base;
  std::mt19937 g(7);
  std::normal_distribution<double> nd(0.0, 0.1);
  std::string yaml = "features: {rows: 6, cols: 14, pitch: 0.0034, contact_threshold: 0.2}\n"
                     "calibration:\n  full_scale: 4095\n  noise_counts: 6\n  max_tare: 409\n  taxels:\n";
  for (int i = 0; i < 84; ++i) {
    const double gain = std::clamp(1.0 + nd(g), 0.75, 1.25);
    std::array<double, 4> c = truthCoeffs(base, i);
    for (double& v : c) v *= gain;
    truth.taxels.push_back(c);
    char b[160];
    std::snprintf(b, sizeof b, "    - [0, %.12g, %.12g, %.12g]\n", c[1], c[2], c[3]);
    yaml += b;
  }
  const std::string truthFile = test::writeTempFile("truth_per_taxel.yaml", yaml);
  const std::string csv = record(truthFile, "--ref-noise " + std::to_string(kRefNoise));
  CalibrationRecording rec;
  ASSERT_TRUE(readCalibrationRecording(csv, 6, 14, rec).ok());

  CalibrationFitOptions opt;
  opt.model = CalibrationModel::PerTaxel;
  CalibrationFit fit;
  ConfigResult r = fitCalibration(rec, base, opt, fit);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(fit.params.taxels.size(), 84u);
  EXPECT_TRUE(fit.at_prior.empty());
  const double sigma = sigmaFrame(truth, 6.0, kRefNoise);
  EXPECT_LE(fit.sigma_n, sigma);
  const Recovery rp = compare(fit, truth, sigma);
  EXPECT_EQ(rp.taxels, 84);
  EXPECT_LT(rp.max_ratio, 1.0) << describe(rp);
  std::printf("[ per-taxel   ] sigma_frame %.3g mN, fit sigma %.3g mN; %s\n", 1000 * sigma, 1000 * fit.sigma_n,
              describe(rp).c_str());

  // Control: the border model on the same recording.
  opt.model = CalibrationModel::Border;
  CalibrationFit fb;
  ASSERT_TRUE(fitCalibration(rec, base, opt, fb).ok());
  const Recovery rb = compare(fb, truth, sigma);
  EXPECT_GT(rb.max_ratio, 1.0) << describe(rb);
  std::printf("[ border model on the spread ] %s\n", describe(rb).c_str());
}

// The tool: PASS, the residual grid, exit 0; the written file keeps the
// input's features, loads through params_io, configures tactile::Calibration
// and the simulated sensor, and gives the fit's forces frame by frame.
TEST(CalibrationFit, ToolWritesAParameterFileTheLoaderReadsWithTheFitsForces) {
  const std::string csv = record(TACTILE_CALIB_TRUTH, "");
  const std::string out = test::writeTempFile("calib_out.yaml", "");
  const ToolRun t = calibrate("--recording " + csv + " --params " + TACTILE_CALIB_TRUTH + " --out " + out);
  ASSERT_EQ(t.code, 0) << t.out << t.err;
  EXPECT_NE(t.out.find("PASS: wrote " + out), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("per-taxel residual"), std::string::npos);
  for (const char* row : {"  r0 ", "  r5 ", "c13"}) EXPECT_NE(t.out.find(row), std::string::npos) << row;
  EXPECT_NE(t.out.find("features.cpf"), std::string::npos);  // what to do next

  FeatureParams fin, fout;
  CalibrationParams cin, cout;
  ASSERT_TRUE(loadParams(TACTILE_CALIB_TRUTH, fin, cin).ok());
  ConfigResult r = loadParams(out, fout, cout);
  ASSERT_TRUE(r.ok()) << r.message() << "\n" << readAll(out);
  EXPECT_EQ(fout.rows, fin.rows);
  EXPECT_EQ(fout.pitch, fin.pitch);
  EXPECT_EQ(fout.contact_threshold, fin.contact_threshold);
  EXPECT_EQ(cout.noise_counts, cin.noise_counts);
  EXPECT_EQ(cout.max_tare, cin.max_tare);
  EXPECT_TRUE(cout.use_border);
  EXPECT_NE(readAll(out).find("# fitted by tactile_calibrate from"), std::string::npos);

  // The fit itself, the tool's default options.
  CalibrationRecording rec;
  ASSERT_TRUE(readCalibrationRecording(csv, 6, 14, rec).ok());
  CalibrationFit fit;
  ASSERT_TRUE(fitCalibration(rec, cin, CalibrationFitOptions{}, fit).ok());
  for (int k = 1; k < 4; ++k) {
    EXPECT_NEAR(cout.coeffs[static_cast<std::size_t>(k)], fit.params.coeffs[static_cast<std::size_t>(k)],
                1e-8 * std::fabs(fit.params.coeffs[static_cast<std::size_t>(k)]));
    EXPECT_NEAR(cout.border_coeffs[static_cast<std::size_t>(k)], fit.params.border_coeffs[static_cast<std::size_t>(k)],
                1e-8 * std::fabs(fit.params.border_coeffs[static_cast<std::size_t>(k)]));
  }
  // The reader, configured from the written file: per loaded frame the sum of
  // its forces is the fit's prediction (the simulated pad's tare is 0; the
  // unloaded taxels read 0). 1e-7 relative: the 9 digits written.
  Calibration cal;
  ASSERT_TRUE(cal.configure(cout).ok());
  RawTactileFrame raw;
  TactileFrame f;
  std::size_t a = 0, checked = 0;
  for (std::size_t j = 0; j < rec.frames() && a < fit.frame_line.size(); ++j) {
    if (rec.line[j] != fit.frame_line[a]) continue;
    for (int i = 0; i < 84; ++i) raw.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(rec.rawAt(j, i));
    ASSERT_EQ(cal.step(raw, f), CalibrationStatus::Ok);
    double sum = 0.0;
    for (int i = 0; i < 84; ++i) sum += f.force[static_cast<std::size_t>(i)];
    EXPECT_NEAR(sum, fit.predicted[a], 1e-7 * fit.predicted[a]) << "line " << rec.line[j];
    ++a;
    ++checked;
  }
  EXPECT_EQ(checked, fit.frames_used);
  // The simulated sensor inverts the written calibration too.
  sim::TaxelResponse resp;
  sim::TaxelResponseParams rp;
  rp.calibration = cout;
  r = resp.configure(rp);
  EXPECT_TRUE(r.ok()) << r.message();
}

// The per-taxel table written and read back.
TEST(CalibrationFit, ToolWritesThePerTaxelTable) {
  const std::string csv = record(TACTILE_CALIB_TRUTH, "--repeats 2");
  const std::string out = test::writeTempFile("calib_pt.yaml", "");
  const ToolRun t = calibrate("--recording " + csv + " --params " + TACTILE_CALIB_TRUTH + " --model per_taxel --out " + out);
  ASSERT_EQ(t.code, 0) << t.out << t.err;
  FeatureParams fp;
  CalibrationParams cp;
  ASSERT_TRUE(loadParams(out, fp, cp).ok());
  ASSERT_EQ(cp.taxels.size(), 84u);
  CalibrationRecording rec;
  ASSERT_TRUE(readCalibrationRecording(csv, 6, 14, rec).ok());
  CalibrationFitOptions opt;
  opt.model = CalibrationModel::PerTaxel;
  CalibrationFit fit;
  ASSERT_TRUE(fitCalibration(rec, cp, opt, fit).ok());
  for (int i = 0; i < 84; ++i)
    EXPECT_NEAR(poly(cp.taxels[static_cast<std::size_t>(i)], 3000.0), fit.force(i, 3000.0), 1e-7) << i;
}

// A recording on a few spots (a cross around taxel (2, 5), two border and a
// corner taxel), then made bad one way at a time: each gives exit 1, FAIL and
// the specific reason; no file is written.
TEST(CalibrationFit, BadRecordingsAreNamedWithExitCode1) {
  const std::string csv = record(TACTILE_CALIB_TRUTH, "--spots 2:5,1:5,3:5,2:4,2:6,0:7,5:3,0:0 --unloaded 10");
  const std::vector<std::string> good = lines(csv);
  ASSERT_GT(good.size(), 100u);
  const std::string params = std::string(" --params ") + TACTILE_CALIB_TRUTH;
  struct Case {
    std::string name;
    std::vector<std::string> rec;
    std::vector<std::string> expect;
  };
  std::vector<Case> cases;
  auto loaded = [](const std::string& l) { return std::stod(split(l)[1]) > 0.05; };
  {  // no load
    Case c{"no_load", {good[0]}, {"no loaded frames", "all 10 frames are unloaded"}};
    for (std::size_t k = 1; k <= 10; ++k) c.rec.push_back(good[k]);
    cases.push_back(c);
  }
  {  // no unloaded frame
    Case c{"no_tare", {good[0]}, {"no unloaded frames", "so no tare", "f_ref_n = 0"}};
    for (std::size_t k = 1; k < good.size(); ++k)
      if (loaded(good[k])) c.rec.push_back(good[k]);
    cases.push_back(c);
  }
  {  // every loaded frame saturated
    Case c{"all_saturated", {good[0]}, {"loaded frames are saturated", "full_scale = 4095", "lighter loads"}};
    for (std::size_t k = 1; k < good.size(); ++k) {
      std::vector<std::string> v = split(good[k]);
      if (loaded(good[k]))
        for (std::size_t i = 2; i < v.size(); ++i)
          if (v[i] != "0") v[i] = "4095";
      c.rec.push_back(join(v));
    }
    cases.push_back(c);
  }
  {  // taxel (2, 5) dead: its column zeroed
    Case c{"dead", {good[0]}, {"dead taxel (2, 5)", "raw_33", "wts_check --press"}};
    for (std::size_t k = 1; k < good.size(); ++k) {
      std::vector<std::string> v = split(good[k]);
      v[2 + 2 * 14 + 5] = "0";
      c.rec.push_back(join(v));
    }
    cases.push_back(c);
  }
  {  // a malformed value, a NaN, a short line, a flipped reference
    Case m{"malformed", good, {"line 31, column 3 (raw_0 = taxel (0, 0)): 'abc' is not a number"}};
    std::vector<std::string> v = split(m.rec[30]);
    v[2] = "abc";
    m.rec[30] = join(v);
    cases.push_back(m);
    Case nan{"nan", good, {"line 41, column 2 (f_ref_n): nan: not a finite value"}};
    v = split(nan.rec[40]);
    v[1] = "nan";
    nan.rec[40] = join(v);
    cases.push_back(nan);
    Case sh{"short", good, {"line 51: 85 values, expected 86"}};
    v = split(sh.rec[50]);
    v.pop_back();
    sh.rec[50] = join(v);
    cases.push_back(sh);
    Case neg{"negative", {good[0]}, {"f_ref_n < -0.05 N", "write -Fz"}};
    for (std::size_t k = 1; k < good.size(); ++k) {
      v = split(good[k]);
      v[1] = std::to_string(-std::stod(v[1]));
      neg.rec.push_back(join(v));
    }
    cases.push_back(neg);
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string rec = writeLines(c.name + ".csv", c.rec);
    const std::string out = test::writeTempFile(c.name + "_never.yaml", "");
    std::remove(out.c_str());
    const ToolRun t = calibrate("--recording " + rec + params + " --out " + out);
    EXPECT_EQ(t.code, 1) << t.out << t.err;
    EXPECT_NE(t.out.find("FAIL: " + rec), std::string::npos) << t.out;  // names the file
    for (const std::string& e : c.expect) EXPECT_NE(t.out.find(e), std::string::npos) << e << "\n" << t.out;
    EXPECT_FALSE(std::ifstream(out).good()) << "a file was written";
  }

  // A few saturated frames are dropped, counted, and the fit passes.
  std::vector<std::string> some = good;
  int saturated = 0;
  for (std::size_t k = 1; k < some.size() && saturated < 5; ++k)
    if (loaded(some[k])) {
      std::vector<std::string> v = split(some[k]);
      for (std::size_t i = 2; i < v.size(); ++i)
        if (v[i] != "0") v[i] = "4095";
      some[k] = join(v);
      ++saturated;
    }
  const ToolRun t = calibrate("--recording " + writeLines("some_sat.csv", some) + params + " --out " +
                          test::writeTempFile("some_sat.yaml", ""));
  EXPECT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("5 saturated dropped"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("note: 5 of"), std::string::npos) << t.out;
}

TEST(CalibrationFit, TooFewLoadsForTheDegree) {
  // Two load levels on interior taxels (the same full-scale force): two loads.
  const std::string csv = record(TACTILE_CALIB_TRUTH, "--spots 2:5,2:6,3:7 --fractions 0.4,0.8");
  const std::string params = std::string(" --params ") + TACTILE_CALIB_TRUTH;
  ToolRun t = calibrate("--recording " + csv + params + " --out " + test::writeTempFile("few.yaml", ""));
  EXPECT_EQ(t.code, 1) << t.out;
  EXPECT_NE(t.out.find("2 distinct load(s)"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("needs at least 4 distinct non-zero loads"), std::string::npos) << t.out;
  // Degree 1 needs 2: the same recording then fits a shared line (the line
  // through the cubic truth misses by ~10 %: the residual limits relaxed; the
  // border model would need the ring loaded).
  t = calibrate("--recording " + csv + params + " --degree 1 --model shared --max-rms-pct 50 --max-se-pct 50 --out " +
                test::writeTempFile("few1.yaml", ""));
  EXPECT_EQ(t.code, 0) << t.out;
  t = calibrate("--recording " + csv + params + " --degree 1 --out " + test::writeTempFile("few2.yaml", ""));
  EXPECT_EQ(t.code, 1) << t.out;
  EXPECT_NE(t.out.find("the outer ring of taxels"), std::string::npos) << t.out;
}

TEST(CalibrationFit, UsageErrorsExitWith2) {
  EXPECT_EQ(calibrate("").code, 2);
  EXPECT_EQ(calibrate("--recording x.csv").code, 2);  // no --out
  EXPECT_EQ(calibrate("--recording /nonexistent/rec.csv --out /tmp/x.yaml").code, 2);
  EXPECT_EQ(calibrate("--recording x.csv --out y.yaml --degree 4").code, 2);
  EXPECT_EQ(calibrate("--recording x.csv --out y.yaml --model linear").code, 2);
  EXPECT_EQ(calibrate("--bogus").code, 2);
}

// replaceCalibrationBlock keeps everything but the calibration section.
TEST(CalibrationFit, ReplacesOnlyTheCalibrationSection) {
  const std::string in =
      "# head\nfeatures:\n  rows: 6   # six\n\ncalibration:   # old\n  coeffs: [0, 1]\n  # inner\n\n"
      "  noise_counts: 3\n# tail comment\nother: 1\n";
  const std::string outText = replaceCalibrationBlock(in, "calibration:\n  coeffs: [0, 2]\n");
  EXPECT_EQ(outText, "# head\nfeatures:\n  rows: 6   # six\n\ncalibration:\n  coeffs: [0, 2]\n# tail comment\nother: 1\n");
  EXPECT_EQ(replaceCalibrationBlock("features:\n  rows: 6", "calibration:\n  coeffs: [0, 2]\n"),
            "features:\n  rows: 6\ncalibration:\n  coeffs: [0, 2]\n");
  // "calibration_x:" is another key.
  EXPECT_EQ(replaceCalibrationBlock("calibration_x: 1\n", "calibration: {}\n"), "calibration_x: 1\ncalibration: {}\n");
}
