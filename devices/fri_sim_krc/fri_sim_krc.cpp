// fri_sim_krc --port P [--cycles N] [--period-ms T] [--fast] [--schedule SPEC] [faults]
//
// A simulated KUKA KRC on loopback: sends FRI measurement packets to
// 127.0.0.1:P (never anywhere else), backed by a first-order plant, and checks
// the replies. Prints its statistics at the end; exit status 0 when no
// protocol violation (MON echo, sequence, flags, non-finite command) was seen.
//
//   --schedule SPEC   comma-separated CYCLE:STATE:QUALITY[:POWER] events,
//                     e.g. 0:MON:PERFECT,200:CMD:PERFECT,800:CMD:BAD,900:MON:OK
//   --loss p --dup p --reorder p --late p --wrong-size p --wrong-id p --cmd-loss p --seed S
//   --burst CYCLE:N   the measurements of cycles CYCLE .. CYCLE+N-1 are not sent (a burst of N lost packets)
//   --local-port P    send from 127.0.0.1:P (the KRC's FRI init file's local port; default ephemeral)
//   --control S       the control strategy the KRC reports: cart (Cartesian impedance, default),
//                     joint (joint impedance), position, other
//   --cart-offset F   the form of cmdCartPos / cmdCartPosFriOffset the KRC sends: none (cmdCartPos
//                     is the set point, default), composed (cmdCartPos * offset as frames) or
//                     elementwise (cmdCartPos + offset over the 12 entries)
//   --msr-sample-ms T --cmd-sample-ms T
//                     the sample times the KRC advertises (desiredMsr/CmdSampleTime; default
//                     --period-ms): a KRC whose advertised cycle disagrees with its real one
//   --wrench FX,FY,FZ the constant external force the KRC reports in estExtTcpFT (N, {g}; default 0:
//                     nothing touches the arm). A bench run whose simulated pad is pressed sets the
//                     force that press would put on the arm, so the servo's sensor checks see
//                     two sensors that agree (docs/design.md, "The sensors against each other")
//   --wrench-tool FX,FY,FZ  the same force in the flange's {e} axes (it turns with the arm)
//   --quality-rule on|off  on: the KRC rates the link from the answers (KrcQualityRule: missed,
//                     or later than 80 % of the cycle, over the last 100 cycles), reports the lower
//                     of that and the schedule's quality, leaves command mode below OK and enters
//                     it only at PERFECT; off (default): the schedule alone
//   --krl FILE        the KRL program this KRC runs (krc/TactileServo.src and the .dat beside
//                     it): its $STIFFNESS.FRAMETYPE gives the axes of estExtTcpFT (#BASE: base,
//                     #TOOL: the flange's), its $LOAD the load the KRC compensates, its
//                     $STIFFNESS.MAXFORCE / CPMAXDELTA the limits beyond which the KRC stops the
//                     arm in command mode (default: base axes, the load of --pad-load, no limits)
//   --wrench-frame F  base | tool: the axes of estExtTcpFT, overriding --krl's (a KRC whose
//                     $STIFFNESS says otherwise than the bridge's fri.wrench_frame)
//   --pad-load M,CX,CY,CZ  the pad's true mass (kg) and centre of mass (mm, flange axes); the
//                     difference to the load --krl names is reported as an external wrench
//                     that turns with the arm (default: the load --krl names, nothing left)
//   --pose X,Y,Z,A,B,C the arm's start pose as the pendant shows it (mm; deg, A about z, B
//                     about y, C about x; default 500,0,400,0,0,180: the flange pointing down)
//   --fast            do not sleep; wait for each reply up to --reply-timeout-ms (default 100)
//   --latency-out F   write one line per cycle to F: "LATENCY_US ON_TIME", the
//                     reply latency in us (measurement sent -> its reply
//                     received, also when the reply came after the next tick
//                     and was ignored as stale: ON_TIME 0), or "nan 0" when
//                     no reply came (scripts/realtime/rt_latency.sh)
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "tactile_fri/krl_settings.hpp"
#include "tactile_fri/sim_krc.hpp"

using namespace tactile::fri;

namespace {
int usage(const std::string& msg) {
  std::fprintf(stderr,
               "fri_sim_krc: %s\nusage: fri_sim_krc --port P [--cycles N] [--period-ms T] [--fast] "
               "[--reply-timeout-ms T] [--latency-out FILE] [--schedule C:STATE:QUALITY[:POWER],...] [--loss p] [--dup p] [--reorder p] "
               "[--late p] [--wrong-size p] [--wrong-id p] [--cmd-loss p] [--seed S] [--burst CYCLE:N] [--local-port P] "
               "[--control cart|joint|position|other] [--cart-offset none|composed|elementwise] [--msr-sample-ms T] [--cmd-sample-ms T]\n"
               "       [--quality-rule on|off] [--wrench FX,FY,FZ | --wrench-tool FX,FY,FZ] [--krl FILE] "
               "[--wrench-frame base|tool] [--pad-load M,CX,CY,CZ] [--pose X,Y,Z,A,B,C]\n",
               msg.c_str());
  return 1;
}
/// --wrench FX,FY,FZ: three finite forces of at most 1000 N.
bool parseWrench(const char* s, std::array<double, 6>& w) {
  double f[3];
  char tail = 0;
  if (std::sscanf(s, "%lf,%lf,%lf%c", &f[0], &f[1], &f[2], &tail) != 3) return false;
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(f[i]) || std::fabs(f[i]) > 1000.0) return false;
    w[static_cast<std::size_t>(i)] = f[i];
  }
  return true;
}
/// N comma-separated finite numbers.
template <std::size_t N>
bool parseNumbers(const char* s, std::array<double, N>& v) {
  std::string rest = s;
  for (std::size_t i = 0; i < N; ++i) {
    char* end = nullptr;
    v[i] = std::strtod(rest.c_str(), &end);
    if (end == rest.c_str() || !std::isfinite(v[i])) return false;
    const char next = *end;
    if ((i + 1 < N && next != ',') || (i + 1 == N && next != '\0')) return false;
    rest = std::string(end + (i + 1 < N ? 1 : 0));
  }
  return true;
}
/// --control cart|joint|position|other.
bool parseControl(const std::string& c, ControlStrategy& out) {
  if (c == "cart") out = ControlStrategy::CartImpedance;
  else if (c == "joint") out = ControlStrategy::JointImpedance;
  else if (c == "position") out = ControlStrategy::Position;
  else if (c == "other") out = ControlStrategy::Other;
  else return false;
  return true;
}

/// --pose X,Y,Z,A,B,C as the pendant shows it (mm within 2000 of the base; deg,
/// A about z, B about y, C about x).
bool parsePose(const char* s, KDL::Frame& pose) {
  std::array<double, 6> x{};
  if (!parseNumbers(s, x) || std::fabs(x[0]) > 2000 || std::fabs(x[1]) > 2000 || std::fabs(x[2]) > 2000) return false;
  const double d = 3.14159265358979323846 / 180.0;
  pose = KDL::Frame(KDL::Rotation::RPY(x[5] * d, x[4] * d, x[3] * d), KDL::Vector(x[0] * 1e-3, x[1] * 1e-3, x[2] * 1e-3));
  return true;
}

/// --schedule SPEC: comma-separated CYCLE:STATE:QUALITY[:POWER] events into p.schedule.
/// 0, or usage()'s exit code.
int parseSchedule(const std::string& spec, SimKrcParams& p) {
  std::size_t pos = 0;
  while (pos <= spec.size()) {
    const std::size_t comma = spec.find(',', pos);
    const std::string ev = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    StateEvent e;
    char st[16] = {0}, q[16] = {0};
    unsigned long long c = 0;
    unsigned pw = 0x7F;
    const int got = std::sscanf(ev.c_str(), "%llu:%15[A-Z]:%15[A-Z]:%x", &c, st, q, &pw);
    if (got < 3 || !parseState(st, e.state) || !parseQuality(q, e.quality) || pw > 0xFFFF)
      return usage("bad --schedule event '" + ev + "' (CYCLE:OFF|MON|CMD:UNACCEPTABLE|BAD|OK|PERFECT[:POWERHEX])");
    e.cycle = c;
    e.power = static_cast<uint16_t>(pw);
    p.schedule.push_back(e);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return 0;
}

/// The command line's settings (parseArgs).
struct Cli {
  SimKrcParams p;
  long port = -1;
  unsigned long long cycles = 1000;
  std::string latency_out;
  std::array<double, 6> wrench{};
  bool wrench_tool = false;
  KrlSettings krl;
  bool have_krl = false, have_pad = false, have_frame = false;
  WrenchFrame frame = WrenchFrame::Base;
  std::array<double, 4> pad{};
};

/// The command line into `cli`: 0, or usage()'s exit code.
int parseArgs(int argc, char** argv, Cli& cli) {
  SimKrcParams& p = cli.p;
  long& port = cli.port;
  unsigned long long& cycles = cli.cycles;
  std::string& latency_out = cli.latency_out;
  std::array<double, 6>& wrench = cli.wrench;
  bool& wrench_tool = cli.wrench_tool;
  KrlSettings& krl = cli.krl;
  bool &have_krl = cli.have_krl, &have_pad = cli.have_pad, &have_frame = cli.have_frame;
  WrenchFrame& frame = cli.frame;
  std::array<double, 4>& pad = cli.pad;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    auto num = [&](double lo, double hi, double& v) {
      char* end = nullptr;
      v = std::strtod(argv[++i], &end);
      return *end == '\0' && std::isfinite(v) && v >= lo && v <= hi;
    };
    double v = 0.0;
    if (a == "--port" && has) {
      if (!num(1, 65535, v)) return usage("--port must be in [1, 65535]");
      port = long(v);
    } else if (a == "--cycles" && has) {
      if (!num(1, 1e12, v)) return usage("--cycles must be >= 1");
      cycles = static_cast<unsigned long long>(v);
    } else if (a == "--period-ms" && has) {
      if (!num(0.01, 100, v)) return usage("--period-ms must be in [0.01, 100]");
      p.period_s = v * 1e-3;
    } else if (a == "--reply-timeout-ms" && has) {
      if (!num(0, 1000, v)) return usage("--reply-timeout-ms must be in [0, 1000]");
      p.reply_timeout_s = v * 1e-3;
    } else if (a == "--latency-out" && has) {
      latency_out = argv[++i];
    } else if (a == "--fast") {
      p.real_time = false;
      p.reply_timeout_s = 0.1;
    } else if (a == "--seed" && has) {
      if (!num(0, 4294967295.0, v)) return usage("--seed must be a u32");
      p.faults.seed = static_cast<uint32_t>(v);
    } else if ((a == "--loss" || a == "--dup" || a == "--reorder" || a == "--late" || a == "--wrong-size" ||
                a == "--wrong-id" || a == "--cmd-loss") && has) {
      if (!num(0, 1, v)) return usage(a + " must be a probability in [0, 1]");
      double& f = a == "--loss" ? p.faults.loss : a == "--dup" ? p.faults.duplicate : a == "--reorder" ? p.faults.reorder
                  : a == "--late" ? p.faults.late : a == "--wrong-size" ? p.faults.wrong_size
                  : a == "--wrong-id" ? p.faults.wrong_id : p.faults.cmd_loss;
      f = v;
    } else if (a == "--burst" && has) {
      unsigned long long c = 0, n = 0;
      char tail = 0;
      if (std::sscanf(argv[++i], "%llu:%llu%c", &c, &n, &tail) != 2 || n < 1 || n > 1000000)
        return usage("--burst must be CYCLE:N with N in [1, 1e6]");
      p.faults.burst_start = c;
      p.faults.burst_length = n;
    } else if (a == "--local-port" && has) {
      if (!num(1, 65535, v)) return usage("--local-port must be in [1, 65535]");
      p.local_port = static_cast<uint16_t>(v);
    } else if (a == "--control" && has) {
      if (!parseControl(argv[++i], p.control)) return usage("--control must be cart, joint, position or other");
    } else if ((a == "--wrench" || a == "--wrench-tool") && has) {
      if (!parseWrench(argv[++i], wrench)) return usage(a + " must be FX,FY,FZ in N, each in [-1000, 1000]");
      wrench_tool = a == "--wrench-tool";
    } else if (a == "--krl" && has) {
      if (tactile::ConfigResult r = readKrlSettings(argv[++i], krl); !r) return usage("--krl: " + r.message());
      have_krl = true;
    } else if (a == "--wrench-frame" && has) {
      if (!parseWrenchFrame(argv[++i], frame)) return usage("--wrench-frame must be base or tool");
      have_frame = true;
    } else if (a == "--pad-load" && has) {
      if (!parseNumbers(argv[++i], pad) || pad[0] < 0.0 || pad[0] > 20.0)
        return usage("--pad-load must be M,CX,CY,CZ (kg in [0, 20], mm)");
      have_pad = true;
    } else if (a == "--pose" && has) {
      if (!parsePose(argv[++i], p.initial_pose))
        return usage("--pose must be X,Y,Z,A,B,C (mm within 2000 of the base, deg)");
    } else if (a == "--cart-offset" && has) {
      if (!parseCartOffset(argv[++i], p.cart_offset)) return usage("--cart-offset must be none, composed or elementwise");
    } else if ((a == "--msr-sample-ms" || a == "--cmd-sample-ms") && has) {
      if (!num(0.01, 100, v)) return usage(a + " must be in [0.01, 100]");
      (a == "--msr-sample-ms" ? p.msr_sample_time_s : p.cmd_sample_time_s) = v * 1e-3;
    } else if (a == "--quality-rule" && has) {
      const std::string q = argv[++i];
      if (q != "on" && q != "off") return usage("--quality-rule must be on or off");
      p.quality_rule.enabled = q == "on";
    } else if (a == "--schedule" && has) {
      if (int rc = parseSchedule(argv[++i], p); rc != 0) return rc;
    } else {
      return usage("unknown or incomplete argument '" + a + "'");
    }
  }
  return 0;
}

/// The run's statistics on stdout; the exit code: 0 when no protocol
/// violation (MON echo, flags, non-finite command) was seen, else 3.
int printStats(const SimKrcStats& s, const SimKrcParams& p) {
  std::printf("fri_sim_krc: cycles %llu sent %llu replies %llu stale %llu malformed %llu missed %llu overruns %llu applied %llu "
              "remote_seq_errors %llu flag_errors %llu nonfinite %llu mon_echo_errors %llu max_step %.6f m %.6f rad "
              "latency mean %.1f us max %.1f us injected loss %llu dup %llu reorder %llu late %llu wrong_size %llu "
              "wrong_id %llu cmd_loss %llu\n",
              (unsigned long long)s.cycles, (unsigned long long)s.sent, (unsigned long long)s.replies,
              (unsigned long long)s.stale_replies, (unsigned long long)s.malformed_replies,
              (unsigned long long)s.missed, (unsigned long long)s.overruns, (unsigned long long)s.applied, (unsigned long long)s.remote_seq_errors,
              (unsigned long long)s.flag_errors, (unsigned long long)s.nonfinite_commands,
              (unsigned long long)s.mon_echo_errors, s.max_cmd_step_m, s.max_cmd_step_rad,
              s.replies ? 1e6 * s.sum_latency_s / double(s.replies) : 0.0, 1e6 * s.max_latency_s,
              (unsigned long long)s.inj_lost, (unsigned long long)s.inj_duplicate, (unsigned long long)s.inj_reorder,
              (unsigned long long)s.inj_late, (unsigned long long)s.inj_wrong_size, (unsigned long long)s.inj_wrong_id,
              (unsigned long long)s.inj_cmd_lost);
  std::printf("fri_sim_krc: quality from timing %s: answers missed %llu late %llu, drops out of CMD %llu; "
              "measurements at UNACCEPTABLE %llu BAD %llu OK %llu PERFECT %llu\n",
              p.quality_rule.enabled ? "on" : "off", (unsigned long long)s.answers_missed,
              (unsigned long long)s.answers_late, (unsigned long long)s.quality_drops,
              (unsigned long long)s.quality_cycles[0], (unsigned long long)s.quality_cycles[1],
              (unsigned long long)s.quality_cycles[2], (unsigned long long)s.quality_cycles[3]);
  const bool clean = s.mon_echo_errors == 0 && s.flag_errors == 0 && s.nonfinite_commands == 0;
  return clean ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  Cli cli;
  if (int rc = parseArgs(argc, argv, cli); rc != 0) return rc;
  SimKrcParams& p = cli.p;
  const long port = cli.port;
  const unsigned long long cycles = cli.cycles;
  const std::string& latency_out = cli.latency_out;
  const KrlSettings& krl = cli.krl;
  const bool have_krl = cli.have_krl;
  const std::array<double, 4>& pad = cli.pad;
  if (port < 0) return usage("--port is required");
  p.remote_port = static_cast<uint16_t>(port);
  if (!p.schedule.empty() && p.schedule.front().cycle == 0) p.initial = p.schedule.front();

  FirstOrderPlant plant;
  plant.setWrench(cli.wrench, cli.wrench_tool);
  p.wrench_frame = cli.have_frame ? cli.frame : krl.wrench_frame;
  if (have_krl) p.limits = krl.limits;
  const KDL::Vector krl_com(krl.load_com_m[0], krl.load_com_m[1], krl.load_com_m[2]);
  const KDL::Vector pad_com(pad[1] * 1e-3, pad[2] * 1e-3, pad[3] * 1e-3);
  if (cli.have_pad) plant.setPadLoad(pad[0], pad_com, have_krl ? krl.load_mass_kg : pad[0], have_krl ? krl_com : pad_com);
  SimKrc krc;
  if (tactile::ConfigResult r = krc.configure(p, plant); !r) {
    std::fprintf(stderr, "fri_sim_krc: %s\n", r.message().c_str());
    return 1;
  }
  std::vector<SimKrc::LatencySample> latencies;
  if (!latency_out.empty()) {
    if (cycles > 100000000ULL) return usage("--latency-out: at most 1e8 cycles");
    latencies.reserve(cycles);
    krc.setLatencyLog(&latencies);
  }
  krc.run(cycles);
  if (!latency_out.empty()) {
    FILE* f = std::fopen(latency_out.c_str(), "w");
    if (f == nullptr) {
      std::fprintf(stderr, "fri_sim_krc: cannot write %s\n", latency_out.c_str());
      return 1;
    }
    for (const SimKrc::LatencySample& l : latencies) std::fprintf(f, "%.2f %d\n", 1e6 * l.latency_s, l.on_time ? 1 : 0);
    std::fclose(f);
  }
  return printStats(krc.stats(), p);
}
