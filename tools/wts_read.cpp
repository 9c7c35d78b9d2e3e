// wts_read: read frames from a Weiss WTS sensor and print one CSV line per frame.
//
//   wts_read --device PATH [--periodic-ms N] [--rle] [--count N] [--raw]
//            [--rows 6 --cols 14] [--no-transpose] [--flip-rows] [--flip-cols]
//            [--params FILE.yaml] [--calib FILE.yaml] [--tare] [--timeout-ms N]
//
// --params reads the `wts:` section (params_io.hpp) and the `calibration:`
// section of a parameter file; options after it override the file.
// Output (stdout): rows*cols comma-separated values per line, row-major in the
// {s} layout (conventions.hpp) -- the input format of `tactile_features`, so
//   wts_read --device /dev/ttyACM0 --periodic-ms 10 | tactile_features -
// works. Values are newtons (tactile::Calibration, App. A: default linear
// 0.002 N/count, or the `calibration:` section of --calib) or raw 12-bit counts
// with --raw. Without --periodic-ms the tool polls with "read single frame".
// Link events (disconnects, reconnects, CRC/format errors, device errors) go to
// stderr. Exit: 0 after --count frames (or on SIGINT/SIGTERM), 1 when the
// device cannot be opened or configured, 2 on usage errors.
#include <csignal>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_wts/driver.hpp"
#include "tactile_wts/params_io.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }

void usage() {
  std::fprintf(stderr,
               "usage: wts_read --device PATH [--periodic-ms N] [--rle] [--count N] [--raw]\n"
               "                [--rows R] [--cols C] [--no-transpose] [--flip-rows] [--flip-cols]\n"
               "                [--params FILE.yaml] [--calib FILE.yaml] [--tare] [--timeout-ms N]\n"
               "Prints one frame per line: rows*cols values, row-major {s} order, newtons (or counts with --raw).\n");
}

bool toLong(const char* s, long& v) {
  char* end = nullptr;
  v = std::strtol(s, &end, 10);
  return end != s && *end == '\0';
}

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// wts_read's command line (parseArgs).
struct ReadArgs {
  tactile::wts::WtsParams wp;
  long count = 0;
  bool raw = false, do_tare = false;
  long timeout_ms = 100;
  std::string calib_file;
};

/// The command line into `args`: -1, or the exit code (help 0, a bad option 2;
/// a bad integer exits with 2 at once).
int parseArgs(int argc, char** argv, ReadArgs& args) {
  tactile::wts::WtsParams& wp = args.wp;
  wp.device.clear();
  wp.periodic_ms = 0;
  long& count = args.count;
  bool &raw = args.raw, &do_tare = args.do_tare;
  long& timeout_ms = args.timeout_ms;
  std::string& calib_file = args.calib_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto num = [&](long& v) {
      if (i + 1 >= argc || !toLong(argv[i + 1], v)) {
        std::fprintf(stderr, "wts_read: %s needs an integer value\n", a.c_str());
        std::exit(2);
      }
      ++i;
    };
    long v = 0;
    if (a == "--device" && i + 1 < argc) {
      wp.device = argv[++i];
    } else if (a == "--periodic-ms") {
      num(v);
      if (v < 1 || v > 1000) {
        std::fprintf(stderr, "wts_read: --periodic-ms = %ld: must be in [1, 1000] (ms)\n", v);
        return 2;
      }
      wp.periodic_ms = static_cast<int>(v);
    } else if (a == "--rle") {
      wp.rle = true;
    } else if (a == "--count") {
      num(count);
      if (count < 0) {
        std::fprintf(stderr, "wts_read: --count = %ld: must be >= 0 (0 = until interrupted)\n", count);
        return 2;
      }
    } else if (a == "--raw") {
      raw = true;
    } else if (a == "--rows") {
      num(v);
      wp.cells.rows = static_cast<int>(v);
    } else if (a == "--cols") {
      num(v);
      wp.cells.cols = static_cast<int>(v);
    } else if (a == "--no-transpose") {
      wp.cells.transpose = false;
    } else if (a == "--flip-rows") {
      wp.cells.flip_rows = true;
    } else if (a == "--flip-cols") {
      wp.cells.flip_cols = true;
    } else if (a == "--params" && i + 1 < argc) {
      const std::string file = argv[++i];
      YAML::Node root;
      tactile::ConfigResult r = tactile::config::loadFile(file, root);
      if (r) r = tactile::wts::loadWtsParams(root["wts"], tactile::config::Where{file, "wts"}, wp);
      if (!r) {
        std::fprintf(stderr, "wts_read: %s\n", r.message().c_str());
        return 2;
      }
      if (root["calibration"]) calib_file = file;
    } else if (a == "--calib" && i + 1 < argc) {
      calib_file = argv[++i];
    } else if (a == "--tare") {
      do_tare = true;
    } else if (a == "--timeout-ms") {
      num(timeout_ms);
      if (timeout_ms < 1 || timeout_ms > 10000) {
        std::fprintf(stderr, "wts_read: --timeout-ms = %ld: must be in [1, 10000]\n", timeout_ms);
        return 2;
      }
      wp.command_timeout_ms = static_cast<int>(timeout_ms) * 3;
    } else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else {
      std::fprintf(stderr, "wts_read: unknown or incomplete option %s\n", a.c_str());
      usage();
      return 2;
    }
  }
  if (wp.device.empty()) {
    std::fprintf(stderr, "wts_read: --device PATH is required\n");
    usage();
    return 2;
  }
  return -1;
}

/// The calibration of --params / --calib (else the defaults) for the
/// cell map of `wp` into `calib`: -1, or the exit code (2).
int loadCalibration(const tactile::wts::WtsParams& wp, const std::string& calib_file, tactile::Calibration& calib) {
  tactile::CalibrationParams cp;
  tactile::ConfigResult cr;
  cp.rows = wp.cells.rows;
  cp.cols = wp.cells.cols;
  if (!calib_file.empty()) {
    YAML::Node root;
    cr = tactile::config::loadFile(calib_file, root);
    if (cr && root["calibration"])
      cr = tactile::loadCalibrationParams(root["calibration"], tactile::config::Where{calib_file, "calibration"},
                                          cp.rows, cp.cols, cp);
    if (!cr) {
      std::fprintf(stderr, "wts_read: %s\n", cr.message().c_str());
      return 2;
    }
  }
  cr = calib.configure(cp);
  if (!cr) {
    std::fprintf(stderr, "wts_read: %s\n", cr.message().c_str());
    return 2;
  }
  return -1;
}

/// The link's changes on stderr: a disconnection, reconnection or device
/// error (once per change), new CRC or format errors.
void reportLink(tactile::wts::WtsDriver& drv, tactile::wts::ReadStatus st, double reconnect_period_s,
                tactile::wts::ReadStatus& last, uint64_t& last_crc, uint64_t& last_bad) {
  if (st != last && (st == tactile::wts::ReadStatus::Disconnected || st == tactile::wts::ReadStatus::Reconnected ||
                     st == tactile::wts::ReadStatus::DeviceError)) {
    std::fprintf(stderr, "wts_read: link %s", tactile::wts::toString(st));
    if (st == tactile::wts::ReadStatus::DeviceError)
      std::fprintf(stderr, " (%s)", tactile::wts::toString(drv.lastDeviceStatus()));
    if (st == tactile::wts::ReadStatus::Disconnected)
      std::fprintf(stderr, " (%s; retrying every %.2f s)", std::strerror(drv.lastErrno()), reconnect_period_s);
    std::fputc('\n', stderr);
  }
  if (st != tactile::wts::ReadStatus::NoData) last = st;
  const auto& ps = drv.parserStats();
  if (ps.crc_errors != last_crc || drv.stats().bad_frames != last_bad) {
    std::fprintf(stderr, "wts_read: link errors: %llu CRC, %llu malformed frames, %llu bytes skipped so far\n",
                 static_cast<unsigned long long>(ps.crc_errors),
                 static_cast<unsigned long long>(drv.stats().bad_frames),
                 static_cast<unsigned long long>(ps.skipped_bytes));
    last_crc = ps.crc_errors;
    last_bad = drv.stats().bad_frames;
  }
}

}  // namespace

int main(int argc, char** argv) {
  ReadArgs args;
  if (int code = parseArgs(argc, argv, args); code >= 0) return code;
  const tactile::wts::WtsParams& wp = args.wp;
  const long count = args.count, timeout_ms = args.timeout_ms;
  const bool raw = args.raw, do_tare = args.do_tare;
  tactile::wts::WtsDriver drv;
  tactile::ConfigResult cr = drv.configure(wp);
  if (!cr) {
    std::fprintf(stderr, "wts_read: %s\n", cr.message().c_str());
    return 2;
  }
  tactile::Calibration calib;
  if (int code = loadCalibration(wp, args.calib_file, calib); code >= 0) return code;
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::signal(SIGPIPE, onSignal);
  std::string why;
  if (drv.open(&why) != tactile::wts::CmdStatus::Ok) {
    std::fprintf(stderr, "wts_read: %s: %s\n", wp.device.c_str(), why.c_str());
    return 1;
  }
  if (do_tare) {
    const auto ts = drv.tare(true);
    if (ts != tactile::wts::CmdStatus::Ok)
      std::fprintf(stderr, "wts_read: tare failed: %s (%s)\n", tactile::wts::toString(ts),
                   tactile::wts::toString(drv.lastDeviceStatus()));
  }

  tactile::RawTactileFrame rawf;
  tactile::TactileFrame frame;
  const int n = wp.cells.rows * wp.cells.cols;
  long printed = 0;
  tactile::wts::ReadStatus last = tactile::wts::ReadStatus::NoData;
  uint64_t last_crc = 0, last_bad = 0;
  std::string line;
  line.reserve(static_cast<std::size_t>(n) * 12);
  char num[32];
  while (!g_stop && (count == 0 || printed < count)) {
    const tactile::wts::ReadStatus st = drv.poll(nowS(), static_cast<int>(timeout_ms), rawf);
    reportLink(drv, st, wp.reconnect_period_s, last, last_crc, last_bad);
    if (st == tactile::wts::ReadStatus::Disconnected) {
      struct timespec ts {0, 20 * 1000 * 1000};
      nanosleep(&ts, nullptr);
      continue;
    }
    if (st != tactile::wts::ReadStatus::NewFrame) continue;
    line.clear();
    if (raw) {
      for (int i = 0; i < n; ++i) {
        std::snprintf(num, sizeof(num), i ? ",%u" : "%u", static_cast<unsigned>(rawf.counts[static_cast<std::size_t>(i)]));
        line += num;
      }
    } else {
      if (calib.step(rawf, frame) == tactile::CalibrationStatus::BadDimensions) {
        std::fprintf(stderr, "wts_read: frame size mismatch\n");
        continue;
      }
      for (int i = 0; i < n; ++i) {
        std::snprintf(num, sizeof(num), i ? ",%.6g" : "%.6g", frame.force[static_cast<std::size_t>(i)]);
        line += num;
      }
    }
    line += '\n';
    if (std::fputs(line.c_str(), stdout) < 0) break;
    std::fflush(stdout);
    ++printed;
  }
  drv.close();
  return 0;
}
