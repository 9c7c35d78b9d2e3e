// wts_sim: a simulated Weiss WTS0614 on a pseudo-terminal.
//
//   wts_sim [--link PATH] [--rows 6 --cols 14] [--pattern blob|ramp|zero|idle|press]
//           [--recording FILE.csv] [--bit-flip P] [--drop-byte P] [--truncate P]
//           [--bad-crc P] [--garbage P] [--stall P] [--stall-ms N] [--seed N]
//           [--noise S] [--offset N] [--press-after S] [--press-counts N]
//           [--dead R,C] [--stuck R,C[=COUNTS]] [--noisy R,C[=SIGMA]]
//           [--fault '{kind: .., start_s: .., ...}' ...] [--duration S]
//
// Prints "device: PATH" on stdout (the slave PTY, or the symlink given with
// --link) and serves the WTS protocol there until SIGINT/SIGTERM or --duration.
// --pattern blob: a 12-bit Gaussian press whose centre circles over the pad;
// ramp: counts (r*cols+c)*40 + t; zero: all zero;
// idle: the pad at no load: each taxel a fixed offset (--offset, default 30
//   counts, +-10 over the pad) plus Gaussian noise of --noise counts (1 sigma,
//   default 6: calibration.noise_counts of params/sensors/wts0614.yaml);
// press: idle, then a whole-pad load (--press-counts added to every taxel,
//   default 1500) from --press-after seconds of device time on (default 5;
//   0 = never by time), or at once on SIGUSR1; SIGUSR2 releases it. The
//   operator's flat-plate press of `wts_check --press`, for scripts.
// --recording: one frame per line, rows*cols raw counts in {s} order (what
// `wts_read --raw` prints), looped.
// Fault probabilities are per packet (see sim_device.hpp). Taxel faults (any
// pattern; row, col from 0 in {s}; repeatable): --dead R,C always 0; --stuck
// R,C[=COUNTS] always COUNTS (default 2000); --noisy R,C[=SIGMA] extra Gaussian
// noise of SIGMA counts (default 60).
// --fault (repeatable, at most 8): a scheduled fault in the device's time (s
// from its start), one entry of a scene's `faults:` list as YAML
// (tactile_sim_faults/sensor_faults.hpp, docs/formats.md "Faults"): stuck (counts
// only), dead, tare_creep, saturated and repeat on the frames' counts; stale
// holds the stream (no frame sent, commands answered); disconnect unplugs the
// device for the window and plugs it back behind the same --link. The kinds
// that need a force model (calibration, stuck's force_n) and the wrench's are
// refused: `--fault '{kind: stuck, start_s: 5, rows: [1, 4], cols: [5, 8], counts: 1200}'`.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tactile_sim_faults/sensor_faults_io.hpp"
#include "tactile_types/sensor_geometry.hpp"
#include "tactile_wts/sim_device.hpp"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }
// The press of --pattern press: set by SIGUSR1, cleared by SIGUSR2, read by the device thread.
std::atomic<int> g_press{-1};  // -1: by time (--press-after), 1: pressed, 0: released
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free atomic");
void onPress(int sig) { g_press.store(sig == SIGUSR1 ? 1 : 0); }

/// "R,C" or "R,C=V" -> row, col (and value, if given).
bool parseTaxel(const char* s, tactile::wts::TaxelFault& f) {
  int r = -1, c = -1, n = 0;
  if (std::sscanf(s, "%d,%d%n", &r, &c, &n) != 2) return false;
  f.row = r;
  f.col = c;
  if (s[n] == '\0') return true;
  if (s[n] != '=') return false;
  char* end = nullptr;
  f.value = std::strtod(s + n + 1, &end);
  return end != s + n + 1 && *end == '\0';
}

bool toDouble(const char* s, double& v) {
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end != s && *end == '\0';
}

/// One --fault: its YAML map, the kinds a device without a force model can play.
bool parseFault(const char* text, std::size_t index, std::vector<tactile::sim::FaultSpec>& out) {
  using tactile::sim::SensorFault;
  const tactile::config::Where w{"wts_sim --fault", "faults[" + std::to_string(index) + "]"};
  YAML::Node n;
  try {
    n = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::fprintf(stderr, "wts_sim: %s: not YAML: %s\n", w.str().c_str(), e.what());
    return false;
  }
  tactile::sim::FaultSpec f;
  const tactile::ConfigResult r = tactile::sim::readFaultSpec(n, w, f);
  if (!r) {
    std::fprintf(stderr, "wts_sim: %s\n", r.message().c_str());
    return false;
  }
  if (f.kind == SensorFault::Calibration || tactile::sim::wrenchFault(f.kind) ||
      (f.kind == SensorFault::Stuck && f.force_n >= 0.0)) {
    std::fprintf(stderr, "wts_sim: %s: %s needs a force model (lab_sim, tactile_sim); here: stuck in counts, dead, "
                         "tare_creep, saturated, stale, repeat, disconnect\n",
                 w.str().c_str(), f.kind == SensorFault::Stuck ? "stuck's force_n" : tactile::sim::toString(f.kind));
    return false;
  }
  out.push_back(f);
  return true;
}

/// The schedule's faults on the counts of a frame at device time t (s):
/// the zero's drift, stuck, dead, saturated, repeat.
void applyFaults(tactile::sim::SensorFaultSchedule& s, double t, tactile::RawTactileFrame& f) {
  const int n = static_cast<int>(f.rows) * static_cast<int>(f.cols);
  const double off = s.electronics() ? s.zeroOffsetCounts(t) : 0.0;
  for (int k = 0; off != 0.0 && k < n; ++k) {
    const double v = std::round(f.counts[static_cast<std::size_t>(k)] + off);
    f.counts[static_cast<std::size_t>(k)] = static_cast<uint16_t>(v < 0.0 ? 0.0 : (v > 4095.0 ? 4095.0 : v));
  }
  if (s.counts()) s.applyCounts(t, nullptr, f);
  f.time_s = t;
  if (s.streams()) s.stream(f);  // repeat; stale and disconnect: main() holds or unplugs the device
}

/// The link's faults at time t (s): the device unplugged in a disconnect's window, held in a stale one.
void linkFaults(const tactile::sim::SensorFaultSchedule& s, double t, tactile::wts::SimulatedWts& sim) {
  const bool down = s.linkDown(t);
  if (down == sim.plugged()) {
    if (down) sim.unplug();
    else sim.replug();
    std::fprintf(stderr, "wts_sim: t %.3f s: %s (--fault disconnect)\n", t, down ? "unplugged" : "plugged back");
  }
  if (s.stalled(t) != sim.held()) {
    sim.hold(s.stalled(t));
    std::fprintf(stderr, "wts_sim: t %.3f s: stream %s (--fault stale)\n", t, sim.held() ? "held" : "resumed");
  }
}

/// wts_sim's command line (parseArgs).
struct SimArgs {
  tactile::wts::SimulatedWts::Params p;
  std::string pattern = "blob", recording;
  std::vector<tactile::sim::FaultSpec> faults;
  double duration = 0.0;
  double noise = 6.0, offset = 30.0, press_after = 5.0, press_counts = 1500.0;
};

/// The command line into `args`: -1, or the exit code (2: a bad option; a
/// bad value exits with 2 at once).
int parseArgs(int argc, char** argv, SimArgs& args) {
  tactile::wts::SimulatedWts::Params& p = args.p;
  std::string &pattern = args.pattern, &recording = args.recording;
  std::vector<tactile::sim::FaultSpec>& faults = args.faults;
  double& duration = args.duration;
  double &noise = args.noise, &offset = args.offset, &press_after = args.press_after, &press_counts = args.press_counts;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto val = [&](double& v) {
      if (i + 1 >= argc || !toDouble(argv[i + 1], v)) {
        std::fprintf(stderr, "wts_sim: %s needs a numeric value\n", a.c_str());
        std::exit(2);
      }
      ++i;
    };
    auto prob = [&](double& v) {
      val(v);
      if (!(v >= 0.0 && v <= 1.0)) {
        std::fprintf(stderr, "wts_sim: %s = %g: must be a probability in [0, 1]\n", a.c_str(), v);
        std::exit(2);
      }
    };
    double v = 0;
    if (a == "--link" && i + 1 < argc) p.link = argv[++i];
    else if (a == "--rows") { val(v); p.cells.rows = static_cast<int>(v); }
    else if (a == "--cols") { val(v); p.cells.cols = static_cast<int>(v); }
    else if (a == "--pattern" && i + 1 < argc) pattern = argv[++i];
    else if (a == "--recording" && i + 1 < argc) recording = argv[++i];
    else if (a == "--bit-flip") prob(p.faults.bit_flip);
    else if (a == "--drop-byte") prob(p.faults.drop_byte);
    else if (a == "--truncate") prob(p.faults.truncate);
    else if (a == "--bad-crc") prob(p.faults.bad_crc);
    else if (a == "--garbage") prob(p.faults.garbage);
    else if (a == "--stall") prob(p.faults.stall);
    else if (a == "--stall-ms") { val(v); p.faults.stall_ms = static_cast<int>(v); }
    else if (a == "--seed") { val(v); p.faults.seed = static_cast<uint32_t>(v); }
    else if (a == "--duration") { val(duration); }
    else if (a == "--noise") { val(noise); }
    else if (a == "--offset") { val(offset); }
    else if (a == "--press-after") { val(press_after); }
    else if (a == "--press-counts") { val(press_counts); }
    else if (a == "--fault" && i + 1 < argc) {
      if (!parseFault(argv[++i], faults.size(), faults)) return 2;
    }
    else if ((a == "--dead" || a == "--stuck" || a == "--noisy") && i + 1 < argc) {
      tactile::wts::TaxelFault f;
      f.kind = a == "--dead" ? tactile::wts::TaxelFaultKind::Dead
               : a == "--stuck" ? tactile::wts::TaxelFaultKind::Stuck : tactile::wts::TaxelFaultKind::Noisy;
      f.value = a == "--stuck" ? 2000.0 : a == "--noisy" ? 60.0 : 0.0;
      if (!parseTaxel(argv[i + 1], f) || (a == "--dead" && f.value != 0.0)) {
        std::fprintf(stderr, "wts_sim: %s %s: expected ROW,COL%s\n", a.c_str(), argv[i + 1],
                     a == "--dead" ? "" : "[=VALUE]");
        std::exit(2);
      }
      ++i;
      p.taxel_faults.push_back(f);
    }
    else {
      std::fprintf(stderr, "wts_sim: unknown or incomplete option %s (see the header of wts_sim.cpp)\n", a.c_str());
      return 2;
    }
  }
  if (!(noise >= 0.0 && noise <= 1000.0) || !(offset >= 0.0 && offset <= 4095.0) ||
      !(press_after >= 0.0) || !(press_counts >= 0.0 && press_counts <= 4095.0)) {
    std::fprintf(stderr, "wts_sim: --noise must be in [0, 1000], --offset and --press-counts in [0, 4095] "
                         "(counts), --press-after >= 0 (s)\n");
    return 2;
  }
  return -1;
}

/// --recording: one frame per line, rows*cols comma-separated counts ('#'
/// lines and blank lines skipped), into `frames`. -1, or the exit code (2).
int readRecording(std::ifstream& in, const std::string& recording, int rows, int cols,
                  std::vector<tactile::RawTactileFrame>& frames) {
  std::string line;
  long lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    tactile::RawTactileFrame f;
    f.rows = static_cast<uint16_t>(rows);
    f.cols = static_cast<uint16_t>(cols);
    std::stringstream ss(line);
    std::string cell;
    int k = 0;
    while (std::getline(ss, cell, ',')) {
      double x = 0;
      if (k >= rows * cols || !toDouble(cell.c_str(), x) || x < 0 || x > 4095) {
        std::fprintf(stderr, "wts_sim: %s:%ld: value %d is not a count in [0, 4095] or too many values\n",
                     recording.c_str(), lineno, k + 1);
        return 2;
      }
      f.counts[static_cast<std::size_t>(k++)] = static_cast<uint16_t>(x);
    }
    if (k != rows * cols) {
      std::fprintf(stderr, "wts_sim: %s:%ld: expected %d values, got %d\n", recording.c_str(), lineno, rows * cols, k);
      return 2;
    }
    frames.push_back(f);
  }
  return -1;
}

/// --pattern blob (a contact circling the pad), ramp or zero.
tactile::wts::FrameSource patternSource(const std::string& pattern, int rows, int cols) {
  const tactile::SensorGeometry geometry{rows, cols, tactile::kDefaultPitch};
  return [=](uint32_t t_ms, tactile::RawTactileFrame& f) {
    const double t = t_ms * 1e-3;
    const double cx = 0.012 * std::cos(0.5 * t), cy = 0.004 * std::sin(0.5 * t);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        double v = 0;
        if (pattern == "blob") {
          const double x = geometry.x(c), y = geometry.y(r);
          v = 2000.0 * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * 0.004 * 0.004));
        } else if (pattern == "ramp") {
          v = std::fmod((r * cols + c) * 40.0 + t_ms, 4096.0);
        }
        f.counts[static_cast<std::size_t>(r * cols + c)] = static_cast<uint16_t>(v);
      }
  };
}

/// --pattern idle or press: per-taxel offsets and noise from the seed; press:
/// press_counts more on every taxel after press_after s or on SIGUSR1.
tactile::wts::FrameSource noiseSource(const std::string& pattern, int rows, int cols, uint32_t seed, double noise,
                                      double offset, double press_after, double press_counts) {
  // Per-taxel offsets fixed by the seed, noise from the same seed: one
  // generator, called from the device thread only (under its lock).
  struct Noise {
    std::mt19937 gen;
    std::normal_distribution<double> normal{0.0, 1.0};
    std::vector<double> offsets;
  };
  auto st = std::make_shared<Noise>();
  st->gen.seed(seed + 7919u);
  std::uniform_real_distribution<double> spread(-10.0, 10.0);
  for (int k = 0; k < rows * cols; ++k) st->offsets.push_back(std::max(0.0, offset + spread(st->gen)));
  const bool press = pattern == "press";
  return [=](uint32_t t_ms, tactile::RawTactileFrame& f) {
    const int ps = g_press.load();
    const bool pressed = press && (ps == 1 || (ps == -1 && press_after > 0.0 && t_ms * 1e-3 >= press_after));
    for (int k = 0; k < rows * cols; ++k) {
      double v = st->offsets[static_cast<std::size_t>(k)] + noise * st->normal(st->gen) + (pressed ? press_counts : 0.0);
      v = std::round(v);
      f.counts[static_cast<std::size_t>(k)] = static_cast<uint16_t>(v < 0.0 ? 0.0 : (v > 4095.0 ? 4095.0 : v));
    }
  };
}

}  // namespace

int main(int argc, char** argv) {
  SimArgs args;
  if (int code = parseArgs(argc, argv, args); code >= 0) return code;
  const tactile::wts::SimulatedWts::Params& p = args.p;
  const std::string &pattern = args.pattern, &recording = args.recording;
  const std::vector<tactile::sim::FaultSpec>& faults = args.faults;
  const double duration = args.duration;
  const int rows = p.cells.rows, cols = p.cells.cols;
  auto schedule = std::make_shared<tactile::sim::SensorFaultSchedule>();
  if (const tactile::ConfigResult r = schedule->configure(faults, rows, cols, p.full_scale); !r) {
    std::fprintf(stderr, "wts_sim: --fault: %s\n", r.message().c_str());
    return 2;
  }
  tactile::wts::SimulatedWts sim;
  tactile::wts::FrameSource src;  // the pattern's or the recording's frames (with faults: then theirs)
  if (!recording.empty()) {
    std::ifstream in(recording);
    if (!in) {
      std::fprintf(stderr, "wts_sim: cannot open %s\n", recording.c_str());
      return 2;
    }
    std::vector<tactile::RawTactileFrame> frames;
    if (int code = readRecording(in, recording, rows, cols, frames); code >= 0) return code;
    if (faults.empty()) {
      sim.setRecording(std::move(frames));
    } else {  // looped as setRecording() does, so that the faults apply to its frames
      auto rec = std::make_shared<std::vector<tactile::RawTactileFrame>>(std::move(frames));
      auto next = std::make_shared<std::size_t>(0);
      src = [rec, next](uint32_t, tactile::RawTactileFrame& f) { f = (*rec)[(*next)++ % rec->size()]; };
    }
  } else if (pattern == "blob" || pattern == "ramp" || pattern == "zero") {
    src = patternSource(pattern, rows, cols);
  } else if (pattern == "idle" || pattern == "press") {
    src = noiseSource(pattern, rows, cols, p.faults.seed, args.noise, args.offset, args.press_after, args.press_counts);
  } else {
    std::fprintf(stderr, "wts_sim: --pattern = %s: must be blob, ramp, zero, idle or press\n", pattern.c_str());
    return 2;
  }
  if (src && faults.empty()) sim.setSource(src);
  if (src && !faults.empty())
    sim.setSource([src, schedule](uint32_t t_ms, tactile::RawTactileFrame& f) {
      src(t_ms, f);
      applyFaults(*schedule, t_ms * 1e-3, f);
    });
  std::string why;
  if (!sim.start(p, &why)) {
    std::fprintf(stderr, "wts_sim: %s\n", why.c_str());
    return 1;
  }
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::signal(SIGUSR1, onPress);
  std::signal(SIGUSR2, onPress);
  std::printf("device: %s\n", sim.path().c_str());
  std::fflush(stdout);
  const auto t0 = std::chrono::steady_clock::now();
  while (!g_stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (schedule->streams()) linkFaults(*schedule, t, sim);
    if (duration > 0 && t > duration) break;
  }
  const auto s = sim.stats();
  sim.stop();
  std::fprintf(stderr, "wts_sim: %llu commands, %llu frames, %llu faulted packets, %llu bad commands\n",
               static_cast<unsigned long long>(s.commands), static_cast<unsigned long long>(s.frames),
               static_cast<unsigned long long>(s.faults), static_cast<unsigned long long>(s.bad_commands));
  return 0;
}
