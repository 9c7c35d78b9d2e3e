// tactile_calibration_record: the calibration recording of the simulated
// WTS0614, for testing tactile_calibrate against a known calibration and for
// rehearsing the lab procedure (docs/calibration.md).
//
//   tactile_calibration_record --out REC.csv [--params FILE.yaml] [--spots all|interior|border|centre|R:C,...]
//                              [--fractions F,...] [--repeats N=3] [--unloaded N=20] [--probe-radius M=0.0016]
//                              [--ref-noise N=0] [--noise-counts C] [--threshold N] [--seed S=1] [--rate HZ=140]
//
// The rig (App. A's, on the simulated arm): the quasi-static World (world.hpp)
// holds the pad facing down over a fixed spherical probe of --probe-radius
// (default 1.6 mm: its footprint, at most a disc of that radius however deep
// it sinks, stays inside the 3.4 mm taxel it is centred on, like the paper's
// 1 mm cylindrical indenter), and for each spot (a taxel centre) presses it
// to a list of loads:
//     F_k = t + phi_k (f_full - t)
// with t the firing threshold (--threshold, default features.contact_threshold
// of --params), f_full the taxel's force at full scale under the calibration
// and phi_k the --fractions (default 0.05, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9,
// 0.95): from just above the threshold to just below saturation. Each load is
// reached by adjusting the commanded depth (bracketing secant on the arm's
// equilibrium, to 0.2 %), then --repeats frames are acquired (new noise
// each). Before each spot the probe is lifted 3 mm and one unloaded frame is
// recorded; --unloaded frames open the recording.
//
// The sensor's electronics (tactile::sim::TaxelResponse inside the pad)
// invert the `calibration:` block of --params (default the source tree's
// wts0614.yaml): that block is the ground truth a fit must recover. Noise:
// --noise-counts (default calibration.noise_counts of --params, else 6)
// counts 1 sigma, 12-bit rounding, saturation, 0 below the threshold.
//
// f_ref_n = -Fz of the true contact wrench on the sensor ({s}, SensorTruth::
// wrench_s, pressing gives Fz < 0: an F/T sensor under the pad), the layer's
// and the housing's share, plus Gaussian --ref-noise (N, 1 sigma: the
// reference sensor's noise; unloaded frames get it too).
//
// Prints the frames written, the loads, and two checks of the rig: the largest
// share of a frame's true force on taxels other than the probed one (0 for a
// probe within its taxel) and the largest housing force (0: the reference
// then equals the layer's load).
// Exit: 0 written, 1 the simulation failed, 2 usage or parameter error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>

#include "tactile_config/cli_args.hpp"
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_sim_lwr/world.hpp"

#ifndef TACTILE_RECORD_DEFAULT_PARAMS
#define TACTILE_RECORD_DEFAULT_PARAMS ""
#endif

namespace {

using namespace tactile;
using namespace tactile::sim;

void usage() {
  std::fprintf(stderr,
               "usage: tactile_calibration_record --out REC.csv [--params FILE.yaml]\n"
               "         [--spots all|interior|border|centre|R:C,...] [--fractions F,...] [--repeats N=3]\n"
               "         [--unloaded N=20] [--probe-radius M=0.0016] [--ref-noise N=0] [--noise-counts C]\n"
               "         [--threshold N] [--seed S=1] [--rate HZ=140]\n"
               "Presses a probe onto the simulated WTS0614 at each spot and load; writes time_s, f_ref_n, raw_0..\n");
}

bool parseList(const std::string& s, std::vector<double>& out) {
  out.clear();
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0') return false;
    out.push_back(v);
  }
  return !out.empty();
}

/// tactile_calibration_record's command line (parseArgs).
struct RecordArgs {
  std::string out_file, params_file = TACTILE_RECORD_DEFAULT_PARAMS, spots_arg = "all";
  std::vector<double> fractions = {0.05, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 0.95};
  int repeats = 3, unloaded = 20;
  double radius = 0.0016, ref_noise = 0.0, noise_counts = -1.0, threshold = -1.0, rate = 140.0;
  long seed = 1;
};

/// The command line into `args`: -1, or the exit code (help 0, a bad option 2).
int parseArgs(int argc, char** argv, RecordArgs& args) {
  std::string &out_file = args.out_file, &params_file = args.params_file, &spots_arg = args.spots_arg;
  std::vector<double>& fractions = args.fractions;
  int &repeats = args.repeats, &unloaded = args.unloaded;
  double &radius = args.radius, &ref_noise = args.ref_noise, &noise_counts = args.noise_counts,
         &threshold = args.threshold, &rate = args.rate;
  long& seed = args.seed;
  const config::CliArgs cli("tactile_calibration_record", argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() { return cli.value(i); };
    auto number = [&](double lo, double hi) { return cli.number(i, lo, hi); };
    if (a == "--out") out_file = value();
    else if (a == "--params") params_file = value();
    else if (a == "--spots") spots_arg = value();
    else if (a == "--fractions") {
      const std::string v = value();
      if (!parseList(v, fractions) ||
          std::any_of(fractions.begin(), fractions.end(), [](double f) { return !(f > 0.0 && f <= 1.0); })) {
        std::fprintf(stderr, "tactile_calibration_record: --fractions '%s': comma-separated numbers in (0, 1]\n", v.c_str());
        return 2;
      }
    } else if (a == "--repeats") repeats = static_cast<int>(number(1, 1000));
    else if (a == "--unloaded") unloaded = static_cast<int>(number(0, 100000));
    else if (a == "--probe-radius") radius = number(1e-4, 0.05);
    else if (a == "--ref-noise") ref_noise = number(0, 10);
    else if (a == "--noise-counts") noise_counts = number(0, 1000);
    else if (a == "--threshold") threshold = number(0, 100);
    else if (a == "--seed") seed = static_cast<long>(number(0, 2e9));
    else if (a == "--rate") rate = number(1, 10000);
    else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else {
      std::fprintf(stderr, "tactile_calibration_record: unknown argument %s\n", a.c_str());
      usage();
      return 2;
    }
  }
  if (out_file.empty() || params_file.empty()) {
    std::fprintf(stderr, "tactile_calibration_record: --out (and --params, no default found) required\n");
    usage();
    return 2;
  }
  return -1;
}

/// --spots: all, interior, border, centre or R:C,... (row-major taxel
/// indices). -1, or the exit code (2).
int parseSpots(const std::string& spots_arg, int rows, int cols, std::vector<int>& spots) {
  for (int i = 0; i < rows * cols; ++i) {
    const int rr = i / cols, c = i % cols;
    const bool border = rr == 0 || c == 0 || rr == rows - 1 || c == cols - 1;
    if (spots_arg == "all" || (spots_arg == "interior" && !border) || (spots_arg == "border" && border)) spots.push_back(i);
  }
  if (spots_arg == "centre") spots = {(rows / 2) * cols + cols / 2};
  if (spots.empty()) {
    std::stringstream ss(spots_arg);
    std::string item;
    while (std::getline(ss, item, ',')) {
      int rr = -1, c = -1;
      if (std::sscanf(item.c_str(), "%d:%d", &rr, &c) != 2 || rr < 0 || rr >= rows || c < 0 || c >= cols) {
        std::fprintf(stderr, "tactile_calibration_record: --spots '%s': all, interior, border, centre or R:C,... "
                     "(row in [0, %d], col in [0, %d])\n", spots_arg.c_str(), rows - 1, cols - 1);
        return 2;
      }
      spots.push_back(rr * cols + c);
    }
  }
  return -1;
}

/// The simulated rig: the pad facing down over a fixed spherical probe of
/// `radius` at (cx, cy) in {g} (in the LWR's comfortable workspace), the
/// recording file, and what the recording saw.
struct Rig {
  Rig(const RecordArgs& a, int rows_, int cols_, double pitch_, const WorldParams& wp)
      : args(a), rows(rows_), cols(cols_), pitch(pitch_), radius(a.radius), ref_noise(a.ref_noise),
        T_es(KDL::Rotation::Quaternion(wp.pad.mount.q[0], wp.pad.mount.q[1], wp.pad.mount.q[2], wp.pad.mount.q[3]),
             KDL::Vector(wp.pad.mount.p[0], wp.pad.mount.p[1], wp.pad.mount.p[2])) {}

  static constexpr double cx = 0.58, cy = 0.0;  // probe centre (x, y) in {g}
  const RecordArgs& args;
  const int rows, cols;
  const double pitch, radius, ref_noise;
  const KDL::Rotation R_gs = KDL::Rotation::Quaternion(0.0, 1.0, 0.0, 0.0);  // z_s = -z_g: facing down
  const KDL::Frame T_es;
  World w;
  FILE* out = nullptr;
  std::mt19937_64 rng;  // the reference's own noise (seeded in main)
  std::normal_distribution<double> nd{0.0, 1.0};
  SimState s;
  RawTactileFrame raw;
  SensorTruth truth;
  TactileFrame img;
  long frames = 0;
  double max_spill = 0.0, max_housing = 0.0;
  int probed = -1;

  // Flange command that puts the sensor point (x_s, y_s, 0) `gap` above the probe's top (gap < 0: pressed).
  Pose command(int taxel, double gap) const {
    const double xs = (taxel % cols - (cols - 1) / 2.0) * pitch, ys = (taxel / cols - (rows - 1) / 2.0) * pitch;
    const KDL::Vector top(cx, cy, 2.0 * radius + gap);
    const KDL::Frame T_gs(R_gs, top - R_gs * KDL::Vector(xs, ys, 0.0));
    const KDL::Frame T_ge = T_gs * T_es.Inverse();
    Pose p;
    p.p = {T_ge.p.x(), T_ge.p.y(), T_ge.p.z()};
    T_ge.M.GetQuaternion(p.q[0], p.q[1], p.q[2], p.q[3]);
    return p;
  }

  SimStatus settle(const Pose& cmd, double dt) {
    SimStatus st = w.step(cmd, dt, s);
    for (int k = 0; k < 50 && st == SimStatus::NotConverged; ++k) st = w.step(cmd, dt, s);
    return st;
  }

  // One frame into the recording: the reference force and the raw counts.
  void record() {
    w.acquire(raw, truth);
    const double f = -truth.wrench_s[2] + ref_noise * nd(rng);
    std::fprintf(out, "%.4f,%.6f", truth.time_s, f);
    for (int i = 0; i < rows * cols; ++i) std::fprintf(out, ",%u", static_cast<unsigned>(raw.counts[static_cast<std::size_t>(i)]));
    std::fprintf(out, "\n");
    ++frames;
    max_housing = std::max(max_housing, truth.housing_force);
    if (probed >= 0 && truth.layer.force > 0.0) {
      const TactileFrame& tf = w.pad().trueTaxelForces();
      const double other = truth.layer.force - tf.force[static_cast<std::size_t>(probed)];
      max_spill = std::max(max_spill, other / truth.layer.force);
    }
  }

  int failSim(const std::string& what, SimStatus st) {
    std::fprintf(stderr, "tactile_calibration_record: %s: %s\n", what.c_str(), toString(st));
    std::fclose(out);
    return 1;
  }

  // Commanded depth at `spot` -> true normal force (layer + housing). The true
  // force is the image's (SensorTruth, what f_ref_n records), not the physics
  // sampling's: they differ for a probe this small.
  double forceAt(int spot, double depth, double dt_move, SimStatus& st) {
    st = settle(command(spot, -depth), dt_move);
    w.acquireForces(img, truth);
    return -truth.wrench_s[2];
  }

  // The depth at `spot` that gives the true force `target`: the force is
  // monotone in the depth: bracket, then regula falsi (Illinois) to 0.2 %.
  // False when the world failed (st).
  bool pressDepth(int spot, double target, double dt_move, SimStatus& st, double& depth) {
    auto force = [&](double d) { return forceAt(spot, d, dt_move, st); };
    double lo = 0.0, f_lo = -target, hi = target / 1000.0 + 0.001, f_hi = force(hi) - target;
    for (int k = 0; k < 20 && f_hi < 0.0 && !fatal(st); ++k) {
      lo = hi;
      f_lo = f_hi;
      hi *= 2.0;
      f_hi = force(hi) - target;
    }
    if (fatal(st)) return false;
    int side = 0;
    depth = hi;
    double fx = f_hi;
    for (int k = 0; k < 60 && std::fabs(fx) > 0.002 * target; ++k) {
      depth = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
      fx = force(depth) - target;
      if (fatal(st)) return false;
      if (fx > 0.0) {
        hi = depth;
        f_hi = fx;
        if (side == 1) f_lo /= 2.0;
        side = 1;
      } else {
        lo = depth;
        f_lo = fx;
        if (side == -1) f_hi /= 2.0;
        side = -1;
      }
    }
    return true;
  }

  // One spot: lift, move over it from `prev` in steps of at most 5 mm, one
  // unloaded frame; then each load fraction of its full-scale force (above
  // the threshold), held for args.repeats frames. -1, or the exit code.
  int probeSpot(int prev, int spot, const CalibrationParams& cal, double lift, double dt, double dt_move, double max_step_s,
                std::vector<double>& loads, double& f_max) {
    SimStatus st = SimStatus::Ok;
    probed = -1;
    const Pose a = command(prev, lift), b = command(spot, lift);
    const double dist = std::hypot(b.p[0] - a.p[0], b.p[1] - a.p[1]);
    const int steps = std::max(1, static_cast<int>(std::ceil(dist / 0.005)));
    for (int k = 1; k <= steps; ++k) {
      Pose m = b;
      for (int j = 0; j < 3; ++j) m.p[static_cast<std::size_t>(j)] = a.p[static_cast<std::size_t>(j)] +
                                                                    (b.p[static_cast<std::size_t>(j)] - a.p[static_cast<std::size_t>(j)]) * k / steps;
      if (fatal(st = settle(m, dt_move))) return failSim("moving to a spot", st);
    }
    record();
    probed = spot;
    const double f_full = w.pad().forceFor(spot / cols, spot % cols, cal.full_scale);
    for (double phi : args.fractions) {
      const double target = args.threshold + phi * (f_full - args.threshold);
      double depth = 0.0;
      if (!pressDepth(spot, target, dt_move, st, depth)) return failSim("pressing", st);
      forceAt(spot, depth, dt_move, st);
      for (int k = 0; k < args.repeats; ++k) {
        if (fatal(st = settle(command(spot, -depth), std::min(dt, max_step_s)))) return failSim("holding", st);
        record();
      }
      loads.push_back(target);
      f_max = std::max(f_max, target);
    }
    if (fatal(st = settle(command(spot, lift), dt_move))) return failSim("lifting", st);
    return -1;
  }
};

}  // namespace

int main(int argc, char** argv) {
  RecordArgs args;
  if (int code = parseArgs(argc, argv, args); code >= 0) return code;
  const std::string &out_file = args.out_file, &params_file = args.params_file;
  double &noise_counts = args.noise_counts, &threshold = args.threshold;
  const double radius = args.radius;
  const long seed = args.seed;

  // The sensor: size and pitch (features:), the calibration its electronics invert.
  FeatureParams fp;
  CalibrationParams cal;
  ConfigResult r = loadSensorParamFile(params_file, fp, cal);
  if (!r) {
    std::fprintf(stderr, "tactile_calibration_record: %s\n", r.message().c_str());
    return 2;
  }
  const int rows = fp.rows, cols = fp.cols;
  if (noise_counts < 0.0) noise_counts = cal.noise_counts > 0.0 ? cal.noise_counts : 6.0;
  if (threshold < 0.0) threshold = fp.contact_threshold;

  // Spots.
  std::vector<int> spots;
  if (int code = parseSpots(args.spots_arg, rows, cols, spots); code >= 0) return code;

  // The world: the pad facing down, the probe fixed below it.
  WorldParams wp;
  wp.fidelity = Fidelity::QuasiStatic;
  wp.seed = static_cast<uint64_t>(seed);
  wp.pad.rows = rows;
  wp.pad.cols = cols;
  wp.pad.pitch = fp.pitch;
  wp.pad.use_calibration = true;
  wp.pad.calibration = cal;
  wp.pad.noise_counts = noise_counts;
  wp.pad.threshold = threshold;
  const double cx = Rig::cx, cy = Rig::cy;  // probe centre (x, y) in {g}, in the LWR's comfortable workspace
  ObjectParams probe;
  probe.name = "probe";
  probe.type = ObjectType::Sphere;
  probe.center = {cx, cy, radius};
  probe.radius = radius;
  wp.objects = {probe};
  Rig rig(args, rows, cols, fp.pitch, wp);
  World& w = rig.w;
  const double lift = 0.003;
  wp.use_initial_flange_pose = true;
  wp.initial_flange_pose = rig.command(spots[0], lift);
  if (!(r = w.configure(wp))) {
    std::fprintf(stderr, "tactile_calibration_record: the simulated rig: %s\n", r.message().c_str());
    return 2;
  }

  FILE*& out = rig.out;
  out = std::fopen(out_file.c_str(), "w");
  if (!out) {
    std::fprintf(stderr, "tactile_calibration_record: cannot write %s\n", out_file.c_str());
    return 2;
  }
  std::fprintf(out, "time_s,f_ref_n");
  for (int i = 0; i < rows * cols; ++i) std::fprintf(out, ",raw_%d", i);
  std::fprintf(out, "\n");

  rig.rng.seed(static_cast<uint64_t>(seed) ^ 0xF0F0A5A5C3C3ULL);  // the reference's own noise
  const double dt = 1.0 / args.rate;
  const double dt_move = std::min(0.01, wp.max_step_s);

  SimStatus st = rig.settle(rig.command(spots[0], lift), dt_move);
  if (fatal(st)) return rig.failSim("the start pose", st);
  for (int k = 0; k < args.unloaded; ++k) {
    if (fatal(st = rig.settle(rig.command(spots[0], lift), std::min(dt, wp.max_step_s)))) return rig.failSim("unloaded", st);
    rig.record();
  }
  std::vector<double> loads;
  double f_max = 0.0;
  int prev = spots[0];
  for (int spot : spots) {
    if (int code = rig.probeSpot(prev, spot, cal, lift, dt, dt_move, wp.max_step_s, loads, f_max); code >= 0)
      return code;
    prev = spot;
  }
  std::fclose(out);
  std::printf("tactile_calibration_record: wrote %s: %ld frames (%d unloaded at the start, 1 per spot), %zu spots x "
              "%zu loads x %d repeats\n",
              out_file.c_str(), rig.frames, args.unloaded, spots.size(), args.fractions.size(), args.repeats);
  std::printf("  truth: the calibration of %s, noise %.3g counts, threshold %.3g N, reference noise %.3g N\n",
              params_file.c_str(), noise_counts, threshold, args.ref_noise);
  std::printf("  loads %.3g .. %.3g N; probe radius %.4g m; largest share of the load off the probed taxel %.3g; "
              "largest housing force %.3g N\n",
              *std::min_element(loads.begin(), loads.end()), f_max, radius, rig.max_spill, rig.max_housing);
  return 0;
}
