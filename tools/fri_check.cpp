// fri_check --port P [--cycles N] [--motion hold|circle] [options]
//
// Runs the real FRI bridge core against whatever KRC sends to UDP port P (the
// KUKA controller, or fri_sim_krc). In MON it echoes the measured pose; in CMD
// at quality >= OK it commands a hold of the pose where CMD was entered, or a
// small smooth circle in the base x-y plane around it. It prints the state and
// quality transitions and, at the end, the loss and latency statistics, and
// exits after N accepted measurement packets.
//
// Options:
//   --params FILE        bridge/UDP parameters from the `fri:` mapping of FILE
//                        (params/fri.yaml); other options override it
//   --bind ADDR          local IPv4 address to bind (default 0.0.0.0)
//   --radius M           circle radius (default 0.01 m), ramped in smoothly
//   --circle-period S    circle period (default 10 s)
//   --max-lin-speed V    bridge rate limit (default 0.05 m/s)
//   --max-rot-speed W    bridge rate limit (default 0.25 rad/s)
//   --idle-timeout S     give up when nothing arrives for S seconds (default 10)
//   --cart-offset F      how this run's bridge reads the KRC's set point (none |
//                        composed | elementwise; default none: cmdCartPos alone, the
//                        set point at a fresh friStart in every form, the bridge's
//                        set point check guarding the rest)
// Exit status: 0 after N cycles, 2 on idle timeout, 1 on usage/configuration errors.
//
// The KRC's set point form (fri.cart_offset): in CMD at quality >= OK, each
// measurement's cmdCartPos and cmdCartPosFriOffset describe the set point the
// KRC holds, which is the command it took last (reflSeqCount = our last
// command). fri_check reads them in each form (none, composed, elementwise;
// protocol.hpp CartOffset) and compares with that command. Samples count once
// the command moved >= 2 mm from where CMD was entered (there the forms
// differ by the motion); a form agrees when its reading is a pose within
// 1 mm / 0.01 rad of the command on every such sample. At the end one line
// per form and the verdict:
//   cart_offset: use elementwise (...)   the one form that agrees: set it in fri.yaml
//   cart_offset: use none (...)          the offset stayed zero: cmdCartPos is the set point
//   cart_offset: undetermined (...)      too little motion (run --motion circle), this
//                                        run's bridge read another form (--cart-offset
//                                        composed | elementwise) and held, or no form or
//                                        more than one agrees
//
// MONITOR MODE (bring-up: is the link what fri.yaml says?):
//
//   fri_check --monitor --params params/fri.yaml [--seconds S] [--cycles N] [--port P] [--bind ADDR]
//             [--period-tolerance F] [--max-jitter-ms J] [--max-loss-rate R] [--json FILE]
//             [--max-late-share R] [--min-perfect-share P] [--quality-drop fail|warn] [--record FILE]
//
// Never commands motion: the bridge runs in its dry run (FriBridge::setDryRun)
// with no desired pose, so in MON it echoes the measured pose and in CMD it
// holds the pose where CMD was entered (a joint hold under another strategy).
// It observes the KRC for S seconds from its first packet (default 5), or
// until the KRC's sequence counter has covered N packets (lost ones included),
// and reports, each item PASS / WARN / FAIL with what to do next:
//   packets     what arrived, from where; malformed datagrams FAIL; the KRC
//               falling silent before the end FAILs;
//   cycle time  the KRC's desiredMsrSampleTime / desiredCmdSampleTime (friOpen's
//               cycle) against fri.cycle_time_s (1e-5 s tolerance, as the
//               bridge's own check);
//   krc port    the KRC's UDP source port against fri.udp.krc_port (0 = any:
//               PASS, with the port to set); more than one sender FAILs;
//   control     the KRC's control strategy: Cartesian impedance, else FAIL;
//   period      the measured packet period (host receive times, p50) within
//               +-period_tolerance (default 0.25) of the KRC's cycle;
//   jitter      p50 / p99 / max of the inter-arrival times; FAIL when
//               p99 - p50 > max_jitter_ms (default half the KRC's cycle: 0.5 ms
//               at 1 ms, 1 ms at 2 ms);
//   loss        sequence gaps / packets the KRC sent <= max_loss_rate (default
//               0.001);
//   order       duplicates and out-of-order packets: any FAILs;
//   state       MON / CMD (and drives off: WARN) over time;
//   quality     the KRC's link quality over time: FAIL when it is below OK at the
//               end or drops below OK after having reached it; WARN when it
//               started below OK (the KRC rates the link once answers arrive).
//               --quality-drop warn makes a drop that recovers a WARN: for a
//               host whose wake-up latency is known to reach several cycles
//               (the rehearsal against the simulated KRC on a machine without
//               a real-time kernel), where [cycle] judges whether the link is
//               sustained; on the arm keep the default, fail;
//   cycle       whether this PC sustains the KRC's cycle: the share of answers the
//               KRC missed (its missCounter over the run), the share this host
//               answered later than 80 % of the cycle after the packet's due
//               time (the KRC's send grid: the earliest answer within 100
//               packets either side, this host's clock: a host that wakes late answers
//               late), and the share of packets at
//               PERFECT once PERFECT was first reached. Sustained (PASS): at most
//               max_late_share (default 0.02) missed or late and PERFECT in at
//               least min_perfect_share (default 0.99) of the packets (the
//               simulated KRC's thresholds, KrcQualityRule). Otherwise at 1 ms: WARN, advise
//               friOpen(2) with fri.cycle_time_s 0.002 and this check again; at
//               2 ms or more: FAIL, the host must be fixed first.
// --record FILE writes every accepted measurement (time, state, quality,
// msrCartPos, estExtTcpFT as sent) as one CSV line: the input of the wrench
// checks below.
// The timing items (period, jitter) are diagnostics of this host and network,
// measured with its clock. Exit (monitor mode): 0 every item PASS or WARN, 3 an
// item FAILed, 2 no packet within --idle-timeout, 1 usage/configuration errors.
//
// THE WRENCH CHECKS (offline, on --record files; fri_check_wrench.hpp):
//   fri_check --wrench-check --mass KG --tare FILE --loaded FILE [--params FILE] [--direction ...]
//   fri_check --load-data --sensor-params FILE [--params FILE] REST1 REST2 REST3 [...]
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "tactile_config/cli_args.hpp"
#include <vector>

#include <arpa/inet.h>

#include "fri_check_wrench.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/params_io.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_fri/wrench_checks.hpp"

using namespace tactile;
using namespace tactile::fri;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int usage(const char* msg) {
  std::fprintf(stderr,
               "fri_check: %s\nusage: fri_check --port P [--cycles N] [--motion hold|circle] [--bind ADDR] "
               "[--radius M] [--circle-period S] [--max-lin-speed V] [--max-rot-speed W] [--idle-timeout S] [--cart-offset none|composed|elementwise]\n"
               "       fri_check --monitor --params FILE [--seconds S] [--cycles N] [--port P] [--bind ADDR] "
               "[--period-tolerance F] [--max-jitter-ms J] [--max-loss-rate R] [--json FILE] [--idle-timeout S]\n"
               "       [--max-late-share R] [--min-perfect-share P] [--quality-drop fail|warn] [--record FILE]\n"
               "       fri_check --wrench-check --mass KG --tare FILE --loaded FILE [--params FILE] [--direction base|tool:X,Y,Z]\n"
               "       fri_check --load-data --sensor-params FILE [--params FILE] REST1 REST2 REST3 [...]\n",
               msg);
  return 1;
}

bool parseDouble(const char* s, double& v) {
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(v);
}

struct RunningStat {
  double sum = 0.0, sum2 = 0.0, max = 0.0;
  uint64_t n = 0;
  void add(double x) {
    sum += x;
    sum2 += x * x;
    max = n == 0 ? x : std::max(max, x);
    ++n;
  }
  double mean() const { return n ? sum / double(n) : 0.0; }
  double stddev() const { return n > 1 ? std::sqrt(std::max(0.0, sum2 / double(n) - mean() * mean())) : 0.0; }
};

// ---- the KRC's set point form -------------------------------------------------

struct OffsetProbe {
  static constexpr double kDecisiveM = 0.002;  // command motion from the CMD entry (m)
  static constexpr double kTolM = 0.001;       // reading vs the command (m)
  static constexpr double kTolRad = 0.01;      // (rad)
  struct PerForm {
    uint64_t unreadable = 0;  // not a pose in this form
    double max_m = 0.0, max_rad = 0.0;
  };
  std::array<PerForm, 3> form{};
  uint64_t samples = 0, nonzero = 0;
  double max_motion = 0.0;

  /// `taken`: the command the KRC reflects (its set point now); `entry`: where CMD was entered.
  void add(const MsrPacket& m, const KDL::Frame& taken, const KDL::Frame& entry) {
    const double motion = (taken.p - entry.p).Norm();
    max_motion = std::max(max_motion, motion);
    if (motion < kDecisiveM) return;
    ++samples;
    bool zero = true;
    for (float v : m.data.cmd_cart_pos_fri_offset) zero = zero && v == 0.0f;
    if (!zero) ++nonzero;
    for (int i = 0; i < 3; ++i) {
      PerForm& f = form[static_cast<std::size_t>(i)];
      KDL::Frame sp;
      if (!readSetPoint(m.data.cmd_cart_pos, m.data.cmd_cart_pos_fri_offset, static_cast<CartOffset>(i), sp)) {
        ++f.unreadable;
        continue;
      }
      KDL::Vector axis;
      f.max_m = std::max(f.max_m, (sp.p - taken.p).Norm());
      f.max_rad = std::max(f.max_rad, rotationAngle(taken.M.Inverse() * sp.M, axis));
    }
  }
  bool agrees(int i) const {
    const PerForm& f = form[static_cast<std::size_t>(i)];
    return samples > 0 && f.unreadable == 0 && f.max_m <= kTolM && f.max_rad <= kTolRad;
  }
  void report(CartOffset ran_with, bool held_at_mismatch) const {
    for (int i = 0; i < 3; ++i) {
      const PerForm& f = form[static_cast<std::size_t>(i)];
      if (samples == 0) break;
      if (f.unreadable > 0)
        std::printf("cart_offset %-11s no pose in %llu of %llu samples\n", toString(static_cast<CartOffset>(i)),
                    static_cast<unsigned long long>(f.unreadable), static_cast<unsigned long long>(samples));
      else
        std::printf("cart_offset %-11s max error %.3f mm %.4f rad over %llu samples: %s\n",
                    toString(static_cast<CartOffset>(i)), f.max_m * 1e3, f.max_rad,
                    static_cast<unsigned long long>(samples), agrees(i) ? "agrees" : "disagrees");
    }
    int n_agree = 0, which = -1;
    for (int i = 0; i < 3; ++i)
      if (agrees(i)) ++n_agree, which = which < 0 ? i : which;
    if (samples == 0 && held_at_mismatch) {
      std::printf("cart_offset: undetermined (this run's bridge read %s, the KRC sends another form: it held at "
                  "offset_mismatch after %.2f mm; run again with --cart-offset none)\n",
                  toString(ran_with), max_motion * 1e3);
    } else if (samples == 0) {
      std::printf("cart_offset: undetermined (the command moved %.2f mm from the CMD entry, < %.0f mm: run "
                  "--motion circle with the KRC in CMD)\n",
                  max_motion * 1e3, kDecisiveM * 1e3);
    } else if (nonzero == 0 && n_agree > 0) {
      std::printf("cart_offset: use none (the KRC's cmdCartPosFriOffset stayed zero: cmdCartPos is the set point, "
                  "every form reads it alike)\n");
    } else if (n_agree == 1) {
      const CartOffset f = static_cast<CartOffset>(which);
      std::printf("cart_offset: use %s (set fri.cart_offset: %s in fri.yaml%s)\n", toString(f), toString(f),
                  f == ran_with || !held_at_mismatch
                      ? ""
                      : "; this run's bridge read it otherwise and held at offset_mismatch once it noticed");
    } else {
      std::printf("cart_offset: undetermined (%d forms agree with the commands taken: see the lines above and "
                  "docs/bringup.md)\n", n_agree);
    }
  }
};

// ---- monitor mode -------------------------------------------------------------

const char* strategyName(uint16_t c) {
  switch (static_cast<ControlStrategy>(c)) {
    case ControlStrategy::Position: return "position";
    case ControlStrategy::CartImpedance: return "Cartesian impedance";
    case ControlStrategy::JointImpedance: return "joint impedance";
    case ControlStrategy::Other: return "other";
  }
  return "unknown";
}

using config::fmt;
using config::jsonString;


enum class Verdict { Pass, Warn, Fail };
const char* toString(Verdict v) { return v == Verdict::Pass ? "PASS" : v == Verdict::Warn ? "WARN" : "FAIL"; }

struct Item {
  std::string key, label;
  Verdict verdict = Verdict::Pass;
  std::string message;
  std::vector<std::string> next;
  std::vector<std::pair<std::string, std::string>> json;  ///< extra fields, values already JSON
};

struct MonitorOptions {
  double seconds = 5.0;
  long cycles = 0;  ///< 0: by time only
  double idle_timeout = 10.0;
  double period_tolerance = 0.25;
  double max_jitter_ms = -1.0;  ///< < 0: half the KRC's cycle
  double max_loss_rate = 0.001;
  double max_late_share = 0.02;     ///< [cycle]: missed + late answers (KrcQualityRule's PERFECT share)
  double min_perfect_share = 0.99;  ///< [cycle]: packets at PERFECT once reached
  bool quality_drop_warns = false;  ///< [quality]: a drop below OK that recovers is a WARN (--quality-drop warn)
  std::string json_file;
  std::string params_file;
  std::string record_file;  ///< every accepted measurement, one CSV line (wrench_checks.hpp)
};

/// Nearest-rank percentile of a sorted vector (q in [0, 1]).
double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const std::size_t i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size() - 1, i == 0 ? 0 : i - 1)];
}

/// An answer later than this share of the cycle counts as late (the
/// simulated KRC's KrcQualityRule::late_fraction, our reading of the KRC's
/// rating: KUKA does not publish its own).
constexpr double kLateShare = 0.8;

/// The share of `answers` (packet index k on the KRC's grid, reply time) sent
/// later than kLateShare of `cycle` after the packet's due time: the grid's
/// origin is the earliest t_reply - k * cycle within kGrid packets either side
/// (the earliest answer marks the grid plus this host's least delay; local,
/// so that the clocks' drift and a sender that re-anchors its grid after a
/// stall, as the simulated KRC does, shift it for at most kGrid packets).
double lateShare(const std::vector<std::pair<double, double>>& answers, double cycle) {
  if (answers.empty() || !(cycle > 0.0)) return 0.0;
  constexpr std::size_t kGrid = 100;
  uint64_t late = 0;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    double origin = 1e300;
    const std::size_t lo = i >= kGrid ? i - kGrid : 0, hi = std::min(answers.size(), i + kGrid);
    for (std::size_t j = lo; j < hi; ++j) origin = std::min(origin, answers[j].second - answers[j].first * cycle);
    if (answers[i].second - (origin + answers[i].first * cycle) > kLateShare * cycle) ++late;
  }
  return double(late) / double(answers.size());
}

/// What the [cycle] item judges (runMonitor's counts).
struct CycleFacts {
  double krc_cycle = 0.0;      ///< the KRC's cycle (s)
  uint64_t sent = 0;           ///< packets the KRC sent (accepted + sequence gaps)
  uint64_t misses = 0;         ///< the KRC's miss counter over the run
  double late_share = 0.0;     ///< lateShare()
  double perfect_share = 0.0;  ///< packets at PERFECT once reached
  bool reached_perfect = false;
};

/// [cycle]: whether this host sustains the KRC's cycle, and which to use.
Item cycleItem(const CycleFacts& f, const MonitorOptions& mo) {
  Item it{"cycle", "[cycle]", Verdict::Pass, "", {}, {}};
  const double miss_share = f.sent ? double(f.misses) / double(f.sent) : 0.0;
  const double cyc_ms = 1e3 * f.krc_cycle;
  it.message = fmt("at the KRC's %.0f ms cycle: %.2f %% of the answers missed (the KRC's miss counter: %llu), "
                   "%.2f %% answered later than %.0f %% of the cycle after the packet was due (this host's clock), "
                   "PERFECT in %.1f %% of the packets once reached (sustained: at most %g %% missed or late, PERFECT "
                   "in %g %%)",
                   cyc_ms, 100 * miss_share, static_cast<unsigned long long>(f.misses), 100 * f.late_share,
                   100 * kLateShare, 100 * f.perfect_share, 100 * mo.max_late_share, 100 * mo.min_perfect_share);
  const bool sustained = f.reached_perfect && miss_share + f.late_share <= mo.max_late_share &&
                         f.perfect_share >= mo.min_perfect_share;
  if (sustained) {
    it.next.push_back(fmt("this PC sustains the %.0f ms cycle: keep friOpen(%.0f) and fri.cycle_time_s %g%s", cyc_ms,
                          cyc_ms, f.krc_cycle, cyc_ms > 1.5 ? "; 1 ms may be sustained too: try friOpen(1)" : ""));
  } else if (cyc_ms > 0.0 && cyc_ms < 1.5) {
    it.verdict = Verdict::Warn;
    it.next.push_back("this PC does not sustain 1 ms: use 2 ms, friOpen(2) in krc/TactileServo.src and "
                      "fri.cycle_time_s: 0.002 in fri.yaml (krc/check_krc_config.py compares them), then run this "
                      "check again (docs/bringup.md)");
  } else {
    it.verdict = Verdict::Fail;
    it.next.push_back(fmt("this PC does not sustain even %.0f ms: a real-time host (scripts/realtime), a dedicated "
                          "NIC on a direct cable, nothing else on this host, before any motion", cyc_ms));
  }
  const char* advice = sustained ? (cyc_ms < 1.5 ? "1ms" : "keep") : (cyc_ms < 1.5 ? "2ms" : "fix_host");
  it.json = {{"krc_cycle_s", fmt("%.6g", f.krc_cycle)}, {"missed", std::to_string(f.misses)},
             {"missed_share", fmt("%.6g", miss_share)},  {"late_share", fmt("%.6g", f.late_share)},
             {"perfect_share", fmt("%.6g", f.perfect_share)}, {"sustained", sustained ? "true" : "false"},
             {"advice", jsonString(advice)}};
  return it;
}

/// One --monitor run: the bridge in dry run on the socket, what it saw
/// (observe), the items judged from it (judge) and the report (report).
struct Monitor {
  Monitor(const MonitorOptions& mo_, const BridgeParams& bp_, const UdpParams& up_)
      : mo(mo_), bp(bp_), up(up_), yaml(mo_.params_file.empty() ? std::string("the defaults") : mo_.params_file) {}

  const MonitorOptions& mo;
  const BridgeParams& bp;
  const UdpParams& up;
  const std::string yaml;  // the parameter file, as the messages name it
  FriBridge bridge;
  UdpSocket sock;
  BridgeOutput out;
  PoseCommand desired;  // never set: status NotConfigured (a second guard: nothing to follow)
  std::vector<double> arrivals;
  uint64_t state_count[3] = {0, 0, 0}, quality_count[4] = {0, 0, 0, 0}, power_off = 0;
  uint64_t status_count[32] = {};
  uint64_t strategy_count[5] = {};  // 0..3, 4 = unknown value
  uint64_t send_errors = 0, truncated = 0;
  double msr_min = 1e9, msr_max = -1e9, cmd_min = 1e9, cmd_max = -1e9;
  std::vector<std::pair<std::string, uint16_t>> peers;  // distinct sender address:port
  bool have_first = false, silent_end = false;
  double t_first = 0.0, t_last_rx = 0.0, t_start = 0.0;
  uint16_t first_seq = 0;
  bool reached_ok = false, dropped_below_ok = false, started_below_ok = false;
  bool reached_perfect = false, have_miss0 = false;
  uint64_t after_perfect = 0, perfect_after = 0;
  uint32_t miss0 = 0;
  std::vector<std::pair<double, double>> answers;  // (packet index on the KRC's grid, reply sent - its arrival)
  Quality worst_after_ok = Quality::Perfect;
  std::vector<std::string> timeline;
  MsrPacket last{};
  std::unique_ptr<FILE, int (*)(FILE*)> rec{nullptr, &std::fclose};
  uint64_t recorded = 0;
  // judge(): the inter-arrival times (sorted) and the items
  double span = 0.0, p50 = 0.0, p99 = 0.0, pmax = 0.0, krc_cycle = 0.0;
  std::vector<double> ia;
  std::vector<Item> items;

  /// The bridge and the socket; the record file. -1, or the exit code.
  int open() {
    if (ConfigResult r = bridge.configure(bp); !r) {
      std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
      return 1;
    }
    bridge.setDryRun(true);  // CMD: hold the pose where CMD was entered, whatever the desired pose
    if (ConfigResult r = sock.open(up); !r) {
      std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
      return 1;
    }
    std::printf("fri_check: listening on %s:%u, monitor mode: never commands motion (MON: the measured pose echoed, "
                "CMD: the pose where CMD was entered held)\n",
                up.bind_address.c_str(), unsigned(sock.localPort()));
    std::printf("fri_check: expected from %s: cycle_time_s %g, krc_port %d%s, control Cartesian impedance; observing "
                "%g s%s\n",
                yaml.c_str(), bp.cycle_time_s, bp.krc_port, bp.krc_port == 0 ? " (any)" : "", mo.seconds,
                mo.cycles > 0 ? fmt(" or %ld packets", mo.cycles).c_str() : "");
    std::fflush(stdout);
    arrivals.reserve(static_cast<std::size_t>(std::min(2e6, 2.0 * mo.seconds / bp.cycle_time_s + 1000.0)));
    t_last_rx = now();
    t_start = t_last_rx;
    answers.reserve(arrivals.capacity());
    if (!mo.record_file.empty()) {
      rec.reset(std::fopen(mo.record_file.c_str(), "w"));
      if (!rec) {
        std::fprintf(stderr, "fri_check: cannot write %s\n", mo.record_file.c_str());
        return 1;
      }
      writeRecordingHeader(rec.get());
    }
    return -1;
  }

  /// No packet within the idle timeout: the report and exit code 2.
  int noKrc() const {
    std::printf("%-13s FAIL  no packet from the KRC within %.1f s on %s:%u\n", "[packets]", mo.idle_timeout,
                up.bind_address.c_str(), unsigned(sock.localPort()));
    std::printf("      next: in the KRC's C:\\KRC\\Roboter\\INIT\\dlrrc.ini, FRIHOST = this host's address on the "
                "cable to the KRC and FRISOCK = %u,0 (krc/dlrrc.ini; reboot the KRC after a change); the KRL "
                "program (krc/TactileServo.src) must have called friOpen; ping both ways; no firewall on UDP "
                "%u\n",
                unsigned(sock.localPort()), unsigned(sock.localPort()));
    std::printf("fri_check: no KRC (exit 2)\n");
    if (!mo.json_file.empty()) {
      if (FILE* f = std::fopen(mo.json_file.c_str(), "w")) {
        std::fprintf(f, "{\n  \"tool\": \"fri_check --monitor\",\n  \"exit_code\": 2,\n  \"result\": \"no_krc\"\n}\n");
        std::fclose(f);
      }
    }
    return 2;
  }

  /// Packets until the time or packet budget, or the KRC falls silent. -1,
  /// or the exit code.
  int observe() {
    static uint8_t buf[2048];
    static uint8_t tx[kCmdPacketSize];
    for (;;) {
      const double t = now();
      if (have_first && t - t_first >= mo.seconds) break;
      if (have_first && mo.cycles > 0 && bridge.stats().accepted > 0 &&
          seqDelta(first_seq, bridge.lastMeasurement().head.send_seq) + 1 >= mo.cycles)
        break;
      std::size_t n = 0;
      const UdpStatus us = sock.receive(buf, sizeof buf, n, 100000);
      const double t_rx = now();
      if (us == UdpStatus::Timeout) {
        if (!have_first && t_rx - t_start > mo.idle_timeout) return noKrc();
        if (have_first && t_rx - t_last_rx > mo.idle_timeout) {
          silent_end = true;
          break;
        }
        continue;
      }
      if (us != UdpStatus::Ok && us != UdpStatus::Truncated) {
        std::fprintf(stderr, "fri_check: receive: %s (errno %d)\n", toString(us), sock.lastErrno());
        return 1;
      }
      t_last_rx = t_rx;
      if (us == UdpStatus::Truncated) ++truncated;
      const sockaddr_in& peer = sock.lastPeer();
      char addr[INET_ADDRSTRLEN] = "?";
      inet_ntop(AF_INET, &peer.sin_addr, addr, sizeof addr);
      const uint16_t peer_port = ntohs(peer.sin_port);
      bool known = false;
      for (const auto& pp : peers) known = known || (pp.first == addr && pp.second == peer_port);
      if (!known) peers.emplace_back(addr, peer_port);
      bridge.notePeerPort(peer_port);
      bridge.stepDatagram(buf, us == UdpStatus::Truncated ? sizeof buf + 1 : n, desired, t_rx, out);
      double t_reply = 0.0;
      if (out.reply) {
        std::size_t w = 0;
        encodeCommand(out.cmd, tx, sizeof tx, w);
        if (sock.reply(tx, w) != UdpStatus::Ok) ++send_errors;
        t_reply = now();
      }
      ++status_count[static_cast<std::size_t>(out.status) & 31u];
      if (out.status == BridgeStatus::Malformed || out.status == BridgeStatus::DroppedDuplicate ||
          out.status == BridgeStatus::DroppedOutOfOrder || out.status == BridgeStatus::NotConfigured)
        continue;
      notePacket(t_rx, t_reply, addr, peer_port);
    }
    return -1;
  }

  /// One accepted measurement (received at t_rx, answered at t_reply) into the counts.
  void notePacket(double t_rx, double t_reply, const char* addr, uint16_t peer_port) {
    const MsrPacket& msr = bridge.lastMeasurement();
    if (!have_miss0) miss0 = msr.intf.stat.miss_counter, have_miss0 = true;
    if (qualityOf(msr) == Quality::Perfect) reached_perfect = true;
    if (reached_perfect) {
      ++after_perfect;
      perfect_after += qualityOf(msr) == Quality::Perfect;
    }
    last = msr;
    if (!have_first) {
      have_first = true;
      t_first = t_rx;
      first_seq = msr.head.send_seq;
    }
    if (rec) writeRecordingLine(rec.get(), t_rx - t_first, msr), ++recorded;
    arrivals.push_back(t_rx);
    if (out.reply) answers.emplace_back(double(seqDelta(first_seq, msr.head.send_seq)), t_reply);
    const State st = stateOf(msr);
    const Quality q = qualityOf(msr);
    ++state_count[static_cast<std::size_t>(st)];
    ++quality_count[static_cast<std::size_t>(q)];
    if (!powerOn(msr)) ++power_off;
    ++strategy_count[msr.robot.control <= 3 ? msr.robot.control : 4];
    msr_min = std::min(msr_min, double(msr.intf.desired_msr_sample_time));
    msr_max = std::max(msr_max, double(msr.intf.desired_msr_sample_time));
    cmd_min = std::min(cmd_min, double(msr.intf.desired_cmd_sample_time));
    cmd_max = std::max(cmd_max, double(msr.intf.desired_cmd_sample_time));
    if (q >= Quality::Ok) reached_ok = true;
    if (!reached_ok) started_below_ok = true;
    if (reached_ok && q < Quality::Ok) {
      dropped_below_ok = true;
      worst_after_ok = std::min(worst_after_ok, q);
    }
    if (out.state_changed) {
      const std::string line =
          fmt("t=%7.3f s  packet %llu: state %s quality %s power 0x%02x control %u (%s), sample times msr %.3f ms "
              "cmd %.3f ms, from %s:%u; bridge %s",
              t_rx - t_first, static_cast<unsigned long long>(bridge.stats().accepted), toString(st), toString(q),
              unsigned(msr.robot.power), unsigned(msr.robot.control), strategyName(msr.robot.control),
              1e3 * double(msr.intf.desired_msr_sample_time), 1e3 * double(msr.intf.desired_cmd_sample_time), addr,
              unsigned(peer_port), toString(out.status));
      timeline.push_back(line);
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    }
  }

  Item& item(const char* key, const char* label) {
    items.push_back(Item{key, label, Verdict::Pass, "", {}, {}});
    return items.back();
  }
  static void worsen(Item& it, Verdict v) {
    if (static_cast<int>(v) > static_cast<int>(it.verdict)) it.verdict = v;
  }

  /// The items, from the counts.
  void judge() {
    // ---- the items
    span = arrivals.size() > 1 ? arrivals.back() - arrivals.front() : 0.0;
    for (std::size_t i = 1; i < arrivals.size(); ++i) ia.push_back(arrivals[i] - arrivals[i - 1]);
    std::sort(ia.begin(), ia.end());
    p50 = percentile(ia, 0.5);
    p99 = percentile(ia, 0.99);
    pmax = ia.empty() ? 0.0 : ia.back();
    krc_cycle = double(last.intf.desired_msr_sample_time);
    packetsItem();
    cycleTimeItem();
    krcPortItem();
    controlItem();
    periodItem();
    jitterItem();
    lossItem();
    orderItem();
    stateItem();
    qualityItem();
    cycleFactsItem();
  }

  /// [packets]: the datagrams, their senders, the end of the stream.
  void packetsItem() {
    const BridgeStats& bs = bridge.stats();
    Item& it = item("packets", "[packets]");
    std::string from;
    for (const auto& pp : peers) from += fmt("%s%s:%u", from.empty() ? "" : ", ", pp.first.c_str(), unsigned(pp.second));
    it.message = fmt("%llu accepted of %llu datagrams in %.3f s from %s; %llu malformed, %llu replies, %llu send errors",
                     static_cast<unsigned long long>(bs.accepted), static_cast<unsigned long long>(bs.received), span,
                     from.c_str(), static_cast<unsigned long long>(bs.malformed),
                     static_cast<unsigned long long>(bs.replies), static_cast<unsigned long long>(send_errors));
    if (bs.malformed > 0 || truncated > 0) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("%llu datagrams were not FRI measurement packets (916 bytes, id 0x2006): another program "
                            "sends to this port, or the KRC's FRI version differs",
                            static_cast<unsigned long long>(bs.malformed + truncated)));
    }
    if (silent_end) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("the KRC stopped sending after %.3f s (silent for %.1f s): friClose in the KRL program, "
                            "an error on the KRC (its message window), or the cable",
                            span, mo.idle_timeout));
    }
    if (send_errors > 0) {
      worsen(it, Verdict::Fail);
      it.next.push_back("replies could not be sent: the socket's buffer or the route to the KRC");
    }
    if (it.verdict == Verdict::Pass) it.next.push_back("the KRC reaches this host; the items below say how well");
    it.json = {{"accepted", std::to_string(bs.accepted)},   {"received", std::to_string(bs.received)},
               {"malformed", std::to_string(bs.malformed)}, {"seconds", fmt("%.4f", span)},
               {"silent_end", silent_end ? "true" : "false"}};
  }

  /// [cycle time]: the KRC's sample times against fri.cycle_time_s.
  void cycleTimeItem() {
    Item& it = item("cycle_time", "[cycle time]");
    constexpr double kTol = 1e-5;  // s: the bridge's tolerance (whole ms as float seconds)
    const bool msr_ok = std::fabs(msr_min - bp.cycle_time_s) <= kTol && std::fabs(msr_max - bp.cycle_time_s) <= kTol;
    const bool cmd_ok = std::fabs(cmd_min - bp.cycle_time_s) <= kTol && std::fabs(cmd_max - bp.cycle_time_s) <= kTol;
    it.message = fmt("the KRC's desiredMsrSampleTime %.3f ms, desiredCmdSampleTime %.3f ms%s; fri.cycle_time_s = "
                     "%g (%.3f ms)",
                     1e3 * msr_max, 1e3 * cmd_max,
                     (msr_min != msr_max || cmd_min != cmd_max) ? " (changed during the run)" : "", bp.cycle_time_s,
                     1e3 * bp.cycle_time_s);
    if (!msr_ok || !cmd_ok) {
      worsen(it, Verdict::Fail);
      const double krc = !msr_ok ? msr_max : cmd_max;
      it.message += fmt("; %llu packets flagged cycle_mismatch by the bridge",
                        static_cast<unsigned long long>(status_count[static_cast<int>(BridgeStatus::CycleMismatch)]));
      it.next.push_back(fmt("the KRC sends every %g ms but %s expects %g ms: call friOpen(%g) in the KRL program or "
                            "set fri.cycle_time_s: %g",
                            1e3 * krc, yaml.c_str(), 1e3 * bp.cycle_time_s, std::round(1e3 * bp.cycle_time_s), krc));
    } else {
      it.next.push_back("friOpen's cycle is the configured one");
    }
    it.json = {{"krc_msr_sample_time_s", fmt("%.6g", msr_max)},
               {"krc_cmd_sample_time_s", fmt("%.6g", cmd_max)},
               {"configured_s", fmt("%.6g", bp.cycle_time_s)}};
  }

  /// [krc port]: the sender's UDP port against fri.udp.krc_port.
  void krcPortItem() {
    Item& it = item("krc_port", "[krc port]");
    const uint16_t port = peers.empty() ? 0 : peers.front().second;
    it.message = fmt("the KRC sends from UDP port %u; fri.udp.krc_port = %d%s", unsigned(port), bp.krc_port,
                     bp.krc_port == 0 ? " (any)" : "");
    if (peers.size() > 1) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("%zu different senders: only the KRC may send to this port; set fri.udp.krc_port to the "
                            "KRC's port and stop the other sender", peers.size()));
    }
    if (bp.krc_port != 0 && port != bp.krc_port) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("the KRC sends from port %u but %s expects %d: set fri.udp.krc_port: %u (or 0: any "
                            "port); if %u is not the KRC, another program sends to this port: stop it",
                            unsigned(port), yaml.c_str(), bp.krc_port, unsigned(port), unsigned(port)));
    } else if (bp.krc_port == 0) {
      it.next.push_back(fmt("fri.udp.krc_port: %u makes the bridge refuse any other sender", unsigned(port)));
    } else {
      it.next.push_back("the configured KRC port");
    }
    it.json = {{"krc_port", std::to_string(port)}, {"configured", std::to_string(bp.krc_port)},
               {"senders", std::to_string(peers.size())}};
  }

  /// [control]: the KRC's control strategy (the bridge needs Cartesian impedance).
  void controlItem() {
    const BridgeStats& bs = bridge.stats();
    Item& it = item("control", "[control]");
    const uint16_t c = last.robot.control;
    uint64_t other = 0;
    for (int k = 0; k < 5; ++k)
      if (k != static_cast<int>(ControlStrategy::CartImpedance)) other += strategy_count[k];
    it.message = fmt("the KRC runs %s (control %u)%s; the bridge commands Cartesian poses (Cartesian impedance, 2)",
                     strategyName(c), unsigned(c), other > 0 && other < bs.accepted ? " (changed during the run)" : "");
    if (other > 0) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("%llu packets in %s: select Cartesian impedance in the KRL program before friStart "
                            "($STIFFNESS.STRATEGY = 20, $STIFFNESS.COMMIT = TRUE, as krc/TactileServo.src); in CMD the bridge would only "
                            "hold the joints (status wrong_strategy)",
                            static_cast<unsigned long long>(other), strategyName(c == 2 ? 0 : c)));
    } else {
      it.next.push_back("the strategy the bridge needs");
    }
    it.json = {{"control", std::to_string(c)}, {"name", jsonString(strategyName(c))}};
  }

  /// [period]: the inter-arrival p50 against the KRC's cycle.
  void periodItem() {
    Item& it = item("period", "[period]");
    it.message = fmt("packets every %.3f ms (p50 of %zu inter-arrival times, this host's clock); the KRC's cycle "
                     "%.3f ms, band +-%.0f %%",
                     1e3 * p50, ia.size(), 1e3 * krc_cycle, 100 * mo.period_tolerance);
    if (ia.empty() || krc_cycle <= 0.0) {
      worsen(it, Verdict::Fail);
      it.next.push_back("too few packets to measure the period: observe longer (--seconds)");
    } else if (std::fabs(p50 / krc_cycle - 1.0) > mo.period_tolerance) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("packets arrive every %.3f ms but the KRC's cycle is %.3f ms: %s", 1e3 * p50,
                            1e3 * krc_cycle,
                            p50 > krc_cycle ? "packets are lost or held up on the way (a switch, a shared NIC) or "
                                              "this host reads late (load, no real-time priority)"
                                            : "more than one sender, or the KRC sends bursts"));
    } else {
      it.next.push_back("the packets come at the KRC's cycle");
    }
    it.json = {{"p50_s", fmt("%.6g", p50)}, {"krc_cycle_s", fmt("%.6g", krc_cycle)},
               {"tolerance", fmt("%g", mo.period_tolerance)}};
  }

  /// [jitter]: the inter-arrival p99 - p50.
  void jitterItem() {
    const double max_jitter_ms = mo.max_jitter_ms >= 0.0 ? mo.max_jitter_ms : 0.5e3 * krc_cycle;
    Item& it = item("jitter", "[jitter]");
    it.message = fmt("inter-arrival p50 %.3f ms, p99 %.3f ms, max %.3f ms; p99 - p50 = %.3f ms (limit %.3f ms)",
                     1e3 * p50, 1e3 * p99, 1e3 * pmax, 1e3 * (p99 - p50), max_jitter_ms);
    if (!ia.empty() && 1e3 * (p99 - p50) > max_jitter_ms) {
      worsen(it, Verdict::Fail);
      it.next.push_back("this host or the network delays packets: run the bridge on the real-time host "
                        "(PREEMPT_RT or Xenomai, SCHED_FIFO), a dedicated NIC on a direct cable to the KRC, no power "
                        "saving (C-states), interrupt coalescing off on that NIC");
    } else {
      it.next.push_back("the arrival times are regular enough");
    }
    it.json = {{"p50_s", fmt("%.6g", p50)}, {"p99_s", fmt("%.6g", p99)}, {"max_s", fmt("%.6g", pmax)},
               {"limit_ms", fmt("%g", max_jitter_ms)}};
  }

  /// [loss]: sequence gaps.
  void lossItem() {
    const BridgeStats& bs = bridge.stats();
    Item& it = item("loss", "[loss]");
    const uint64_t sent = bs.accepted + bs.lost;
    const double rate = sent ? double(bs.lost) / double(sent) : 0.0;
    it.message = fmt("%llu lost of %llu the KRC sent (sequence gaps, %.2f %%; limit %.2f %%)",
                     static_cast<unsigned long long>(bs.lost), static_cast<unsigned long long>(sent), 100 * rate,
                     100 * mo.max_loss_rate);
    if (rate > mo.max_loss_rate) {
      worsen(it, Verdict::Fail);
      it.next.push_back("measurement packets are lost between the KRC and this host: a direct cable (no switch), "
                        "a dedicated NIC, a larger socket receive buffer; the KRC's quality drops with them");
    } else {
      it.next.push_back("no loss beyond the limit");
    }
    it.json = {{"lost", std::to_string(bs.lost)}, {"sent", std::to_string(sent)}, {"rate", fmt("%.6g", rate)},
               {"limit", fmt("%g", mo.max_loss_rate)}};
  }

  /// [order]: duplicates, reordering, restarts.
  void orderItem() {
    const BridgeStats& bs = bridge.stats();
    Item& it = item("order", "[order]");
    it.message = fmt("%llu duplicates, %llu out of order, %llu sequence restarts",
                     static_cast<unsigned long long>(bs.duplicates), static_cast<unsigned long long>(bs.out_of_order),
                     static_cast<unsigned long long>(bs.resyncs));
    if (bs.duplicates + bs.out_of_order > 0) {
      worsen(it, Verdict::Fail);
      it.next.push_back("a KRC sends each packet once, in order: a second sender on this port, or a network that "
                        "duplicates/reorders (a switch or bridge in the path)");
    } else {
      it.next.push_back("in order, once each");
    }
    it.json = {{"duplicates", std::to_string(bs.duplicates)}, {"out_of_order", std::to_string(bs.out_of_order)}};
  }

  /// [state]: MON / CMD / OFF and the drives.
  void stateItem() {
    const BridgeStats& bs = bridge.stats();
    Item& it = item("state", "[state]");
    const double tot = std::max<double>(1.0, double(bs.accepted));
    it.message = fmt("MON %.1f %%, CMD %.1f %%, OFF %.1f %% of the packets; drives off in %.1f %%; last %s",
                     100 * double(state_count[1]) / tot, 100 * double(state_count[2]) / tot, 100 * double(state_count[0]) / tot,
                     100 * double(power_off) / tot, toString(stateOf(last)));
    if (state_count[2] > 0)
      it.message += fmt("; in CMD the bridge held the entry pose (%llu dry_run, %llu other holds)",
                        static_cast<unsigned long long>(status_count[static_cast<int>(BridgeStatus::DryRun)]),
                        static_cast<unsigned long long>(state_count[2] -
                                                        status_count[static_cast<int>(BridgeStatus::DryRun)]));
    if (power_off > 0) {
      worsen(it, Verdict::Warn);
      it.next.push_back("the drives were off: switch them on (the KRC's enabling switch) before friStart");
    }
    it.next.push_back(state_count[2] > 0 ? "CMD works: the servo can run (without --monitor the bridge follows it)"
                                         : "MON: friStart in the KRL program (krc/TactileServo.src) switches to CMD once the servo runs");
    it.json = {{"mon", std::to_string(state_count[1])}, {"cmd", std::to_string(state_count[2])},
               {"off", std::to_string(state_count[0])}, {"power_off", std::to_string(power_off)}};
  }

  /// [quality]: the KRC's rating of the link.
  void qualityItem() {
    const BridgeStats& bs = bridge.stats();
    Item& it = item("quality", "[quality]");
    const double tot = std::max<double>(1.0, double(bs.accepted));
    it.message = fmt("PERFECT %.1f %%, OK %.1f %%, BAD %.1f %%, UNACCEPTABLE %.1f %% of the packets; last %s; the "
                     "KRC's statistics: answer rate %.3f, latency %.3f ms, jitter %.3f ms, %u misses",
                     100 * double(quality_count[3]) / tot, 100 * double(quality_count[2]) / tot, 100 * double(quality_count[1]) / tot,
                     100 * double(quality_count[0]) / tot, toString(qualityOf(last)), double(last.intf.stat.answer_rate),
                     1e3 * double(last.intf.stat.latency), 1e3 * double(last.intf.stat.jitter),
                     unsigned(last.intf.stat.miss_counter));
    if (qualityOf(last) < Quality::Ok || (dropped_below_ok && !mo.quality_drop_warns)) {
      worsen(it, Verdict::Fail);
      it.next.push_back(fmt("the quality %s %s: the KRC misses or gets late answers: the jitter and loss items; a "
                            "real-time host; nothing else on the FRI NIC",
                            dropped_below_ok ? "dropped to" : "is",
                            toString(dropped_below_ok ? worst_after_ok : qualityOf(last))));
    } else if (dropped_below_ok) {
      worsen(it, Verdict::Warn);
      it.next.push_back(fmt("the quality dropped to %s and recovered (a WARN by --quality-drop warn): the KRC missed "
                            "or got late answers for a while; [cycle] says whether the link is sustained",
                            toString(worst_after_ok)));
    } else if (started_below_ok) {
      worsen(it, Verdict::Warn);
      it.next.push_back("the quality was below OK at first and rose: the KRC rates the link once answers arrive; "
                        "wait for PERFECT before friStart");
    } else {
      it.next.push_back("the KRC rates the link OK or better throughout");
    }
    it.json = {{"perfect", std::to_string(quality_count[3])}, {"ok", std::to_string(quality_count[2])},
               {"bad", std::to_string(quality_count[1])}, {"unacceptable", std::to_string(quality_count[0])},
               {"last", jsonString(toString(qualityOf(last)))}};
  }

  /// [cycle]: cycleItem() on this run's counts.
  void cycleFactsItem() {
    const BridgeStats& bs = bridge.stats();
    CycleFacts cf;
    cf.krc_cycle = krc_cycle;
    cf.sent = bs.accepted + bs.lost;
    cf.misses = have_miss0 && last.intf.stat.miss_counter >= miss0 ? last.intf.stat.miss_counter - miss0 : 0;
    cf.late_share = lateShare(answers, krc_cycle);
    cf.perfect_share = after_perfect ? double(perfect_after) / double(after_perfect) : 0.0;
    cf.reached_perfect = reached_perfect;
    items.push_back(cycleItem(cf, mo));
  }

  /// The items on stdout (and --json); the exit code: 3 when an item failed.
  int report() const {
    int code = 0;
    for (const Item& it : items) {
      std::printf("%-13s %s  %s\n", it.label.c_str(), toString(it.verdict), it.message.c_str());
      for (const std::string& nx : it.next) std::printf("      next: %s\n", nx.c_str());
      if (it.verdict == Verdict::Fail) code = 3;
    }
    if (rec)
      std::printf("fri_check: %llu measurements recorded in %s (for fri_check --wrench-check / --load-data; the timing "
                  "items do not matter there)\n",
                  static_cast<unsigned long long>(recorded), mo.record_file.c_str());
    std::printf("fri_check: %s (exit %d)\n", code == 0 ? "every item passed" : "an item failed", code);
    if (!mo.json_file.empty()) {
      FILE* f = std::fopen(mo.json_file.c_str(), "w");
      if (f == nullptr) {
        std::fprintf(stderr, "fri_check: cannot write %s\n", mo.json_file.c_str());
        return code == 0 ? 1 : code;
      }
      std::fprintf(f, "{\n  \"tool\": \"fri_check --monitor\",\n  \"exit_code\": %d,\n  \"result\": %s", code,
                   code == 0 ? "\"pass\"" : "\"fail\"");
      for (const Item& it : items) {
        std::string next = "[";
        for (std::size_t i = 0; i < it.next.size(); ++i) next += (i ? ", " : "") + jsonString(it.next[i]);
        std::fprintf(f, ",\n  %s: {\"verdict\": %s, \"message\": %s, \"next\": %s]", jsonString(it.key).c_str(),
                     jsonString(toString(it.verdict)).c_str(), jsonString(it.message).c_str(), next.c_str());
        for (const auto& kv : it.json) std::fprintf(f, ", %s: %s", jsonString(kv.first).c_str(), kv.second.c_str());
        std::fprintf(f, "}");
      }
      std::string tl = "[";
      for (std::size_t i = 0; i < timeline.size(); ++i) tl += (i ? ", " : "") + jsonString(timeline[i]);
      std::fprintf(f, ",\n  \"timeline\": %s]\n}\n", tl.c_str());
      std::fclose(f);
    }
    return code;
  }
};

int runMonitor(const MonitorOptions& mo, const BridgeParams& bp, const UdpParams& up) {
  Monitor m(mo, bp, up);
  if (int code = m.open(); code >= 0) return code;
  if (int code = m.observe(); code >= 0) return code;
  m.judge();
  return m.report();
}

/// fri_check's command line (parseArgs).
struct CheckArgs {
  long port = -1;
  long cycles = 1000;
  std::string motion = "hold";
  UdpParams up;
  BridgeParams bp;
  double radius = 0.01, circle_period = 10.0, idle_timeout = 10.0;
  bool monitor = false, motion_given = false, cycles_given = false, offset_given = false;
  CartOffset check_offset = CartOffset::None;
  MonitorOptions mo;
};

/// The parameter file (--params), then the options over it, into `args`.
/// -1, or the exit code (a bad option: usage()'s).
int parseArgs(int argc, char** argv, CheckArgs& args) {
  long& port = args.port;
  long& cycles = args.cycles;
  std::string& motion = args.motion;
  UdpParams& up = args.up;
  BridgeParams& bp = args.bp;
  double &radius = args.radius, &circle_period = args.circle_period, &idle_timeout = args.idle_timeout;
  bool &monitor = args.monitor, &motion_given = args.motion_given, &cycles_given = args.cycles_given,
       &offset_given = args.offset_given;
  CartOffset& check_offset = args.check_offset;
  MonitorOptions& mo = args.mo;
  for (int i = 1; i + 1 < argc; ++i) {  // the parameter file first, so that options override it
    if (std::string(argv[i]) == "--params") {
      if (ConfigResult r = loadBridgeParamsFile(argv[i + 1], bp, up); !r) {
        std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
        return 1;
      }
    }
  }
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    double v = 0.0;
    if (a == "--port" && has) {
      char* end = nullptr;
      port = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || port < 0 || port > 65535) return usage("--port must be in [0, 65535]");
    } else if (a == "--cycles" && has) {
      char* end = nullptr;
      cycles = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || cycles < 1) return usage("--cycles must be >= 1");
      cycles_given = true;
    } else if (a == "--motion" && has) {
      motion = argv[++i];
      if (motion != "hold" && motion != "circle") return usage("--motion must be hold or circle");
      motion_given = true;
    } else if (a == "--params" && has) {
      mo.params_file = argv[++i];  // loaded above
    } else if (a == "--monitor") {
      monitor = true;
    } else if (a == "--seconds" && has) {
      if (!parseDouble(argv[++i], mo.seconds) || mo.seconds <= 0.0 || mo.seconds > 86400.0)
        return usage("--seconds must be in (0, 86400]");
    } else if (a == "--period-tolerance" && has) {
      if (!parseDouble(argv[++i], mo.period_tolerance) || mo.period_tolerance <= 0.0 || mo.period_tolerance > 10.0)
        return usage("--period-tolerance must be in (0, 10]");
    } else if (a == "--max-jitter-ms" && has) {
      if (!parseDouble(argv[++i], mo.max_jitter_ms) || mo.max_jitter_ms < 0.0) return usage("--max-jitter-ms must be >= 0");
    } else if (a == "--max-late-share" && has) {
      if (!parseDouble(argv[++i], mo.max_late_share) || mo.max_late_share < 0.0 || mo.max_late_share > 1.0)
        return usage("--max-late-share must be in [0, 1]");
    } else if (a == "--min-perfect-share" && has) {
      if (!parseDouble(argv[++i], mo.min_perfect_share) || mo.min_perfect_share < 0.0 || mo.min_perfect_share > 1.0)
        return usage("--min-perfect-share must be in [0, 1]");
    } else if (a == "--quality-drop" && has) {
      const std::string mode = argv[++i];
      if (mode != "fail" && mode != "warn") return usage("--quality-drop must be fail or warn");
      mo.quality_drop_warns = mode == "warn";
    } else if (a == "--max-loss-rate" && has) {
      if (!parseDouble(argv[++i], mo.max_loss_rate) || mo.max_loss_rate < 0.0 || mo.max_loss_rate > 1.0)
        return usage("--max-loss-rate must be in [0, 1]");
    } else if (a == "--json" && has) {
      mo.json_file = argv[++i];
    } else if (a == "--record" && has) {
      mo.record_file = argv[++i];
    } else if (a == "--bind" && has) {
      up.bind_address = argv[++i];
    } else if (a == "--radius" && has) {
      if (!parseDouble(argv[++i], radius) || radius < 0.0 || radius > 0.05) return usage("--radius must be in [0, 0.05] m");
    } else if (a == "--circle-period" && has) {
      if (!parseDouble(argv[++i], circle_period) || circle_period < 1.0) return usage("--circle-period must be >= 1 s");
    } else if (a == "--max-lin-speed" && has) {
      if (!parseDouble(argv[++i], v)) return usage("--max-lin-speed needs a number");
      bp.max_lin_speed = v;
    } else if (a == "--max-rot-speed" && has) {
      if (!parseDouble(argv[++i], v)) return usage("--max-rot-speed needs a number");
      bp.max_rot_speed = v;
    } else if (a == "--cart-offset" && has) {
      if (!parseCartOffset(argv[++i], check_offset)) return usage("--cart-offset must be none, composed or elementwise");
      offset_given = true;
    } else if (a == "--idle-timeout" && has) {
      if (!parseDouble(argv[++i], idle_timeout) || idle_timeout <= 0.0) return usage("--idle-timeout must be > 0 s");
    } else {
      return usage(("unknown or incomplete argument '" + a + "'").c_str());
    }
  }
  return -1;
}

/// The motion check: the bridge on the socket following a held or circling
/// pose (open, run), then its statistics (summary).
struct MotionCheck {
  explicit MotionCheck(const CheckArgs& a)
      : motion(a.motion), cycles(a.cycles), radius(a.radius), circle_period(a.circle_period),
        idle_timeout(a.idle_timeout), bp(a.bp), up(a.up) {}

  const std::string& motion;
  const long cycles;
  const double radius, circle_period, idle_timeout;
  const BridgeParams& bp;
  const UdpParams& up;
  FriBridge bridge;
  UdpSocket sock;
  BridgeOutput out;
  PoseCommand desired;
  KDL::Frame anchor = KDL::Frame::Identity();
  bool have_anchor = false;
  OffsetProbe probe;
  bool saw_offset_mismatch = false;
  KDL::Frame last_sent = KDL::Frame::Identity();
  uint16_t last_sent_seq = 0;
  bool last_sent_taken = false;  // the last reply went out in CMD at quality >= OK (the KRC applies it)  // the desired pose starts where the robot is (the bridge's start gate)
  bool in_cmd = false;
  uint64_t cmd_cycles = 0;
  RunningStat processing_us, period_ms;
  double last_arrival = 0.0, last_packet_time = 0.0;
  uint64_t timeouts = 0, send_errors = 0, truncated = 0, status_changes = 0;
  BridgeStatus last_status = BridgeStatus::NotConfigured;
  float krc_latency = 0.0f, krc_answer_rate = 0.0f;
  uint32_t krc_miss = 0;

  /// The bridge and the socket. -1, or the exit code.
  int open() {
    if (ConfigResult r = bridge.configure(bp); !r) {
      std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
      return 1;
    }
    if (ConfigResult r = sock.open(up); !r) {
      std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
      return 1;
    }
    std::printf("fri_check: listening on %s:%u, motion %s, %ld cycles, cart_offset %s\n", up.bind_address.c_str(),
                unsigned(sock.localPort()), motion.c_str(), cycles, toString(bp.cart_offset));
    std::fflush(stdout);
    desired.status = ServoStatus::Ok;
    last_packet_time = now();
    return -1;
  }

  // The desired pose: hold the CMD entry pose, or a circle around it.
  // Motion time base: CMD cycles times the KRC's command period (from the
  // previous packet), so the motion is smooth whatever the host's timing.
  void setDesired(double t_rx) {
    const double krc_T = double(bridge.lastMeasurement().intf.desired_cmd_sample_time);
    const double T = (krc_T > 0.0 && krc_T <= 0.1) ? krc_T : bp.cycle_time_s;
    const double tc = static_cast<double>(cmd_cycles) * T;
    KDL::Frame target = anchor;
    if (motion == "circle") {
      const double ramp = tc < 2.0 ? 0.5 * (1.0 - std::cos(kPi * tc / 2.0)) : 1.0;  // smooth 2 s radius ramp
      const double w = 2.0 * kPi / circle_period;
      target.p = anchor.p + KDL::Vector(ramp * radius * (std::cos(w * tc) - 1.0), ramp * radius * std::sin(w * tc), 0.0);
    }
    toPose(target, desired.pose);
    desired.time_s = t_rx;
  }

  /// One accepted measurement (received at t_rx, answered at t_tx): timing,
  /// the offset probe, the CMD anchor, and the state changes on stdout.
  void notePacket(double t_rx, double t_tx) {
    processing_us.add((t_tx - t_rx) * 1e6);
    if (last_arrival > 0.0) period_ms.add((t_rx - last_arrival) * 1e3);
    last_arrival = t_rx;
    const MsrPacket& msr = bridge.lastMeasurement();
    krc_latency = msr.intf.stat.latency;
    krc_answer_rate = msr.intf.stat.answer_rate;
    krc_miss = msr.intf.stat.miss_counter;

    const bool cmd_now = out.state == State::Cmd && powerOn(msr);
    // The KRC's set point is the command it took last (when it was applied).
    if (cmd_now && out.quality >= Quality::Ok && last_sent_taken && msr.head.refl_seq == last_sent_seq && have_anchor)
      probe.add(msr, last_sent, anchor);
    last_sent_taken = out.reply && cmd_now && out.quality >= Quality::Ok;
    if (out.reply) {
      last_sent = out.commanded;
      last_sent_seq = out.cmd.head.send_seq;
    }
    if ((!cmd_now || !have_anchor) && out.reply) {
      // outside CMD (or the KRC came up in CMD): the echoed/held measured pose; CMD starts from it
      anchor = out.commanded;
      have_anchor = true;
      cmd_cycles = 0;
    }
    in_cmd = cmd_now;
    if (in_cmd && out.quality >= Quality::Ok) ++cmd_cycles;

    if (out.state_changed) {
      std::printf("cycle %llu: state %s quality %s power 0x%02x control %u\n",
                  static_cast<unsigned long long>(bridge.stats().accepted), toString(out.state),
                  toString(out.quality), unsigned(msr.robot.power), unsigned(msr.robot.control));
    }
    if (out.status == BridgeStatus::OffsetMismatch) saw_offset_mismatch = true;
    if (out.status != last_status) {
      ++status_changes;
      std::printf("cycle %llu: bridge %s\n", static_cast<unsigned long long>(bridge.stats().accepted),
                  toString(out.status));
      last_status = out.status;
    }
    if (out.lost_before > 0) {
      std::printf("cycle %llu: %u packet(s) lost\n", static_cast<unsigned long long>(bridge.stats().accepted),
                  unsigned(out.lost_before));
    }
  }

  /// Packets until `cycles` were accepted; the exit code (no packet for
  /// idle_timeout: 2, a socket error: 1).
  int run() {
    static uint8_t buf[2048];
    static uint8_t tx[kCmdPacketSize];
    int exit_code = 0;
    while (bridge.stats().accepted < static_cast<uint64_t>(cycles)) {
      std::size_t n = 0;
      const UdpStatus us = sock.receive(buf, sizeof buf, n, 100000);
      const double t_rx = now();
      if (us == UdpStatus::Timeout) {
        ++timeouts;
        if (t_rx - last_packet_time > idle_timeout) {
          std::fprintf(stderr, "fri_check: no packet for %.1f s, giving up\n", idle_timeout);
          exit_code = 2;
          break;
        }
        continue;
      }
      if (us != UdpStatus::Ok && us != UdpStatus::Truncated) {
        std::fprintf(stderr, "fri_check: receive: %s (errno %d)\n", toString(us), sock.lastErrno());
        exit_code = 1;
        break;
      }
      last_packet_time = t_rx;
      if (us == UdpStatus::Truncated) ++truncated;

      setDesired(t_rx);

      bridge.stepDatagram(buf, us == UdpStatus::Truncated ? sizeof buf + 1 : n, desired, t_rx, out);
      if (out.reply) {
        std::size_t w = 0;
        encodeCommand(out.cmd, tx, sizeof tx, w);
        if (sock.reply(tx, w) != UdpStatus::Ok) ++send_errors;
      }
      const double t_tx = now();

      if (out.status == BridgeStatus::Malformed) {
        std::printf("cycle %llu: malformed datagram (%zu bytes): %s\n",
                    static_cast<unsigned long long>(bridge.stats().accepted), n, toString(out.packet_status));
        continue;
      }
      if (out.status == BridgeStatus::DroppedDuplicate || out.status == BridgeStatus::DroppedOutOfOrder) continue;

      notePacket(t_rx, t_tx);
    }
    return exit_code;
  }

  void summary() {
    const BridgeStats& s = bridge.stats();
    char peer[INET_ADDRSTRLEN] = "-";
    if (sock.hasPeer()) inet_ntop(AF_INET, &sock.lastPeer().sin_addr, peer, sizeof peer);
    std::printf("summary: cycles %llu received %llu replies %llu lost %llu duplicates %llu out_of_order %llu "
                "malformed %llu truncated %llu resyncs %llu limited %llu holds %llu send_errors %llu timeouts %llu peer %s\n",
                static_cast<unsigned long long>(s.accepted), static_cast<unsigned long long>(s.received),
                static_cast<unsigned long long>(s.replies), static_cast<unsigned long long>(s.lost),
                static_cast<unsigned long long>(s.duplicates), static_cast<unsigned long long>(s.out_of_order),
                static_cast<unsigned long long>(s.malformed), static_cast<unsigned long long>(truncated),
                static_cast<unsigned long long>(s.resyncs), static_cast<unsigned long long>(s.limited),
                static_cast<unsigned long long>(s.holds), static_cast<unsigned long long>(send_errors),
                static_cast<unsigned long long>(timeouts), peer);
    probe.report(bp.cart_offset, saw_offset_mismatch);
    std::printf("latency: processing mean %.1f us max %.1f us; inter-arrival mean %.3f ms sd %.3f ms max %.3f ms; "
                "KRC-reported latency %.6f s answer_rate %.3f miss_counter %u\n",
                processing_us.mean(), processing_us.max, period_ms.mean(), period_ms.stddev(), period_ms.max,
                double(krc_latency), double(krc_answer_rate), krc_miss);
  }
};

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {  // the offline wrench checks
    if (std::string(argv[i]) == "--wrench-check") return runWrenchCheck(argc, argv);
    if (std::string(argv[i]) == "--load-data") return runLoadData(argc, argv);
  }
  CheckArgs args;
  if (int code = parseArgs(argc, argv, args); code >= 0) return code;
  const long port = args.port, cycles = args.cycles;
  UdpParams& up = args.up;
  const bool monitor = args.monitor, motion_given = args.motion_given, cycles_given = args.cycles_given,
             offset_given = args.offset_given;
  const double idle_timeout = args.idle_timeout;
  const BridgeParams& bp = args.bp;
  MonitorOptions& mo = args.mo;
  bool have_params = false;
  for (int i = 1; i < argc; ++i) have_params = have_params || std::string(argv[i]) == "--params";
  if (port < 0 && !have_params) return usage("--port (or --params FILE with fri.udp.port) is required");
  if (port >= 0) up.port = static_cast<uint16_t>(port);
  if (offset_given && monitor) return usage("--cart-offset is for the motion check (monitor mode reads fri.yaml's)");
  if (!mo.record_file.empty() && !monitor) return usage("--record is for --monitor (the arm held, never commanded)");
  if (monitor) {
    if (motion_given) return usage("--monitor never commands motion: no --motion");
    mo.cycles = cycles_given ? cycles : 0;
    mo.idle_timeout = idle_timeout;
    return runMonitor(mo, bp, up);
  }

  args.bp.cart_offset = args.check_offset;
  MotionCheck check(args);
  if (int code = check.open(); code >= 0) return code;
  const int exit_code = check.run();
  check.summary();
  return exit_code;
}
