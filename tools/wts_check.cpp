// wts_check: the first-day check of a Weiss WTS tactile sensor (WTS0614), in
// stages, each printed with PASS / WARN / FAIL (or SKIP) and what to do next.
//
//   wts_check [--device PATH] [--params FILE.yaml] [--seconds S] [--frames N]
//             [--press] [--no-prompt] [--json FILE] [thresholds, see usage()]
//
// Stages:
//  a. device: --device PATH (or wts.device of --params), else every candidate
//     of --candidates (default "/dev/serial/by-id/* /dev/ttyACM*") is opened
//     and asked for its matrix info (0x30), system info (0x50: firmware,
//     serial) and sensor type (0x38); the first that answers the matrix info
//     is the WTS. Its matrix must be the one the configured cell map expects
//     (wts.rows/cols/transpose), as WtsDriver::open() requires.
//  b. rate and link: the driver streams for --seconds (default 5) or until
//     --frames frames, with the acquisition of the deployments (the `wts:`
//     section of --params, else WtsParams' defaults, which
//     deployments/wts_reader.cpf uses: periodic_ms 10, plain frames). Checks:
//       - frames arrive at 1000 / periodic_ms per s within +-rate_tolerance
//         (default 0.2: the host clock, the frames the driver returned);
//       - link errors (CRC errors + format errors: frames of the wrong size,
//         bad RLE, oversize or impossible headers) per packet <= max_error_rate
//         (default 0.001; a USB CDC link shows none);
//       - disconnects <= max_disconnects (default 0); watchdog restarts: WARN;
//       - at least min_frames (default 50) frames, else c, d, e are skipped.
//     The pad must not be touched: stages c and d use these frames.
//  c. no-load noise: per taxel the standard deviation of the raw counts, as a
//     rows x cols grid, against the sensor's stated noise, calibration.noise_counts
//     (params/sensors/wts0614.yaml, or the `calibration:` section
//     of --params): a taxel above k x stated (--k, default 3: 3 sigma of the
//     stated noise; with >= 50 frames the sample std of a healthy taxel is
//     within +-20 % of its true value) FAILs. A taxel whose no-load mean is
//     above calibration.max_tare FAILs too (tactile::Calibration would refuse
//     to tare it).
//  d. stuck taxels: a taxel whose value never changes over the window while
//     the pad's median std is at least 0.5 count (the others show noise)
//     FAILs, unless it reads 0 throughout (WARN: silent; dead or not, --press
//     tells); a taxel whose no-load mean is within fullscale_margin (default
//     0.05) of full scale FAILs. A pad without any noise at no load gets a WARN
//     (the constant-value test does not apply).
//  e. dead taxels (--press): the operator presses the whole pad (a flat plate
//     or a palm). The tool waits (at most --press-timeout s, progress every
//     second) until press_fraction (default 0.5) of the taxels have risen
//     above their no-load mean by the rise threshold, max(press_min_rise
//     (default 100 counts), k x the taxel's noise), then records press_frames
//     (default 100) frames. A taxel that never rose while at least half of
//     its (up to 8) neighbours did is dead (FAIL, named); one whose
//     neighbours did not rise either was not loaded (WARN: press flat).
//
// Taxels are named (row, col) in {s} (conventions.hpp): row 0 = most negative
// y, col 0 = most negative x, as `wts_read --raw` orders them.
// --no-prompt (or a stdin that is not a terminal): no waiting for Enter; the
// instructions are printed all the same. --json FILE: a summary of every stage.
// Exit: 0 every stage passed (WARN allowed), 1 a check failed, 2 usage or
// parameter error, 3 no WTS found (or the one named could not be used).
#include <glob.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <set>
#include <sstream>
#include <string>

#include "tactile_config/cli_args.hpp"
#include <vector>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_wts/driver.hpp"
#include "tactile_wts/params_io.hpp"
#include "tactile_wts/protocol.hpp"
#include "tactile_wts/serial_port.hpp"

#ifndef WTS_CHECK_DEFAULT_PARAMS
#define WTS_CHECK_DEFAULT_PARAMS ""
#endif
#ifndef WTS_CHECK_INSTALLED_PARAMS
#define WTS_CHECK_INSTALLED_PARAMS ""
#endif

namespace {

using namespace tactile;
using namespace tactile::wts;

void usage() {
  std::fprintf(stderr,
               "usage: wts_check [--device PATH] [--params FILE.yaml] [--seconds S] [--frames N] [--periodic-ms N]\n"
               "                 [--press] [--no-prompt] [--json FILE] [--candidates \"GLOB ...\"]\n"
               "  thresholds: [--k K=3] [--rate-tolerance F=0.2] [--max-error-rate R=0.001] [--max-disconnects N=0]\n"
               "              [--min-frames N=50] [--fullscale-margin F=0.05] [--probe-timeout-ms N=300]\n"
               "  press:      [--press-timeout S=30] [--press-frames N=100] [--press-fraction F=0.5]\n"
               "              [--press-min-rise COUNTS=100]\n"
               "Stages: a device, b rate and link, c no-load noise, d stuck taxels, e dead taxels (--press).\n"
               "Exit: 0 all passed, 1 a check failed, 2 usage, 3 no WTS found. Details: tools/wts_check.cpp.\n");
}

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void sleepMs(int ms) {
  timespec ts{ms / 1000, (ms % 1000) * 1000000L};
  nanosleep(&ts, nullptr);
}

bool toDouble(const char* s, double& v) {
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(v);
}

using config::fmt;
using config::jsonString;

std::string taxelName(int r, int c) { return fmt("(row %d, col %d)", r, c); }


enum class Verdict { Pass, Warn, Fail, Skip };
const char* toString(Verdict v) {
  switch (v) {
    case Verdict::Pass: return "PASS";
    case Verdict::Warn: return "WARN";
    case Verdict::Fail: return "FAIL";
    case Verdict::Skip: return "SKIP";
  }
  return "?";
}

/// One stage's outcome: what is printed and what goes to the JSON summary.
struct Stage {
  std::string key;    ///< JSON key
  std::string label;  ///< "[a] device"
  Verdict verdict = Verdict::Skip;
  std::string message;
  std::vector<std::string> details;  ///< printed under the verdict line (grids, lists)
  std::vector<std::string> next;     ///< what to do next
  std::vector<std::pair<std::string, std::string>> json;  ///< extra fields, values already JSON
};

void worsen(Stage& s, Verdict v) {
  auto rank = [](Verdict x) { return x == Verdict::Fail ? 3 : x == Verdict::Warn ? 2 : x == Verdict::Pass ? 1 : 0; };
  if (rank(v) > rank(s.verdict)) s.verdict = v;
}

void printStage(const Stage& s) {
  std::printf("%-18s %s  %s\n", s.label.c_str(), toString(s.verdict), s.message.c_str());
  for (const std::string& d : s.details) std::printf("      %s\n", d.c_str());
  for (const std::string& n : s.next) std::printf("      next: %s\n", n.c_str());
  std::fflush(stdout);
}

struct TaxelRef {
  int row = 0, col = 0;
  double value = 0.0;
  std::string what;
};

std::string jsonTaxels(const std::vector<TaxelRef>& v) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i)
    o += fmt("%s{\"row\": %d, \"col\": %d, \"value\": %.3f, \"what\": %s}", i ? ", " : "", v[i].row, v[i].col,
             v[i].value, jsonString(v[i].what).c_str());
  return o + "]";
}

std::string jsonGrid(const std::vector<double>& g, int rows, int cols) {
  std::string o = "[";
  for (int r = 0; r < rows; ++r) {
    o += r ? ", [" : "[";
    for (int c = 0; c < cols; ++c) o += fmt("%s%.3f", c ? ", " : "", g[static_cast<std::size_t>(r * cols + c)]);
    o += "]";
  }
  return o + "]";
}

/// rows x cols grid, one line per row, "*" after values that failed.
std::vector<std::string> gridLines(const std::vector<double>& g, const std::vector<bool>& flagged, int rows, int cols,
                                   const char* num_fmt) {
  std::vector<std::string> out;
  std::string head = "       ";
  for (int c = 0; c < cols; ++c) head += fmt("%6s ", fmt("c%d", c).c_str());
  out.push_back(head);
  for (int r = 0; r < rows; ++r) {
    std::string line = fmt("  r%-3d ", r);
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = static_cast<std::size_t>(r * cols + c);
      line += fmt("%6s%c", fmt(num_fmt, g[i]).c_str(), flagged[i] ? '*' : ' ');
    }
    out.push_back(line);
  }
  return out;
}

// ---- stage a: probe one path -------------------------------------------------

struct Probe {
  std::string path;
  bool opened = false;
  int open_errno = 0;
  bool is_wts = false;
  MatrixInfo mi;
  bool have_sysinfo = false;
  uint8_t type = 0, hw_rev = 0;
  uint16_t firmware = 0;
  uint32_t serial = 0;
  std::string sensor_type;
  std::string why;  ///< why it is not (usable as) a WTS
};

/// Sends command `c` and waits for the reply with its id; `payload`/`size` =
/// the reply's payload after the status. Up to `tries` attempts (a reply lost
/// on a bad link is asked again).
bool ask(SerialPort& port, Command c, int timeout_ms, int tries, std::vector<uint8_t>& payload, StatusCode& st,
         std::string& why) {
  uint8_t tx[16];
  const std::size_t len = encodeSimple(c, tx, sizeof tx);
  for (int attempt = 0; attempt < tries; ++attempt) {
    Parser parser(Direction::FromDevice);
    if (port.write(tx, len, timeout_ms) != IoStatus::Ok) {
      why = fmt("cannot write to it (%s)", std::strerror(port.lastErrno()));
      return false;
    }
    const double deadline = nowS() + 1e-3 * timeout_ms;
    uint8_t rx[512];
    while (nowS() < deadline) {
      std::size_t got = 0;
      const IoStatus io = port.read(rx, sizeof rx, static_cast<int>(1e3 * (deadline - nowS())) + 1, got);
      if (io == IoStatus::Disconnected) {
        why = "it hung up (unplugged?)";
        return false;
      }
      if (io != IoStatus::Ok) continue;
      std::size_t off = 0;
      while (off < got) {
        off += parser.feed(rx + off, got - off);
        PacketView pkt;
        ParseStatus ps;
        while ((ps = parser.next(pkt)) != ParseStatus::NeedMore) {
          if (ps != ParseStatus::Packet || pkt.id != static_cast<uint8_t>(c)) continue;
          st = StatusCode::CmdFormatError;
          pkt.status(st);
          payload.assign(pkt.payload + (pkt.size >= 2 ? 2 : pkt.size), pkt.payload + pkt.size);
          if (c == Command::MatrixInfo) {  // keep the status for decodeMatrixInfo
            payload.assign(pkt.payload, pkt.payload + pkt.size);
          }
          return true;
        }
      }
    }
  }
  why = fmt("no reply to %s (0x%02x) within %d ms (%d tries)", commandName(static_cast<uint8_t>(c)),
            static_cast<unsigned>(c), timeout_ms, tries);
  return false;
}

Probe probe(const std::string& path, int timeout_ms) {
  Probe p;
  p.path = path;
  SerialPort port;
  if (port.open(path.c_str()) != IoStatus::Ok) {
    p.open_errno = port.lastErrno();
    p.why = fmt("cannot open it: %s", std::strerror(p.open_errno));
    return p;
  }
  p.opened = true;
  std::vector<uint8_t> pl;
  StatusCode st = StatusCode::Success;
  if (!ask(port, Command::MatrixInfo, timeout_ms, 3, pl, st, p.why)) return p;
  PacketView v;
  v.id = static_cast<uint8_t>(Command::MatrixInfo);
  v.payload = pl.data();
  v.size = static_cast<uint16_t>(pl.size());
  if (st != StatusCode::Success || !decodeMatrixInfo(v, p.mi)) {
    p.why = fmt("its matrix-info reply is not a WTS's (status %s, %zu bytes)", toString(st), pl.size());
    return p;
  }
  p.is_wts = true;
  std::string ignored;
  if (ask(port, Command::SystemInfo, timeout_ms, 3, pl, st, ignored) && st == StatusCode::Success && pl.size() >= 8) {
    p.have_sysinfo = true;
    p.type = pl[0];
    p.hw_rev = pl[1];
    p.firmware = getU16(pl.data() + 2);
    p.serial = getU32(pl.data() + 4);
  }
  if (ask(port, Command::SensorType, timeout_ms, 3, pl, st, ignored) && st == StatusCode::Success) {
    for (const uint8_t b : pl)
      if (b >= 0x20 && b < 0x7F) p.sensor_type += static_cast<char>(b);
  }
  return p;
}

std::vector<std::string> candidates(const std::string& globs) {
  std::vector<std::string> out;
  std::set<std::string> seen;  // real paths: a by-id link and its ttyACM are one device
  std::istringstream ss(globs);
  std::string pattern;
  while (ss >> pattern) {
    glob_t g{};
    if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
      for (std::size_t i = 0; i < g.gl_pathc; ++i) {
        const std::string path = g.gl_pathv[i];
        char real[4096];
        const std::string key = ::realpath(path.c_str(), real) ? std::string(real) : path;
        if (seen.insert(key).second) out.push_back(path);
      }
    }
    globfree(&g);
  }
  return out;
}

// ---- per-taxel statistics ------------------------------------------------------

struct TaxelStats {
  uint64_t n = 0;
  double mean = 0.0, m2 = 0.0;
  uint16_t min = 0xFFFF, max = 0;
  void add(uint16_t v) {
    ++n;
    const double d = v - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (v - mean);
    min = std::min(min, v);
    max = std::max(max, v);
  }
  double stddev() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : 0.0; }
};

struct Options {
  std::string device;
  std::string params_file;
  std::string json_file;
  std::string candidates = "/dev/serial/by-id/* /dev/ttyACM*";
  double seconds = 5.0;
  long frames = 0;
  long periodic_ms = -1;
  bool press = false;
  bool no_prompt = false;
  double k = 3.0;
  double rate_tolerance = 0.2;
  double max_error_rate = 0.001;
  long max_disconnects = 0;
  long min_frames = 50;
  double fullscale_margin = 0.05;
  long probe_timeout_ms = 300;
  double press_timeout = 30.0;
  long press_frames = 100;
  double press_fraction = 0.5;
  double press_min_rise = 100.0;
};

bool interactive(const Options& o) { return !o.no_prompt && ::isatty(0); }

void waitEnter(const Options& o) {
  if (!interactive(o)) return;
  std::printf("Press Enter to start.\n");
  std::fflush(stdout);
  char line[64];
  if (std::fgets(line, sizeof line, stdin) == nullptr) return;
}

/// The command line into `o`: -1, or the exit code (help 0, a bad option 2;
/// a bad number exits with 2 at once).
int parseArgs(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    auto num = [&](double lo, double hi, double& v) {
      if (!has || !toDouble(argv[i + 1], v) || v < lo || v > hi) {
        std::fprintf(stderr, "wts_check: %s %s: must be a number in [%g, %g]\n", a.c_str(), has ? argv[i + 1] : "",
                     lo, hi);
        std::exit(2);
      }
      ++i;
    };
    auto integer = [&](long lo, long hi, long& v) {
      double d = 0;
      num(static_cast<double>(lo), static_cast<double>(hi), d);
      if (d != std::floor(d)) {
        std::fprintf(stderr, "wts_check: %s %s: must be an integer\n", a.c_str(), argv[i]);
        std::exit(2);
      }
      v = static_cast<long>(d);
    };
    if (a == "--device" && has) o.device = argv[++i];
    else if (a == "--params" && has) o.params_file = argv[++i];
    else if (a == "--json" && has) o.json_file = argv[++i];
    else if (a == "--candidates" && has) o.candidates = argv[++i];
    else if (a == "--seconds") num(0.1, 3600, o.seconds);
    else if (a == "--frames") integer(1, 100000000, o.frames);
    else if (a == "--periodic-ms") integer(1, 1000, o.periodic_ms);
    else if (a == "--press") o.press = true;
    else if (a == "--no-prompt") o.no_prompt = true;
    else if (a == "--k") num(1, 100, o.k);
    else if (a == "--rate-tolerance") num(0.01, 10, o.rate_tolerance);
    else if (a == "--max-error-rate") num(0, 1, o.max_error_rate);
    else if (a == "--max-disconnects") integer(0, 1000000, o.max_disconnects);
    else if (a == "--min-frames") integer(2, 100000000, o.min_frames);
    else if (a == "--fullscale-margin") num(0, 1, o.fullscale_margin);
    else if (a == "--probe-timeout-ms") integer(10, 10000, o.probe_timeout_ms);
    else if (a == "--press-timeout") num(0.1, 3600, o.press_timeout);
    else if (a == "--press-frames") integer(1, 100000000, o.press_frames);
    else if (a == "--press-fraction") num(0.01, 1, o.press_fraction);
    else if (a == "--press-min-rise") num(1, 4095, o.press_min_rise);
    else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else {
      std::fprintf(stderr, "wts_check: unknown or incomplete option %s\n", a.c_str());
      usage();
      return 2;
    }
  }
  return -1;
}

/// One bring-up check: the stages a..e in order on the parameters of `o`,
/// the device and the driver, and what each stage leaves for the next.
struct Check {
  explicit Check(const Options& o_) : o(o_) {}

  const Options& o;
  WtsParams wp;
  bool device_from_params = false;
  std::string calib_file;
  CalibrationParams cp;
  int rows = 0, cols = 0, n = 0;
  Stage sa{"device", "[a] device", Verdict::Skip, "", {}, {}, {}};
  Stage sb{"link", "[b] rate and link", Verdict::Skip, "not run", {}, {}, {}};
  Stage sc{"noise", "[c] no-load noise", Verdict::Skip, "not run", {}, {}, {}};
  Stage sd{"stuck", "[d] stuck taxels", Verdict::Skip, "not run", {}, {}, {}};
  Stage se{"dead", "[e] dead taxels", Verdict::Skip, o.press ? "not run" : "not run (add --press)", {}, {}, {}};
  uint16_t full_scale = 0;  // the device's, else calibration.full_scale
  WtsDriver drv;
  // b: the no-load window (also of c and d)
  std::vector<TaxelStats> ts;
  RawTactileFrame raw;
  uint64_t frames = 0;
  double t_first = 0.0, t_last = 0.0;
  uint32_t dev_first = 0, dev_last = 0;
  // c: per taxel, the no-load std and mean; d: the stuck ones
  std::vector<double> sd_grid, mean_grid;
  double median_sd = 0.0;
  std::vector<bool> is_stuck;

  /// The parameters: the `wts:` section (acquisition) and `calibration:` (noise,
  /// max_tare); the banner. -1, or the exit code.
  int loadParams() {
    YAML::Node calib_node;
    if (!o.params_file.empty()) {
      YAML::Node root;
      ConfigResult r = config::loadFile(o.params_file, root);
      if (r) r = loadWtsParams(root["wts"], config::Where{o.params_file, "wts"}, wp);
      if (!r) {
        std::fprintf(stderr, "wts_check: %s\n", r.message().c_str());
        return 2;
      }
      device_from_params = root["wts"] && root["wts"]["device"];
      if (root["calibration"]) {
        calib_file = o.params_file;
        calib_node = root["calibration"];
      }
    }
    if (calib_file.empty()) {
      for (const char* f : {WTS_CHECK_DEFAULT_PARAMS, WTS_CHECK_INSTALLED_PARAMS}) {
        if (*f == '\0' || ::access(f, R_OK) != 0) continue;
        YAML::Node root;
        ConfigResult r = config::loadFile(f, root);
        if (r && root["calibration"]) {
          calib_file = f;
          calib_node = root["calibration"];
          break;
        }
      }
    }
    cp.rows = wp.cells.rows;
    cp.cols = wp.cells.cols;
    if (!calib_file.empty()) {
      ConfigResult r = loadCalibrationParams(calib_node, config::Where{calib_file, "calibration"}, cp.rows, cp.cols, cp);
      if (!r) {
        std::fprintf(stderr, "wts_check: %s\n", r.message().c_str());
        return 2;
      }
    }
    if (o.periodic_ms > 0) wp.periodic_ms = static_cast<int>(o.periodic_ms);
    rows = wp.cells.rows;
    cols = wp.cells.cols;
    n = rows * cols;
    {
      WtsDriver scratch;  // the ranges of the `wts:` section, before touching any device
      WtsParams probe_params = wp;
      if (probe_params.device.empty()) probe_params.device = "/dev/null";
      if (ConfigResult r = scratch.configure(probe_params); !r) {
        std::fprintf(stderr, "wts_check: %s\n", r.message().c_str());
        return 2;
      }
    }
    std::printf("wts_check: WTS bring-up check; taxels are (row, col) in {s}: row 0 = most negative y, col 0 = most "
                "negative x\n");
    std::printf("wts_check: acquisition %s (periodic_ms %d, %s frames), stated noise %.3g counts and max_tare %u from %s\n",
                o.params_file.empty() ? "of the deployments (WtsParams defaults)" : ("of " + o.params_file).c_str(),
                wp.periodic_ms, wp.rle ? "RLE" : "plain", cp.noise_counts, static_cast<unsigned>(cp.max_tare),
                calib_file.empty() ? "(no calibration file found: defaults)" : calib_file.c_str());
    std::fflush(stdout);
    return -1;
  }

  /// The verdict line and the --json report; returns `code` (or 1: the report
  /// could not be written).
  int finish(int code) const {
    std::printf("wts_check: %s (exit %d)\n",
                code == 0 ? "every stage passed" : code == 3 ? "no WTS found" : "a check failed", code);
    if (!o.json_file.empty()) {
      FILE* f = std::fopen(o.json_file.c_str(), "w");
      if (f == nullptr) {
        std::fprintf(stderr, "wts_check: cannot write %s: %s\n", o.json_file.c_str(), std::strerror(errno));
        return code == 0 ? 1 : code;
      }
      std::fprintf(f, "{\n  \"tool\": \"wts_check\",\n  \"exit_code\": %d,\n  \"result\": %s", code,
                   code == 0 ? "\"pass\"" : code == 3 ? "\"no_device\"" : "\"fail\"");
      for (const Stage* s : {&sa, &sb, &sc, &sd, &se}) {
        std::fprintf(f, ",\n  %s: {\"verdict\": %s, \"message\": %s", jsonString(s->key).c_str(),
                     jsonString(toString(s->verdict)).c_str(), jsonString(s->message).c_str());
        std::string next = "[";
        for (std::size_t i = 0; i < s->next.size(); ++i) next += (i ? ", " : "") + jsonString(s->next[i]);
        std::fprintf(f, ", \"next\": %s]", next.c_str());
        for (const auto& kv : s->json) std::fprintf(f, ", %s: %s", jsonString(kv.first).c_str(), kv.second.c_str());
        std::fprintf(f, "}");
      }
      std::fprintf(f, "\n}\n");
      std::fclose(f);
    }
    return code;
  }

  /// a. Find the device. -1, or the exit code.
  int findDevice() {
    std::vector<std::string> paths;
    const bool named = !o.device.empty() || device_from_params;
    if (!o.device.empty()) paths.push_back(o.device);
    else if (device_from_params) paths.push_back(wp.device);
    else paths = candidates(o.candidates);
    std::vector<Probe> probes;
    const Probe* wts = nullptr;
    bool permission = false;
    for (const std::string& p : paths) {
      probes.push_back(probe(p, static_cast<int>(o.probe_timeout_ms)));
      permission = permission || probes.back().open_errno == EACCES || probes.back().open_errno == EPERM;
    }
    for (const Probe& p : probes) {
      if (p.is_wts && wts == nullptr) wts = &p;
      sa.details.push_back(p.path + ": " + (p.is_wts ? "a WTS" : p.why));
    }
    sa.json.emplace_back("candidates", [&] {
      std::string j = "[";
      for (std::size_t i = 0; i < probes.size(); ++i)
        j += (i ? ", " : "") + fmt("{\"path\": %s, \"wts\": %s, \"why\": %s}", jsonString(probes[i].path).c_str(),
                                   probes[i].is_wts ? "true" : "false", jsonString(probes[i].why).c_str());
      return j + "]";
    }());
    if (wts == nullptr) {
      sa.verdict = Verdict::Fail;
      sa.message = paths.empty() ? "no serial device found (looked at " + o.candidates + ")"
                                 : named ? "no WTS at " + paths.front() : "none of the serial devices is a WTS";
      sa.next.push_back("check the USB cable and that the WTS is powered; plugged in, `dmesg | tail` shows cdc_acm and "
                        "the ttyACM it got, and /dev/serial/by-id/ lists it");
      if (permission)
        sa.next.push_back("permission denied: add the user to the dialout group (sudo usermod -aG dialout $USER, then "
                          "log in again), or a udev rule giving the device GROUP=\"dialout\", MODE=\"0660\" (its "
                          "attributes: udevadm info -a -n /dev/ttyACM0)");
      sa.next.push_back("a device that opens but does not answer: another device, or the WTS still starting (wait 2 s, "
                        "run again); name it with --device PATH");
      printStage(sa);
      for (Stage* s : {&sb, &sc, &sd, &se}) printStage(*s);
      return finish(3);
    }
    if (int code = describeDevice(*wts); code >= 0) return code;
    wp.device = wts->path;
    full_scale = wts->mi.full_scale > 0 ? wts->mi.full_scale : cp.full_scale;
    return -1;
  }

  /// a. The WTS found at p against the configured cell map. -1, or the exit code.
  int describeDevice(const Probe& p) {
    CellMap map;
    map.configure(wp.cells);
    std::string fw = p.have_sysinfo ? fmt(", firmware %u.%u (0x%04x), hardware rev %u, serial %u", p.firmware >> 8,
                                          p.firmware & 0xFF, p.firmware, p.hw_rev, p.serial)
                                    : ", no system info (0x50)";
    sa.message = fmt("%s is a WTS%s: matrix res_x %u x res_y %u (cell %.2f mm, full scale %u)%s", p.path.c_str(),
                     p.sensor_type.empty() ? "" : (" \"" + p.sensor_type + "\"").c_str(), p.mi.res_x, p.mi.res_y,
                     1e3 * p.mi.cell_width, p.mi.full_scale, fw.c_str());
    sa.json.emplace_back("path", jsonString(p.path));
    sa.json.emplace_back("res_x", std::to_string(p.mi.res_x));
    sa.json.emplace_back("res_y", std::to_string(p.mi.res_y));
    sa.json.emplace_back("rows", std::to_string(rows));
    sa.json.emplace_back("cols", std::to_string(cols));
    sa.json.emplace_back("full_scale", std::to_string(p.mi.full_scale));
    sa.json.emplace_back("sensor_type", jsonString(p.sensor_type));
    sa.json.emplace_back("firmware", p.have_sysinfo ? jsonString(fmt("%u.%u", p.firmware >> 8, p.firmware & 0xFF))
                                                    : std::string("null"));
    sa.json.emplace_back("serial", p.have_sysinfo ? std::to_string(p.serial) : std::string("null"));
    if (p.mi.res_x != map.resX() || p.mi.res_y != map.resY()) {
      sa.verdict = Verdict::Fail;
      sa.message += fmt("; but the configured cell map (wts.rows %d, cols %d, transpose %s) expects %d x %d", rows, cols,
                        wp.cells.transpose ? "true" : "false", map.resX(), map.resY());
      sa.next.push_back("set wts.rows / wts.cols / wts.transpose (tactile_wts/protocol.hpp, CellMap) to the device's "
                        "matrix; the driver refuses a mismatch");
      printStage(sa);
      for (Stage* s : {&sb, &sc, &sd, &se}) printStage(*s);
      return finish(1);
    }
    sa.verdict = Verdict::Pass;
    sa.message += fmt("; %d x %d taxels in {s} as configured", rows, cols);
    sa.next.push_back("use this path: wts_read --device " + p.path + " (or the device property of "
                      "deployments/wts_reader.cpf)");
    printStage(sa);
    return -1;
  }

  /// b. The driver on the device, the acquisition started. -1, or the exit code.
  int openDriver() {
    if (ConfigResult r = drv.configure(wp); !r) {
      std::fprintf(stderr, "wts_check: %s\n", r.message().c_str());
      return finish(2);
    }
    std::string why;
    CmdStatus os = CmdStatus::NotOpen;
    for (int attempt = 0; attempt < 3 && os != CmdStatus::Ok; ++attempt) os = drv.open(&why);
    if (os != CmdStatus::Ok) {
      sb.verdict = Verdict::Fail;
      sb.message = "the driver could not start the acquisition: " + why;
      sb.next.push_back("run again; if it persists the link loses commands: another cable / USB port, no hub");
      printStage(sb);
      for (Stage* s : {&sc, &sd, &se}) printStage(*s);
      return finish(1);
    }
    std::printf("Leave the pad unloaded (nothing touching it) for the next %.0f s%s.\n", o.seconds,
                o.frames > 0 ? fmt(" or %ld frames", o.frames).c_str() : "");
    std::fflush(stdout);
    waitEnter(o);
    return -1;
  }

  /// b. The no-load window: per-taxel statistics over o.seconds or o.frames.
  void recordNoLoad() {
    ts.assign(static_cast<std::size_t>(n), TaxelStats{});
    const double t_start = nowS();
    while (nowS() - t_start < o.seconds && (o.frames == 0 || static_cast<long>(frames) < o.frames)) {
      const ReadStatus st = drv.poll(nowS(), 50, raw);
      if (st == ReadStatus::Disconnected) {
        sleepMs(20);
        continue;
      }
      if (st != ReadStatus::NewFrame) continue;
      if (frames == 0) {
        t_first = raw.time_s;
        dev_first = raw.device_time_ms;
      }
      t_last = raw.time_s;
      dev_last = raw.device_time_ms;
      ++frames;
      for (int i = 0; i < n; ++i) ts[static_cast<std::size_t>(i)].add(raw.counts[static_cast<std::size_t>(i)]);
    }
  }

  /// b. Rate and link from the no-load window.
  void judgeLink() {
    const double window = t_last - t_first;
    const ParserStats ps = drv.parserStats();
    const DriverStats ds = drv.stats();
    const uint64_t crc = ps.crc_errors;
    const uint64_t format = ds.bad_frames + ps.oversize + ps.bad_headers;
    const uint64_t resyncs = ps.crc_errors + ps.oversize + ps.bad_headers;
    const double error_rate = static_cast<double>(crc + format) / static_cast<double>(std::max<uint64_t>(1, frames + crc + format));
    const double rate = frames > 1 && window > 0 ? static_cast<double>(frames - 1) / window : 0.0;
    const double dev_rate = frames > 1 && dev_last != dev_first
                                ? static_cast<double>(frames - 1) / (1e-3 * static_cast<double>(dev_last - dev_first))
                                : 0.0;
    const double expected = wp.periodic_ms > 0 ? 1000.0 / wp.periodic_ms : 0.0;
    sb.verdict = Verdict::Pass;
    sb.message = fmt("%llu frames in %.2f s: %.1f frames/s", static_cast<unsigned long long>(frames), window, rate);
    if (expected > 0)
      sb.message += fmt(" (expected %.1f from wts.periodic_ms = %d, band +-%.0f %%; device clock %.1f)", expected,
                        wp.periodic_ms, 100 * o.rate_tolerance, dev_rate);
    else
      sb.message += " (single-frame polling, wts.periodic_ms = 0: no expected rate)";
    sb.message += fmt("; %llu CRC errors, %llu format errors, %llu resyncs, %llu bytes skipped, %llu stream restarts, "
                      "%llu disconnects",
                      static_cast<unsigned long long>(crc), static_cast<unsigned long long>(format),
                      static_cast<unsigned long long>(resyncs), static_cast<unsigned long long>(ps.skipped_bytes),
                      static_cast<unsigned long long>(ds.restarts), static_cast<unsigned long long>(ds.disconnects));
    if (static_cast<long>(frames) < o.min_frames) {
      worsen(sb, Verdict::Fail);
      sb.next.push_back(fmt("only %llu frames (at least %ld needed): the device accepted the start command but does "
                            "not stream; power-cycle it (unplug, plug) and run again",
                            static_cast<unsigned long long>(frames), o.min_frames));
    }
    if (expected > 0 && frames > 1 && std::fabs(rate / expected - 1.0) > o.rate_tolerance) {
      worsen(sb, Verdict::Fail);
      sb.next.push_back(fmt("%.1f frames/s instead of %.1f: %s", rate, expected,
                            rate < expected ? "frames are lost or late (link errors below, a busy host, a USB hub); "
                                              "a WTS that cannot keep up with periodic_ms needs a longer period"
                                            : "the device streams faster than wts.periodic_ms asks (another "
                                              "process started it with a shorter period? unplug, plug)"));
    }
    if (error_rate > o.max_error_rate) {
      worsen(sb, Verdict::Fail);
      sb.next.push_back(fmt("%.2g bad packets per packet (limit %.2g): a bad cable, connector or USB hub, or "
                            "interference; try another cable and port, route it away from the motor cables",
                            error_rate, o.max_error_rate));
    }
    if (static_cast<long>(ds.disconnects) > o.max_disconnects) {
      worsen(sb, Verdict::Fail);
      sb.next.push_back(fmt("%llu disconnects (limit %ld): the USB link drops; check the connector and the cable's "
                            "strain relief at the flange, `dmesg` for USB resets",
                            static_cast<unsigned long long>(ds.disconnects), o.max_disconnects));
    }
    if (ds.restarts > 0) {
      worsen(sb, Verdict::Warn);
      sb.next.push_back(fmt("the stream stopped %llu time(s) for wts.restart_after_s and was restarted: a device reset "
                            "(power dip?)", static_cast<unsigned long long>(ds.restarts)));
    }
    if (sb.verdict == Verdict::Pass) sb.next.push_back("the link is good: the rate the deployments get, no errors");
    sb.json = {{"frames", std::to_string(frames)},
               {"seconds", fmt("%.4f", window)},
               {"rate_hz", fmt("%.3f", rate)},
               {"device_rate_hz", fmt("%.3f", dev_rate)},
               {"expected_hz", fmt("%.3f", expected)},
               {"rate_tolerance", fmt("%g", o.rate_tolerance)},
               {"crc_errors", std::to_string(crc)},
               {"format_errors", std::to_string(format)},
               {"resyncs", std::to_string(resyncs)},
               {"skipped_bytes", std::to_string(ps.skipped_bytes)},
               {"restarts", std::to_string(ds.restarts)},
               {"disconnects", std::to_string(ds.disconnects)},
               {"error_rate", fmt("%.6g", error_rate)},
               {"max_error_rate", fmt("%g", o.max_error_rate)}};
    printStage(sb);
  }

  /// c. No-load noise and offsets.
  void noiseStage() {
    sd_grid.assign(static_cast<std::size_t>(n), 0.0);
    mean_grid.assign(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < n; ++i) {
      sd_grid[static_cast<std::size_t>(i)] = ts[static_cast<std::size_t>(i)].stddev();
      mean_grid[static_cast<std::size_t>(i)] = ts[static_cast<std::size_t>(i)].mean;
    }
    std::vector<double> sorted = sd_grid;
    std::sort(sorted.begin(), sorted.end());
    median_sd = sorted[sorted.size() / 2];
    const double limit = o.k * cp.noise_counts;
    std::vector<TaxelRef> noisy, offset_high;
    std::vector<bool> flag_sd(static_cast<std::size_t>(n), false), flag_mean(static_cast<std::size_t>(n), false);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const std::size_t i = static_cast<std::size_t>(r * cols + c);
        if (cp.noise_counts > 0 && sd_grid[i] > limit) {
          noisy.push_back({r, c, sd_grid[i], "std"});
          flag_sd[i] = true;
        }
        if (mean_grid[i] > cp.max_tare) {
          offset_high.push_back({r, c, mean_grid[i], "mean"});
          flag_mean[i] = true;
        }
      }
    sc.verdict = Verdict::Pass;
    sc.message = fmt("std of the raw counts over %llu frames: median %.2f, max %.2f counts; stated %.3g x k %.3g = "
                     "limit %.3g; no-load means %.0f..%.0f counts (max_tare %u)",
                     static_cast<unsigned long long>(frames), median_sd, sorted.back(), cp.noise_counts, o.k, limit,
                     *std::min_element(mean_grid.begin(), mean_grid.end()),
                     *std::max_element(mean_grid.begin(), mean_grid.end()), static_cast<unsigned>(cp.max_tare));
    sc.details.push_back("std (counts), * above the limit:");
    for (const std::string& l : gridLines(sd_grid, flag_sd, rows, cols, "%.1f")) sc.details.push_back(l);
    sc.details.push_back("no-load offset = mean (counts), * above max_tare:");
    for (const std::string& l : gridLines(mean_grid, flag_mean, rows, cols, "%.0f")) sc.details.push_back(l);
    if (cp.noise_counts <= 0) {
      worsen(sc, Verdict::Warn);
      sc.next.push_back("calibration.noise_counts is 0 (" + (calib_file.empty() ? std::string("no file") : calib_file) +
                        "): no stated noise to compare with; set it to this pad's median std");
    }
    if (!noisy.empty()) {
      worsen(sc, Verdict::Fail);
      std::string names;
      for (const TaxelRef& t : noisy) names += fmt("%s%s std %.1f", names.empty() ? "" : ", ", taxelName(t.row, t.col).c_str(), t.value);
      sc.next.push_back(fmt("noisy taxel(s) above %.3g counts: %s: a cracked cell or a loose contact at that "
                            "taxel; if the whole pad is noisy, a ground/shield problem of the cable", limit, names.c_str()));
    }
    if (!offset_high.empty()) {
      worsen(sc, Verdict::Fail);
      std::string names;
      for (const TaxelRef& t : offset_high)
        names += fmt("%s%s mean %.0f", names.empty() ? "" : ", ", taxelName(t.row, t.col).c_str(), t.value);
      sc.next.push_back(fmt("no-load offset above max_tare %u counts: %s: something presses the pad (a tight cover, "
                            "the mounting screws), or the cell is damaged; the tare would be refused",
                            static_cast<unsigned>(cp.max_tare), names.c_str()));
    }
    if (sc.verdict == Verdict::Pass)
      sc.next.push_back("the noise is the stated one: the features' thresholds (wts0614.yaml) hold for this pad");
    sc.json = {{"frames", std::to_string(frames)},       {"stated_counts", fmt("%g", cp.noise_counts)},
               {"k", fmt("%g", o.k)},                    {"limit_counts", fmt("%g", limit)},
               {"median_std", fmt("%.3f", median_sd)},   {"max_tare", std::to_string(cp.max_tare)},
               {"std", jsonGrid(sd_grid, rows, cols)},   {"mean", jsonGrid(mean_grid, rows, cols)},
               {"noisy", jsonTaxels(noisy)},             {"offset_above_max_tare", jsonTaxels(offset_high)}};
    printStage(sc);
  }

  /// d. Stuck taxels.
  void stuckStage() {
    constexpr double kMinPadNoise = 0.5;  // counts: below this median std the pad shows no noise to compare with
    const double fs_limit = full_scale * (1.0 - o.fullscale_margin);
    std::vector<TaxelRef> stuck, silent;
    is_stuck.assign(static_cast<std::size_t>(n), false);
    int constant = 0;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const std::size_t i = static_cast<std::size_t>(r * cols + c);
        const TaxelStats& t = ts[i];
        if (t.min == t.max) ++constant;
        if (t.mean >= fs_limit) {
          stuck.push_back({r, c, t.mean, "at full scale"});
          is_stuck[i] = true;
        } else if (t.min == t.max && median_sd >= kMinPadNoise) {
          if (t.max == 0) silent.push_back({r, c, 0.0, "reads 0 throughout"});
          else {
            stuck.push_back({r, c, static_cast<double>(t.max), "constant"});
            is_stuck[i] = true;
          }
        }
      }
    sd.verdict = Verdict::Pass;
    sd.message = fmt("%d of %d taxels constant over %llu frames (pad median std %.2f counts); full-scale limit %.0f "
                     "counts",
                     constant, n, static_cast<unsigned long long>(frames), median_sd, fs_limit);
    if (!stuck.empty()) {
      worsen(sd, Verdict::Fail);
      std::string names;
      for (const TaxelRef& t : stuck)
        names += fmt("%s%s %s %.0f", names.empty() ? "" : ", ", taxelName(t.row, t.col).c_str(), t.what.c_str(), t.value);
      sd.message += "; stuck: " + names;
      sd.next.push_back("stuck taxel(s): " + names + ": a shorted cell or a damaged pad; the features have no per-taxel "
                        "mask and read it as a permanent contact: have the pad repaired or replaced (Weiss) before "
                        "experiments");
    }
    if (!silent.empty()) {
      worsen(sd, Verdict::Warn);
      std::string names;
      for (const TaxelRef& t : silent) names += (names.empty() ? "" : ", ") + taxelName(t.row, t.col);
      sd.message += "; silent at no load: " + names;
      sd.next.push_back("taxel(s) reading 0 throughout while the others show noise: " + names +
                        ": dead or below its threshold; run with --press to tell");
    }
    if (median_sd < kMinPadNoise) {
      worsen(sd, Verdict::Warn);
      sd.next.push_back("the pad shows no noise at no load (median std below 0.5 count): a constant taxel cannot be "
                        "told from a healthy one here; run with --press");
    }
    if (sd.verdict == Verdict::Pass) sd.next.push_back("no stuck taxel");
    sd.json = {{"constant_taxels", std::to_string(constant)},
               {"fullscale_limit", fmt("%.1f", fs_limit)},
               {"stuck", jsonTaxels(stuck)},
               {"silent", jsonTaxels(silent)}};
    printStage(sd);
  }

  /// e. Wait for a whole-pad press: `need` taxels above their rise threshold;
  /// false after o.press_timeout (last_count: the most that rose at the end).
  bool waitForPress(const std::vector<double>& rise_thr, int need, int& last_count) {
    const double t0 = nowS();
    double next_progress = t0 + 1.0;
    bool loaded = false;
    while (!loaded && nowS() - t0 < o.press_timeout) {
      if (drv.poll(nowS(), 50, raw) != ReadStatus::NewFrame) {
        if (nowS() >= next_progress) {
          std::printf("  waiting for the load: %d/%d taxels risen (need %d), %.0f s left\n", last_count, n, need,
                      o.press_timeout - (nowS() - t0));
          std::fflush(stdout);
          next_progress += 1.0;
        }
        continue;
      }
      int count = 0;
      for (int i = 0; i < n; ++i) {
        const std::size_t u = static_cast<std::size_t>(i);
        if (raw.counts[u] - mean_grid[u] >= rise_thr[u]) ++count;
      }
      last_count = count;
      loaded = count >= need;
      if (nowS() >= next_progress && !loaded) {
        std::printf("  waiting for the load: %d/%d taxels risen (need %d), %.0f s left\n", count, n, need,
                    o.press_timeout - (nowS() - t0));
        std::fflush(stdout);
        next_progress += 1.0;
      }
    }
    return loaded;
  }

  /// e. Under the press: each taxel's largest rise over its no-load mean; the
  /// number of frames.
  uint64_t recordPress(std::vector<double>& max_rise) {
    uint64_t press_frames = 0;
    const double t1 = nowS();
    // bounded: the frames at the configured rate, plus the press timeout for a slow link
    const double limit_s = o.press_timeout + (wp.periodic_ms > 0 ? 2e-3 * wp.periodic_ms * static_cast<double>(o.press_frames) : 10.0);
    while (static_cast<long>(press_frames) < o.press_frames && nowS() - t1 < limit_s) {
      if (drv.poll(nowS(), 50, raw) != ReadStatus::NewFrame) continue;
      ++press_frames;
      for (int i = 0; i < n; ++i) {
        const std::size_t u = static_cast<std::size_t>(i);
        max_rise[u] = std::max(max_rise[u], raw.counts[u] - mean_grid[u]);
      }
    }
    return press_frames;
  }

  /// e. Dead taxels: did not rise while most of their neighbours did.
  void judgeDead(const std::vector<double>& rise_thr, const std::vector<double>& max_rise, uint64_t press_frames) {
    std::vector<TaxelRef> dead, not_loaded, stuck_again;
    std::vector<bool> rose(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) rose[static_cast<std::size_t>(i)] = max_rise[static_cast<std::size_t>(i)] >= rise_thr[static_cast<std::size_t>(i)];
    std::vector<bool> flag(static_cast<std::size_t>(n), false);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const std::size_t i = static_cast<std::size_t>(r * cols + c);
        if (rose[i]) continue;
        int nb = 0, nb_rose = 0;
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if ((dr == 0 && dc == 0) || rr < 0 || rr >= rows || cc < 0 || cc >= cols) continue;
            ++nb;
            if (rose[static_cast<std::size_t>(rr * cols + cc)]) ++nb_rose;
          }
        flag[i] = true;
        if (is_stuck[i]) stuck_again.push_back({r, c, max_rise[i], "stuck (stage d)"});
        else if (2 * nb_rose >= nb) dead.push_back({r, c, max_rise[i], "never rose"});
        else not_loaded.push_back({r, c, max_rise[i], "not loaded"});
      }
    se.verdict = Verdict::Pass;
    std::vector<double> rise_grid = max_rise;
    se.message = fmt("%llu frames under load; %d of %d taxels rose above their threshold",
                     static_cast<unsigned long long>(press_frames),
                     static_cast<int>(std::count(rose.begin(), rose.end(), true)), n);
    se.details.push_back("largest rise over the no-load mean (counts), * did not rise:");
    for (const std::string& l : gridLines(rise_grid, flag, rows, cols, "%.0f")) se.details.push_back(l);
    if (!dead.empty()) {
      worsen(se, Verdict::Fail);
      std::string names;
      for (const TaxelRef& t : dead) names += (names.empty() ? "" : ", ") + taxelName(t.row, t.col);
      se.message += "; dead: " + names;
      se.next.push_back("dead taxel(s) " + names + ": never rose while their neighbours did: a broken cell or "
                        "trace; the features bridge one silent taxel inside a contact (wts0614.yaml region_gap) but "
                        "its force is missing: have the pad repaired or replaced (Weiss)");
    }
    if (!stuck_again.empty()) {
      std::string names;
      for (const TaxelRef& t : stuck_again) names += (names.empty() ? "" : ", ") + taxelName(t.row, t.col);
      se.message += "; did not rise, stuck (stage d): " + names;
    }
    if (!not_loaded.empty()) {
      worsen(se, Verdict::Warn);
      std::string names;
      for (const TaxelRef& t : not_loaded) names += (names.empty() ? "" : ", ") + taxelName(t.row, t.col);
      se.message += "; not loaded with their neighbours: " + names;
      se.next.push_back("part of the pad was not pressed (" + names + "): press the whole pad flat and run again");
    }
    if (se.verdict == Verdict::Pass) se.next.push_back("every taxel responds to a load");
    se.json = {{"press_frames", std::to_string(press_frames)},
               {"rise", jsonGrid(rise_grid, rows, cols)},
               {"dead", jsonTaxels(dead)},
               {"not_loaded", jsonTaxels(not_loaded)}};
  }

  /// e. Dead taxels under a whole-pad press (--press).
  void pressStage() {
    std::vector<double> rise_thr(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const std::size_t u = static_cast<std::size_t>(i);
      rise_thr[u] = std::max(o.press_min_rise, o.k * std::max(sd_grid[u], cp.noise_counts));
    }
    const int need = std::max(1, static_cast<int>(std::ceil(o.press_fraction * n)));
    std::printf("Press the whole pad now (a flat plate or a palm) and hold it: waiting up to %.0f s for %d of %d "
                "taxels to rise above their no-load level (by %.0f counts or more).\n",
                o.press_timeout, need, n, o.press_min_rise);
    std::fflush(stdout);
    std::vector<double> max_rise(static_cast<std::size_t>(n), -1e9);
    int last_count = 0;
    const bool loaded = waitForPress(rise_thr, need, last_count);
    if (!loaded) {
      se.verdict = Verdict::Fail;
      se.message = fmt("no whole-pad load within %.0f s (at most %d of the %d taxels needed rose)", o.press_timeout,
                       last_count, need);
      se.next.push_back("press the whole pad flat (a plate or a palm, a few newtons) within the timeout; if the "
                        "values do not move at all, check with `wts_read --raw` that the pad responds");
    } else {
      std::printf("  load seen: recording %ld frames, keep pressing\n", o.press_frames);
      std::fflush(stdout);
      const uint64_t press_frames = recordPress(max_rise);
      std::printf("  done: release the pad\n");
      std::fflush(stdout);
      judgeDead(rise_thr, max_rise, press_frames);
    }
    se.json.emplace_back("loaded", loaded ? "true" : "false");
  }

  /// The stages in order; the exit code.
  int run() {
    if (int code = loadParams(); code >= 0) return code;
    if (int code = findDevice(); code >= 0) return code;
    if (int code = openDriver(); code >= 0) return code;
    recordNoLoad();
    judgeLink();
    if (static_cast<long>(frames) < o.min_frames) {
      sc.message = sd.message = se.message = "skipped: too few frames";
      for (Stage* s : {&sc, &sd, &se}) printStage(*s);
      drv.close();
      return finish(1);
    }
    noiseStage();
    stuckStage();
    if (o.press) pressStage();
    printStage(se);
    drv.close();

    int exit_code = 0;
    for (const Stage* s : {&sa, &sb, &sc, &sd, &se})
      if (s->verdict == Verdict::Fail) exit_code = 1;
    return finish(exit_code);
  }
};

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (int code = parseArgs(argc, argv, o); code >= 0) return code;
  Check check(o);
  return check.run();
}
