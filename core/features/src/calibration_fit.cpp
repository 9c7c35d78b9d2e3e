#include "tactile_features/calibration_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace tactile {

namespace {

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string taxelName(int i, int cols) {
  return "(" + std::to_string(i / cols) + ", " + std::to_string(i % cols) + ")";
}

std::string columnName(std::size_t k, int cols) {
  if (k == 0) return "time_s";
  if (k == 1) return "f_ref_n";
  const int i = static_cast<int>(k) - 2;
  return "raw_" + std::to_string(i) + " = taxel " + taxelName(i, cols);
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : line) {
    if (ch == ',') {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(trim(cur));
  return out;
}

// Whole field a number (strtod accepts "nan" and "inf": the caller checks).
bool parseNumber(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && errno != ERANGE;
}

bool isBorder(int i, int rows, int cols) {
  const int r = i / cols, c = i % cols;
  return r == 0 || c == 0 || r == rows - 1 || c == cols - 1;
}

// The coefficient set tactile::Calibration uses for taxel i (same rule as
// Calibration::configure()).
const std::array<double, 4>& coeffsOf(const CalibrationParams& p, int i) {
  if (!p.taxels.empty()) return p.taxels[static_cast<std::size_t>(i)];
  if (p.use_border && isBorder(i, p.rows, p.cols)) return p.border_coeffs;
  return p.coeffs;
}

double poly(const std::array<double, 4>& k, double x) { return k[0] + x * (k[1] + x * (k[2] + x * k[3])); }

// min 1/2 x^T H x - g^T x subject to x >= 0 (H symmetric positive definite,
// column-scaled so its diagonal is ~1): Lawson-Hanson's active-set method on
// the normal equations. Returns the number of coefficients held at 0.
int solveNonnegative(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, Eigen::VectorXd& x) {
  const Eigen::Index n = H.rows();
  x = H.ldlt().solve(g);
  if ((x.array() >= 0.0).all()) return 0;
  std::vector<bool> free_set(static_cast<std::size_t>(n), false);
  x.setZero();
  const double tol = 1e-12 * std::max(1.0, g.cwiseAbs().maxCoeff());
  auto solveFree = [&](Eigen::VectorXd& z) {
    std::vector<Eigen::Index> idx;
    for (Eigen::Index k = 0; k < n; ++k)
      if (free_set[static_cast<std::size_t>(k)]) idx.push_back(k);
    z = Eigen::VectorXd::Zero(n);
    if (idx.empty()) return;
    const auto m = static_cast<Eigen::Index>(idx.size());
    Eigen::MatrixXd Hf(m, m);
    Eigen::VectorXd gf(m);
    for (Eigen::Index a = 0; a < m; ++a) {
      gf(a) = g(idx[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < m; ++b) Hf(a, b) = H(idx[static_cast<std::size_t>(a)], idx[static_cast<std::size_t>(b)]);
    }
    const Eigen::VectorXd zf = Hf.ldlt().solve(gf);
    for (Eigen::Index a = 0; a < m; ++a) z(idx[static_cast<std::size_t>(a)]) = zf(a);
  };
  for (Eigen::Index outer = 0; outer < 3 * n + 10; ++outer) {
    const Eigen::VectorXd w = g - H * x;  // the negative gradient
    Eigen::Index t = -1;
    double best = tol;
    for (Eigen::Index k = 0; k < n; ++k)
      if (!free_set[static_cast<std::size_t>(k)] && w(k) > best) {
        best = w(k);
        t = k;
      }
    if (t < 0) break;  // Karush-Kuhn-Tucker conditions hold
    free_set[static_cast<std::size_t>(t)] = true;
    for (Eigen::Index inner = 0; inner < 3 * n + 10; ++inner) {
      Eigen::VectorXd z;
      solveFree(z);
      bool feasible = true;
      for (Eigen::Index k = 0; k < n; ++k)
        if (free_set[static_cast<std::size_t>(k)] && !(z(k) > 0.0)) feasible = false;
      if (feasible) {
        x = z;
        break;
      }
      double alpha = 1.0;
      for (Eigen::Index k = 0; k < n; ++k)
        if (free_set[static_cast<std::size_t>(k)] && !(z(k) > 0.0)) alpha = std::min(alpha, x(k) / (x(k) - z(k)));
      x += alpha * (z - x);
      for (Eigen::Index k = 0; k < n; ++k)
        if (free_set[static_cast<std::size_t>(k)] && x(k) <= 1e-15) {
          free_set[static_cast<std::size_t>(k)] = false;
          x(k) = 0.0;
        }
    }
  }
  int held = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (!free_set[static_cast<std::size_t>(k)]) {
      x(k) = 0.0;
      ++held;
    }
  return held;
}

// Condition number of the columns `use` of the (column-scaled) Gram matrix
// G = D H D: sqrt(lambda_max / lambda_min) is the design matrix's.
double gramCondition(const Eigen::MatrixXd& G) {
  if (G.rows() == 0) return std::numeric_limits<double>::infinity();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(G, Eigen::EigenvaluesOnly);
  const double lo = es.eigenvalues().minCoeff(), hi = es.eigenvalues().maxCoeff();
  if (!(lo > hi * 1e-300) || !(hi > 0.0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(hi / lo);
}

struct Entry {
  int taxel;
  double x;  // tared counts above the noise
};

}  // namespace

ConfigResult readCalibrationRecording(std::istream& in, const std::string& name, int rows, int cols,
                                      CalibrationRecording& out) {
  out = CalibrationRecording{};
  out.file = name;
  const std::string F = name.empty() ? std::string("<recording>") : name;
  if (rows < 1 || rows > kMaxRows || cols < 1 || cols > kMaxCols)
    return ConfigResult::failure(F + ": sensor size " + std::to_string(rows) + " x " + std::to_string(cols) +
                                 " out of range (rows in [1, " + std::to_string(kMaxRows) + "], cols in [1, " +
                                 std::to_string(kMaxCols) + "])");
  out.rows = rows;
  out.cols = cols;
  const int n = rows * cols;
  const std::size_t expected = static_cast<std::size_t>(2 + n);
  const std::string layout = "time_s, f_ref_n and " + std::to_string(n) + " raw counts raw_0..raw_" +
                             std::to_string(n - 1) + " for a " + std::to_string(rows) + " x " + std::to_string(cols) +
                             " sensor";
  std::string text;
  long lineno = 0;
  bool first = true;
  while (std::getline(in, text)) {
    ++lineno;
    const std::string t = trim(text);
    if (t.empty() || t[0] == '#') continue;
    const std::vector<std::string> fields = splitCsv(t);
    const std::string where = F + ": line " + std::to_string(lineno);
    double v = 0.0;
    if (first) {
      first = false;
      if (!parseNumber(fields[0], v)) {  // the header line
        if (fields.size() != expected)
          return ConfigResult::failure(where + ": the header has " + std::to_string(fields.size()) +
                                       " columns, expected " + std::to_string(expected) + " (" + layout +
                                       "): a recording of another sensor size, or a different format "
                                       "(docs/calibration.md)");
        continue;
      }
    }
    if (fields.size() != expected)
      return ConfigResult::failure(where + ": " + std::to_string(fields.size()) + " values, expected " +
                                   std::to_string(expected) + " (" + layout +
                                   "): a truncated or joined line: fix or delete it");
    const std::size_t base = out.raw.size();
    out.raw.resize(base + static_cast<std::size_t>(n));
    double tm = 0.0, fr = 0.0;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string col = ", column " + std::to_string(k + 1) + " (" + columnName(k, cols) + ")";
      if (!parseNumber(fields[k], v))
        return ConfigResult::failure(where + col + ": '" + fields[k] + "' is not a number: fix or delete the line");
      if (!std::isfinite(v))
        return ConfigResult::failure(where + col + ": " + fields[k] +
                                     ": not a finite value (a sample the recorder could not read): delete the line "
                                     "or record again");
      if (k == 0) {
        tm = v;
      } else if (k == 1) {
        fr = v;
      } else {
        if (v < 0.0 || v > 4095.0)
          return ConfigResult::failure(where + col + ": " + fields[k] +
                                       " outside the 12-bit range [0, 4095]: raw counts, not forces, are expected");
        out.raw[base + k - 2] = v;
      }
    }
    out.time_s.push_back(tm);
    out.f_ref.push_back(fr);
    out.line.push_back(lineno);
  }
  if (out.frames() == 0)
    return ConfigResult::failure(F + ": no frames (" + std::to_string(lineno) +
                                 " lines, none a data line): expected a header and one line per frame (" + layout + ")");
  return ConfigResult::success();
}

ConfigResult readCalibrationRecording(const std::string& file, int rows, int cols, CalibrationRecording& out) {
  std::ifstream in(file);
  if (!in) return ConfigResult::failure(file + ": cannot open the recording");
  return readCalibrationRecording(in, file, rows, cols, out);
}

const char* toString(CalibrationModel m) {
  switch (m) {
    case CalibrationModel::Shared: return "shared";
    case CalibrationModel::Border: return "border";
    case CalibrationModel::PerTaxel: return "per_taxel";
  }
  return "?";
}

bool parseCalibrationModel(const std::string& s, CalibrationModel& out) {
  if (s == "shared") out = CalibrationModel::Shared;
  else if (s == "border") out = CalibrationModel::Border;
  else if (s == "per_taxel") out = CalibrationModel::PerTaxel;
  else return false;
  return true;
}

ConfigResult checkCalibrationFitOptions(const CalibrationFitOptions& o) {
  if (o.degree < 1 || o.degree > 3) return rangeError("degree", o.degree, "must be in [1, 3] (c1..c3; c0 = 0)");
  if (!(o.unloaded_max_n > 0.0) || !std::isfinite(o.unloaded_max_n))
    return rangeError("unloaded_max_n", o.unloaded_max_n, "must be > 0 (N)");
  if (!(o.noise_sigmas > 0.0) || !std::isfinite(o.noise_sigmas))
    return rangeError("noise_sigmas", o.noise_sigmas, "must be > 0");
  if (!(o.min_noise_counts > 0.0) || !std::isfinite(o.min_noise_counts))
    return rangeError("min_noise_counts", o.min_noise_counts, "must be > 0 (counts)");
  if (!(o.loaded_sigmas > 0.0) || !std::isfinite(o.loaded_sigmas))
    return rangeError("loaded_sigmas", o.loaded_sigmas, "must be > 0");
  if (!(o.ridge >= 0.0) || !std::isfinite(o.ridge)) return rangeError("ridge", o.ridge, "must be >= 0");
  if (!(o.distinct_load_resolution > 0.0) || !(o.distinct_load_resolution < 0.5))
    return rangeError("distinct_load_resolution", o.distinct_load_resolution, "must be in (0, 0.5)");
  if (!(o.max_condition > 1.0)) return rangeError("max_condition", o.max_condition, "must be > 1");
  return ConfigResult::success();
}

double CalibrationFit::force(int taxel, double counts) const { return poly(coeffsOf(params, taxel), counts); }

double CalibrationFit::curveStdError(int taxel, double counts) const {
  const std::size_t P = static_cast<std::size_t>(unknowns);
  if (taxel < 0 || static_cast<std::size_t>(taxel) >= param_index.size() || covariance.size() != P * P) return 0.0;
  const double u = counts / params.full_scale;
  double phi[3] = {u, u * u, u * u * u};
  const std::size_t i0 = static_cast<std::size_t>(param_index[static_cast<std::size_t>(taxel)]);
  double v = 0.0;
  for (int a = 0; a < degree; ++a)
    for (int b = 0; b < degree; ++b)
      v += phi[a] * phi[b] * covariance[(i0 + static_cast<std::size_t>(a)) * P + i0 + static_cast<std::size_t>(b)];
  return std::sqrt(std::max(0.0, v));
}

namespace {

// fitCalibration's steps, in order, on the recording and the fit's working
// state: the frames each step keeps, and the normal equations of a model.
struct Fitter {
  Fitter(const CalibrationRecording& rec_, const CalibrationParams& base_, const CalibrationFitOptions& opt_,
         CalibrationFit& out_, const std::string& file)
      : rec(rec_), base(base_), opt(opt_), out(out_), F(file), rows(base_.rows), cols(base_.cols),
        n(base_.rows * base_.cols), d(opt_.degree), FS(base_.full_scale), N(rec_.frames()) {}

  const CalibrationRecording& rec;
  const CalibrationParams& base;
  const CalibrationFitOptions& opt;
  CalibrationFit& out;
  const std::string F;  // the recording's name in the messages
  const int rows, cols, n, d;
  const double FS;
  const std::size_t N;
  std::vector<std::size_t> unloaded, loaded;  // frames (splitFrames)
  std::vector<std::vector<Entry>> rowsUsed;    // per used frame: its taxels above the noise (selectLoaded)
  std::vector<std::size_t> used;               // the loaded frames in the fit
  std::vector<double> maxTared;                // per taxel, over all loaded frames
  std::size_t M = 0;                           // used.size()
  std::vector<double> fref;                    // f_ref of the used frames

  // ---- Frames: unloaded (tare), loaded, impossible (negative) ------------
  ConfigResult splitFrames() {
    std::size_t negative = 0, first_negative = 0;
    for (std::size_t j = 0; j < N; ++j) {
      const double f = rec.f_ref[j];
      if (f < -opt.unloaded_max_n) {
        if (negative++ == 0) first_negative = j;
      } else if (f <= opt.unloaded_max_n) {
        unloaded.push_back(j);
      } else {
        loaded.push_back(j);
      }
    }
    const std::string um = fmt("%g", opt.unloaded_max_n);
    if (negative > 0)
      return ConfigResult::failure(F + ": f_ref_n < -" + um + " N on " + std::to_string(negative) + " frame(s) (first at line " +
                                   std::to_string(rec.line[first_negative]) + ": " + fmt("%g", rec.f_ref[first_negative]) +
                                   " N): a load pressing on the pad is positive; a reference F/T sensor whose z points "
                                   "out of the pad reads -Fz: write -Fz (docs/calibration.md)");
    if (unloaded.empty())
      return ConfigResult::failure(F + ": no unloaded frames (|f_ref_n| <= " + um +
                                   " N), so no tare: record about 1 s with nothing touching the pad and f_ref_n = 0 "
                                   "(at the start, and between loads)");
    if (loaded.empty())
      return ConfigResult::failure(F + ": no loaded frames (f_ref_n > " + um + " N): all " + std::to_string(N) +
                                   " frames are unloaded: record presses with known loads (docs/calibration.md)");
    out.frames_unloaded = unloaded.size();
    out.frames_loaded = loaded.size();
    return ConfigResult::success();
  }

  // ---- Tare and noise from the unloaded frames ----------------------------
  ConfigResult tareAndNoise() {
    out.tare.assign(static_cast<std::size_t>(n), 0.0);
    out.noise.assign(static_cast<std::size_t>(n), opt.min_noise_counts);
    for (int i = 0; i < n; ++i) {
      double s = 0.0;
      for (std::size_t j : unloaded) s += rec.rawAt(j, i);
      const double mean = s / static_cast<double>(unloaded.size());
      double v = 0.0;
      for (std::size_t j : unloaded) v += (rec.rawAt(j, i) - mean) * (rec.rawAt(j, i) - mean);
      const double sd = unloaded.size() > 1 ? std::sqrt(v / static_cast<double>(unloaded.size() - 1)) : 0.0;
      out.tare[static_cast<std::size_t>(i)] = mean;
      out.noise[static_cast<std::size_t>(i)] = std::max(sd, opt.min_noise_counts);
    }
    int worst = -1;
    for (int i = 0; i < n; ++i)
      if (out.tare[static_cast<std::size_t>(i)] > base.max_tare &&
          (worst < 0 || out.tare[static_cast<std::size_t>(i)] > out.tare[static_cast<std::size_t>(worst)]))
        worst = i;
    if (worst >= 0)
      return ConfigResult::failure(
          F + ": taxel " + taxelName(worst, cols) + " reads " + fmt("%.0f", out.tare[static_cast<std::size_t>(worst)]) +
          " counts on average over the unloaded frames, above calibration.max_tare = " + std::to_string(base.max_tare) +
          ": the pad is pressed while f_ref_n says 0 (a cover, a weight left on it, or f_ref_n = 0 written for loaded "
          "frames): record the unloaded frames with nothing touching the pad");
    return ConfigResult::success();
  }

  // ---- Loaded frames: tared counts above the noise; saturated, silent -----
  ConfigResult selectLoaded() {
    maxTared.assign(static_cast<std::size_t>(n), 0.0);
    std::size_t first_sat = 0;
    int first_sat_taxel = -1;
    for (std::size_t j : loaded) {
      bool sat = false;
      std::vector<Entry> e;
      for (int i = 0; i < n; ++i) {
        const double raw = rec.rawAt(j, i);
        const double x = raw - out.tare[static_cast<std::size_t>(i)];
        maxTared[static_cast<std::size_t>(i)] = std::max(maxTared[static_cast<std::size_t>(i)], x);
        if (raw >= FS && !sat) {
          sat = true;
          if (first_sat_taxel < 0) {
            first_sat = j;
            first_sat_taxel = i;
          }
        }
        if (x > opt.noise_sigmas * out.noise[static_cast<std::size_t>(i)]) e.push_back({i, x});
      }
      if (sat) {
        ++out.frames_saturated;
        continue;
      }
      if (e.empty()) {
        ++out.frames_silent;
        continue;
      }
      rowsUsed.push_back(std::move(e));
      used.push_back(j);
    }
    if (out.frames_saturated == loaded.size())
      return ConfigResult::failure(F + ": all " + std::to_string(loaded.size()) +
                                   " loaded frames are saturated (a raw count at full_scale = " + fmt("%.0f", FS) +
                                   "; first at line " + std::to_string(rec.line[first_sat]) + ", taxel " +
                                   taxelName(first_sat_taxel, cols) +
                                   "): a saturated count no longer follows the load: record lighter loads, up to just "
                                   "below saturation");
    if (used.empty())
      return ConfigResult::failure(F + ": none of the " + std::to_string(loaded.size() - out.frames_saturated) +
                                   " unsaturated loaded frames has a taxel above its noise (" + fmt("%g", opt.noise_sigmas) +
                                   " sigma over the tare): the pad does not respond to the loads (loads below the firing "
                                   "threshold, the wrong device, or the raw columns not the pad's)");
    if (out.frames_saturated > 0)
      out.notes.push_back(std::to_string(out.frames_saturated) + " of " + std::to_string(loaded.size()) +
                          " loaded frames dropped: saturated (a raw count >= " + fmt("%.0f", FS) + ", first at line " +
                          std::to_string(rec.line[first_sat]) + ", taxel " + taxelName(first_sat_taxel, cols) +
                          "): the fit covers the counts below full scale");
    if (out.frames_silent > 0)
      out.notes.push_back(std::to_string(out.frames_silent) + " loaded frames dropped: no taxel above its noise (a load "
                          "below the firing threshold or on a dead spot)");
    M = used.size();
    fref.assign(M, 0.0);
    for (std::size_t a = 0; a < M; ++a) fref[a] = rec.f_ref[used[a]];
    return ConfigResult::success();
  }

  // ---- Dead taxels: silent while every 4-neighbour was loaded -------------
  ConfigResult deadTaxels() const {
    std::string dead;
    int ndead = 0;
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      if (maxTared[k] > opt.noise_sigmas * out.noise[k]) continue;
      const int rr = i / cols, cc = i % cols;
      const int nb[4][2] = {{rr - 1, cc}, {rr + 1, cc}, {rr, cc - 1}, {rr, cc + 1}};
      int have = 0, loadedNb = 0;
      std::string list;
      for (const auto& q : nb) {
        if (q[0] < 0 || q[0] >= rows || q[1] < 0 || q[1] >= cols) continue;
        ++have;
        const std::size_t m = static_cast<std::size_t>(q[0] * cols + q[1]);
        if (maxTared[m] > opt.loaded_sigmas * out.noise[m]) ++loadedNb;
      }
      if (have > 0 && loadedNb == have) {
        dead += std::string(ndead ? ", " : "") + taxelName(i, cols) + " (raw_" + std::to_string(i) + ", at most " +
                fmt("%.0f", std::max(0.0, maxTared[k])) + " counts over its tare)";
        ++ndead;
      }
    }
    if (ndead > 0)
      return ConfigResult::failure(
          F + ": dead taxel" + (ndead > 1 ? "s " : " ") + dead + ": never above " + fmt("%g", opt.noise_sigmas) +
          " noise sigmas while each of its neighbours was loaded: check with `wts_check --press`; if it stays "
          "silent the pad has a dead cell (the features read it as 0): repair or replace the pad. If the load simply "
          "never reached it (a spot the recording skipped), press on it and record again");
    return ConfigResult::success();
  }

  // ---- Distinct loads ----------------------------------------------------
  ConfigResult distinctLoads() {
    std::vector<double> f;
    for (std::size_t j : used) f.push_back(rec.f_ref[j]);
    std::sort(f.begin(), f.end());
    out.load_max = f.back();
    const double res = opt.distinct_load_resolution * out.load_max;
    std::vector<double> levels;
    for (double v : f)
      if (levels.empty() || v - levels.back() > res) levels.push_back(v);
    out.distinct_loads = static_cast<int>(levels.size());
    if (out.distinct_loads < d + 1) {
      std::string list;
      for (std::size_t k = 0; k < levels.size() && k < 6; ++k) list += (k ? ", " : "") + fmt("%.3g", levels[k]);
      return ConfigResult::failure(
          F + ": " + std::to_string(out.distinct_loads) + " distinct load(s) (" + list + " N; loads within " +
          fmt("%g", 100.0 * opt.distinct_load_resolution) + " % of the largest count as one) for degree " +
          std::to_string(d) + ": a degree-" + std::to_string(d) + " fit needs at least " + std::to_string(d + 1) +
          " distinct non-zero loads (" + std::to_string(d) +
          " coefficients and one more to see the residual): record more load levels, or lower --degree");
    }
    return ConfigResult::success();
  }

  // ---- Unknowns ------------------------------------------------------------
  // Groups: shared 0; border: interior 0, ring 1; per_taxel: the taxel.
  int groupOf(CalibrationModel m, int i) const {
    if (m == CalibrationModel::Shared) return 0;
    if (m == CalibrationModel::Border) return isBorder(i, rows, cols) ? 1 : 0;
    return i;
  }
  int groupsOf(CalibrationModel m) const {
    return m == CalibrationModel::Shared ? 1 : m == CalibrationModel::Border ? 2 : n;
  }

  // Normal equations of model m: H = A^T A, g = A^T f (normalised counts u).
  void normal(CalibrationModel m, Eigen::MatrixXd& H, Eigen::VectorXd& g) const {
    const Eigen::Index P = groupsOf(m) * d;
    H = Eigen::MatrixXd::Zero(P, P);
    g = Eigen::VectorXd::Zero(P);
    std::vector<std::pair<Eigen::Index, double>> row;
    Eigen::VectorXd dense = Eigen::VectorXd::Zero(P);
    for (std::size_t a = 0; a < M; ++a) {
      // Sum the frame's entries per unknown (several taxels share one in the
      // group models), then add the row's outer product.
      row.clear();
      for (const Entry& e : rowsUsed[a]) {
        const double u = e.x / FS;
        double p = 1.0;
        for (int k = 0; k < d; ++k) {
          p *= u;
          const Eigen::Index c = groupOf(m, e.taxel) * d + k;
          if (dense(c) == 0.0) row.push_back({c, 0.0});
          dense(c) += p;
        }
      }
      for (auto& c : row) {
        c.second = dense(c.first);
        dense(c.first) = 0.0;
      }
      for (const auto& c1 : row) {
        g(c1.first) += c1.second * fref[a];
        for (const auto& c2 : row) H(c1.first, c2.first) += c1.second * c2.second;
      }
    }
  }

  // Scaled solve: columns scaled to a unit diagonal (zero columns left at 1).
  static Eigen::VectorXd scaling(const Eigen::MatrixXd& H) {
    Eigen::VectorXd s(H.rows());
    for (Eigen::Index k = 0; k < H.rows(); ++k) s(k) = H(k, k) > 0.0 ? 1.0 / std::sqrt(H(k, k)) : 1.0;
    return s;
  }
  int solve(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, Eigen::VectorXd& theta) const {
    const Eigen::VectorXd s = scaling(H);
    const Eigen::MatrixXd Hs = s.asDiagonal() * H * s.asDiagonal();
    const Eigen::VectorXd gs = s.asDiagonal() * g;
    Eigen::VectorXd y;
    int held = 0;
    if (opt.nonnegative) {
      held = solveNonnegative(Hs, gs, y);
    } else {
      y = Hs.ldlt().solve(gs);
    }
    theta = s.asDiagonal() * y;
    return held;
  }
  void excitedGroups(CalibrationModel m, std::vector<int>& frames) const {
    frames.assign(static_cast<std::size_t>(groupsOf(m)), 0);
    for (const auto& e : rowsUsed) {
      std::vector<int> seen;
      for (const Entry& x : e) {
        const int gi = groupOf(m, x.taxel);
        if (std::find(seen.begin(), seen.end(), gi) == seen.end()) {
          seen.push_back(gi);
          ++frames[static_cast<std::size_t>(gi)];
        }
      }
    }
  }
  static double designCondition(const Eigen::MatrixXd& H) {
    std::vector<Eigen::Index> idx;
    for (Eigen::Index k = 0; k < H.rows(); ++k)
      if (H(k, k) > 0.0) idx.push_back(k);
    Eigen::MatrixXd G(static_cast<Eigen::Index>(idx.size()), static_cast<Eigen::Index>(idx.size()));
    for (std::size_t a = 0; a < idx.size(); ++a)
      for (std::size_t b = 0; b < idx.size(); ++b)
        G(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
            H(idx[a], idx[b]) / std::sqrt(H(idx[a], idx[a]) * H(idx[b], idx[b]));
    return gramCondition(G);
  }

  // The group model (shared or border) fitted directly, or as the per_taxel prior.
  ConfigResult chooseGroupModel(CalibrationModel& groupModel) {
    groupModel = opt.model == CalibrationModel::Shared ? CalibrationModel::Shared : CalibrationModel::Border;
    std::vector<int> gf;
    excitedGroups(CalibrationModel::Border, gf);
    if (groupModel == CalibrationModel::Border && (gf[0] == 0 || gf[1] == 0)) {
      const std::string which = gf[1] == 0 ? "the outer ring of taxels (row 0, row " + std::to_string(rows - 1) +
                                                 ", column 0, column " + std::to_string(cols - 1) + ")"
                                           : "the interior taxels";
      if (opt.model == CalibrationModel::Border)
        return ConfigResult::failure(F + ": " + which + " never read above the noise in the " + std::to_string(M) +
                                     " loaded frames: the border model fits a polynomial of their own: press on them "
                                     "too, or fit --model shared");
      groupModel = CalibrationModel::Shared;  // per_taxel prior: one polynomial
      out.notes.push_back(which + " never loaded: the per-taxel prior is one shared polynomial");
    }
    return ConfigResult::success();
  }

  // per_taxel: each taxel's polynomial, ridge-regularised towards the group
  // model's (`thetaG`); trace_eff: the effective number of parameters.
  ConfigResult fitPerTaxel(CalibrationModel groupModel, const Eigen::VectorXd& thetaG, Eigen::MatrixXd& Hfinal,
                           Eigen::VectorXd& theta, double& trace_eff) {
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    normal(CalibrationModel::PerTaxel, H, g);
    out.condition = designCondition(H);
    Eigen::VectorXd prior(n * d);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < d; ++k) prior(i * d + k) = thetaG(groupOf(groupModel, i) * d + k);
    Eigen::VectorXd lambda(n * d);
    for (int k = 0; k < d; ++k) {
      double mean = 0.0;
      for (int i = 0; i < n; ++i) mean += H(i * d + k, i * d + k);
      mean /= n;
      for (int i = 0; i < n; ++i) lambda(i * d + k) = opt.ridge * mean;
    }
    for (int i = 0; i < n; ++i)
      if (H(i * d, i * d) == 0.0) out.at_prior.push_back(i);
    if (!out.at_prior.empty() && !(opt.ridge > 0.0))
      return ConfigResult::failure(F + ": " + std::to_string(out.at_prior.size()) +
                                   " taxel(s) never loaded (e.g. " + taxelName(out.at_prior[0], cols) +
                                   ") and ridge 0: per_taxel needs a load on every taxel, or a ridge > 0 (they then keep "
                                   "the border model's polynomial)");
    Hfinal = H;
    Hfinal.diagonal() += lambda;
    const Eigen::VectorXd gr = g + lambda.cwiseProduct(prior);
    {
      const Eigen::VectorXd s = scaling(Hfinal);
      out.condition_regularised = gramCondition(s.asDiagonal() * Hfinal * s.asDiagonal());
    }
    if (!(out.condition_regularised <= opt.max_condition))
      return ConfigResult::failure(F + ": the per-taxel fit is ill-conditioned even with the ridge (condition " +
                                   fmt("%.3g", out.condition_regularised) + ", limit " + fmt("%.3g", opt.max_condition) +
                                   "): raise --ridge or record loads at more spots");
    out.constrained = solve(Hfinal, gr, theta);
    // Effective number of parameters: trace((H + Lambda)^-1 H).
    trace_eff = Hfinal.ldlt().solve(H).trace();
    if (!out.at_prior.empty()) {
      std::string list;
      for (std::size_t k = 0; k < out.at_prior.size() && k < 8; ++k)
        list += (k ? ", " : "") + taxelName(out.at_prior[k], cols);
      if (out.at_prior.size() > 8) list += ", ...";
      out.notes.push_back(std::to_string(out.at_prior.size()) + " taxel(s) never loaded keep the " +
                          toString(groupModel) + " model's polynomial: " + list);
    }
    return ConfigResult::success();
  }

  // ---- Coefficients in counts, the result's parameters ---------------------
  void setCoefficients(CalibrationModel groupModel, CalibrationModel fm, const Eigen::VectorXd& thetaG,
                       const Eigen::VectorXd& theta) {
    auto coefficients = [&](const Eigen::VectorXd& th, int first) {
      std::array<double, 4> c{0.0, 0.0, 0.0, 0.0};
      for (int k = 0; k < d; ++k) c[static_cast<std::size_t>(k + 1)] = th(first + k) / std::pow(FS, k + 1);
      return c;
    };
    out.params = base;
    out.params.taxels.clear();
    if (groupModel == CalibrationModel::Border) {
      out.params.coeffs = coefficients(thetaG, 0);
      out.params.border_coeffs = coefficients(thetaG, d);
      out.params.use_border = true;
    } else {
      out.params.coeffs = coefficients(thetaG, 0);
      out.params.use_border = false;
    }
    if (fm == CalibrationModel::PerTaxel)
      for (int i = 0; i < n; ++i) out.params.taxels.push_back(coefficients(theta, i * d));
  }

  ConfigResult checkCurves(CalibrationModel groupModel, CalibrationModel fm) {
    // A zero slope at 0 counts (the constraint holding c1 at 0): the light loads are missing.
    for (int i = 0; i < n; ++i) {
      const auto& c = coeffsOf(out.params, i);
      if (!(c[1] > 0.0)) {
        const std::string who = fm == CalibrationModel::PerTaxel ? "taxel " + taxelName(i, cols)
                                : (groupModel == CalibrationModel::Border && isBorder(i, rows, cols)) ? "the border polynomial"
                                                                                                       : "the polynomial";
        return ConfigResult::failure(
            F + ": " + who + " fits a slope c1 = " + fmt("%g", c[1]) + " N/count at 0 counts" +
            (opt.nonnegative ? " (held there by the c_k >= 0 constraint)" : "") +
            ", it must be > 0: the loads do not fix the curve near 0 counts (condition " + fmt("%.3g", out.condition) +
            "). Record loads from just above the firing threshold (~0.3 N per taxel); if each load spreads over many "
            "taxels (a plate, a palm), the interior and the border carry it alike and trade scale: add loads on single "
            "taxels (a probe within one taxel), or fit --model shared");
      }
    }
    if (!opt.nonnegative) {
      for (int i = 0; i < n; ++i) {
        const auto& c = coeffsOf(out.params, i);
        bool mono = true;
        for (int s = 0; s <= 64 && mono; ++s) {
          const double x = FS * s / 64.0;
          mono = c[1] + x * (2.0 * c[2] + 3.0 * c[3] * x) > 0.0;
        }
        if (!mono) {
          out.notes.push_back("taxel " + taxelName(i, cols) +
                              " (and perhaps others): the fitted curve is not monotone over [0, full_scale]: the reader "
                              "can use it, the simulated sensor cannot invert it");
          break;
        }
      }
    }
    return ConfigResult::success();
  }

  // ---- Residuals and report --------------------------------------------------
  void residuals(double trace_eff) {
    out.count_min.assign(static_cast<std::size_t>(n), 0.0);
    out.count_max.assign(static_cast<std::size_t>(n), 0.0);
    out.taxel_frames.assign(static_cast<std::size_t>(n), 0);
    std::vector<double> sq(static_cast<std::size_t>(n), 0.0);
    double rss = 0.0;
    for (std::size_t a = 0; a < M; ++a) {
      double pred = 0.0;
      for (const Entry& e : rowsUsed[a]) pred += std::max(0.0, poly(coeffsOf(out.params, e.taxel), e.x));
      const double res = pred - fref[a];
      rss += res * res;
      out.reference.push_back(fref[a]);
      out.predicted.push_back(pred);
      out.frame_line.push_back(rec.line[used[a]]);
      if (std::fabs(res) > out.max_abs_n) {
        out.max_abs_n = std::fabs(res);
        out.max_abs_line = rec.line[used[a]];
      }
      for (const Entry& e : rowsUsed[a]) {
        const std::size_t k = static_cast<std::size_t>(e.taxel);
        const double share = pred > 0.0 ? std::max(0.0, poly(coeffsOf(out.params, e.taxel), e.x)) / pred : 0.0;
        sq[k] += (share * res) * (share * res);
        if (out.taxel_frames[k] == 0 || e.x < out.count_min[k]) out.count_min[k] = e.x;
        out.count_max[k] = std::max(out.count_max[k], e.x);
        ++out.taxel_frames[k];
      }
    }
    out.frames_used = M;
    out.taxel_residual.assign(static_cast<std::size_t>(n), std::numeric_limits<double>::quiet_NaN());
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      if (out.taxel_frames[k] > 0) out.taxel_residual[k] = std::sqrt(sq[k] / out.taxel_frames[k]);
    }
    out.rms_n = std::sqrt(rss / static_cast<double>(M));
    out.rms_pct = 100.0 * out.rms_n / out.load_max;
    const double dof = static_cast<double>(M) - std::max(0.0, trace_eff - out.constrained);
    out.sigma_n = dof >= 1.0 ? std::sqrt(rss / dof) : out.rms_n;
  }

  // Covariance sigma^2 (H + Lambda)^-1 in normalised units.
  void setCovariance(const Eigen::MatrixXd& Hfinal) {
    const Eigen::Index P = Hfinal.rows();
    const Eigen::VectorXd s = scaling(Hfinal);
    const Eigen::MatrixXd Hs = s.asDiagonal() * Hfinal * s.asDiagonal();
    const Eigen::MatrixXd inv = s.asDiagonal() * Hs.ldlt().solve(Eigen::MatrixXd::Identity(P, P)) * s.asDiagonal();
    out.covariance.resize(static_cast<std::size_t>(P * P));
    for (Eigen::Index a = 0; a < P; ++a)
      for (Eigen::Index b = 0; b < P; ++b)
        out.covariance[static_cast<std::size_t>(a * P + b)] = out.sigma_n * out.sigma_n * inv(a, b);
  }
};

}  // namespace

ConfigResult fitCalibration(const CalibrationRecording& rec, const CalibrationParams& base,
                            const CalibrationFitOptions& opt, CalibrationFit& out) {
  out = CalibrationFit{};
  const std::string F = rec.file.empty() ? std::string("<recording>") : rec.file;
  ConfigResult r = checkCalibrationFitOptions(opt);
  if (!r) return ConfigResult::failure(F + ": " + r.message());
  {
    Calibration probe;
    if (!(r = probe.configure(base))) return ConfigResult::failure("base parameters: " + r.message());
  }
  if (rec.rows != base.rows || rec.cols != base.cols)
    return ConfigResult::failure(F + ": a " + std::to_string(rec.rows) + " x " + std::to_string(rec.cols) +
                                 " recording for a " + std::to_string(base.rows) + " x " + std::to_string(base.cols) +
                                 " sensor (the parameter file's features.rows / cols)");
  Fitter w(rec, base, opt, out, F);
  const int n = w.n, d = w.d;
  out.model = opt.model;
  out.degree = d;
  out.frames_total = w.N;
  if (!(r = w.splitFrames()) || !(r = w.tareAndNoise()) || !(r = w.selectLoaded()) || !(r = w.deadTaxels()) ||
      !(r = w.distinctLoads()))
    return r;

  CalibrationModel groupModel = CalibrationModel::Border;
  if (!(r = w.chooseGroupModel(groupModel))) return r;
  Eigen::MatrixXd Hg;
  Eigen::VectorXd gg, thetaG;
  w.normal(groupModel, Hg, gg);
  const double condG = Fitter::designCondition(Hg);
  if (!(condG <= opt.max_condition))
    return ConfigResult::failure(
        F + ": the fit is ill-conditioned (condition " + fmt("%.3g", condG) + " of the column-scaled design, limit " +
        fmt("%.3g", opt.max_condition) + "): the loads do not tell the " + std::to_string(d) +
        " coefficients apart" + (groupModel == CalibrationModel::Border ? " (of the interior and the border)" : "") +
        ": record loads spread over the whole count range on both the interior and the border taxels, or lower --degree");
  int heldG = w.solve(Hg, gg, thetaG);

  Eigen::MatrixXd Hfinal;
  Eigen::VectorXd theta;
  const CalibrationModel fm = opt.model == CalibrationModel::PerTaxel ? CalibrationModel::PerTaxel : groupModel;
  out.param_index.assign(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i) out.param_index[static_cast<std::size_t>(i)] = w.groupOf(fm, i) * d;
  double trace_eff = 0.0;
  if (fm == CalibrationModel::PerTaxel) {
    if (!(r = w.fitPerTaxel(groupModel, thetaG, Hfinal, theta, trace_eff))) return r;
  } else {
    Hfinal = Hg;
    theta = thetaG;
    out.condition = condG;
    out.condition_regularised = condG;
    out.constrained = heldG;
    trace_eff = static_cast<double>(Hg.rows());
  }
  out.unknowns = static_cast<int>(theta.size());

  w.setCoefficients(groupModel, fm, thetaG, theta);
  {
    Calibration probe;
    if (!(r = probe.configure(out.params))) return ConfigResult::failure(F + ": the fitted calibration: " + r.message());
  }
  if (!(r = w.checkCurves(groupModel, fm))) return r;
  w.residuals(trace_eff);
  w.setCovariance(Hfinal);
  return ConfigResult::success();
}

std::string calibrationYaml(const CalibrationParams& p, const std::vector<std::string>& comment) {
  auto list = [](const std::array<double, 4>& c) {
    char b[160];
    std::snprintf(b, sizeof b, "[%.9g, %.9g, %.9g, %.9g]", c[0], c[1], c[2], c[3]);
    return std::string(b);
  };
  std::ostringstream os;
  os << "calibration:\n";
  for (const std::string& c : comment) os << "  #" << (c.empty() ? "" : " ") << c << "\n";
  os << "  full_scale: " << p.full_scale << "\n";
  os << "  coeffs: " << list(p.coeffs) << "\n";
  if (p.use_border) os << "  border_coeffs: " << list(p.border_coeffs) << "\n";
  if (!p.taxels.empty()) {
    os << "  taxels:                  # row-major, row 0 first ({s}: row 0 = most negative y_s): [c0, c1, c2, c3]\n";
    for (std::size_t i = 0; i < p.taxels.size(); ++i)
      os << "    - " << list(p.taxels[i]) << "   # " << taxelName(static_cast<int>(i), p.cols) << "\n";
  }
  os << "  noise_counts: " << fmt("%.9g", p.noise_counts) << "\n";
  os << "  max_tare: " << p.max_tare << "\n";
  return os.str();
}

std::string replaceCalibrationBlock(const std::string& text, const std::string& block) {
  std::vector<std::string> lines;
  {
    std::istringstream is(text);
    std::string l;
    while (std::getline(is, l)) lines.push_back(l);
  }
  // The block: the top-level "calibration:" line and every following line that
  // is indented or blank, up to the next top-level line (trailing blank lines
  // stay outside).
  std::size_t begin = lines.size(), end = lines.size();
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::string& l = lines[k];
    if (l.compare(0, 11, "calibration") == 0) {
      const auto c = l.find_first_not_of(' ', 11);
      if (c != std::string::npos && l[c] == ':') {
        begin = k;
        break;
      }
    }
  }
  std::ostringstream os;
  if (begin == lines.size()) {
    os << text;
    if (!text.empty() && text.back() != '\n') os << "\n";
    os << block;
    return os.str();
  }
  end = begin + 1;
  std::size_t last = begin;
  while (end < lines.size()) {
    const std::string& l = lines[end];
    const bool blank = trim(l).empty();
    if (!blank && l[0] != ' ' && l[0] != '\t') break;
    if (!blank) last = end;
    ++end;
  }
  end = last + 1;
  for (std::size_t k = 0; k < begin; ++k) os << lines[k] << "\n";
  os << block;
  for (std::size_t k = end; k < lines.size(); ++k) os << lines[k] << "\n";
  return os.str();
}

}  // namespace tactile
