// lab_sim: a simulated lab for rehearsing the robot deployment
// (deployments/<experiment>_robot.ops) without the arm: a KUKA KRC speaking
// FRI over UDP on loopback and a Weiss WTS0614 on a pseudo-terminal, both
// backed by ONE simulated world (the scene's LWR 4+, objects and pad).
// docs/lab_sim.md: what it simulates, what it does not, a worked example.
//
//   lab_sim SCENE.yaml [--fri-port P] [--wts-link PATH] [--krc SCRIPT]
//           [--period-ms T] [--krc-cycle-ms C] [--msr-sample-ms M] [--cmd-sample-ms M]
//           [--control cart|joint|position] [--cart-offset F] [--quality-rule on|off]
//           [--krl FILE.src] [--wrench-frame F] [--duration S] [--truth-out FILE.csv] [--truth-period-ms T]
//           [--program FILE | --registry FILE] [--set KEY.PATH=VALUE ...]
//
//   --fri-port P        the FRI bridge's UDP port on 127.0.0.1 (default 49938, fri.yaml's);
//                       measurements go there and only there (loopback)
//   --wts-link PATH     symlink to the simulated WTS0614's PTY (as wts_sim --link);
//                       without it the PTY's own name is printed ("device: PATH")
//   --krc SCRIPT        the KRC's script in KRL's words, times in s
//                       (tactile::fri::KrcScript): "0:friOpen,1.0:friStart,
//                       6.0:quality=BAD,6.3:quality=PERFECT,8.0:friStop,8.5:friStart";
//                       friOpen -> MON, friStart -> CMD, friStop -> MON, friClose ->
//                       the KRC stops sending, quality=UNACCEPTABLE|BAD|OK|PERFECT,
//                       power=off|on (the drives). Default: the scene's `krc`, else
//                       command mode from the start at PERFECT quality
//   --period-ms T       the robot's control cycle: one world step (default: the scene's
//                       1 / rates.sim, 1 ms in every shipped scene)
//   --krc-cycle-ms C    the FRI cycle (friOpen's): one measurement packet every C ms,
//                       a whole number of world steps (default T)
//   --msr-sample-ms M, --cmd-sample-ms M
//                       the sample times the KRC advertises (desiredMsrSampleTime,
//                       desiredCmdSampleTime; default C): set them apart from C to
//                       rehearse a disagreement (the bridge's rate limiter steps by
//                       desiredCmdSampleTime)
//   --control S         the KRC's control strategy: cart (Cartesian impedance, the
//                       default), joint (joint impedance), position; commands are
//                       applied under cart only
//   --cart-offset F     the form in which the KRC sends its set point: none (cmdCartPos,
//                       the offset zero; default), composed (cmdCartPos * offset as
//                       frames), elementwise (cmdCartPos + offset over the 12 entries);
//                       fri.yaml's cart_offset must match (fri_check finds it)
//   --quality-rule R    on (default): the KRC rates the link from the remote's answers
//                       (tactile::fri::KrcQualityRule: missed or late answers over the
//                       last 100 cycles), reports the lower of that and the script's
//                       quality, leaves command mode below OK and enters it (again)
//                       only at PERFECT; off: the script alone
//   --krl FILE.src      the KRL program the KRC runs (krc/TactileServo.src and the .dat
//                       beside it; tactile_fri/krl_settings.hpp): its
//                       $STIFFNESS.FRAMETYPE gives the axes of estExtTcpFT (#BASE: base,
//                       #TOOL: the flange's), and its $STIFFNESS.MAXFORCE / CPMAXDELTA
//                       the KRC applies: beyond either in command mode the KRC brakes
//                       the drives and drops to monitor mode (a fault until the end).
//                       Default: base axes, no limits applied
//   --wrench-frame F    base | tool: the axes of estExtTcpFT, overriding --krl's (a KRC
//                       whose $STIFFNESS disagrees with fri.yaml's wrench_frame)
//   --duration S        stop after S s (default 0: until SIGINT/SIGTERM)
//   --truth-out FILE    the world's ground truth over time, CSV (columns in
//                       docs/lab_sim.md): time, KRC state, flange pose, the set
//                       point the arm followed, true contact force, the wrench
//                       the KRC reported; never seen by the controller
//   --truth-period-ms T one truth row every T ms, a whole number of KRC cycles (default 10)
//   --set K=V           override a scene key before it is read (as tactile_sim run --set)
//   --program FILE      the robot's phase program: its controller.sensor_mount mounts the
//                       pad on the flange (default: the program the registry binds to the
//                       scene, --registry FILE, default this tree's experiments.yaml)
//
// Prints one line per KRC state change and, at the end (duration, SIGINT or
// SIGTERM), a summary: cycles, replies, lost, the largest step between
// consecutive applied commands (the "no pose jump" check), the largest offset
// of the first command after entering CMD, the world's status and the true
// contact force statistics. Exit: 0, 2 on bad arguments or scene, 1 when a
// socket or the PTY cannot be opened, 3 when the remote broke the protocol
// (MON echo, flags, non-finite command), as fri_sim_krc.
//
// Test equipment: threads (the KRC's loop in the main thread, the WTS
// device's thread), sleeps and the wall clock. Not a production library.
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tactile_config/registry.hpp"
#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/krl_settings.hpp"
#include "tactile_fri/sim_krc.hpp"
#include "tactile_lab/krc_schedule.hpp"
#include "tactile_lab/world_plant.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_types/kdl_pose.hpp"
#include "tactile_wts/sim_device.hpp"

using namespace tactile;

namespace {

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop.store(true); }

int usage(const std::string& msg) {
  std::fprintf(stderr,
               "lab_sim: %s\nusage: lab_sim SCENE.yaml [--fri-port P] [--wts-link PATH] [--krc SCRIPT] [--period-ms T]\n"
               "               [--krc-cycle-ms C] [--msr-sample-ms M] [--cmd-sample-ms M] [--control cart|joint|position] [--cart-offset F]\n"
               "               [--quality-rule on|off] [--krl FILE.src] [--wrench-frame base|tool]\n"
               "               [--duration S] [--truth-out FILE.csv] [--truth-period-ms T] [--set KEY.PATH=VALUE ...]\n"
               "               [--program FILE | --registry FILE]\n"
               "(see the header of tools/lab_sim.cpp or docs/lab_sim.md)\n",
               msg.c_str());
  return 2;
}

bool number(const char* s, double& v) {
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(v);
}

/// n such that a = n * b (to 1e-6 relative), n >= 1; 0 if none.
long wholeMultiple(double a, double b) {
  const double n = a / b;
  const long r = std::lround(n);
  return (r >= 1 && std::fabs(n - double(r)) <= 1e-6 * n) ? r : 0;
}

const char* stateWord(bool open, fri::State s) {
  if (!open) return "closed";
  return fri::toString(s);
}

/// Running mean / sd / min / max.
struct Stat {
  uint64_t n = 0;
  double mean = 0.0, m2 = 0.0, min = 0.0, max = 0.0;
  void add(double x) {
    if (n == 0) min = max = x;
    min = std::min(min, x);
    max = std::max(max, x);
    ++n;
    const double d = x - mean;
    mean += d / double(n);
    m2 += d * (x - mean);
  }
  double sd() const { return n > 1 ? std::sqrt(m2 / double(n - 1)) : 0.0; }
};

/// The scene's link faults on the WTS device: unplugged for a disconnect's
/// window (the reader sees the hangup and reconnects to the new PTY behind
/// the same link), held (no frame sent) for a stale window.
void linkFaults(const lab::WorldPlant& plant, wts::SimulatedWts& wts, double t, uint64_t& unplugs) {
  const bool down = plant.sensorLinkDown();
  if (down == wts.plugged()) {
    if (down) {
      wts.unplug();
      ++unplugs;
    } else if (!wts.replug()) {
      std::printf("t %8.3f s  WTS: plugging back failed\n", t);
    }
    std::printf("t %8.3f s  WTS %s (faults: disconnect)\n", t, down ? "unplugged" : "plugged back");
    std::fflush(stdout);
  }
  const bool stall = plant.sensorStalled();
  if (stall != wts.held()) {
    wts.hold(stall);
    std::printf("t %8.3f s  WTS stream %s (faults: stale)\n", t, stall ? "stalled" : "resumed");
    std::fflush(stdout);
  }
}

void printForce(const char* label, const Stat& s, double cycle_s) {
  if (s.n == 0) {
    std::printf("lab_sim: true contact force %s: no contact\n", label);
    return;
  }
  std::printf("lab_sim: true contact force %s: %.3f s in contact, mean %.3f N sd %.3f N min %.3f N max %.3f N\n", label,
              double(s.n) * cycle_s, s.mean, s.sd(), s.min, s.max);
}


/// lab_sim's command line (parseArgs).
struct LabArgs {
  std::string scene_file, wts_link, truth_out, krc_spec, control = "cart", krl_file, program_file;
  std::string registry = TACTILE_SOURCE_DIR "/experiments.yaml";  // --program's default: its binding
  bool quality_rule = true;
  fri::CartOffset cart_offset = fri::CartOffset::None;
  fri::WrenchFrame frame_override = fri::WrenchFrame::Base;
  fri::KrlSettings krl;  // --krl: read once here, applied in krcParams()
  bool krc_given = false, frame_given = false;
  long fri_port = fri::kDefaultPort;
  double period_ms = 0.0, krc_cycle_ms = 0.0, msr_sample_ms = 0.0, cmd_sample_ms = 0.0, duration_s = 0.0,
         truth_period_ms = 10.0;
  std::vector<std::string> overrides;
};

/// The command line into `args` (--period-ms as a rates.sim override): -1, or
/// usage()'s exit code.
int parseArgs(int argc, char** argv, LabArgs& args) {
  std::string &scene_file = args.scene_file, &wts_link = args.wts_link, &truth_out = args.truth_out,
              &krc_spec = args.krc_spec, &control = args.control, &krl_file = args.krl_file;
  bool& quality_rule = args.quality_rule;
  fri::CartOffset& cart_offset = args.cart_offset;
  fri::WrenchFrame& frame_override = args.frame_override;
  fri::KrlSettings& krl = args.krl;
  bool &krc_given = args.krc_given, &frame_given = args.frame_given;
  long& fri_port = args.fri_port;
  double &period_ms = args.period_ms, &krc_cycle_ms = args.krc_cycle_ms, &msr_sample_ms = args.msr_sample_ms,
         &cmd_sample_ms = args.cmd_sample_ms, &duration_s = args.duration_s, &truth_period_ms = args.truth_period_ms;
  std::vector<std::string>& overrides = args.overrides;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has = i + 1 < argc;
    double v = 0.0;
    auto num = [&](double lo, double hi, double& out) {
      if (!number(argv[++i], v) || v < lo || v > hi) return false;
      out = v;
      return true;
    };
    if (a == "--fri-port" && has) {
      double p = 0;
      if (!num(1, 65535, p) || p != std::floor(p)) return usage("--fri-port must be an integer in [1, 65535]");
      fri_port = long(p);
    } else if (a == "--wts-link" && has) {
      wts_link = argv[++i];
    } else if (a == "--krc" && has) {
      krc_spec = argv[++i];
      krc_given = true;
    } else if (a == "--period-ms" && has) {
      if (!num(0.1, 10, period_ms)) return usage("--period-ms must be in [0.1, 10] (ms)");
    } else if (a == "--krc-cycle-ms" && has) {
      if (!num(0.1, 100, krc_cycle_ms)) return usage("--krc-cycle-ms must be in [0.1, 100] (ms)");
    } else if (a == "--msr-sample-ms" && has) {
      if (!num(0.1, 100, msr_sample_ms)) return usage("--msr-sample-ms must be in [0.1, 100] (ms)");
    } else if (a == "--cmd-sample-ms" && has) {
      if (!num(0.1, 100, cmd_sample_ms)) return usage("--cmd-sample-ms must be in [0.1, 100] (ms)");
    } else if (a == "--control" && has) {
      control = argv[++i];
      if (control != "cart" && control != "joint" && control != "position")
        return usage("--control must be cart, joint or position");
    } else if (a == "--cart-offset" && has) {
      if (!fri::parseCartOffset(argv[++i], cart_offset))
        return usage("--cart-offset must be none, composed or elementwise");
    } else if (a == "--quality-rule" && has) {
      const std::string rule = argv[++i];
      if (rule != "on" && rule != "off") return usage("--quality-rule must be on or off");
      quality_rule = rule == "on";
    } else if (a == "--krl" && has) {
      krl_file = argv[++i];
      if (ConfigResult r = fri::readKrlSettings(krl_file, krl); !r) return usage("--krl: " + r.message());
    } else if (a == "--wrench-frame" && has) {
      if (!fri::parseWrenchFrame(argv[++i], frame_override)) return usage("--wrench-frame must be base or tool");
      frame_given = true;
    } else if (a == "--duration" && has) {
      if (!num(0, 1e7, duration_s)) return usage("--duration must be in [0, 1e7] (s; 0 = until killed)");
    } else if (a == "--truth-out" && has) {
      truth_out = argv[++i];
    } else if (a == "--truth-period-ms" && has) {
      if (!num(0.1, 1000, truth_period_ms)) return usage("--truth-period-ms must be in [0.1, 1000] (ms)");
    } else if (a == "--set" && has) {
      overrides.emplace_back(argv[++i]);
    } else if (a == "--program" && has) {
      args.program_file = argv[++i];
    } else if (a == "--registry" && has) {
      args.registry = argv[++i];
    } else if (!a.empty() && a[0] != '-' && scene_file.empty()) {
      scene_file = a;
    } else {
      return usage("unknown or incomplete argument '" + a + "'");
    }
  }
  if (scene_file.empty()) return usage("a scene file is required");
  if (period_ms > 0.0) overrides.push_back("rates.sim=" + std::to_string(1000.0 / period_ms));
  return -1;
}

/// The simulated KRC's parameters: the command line's over the scene's
/// start pose, at the KRC cycle T_krc.
fri::SimKrcParams krcParams(const LabArgs& args, double T_krc, const lab::WorldPlant& plant) {
  const std::string& control = args.control;
  fri::SimKrcParams kp;
  kp.remote_port = static_cast<uint16_t>(args.fri_port);
  kp.period_s = T_krc;
  kp.real_time = true;
  kp.msr_sample_time_s = args.msr_sample_ms * 1e-3;
  kp.cmd_sample_time_s = args.cmd_sample_ms * 1e-3;
  kp.initial_pose = plant.initialPose();
  kp.cart_offset = args.cart_offset;
  kp.quality_rule.enabled = args.quality_rule;
  if (!args.krl_file.empty()) {
    kp.limits = args.krl.limits;
    kp.wrench_frame = args.krl.wrench_frame;
  }
  if (args.frame_given) kp.wrench_frame = args.frame_override;
  kp.control = control == "cart"    ? fri::ControlStrategy::CartImpedance
               : control == "joint" ? fri::ControlStrategy::JointImpedance
                                    : fri::ControlStrategy::Position;
  return kp;
}

/// --truth-out: the file with its header line, or nullptr (after the message).
FILE* openTruth(const std::string& truth_out) {
  FILE* truth = std::fopen(truth_out.c_str(), "w");
  if (truth == nullptr) {
    std::fprintf(stderr, "lab_sim: cannot write %s\n", truth_out.c_str());
    return nullptr;
  }
  std::fprintf(truth,
               "t,krc_open,krc_state,krc_quality,krc_power,applied,flange_x,flange_y,flange_z,flange_qx,flange_qy,"
               "flange_qz,flange_qw,setpoint_x,setpoint_y,setpoint_z,setpoint_qx,setpoint_qy,setpoint_qz,setpoint_qw,"
               "force_true,force_layer,housing_force,in_contact,est_fx,est_fy,est_fz,sim_status\n");
  return truth;
}

/// The run's settings, the start pose and the WTS device on stdout.
void printBanner(const LabArgs& args, const sim::Scene& scene, const fri::SimKrcParams& kp, double T_world, double T_krc,
                 const lab::WorldPlant& plant, const wts::SimulatedWts& wts) {
  const KDL::Frame p0 = plant.initialPose();
  std::printf("lab_sim: scene %s (%s), world step %.3f ms, KRC cycle %.3f ms (advertised msr %.3f ms cmd %.3f ms), "
              "control %s, cart_offset %s, quality from timing %s, $STIFFNESS limits %s, estExtTcpFT in %s axes, "
              "FRI -> 127.0.0.1:%ld, WTS %dx%d at %.0f Hz\n",
              scene.name.c_str(), scene.file.c_str(), T_world * 1e3, T_krc * 1e3,
              (kp.msr_sample_time_s > 0 ? kp.msr_sample_time_s : T_krc) * 1e3,
              (kp.cmd_sample_time_s > 0 ? kp.cmd_sample_time_s : T_krc) * 1e3, args.control.c_str(), fri::toString(args.cart_offset),
              args.quality_rule ? "on" : "off", args.krl_file.empty() ? "off" : args.krl_file.c_str(), fri::toString(kp.wrench_frame),
              args.fri_port,
              scene.features.rows, scene.features.cols, scene.rates.wts);
  std::printf("lab_sim: flange at (%.4f, %.4f, %.4f) m, true contact force %.3f N\n", p0.p.x(), p0.p.y(), p0.p.z(),
              -plant.state().wrench_s[2]);
  std::printf("device: %s\n", wts.path().c_str());
  std::fflush(stdout);

}

/// The run, cycle by cycle: the KRC's cycle, the link faults, and what
/// changed on stdout (the remote's replies, the KRC's state, the world's),
/// the contact force and the truth file; the summary at the end.
struct LabRun {
  LabRun(fri::SimKrc& krc_, lab::WorldPlant& plant_, wts::SimulatedWts& wts_,
         const std::vector<lab::ScheduledWord>& words_, double T_krc_, FILE* truth_, long truth_every_)
      : krc(krc_), plant(plant_), wts(wts_), words(words_), T_krc(T_krc_), truth(truth_), truth_every(truth_every_) {}

  fri::SimKrc& krc;
  lab::WorldPlant& plant;
  wts::SimulatedWts& wts;
  const std::vector<lab::ScheduledWord>& words;
  const double T_krc;
  FILE* truth;
  const long truth_every;
    std::size_t next_word = 0;
    bool was_open = false;
    fri::State was_state = fri::State::Off;
    fri::Quality was_quality = fri::Quality::Perfect;
    uint16_t was_power = 0;
    bool first = true;
    Stat force_all, force_cmd;
    sim::SimStatus last_world_status = sim::SimStatus::Ok;
    // The remote's session: from its first to its last reply (the loss before
    // and after is the remote not running yet / any more, not lost packets).
    uint64_t first_reply_cycle = 0, missed_at_first = 0, closed_at_first = 0;
    uint64_t last_reply_cycle = 0, missed_at_last = 0, closed_at_last = 0, replies_seen = 0;
    bool answered = false;
    uint64_t unplugs = 0;
    bool fault_printed = false;

  void cycle() {
    const uint64_t c = krc.stats().cycles;  // this cycle's index: its scheduled events apply now
    krc.runCycle();
    const double t = double(c) * T_krc;
    linkFaults(plant, wts, t, unplugs);
    noteReplies(c, t);
    noteState(c, t);
    noteWorld(c, t);
  }

  /// The remote's first and last reply (its session).
  void noteReplies(uint64_t c, double t) {
    if (krc.stats().replies != replies_seen) {
      replies_seen = krc.stats().replies;
      if (!answered) {
        answered = true;
        first_reply_cycle = c;
        missed_at_first = krc.stats().missed;
        closed_at_first = krc.stats().closed_cycles;
        std::printf("t %8.3f s  cycle %llu: first reply from the remote\n", t, static_cast<unsigned long long>(c));
        std::fflush(stdout);
      }
      last_reply_cycle = c;
      missed_at_last = krc.stats().missed;
      closed_at_last = krc.stats().closed_cycles;
    }
  }

  /// The KRC's state, quality and drives when they change (with the script's
  /// words that led there); a KRC fault once.
  void noteState(uint64_t c, double t) {
    const bool open = krc.open();
    const fri::State st = krc.state();
    const fri::Quality q = krc.quality();
    const uint16_t pw = krc.power();
    if (first || open != was_open || st != was_state || q != was_quality || (pw != 0) != (was_power != 0)) {
      std::string said;
      while (next_word < words.size() && words[next_word].cycle <= c) {
        said += (said.empty() ? "" : ", ") + words[next_word].word;
        ++next_word;
      }
      std::printf("t %8.3f s  cycle %llu: %s%sKRC %s quality %s drives %s\n", t, static_cast<unsigned long long>(c),
                  said.c_str(), said.empty() ? "" : " -> ", stateWord(open, st), fri::toString(q), pw ? "on" : "off");
      std::fflush(stdout);
      was_open = open, was_state = st, was_quality = q, was_power = pw;
      first = false;
    }
    while (next_word < words.size() && words[next_word].cycle <= c) ++next_word;  // words that changed nothing
    if (krc.fault() != fri::KrcFault::None && !fault_printed) {
      const fri::PlantState& ps = krc.plantState();
      std::printf("t %8.3f s  cycle %llu: KRC fault %s: the drives braked, monitor mode (estExtTcpFT %.2f %.2f %.2f N)\n",
                  t, static_cast<unsigned long long>(c), fri::toString(krc.fault()), ps.wrench[0], ps.wrench[1],
                  ps.wrench[2]);
      std::fflush(stdout);
      fault_printed = true;
    }
  }

  /// The world's fatal status changes, the contact force, the truth line.
  void noteWorld(uint64_t c, double t) {
    const bool open = krc.open();
    const fri::State st = krc.state();
    const fri::Quality q = krc.quality();
    const uint16_t pw = krc.power();
    const sim::SimState& s = plant.state();
    if (s.status != last_world_status && (sim::fatal(s.status) || sim::fatal(last_world_status))) {
      std::printf("t %8.3f s  world: %s\n", t, sim::toString(s.status));
      std::fflush(stdout);
    }
    last_world_status = s.status;
    const double f_true = -s.wrench_s[2];  // the runner's force_true: normal force on the sensor
    const bool contact = s.normal_force + s.housing_force > 0.0;
    if (contact) {
      force_all.add(f_true);
      if (open && st == fri::State::Cmd) force_cmd.add(f_true);
    }
    if (truth != nullptr && c % static_cast<uint64_t>(truth_every) == 0) {
      const Pose& fl = s.flange_g;
      const Pose& sp = s.command_g;
      const Wrench& w = plant.estimatedWrench();
      std::fprintf(truth,
                   "%.6f,%d,%s,%s,%d,%llu,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,"
                   "%.6f,%d,%.6f,%.6f,%.6f,%s\n",
                   s.time_s, open ? 1 : 0, stateWord(open, st), fri::toString(q), pw ? 1 : 0,
                   static_cast<unsigned long long>(krc.stats().applied), fl.p[0], fl.p[1], fl.p[2], fl.q[0], fl.q[1],
                   fl.q[2], fl.q[3], sp.p[0], sp.p[1], sp.p[2], sp.q[0], sp.q[1], sp.q[2], sp.q[3], f_true,
                   s.normal_force, s.housing_force, contact ? 1 : 0, w.w[0], w.w[1], w.w[2], sim::toString(s.status));
    }
  }

  /// The statistics on stdout; the exit code: 0 when no protocol violation
  /// (MON echo, flags, non-finite command) was seen, else 3.
  int summary(const fri::SimKrcParams& kp) {
    if (truth != nullptr) std::fclose(truth);
    const wts::SimStats ws = wts.stats();
    wts.stop();

    const fri::SimKrcStats& k = krc.stats();
    const lab::WorldPlantStats& w = plant.stats();
    std::printf("lab_sim: %s after %.3f s\n", g_stop.load() ? "stopped by a signal" : "duration reached",
                double(k.cycles) * T_krc);
    std::printf("lab_sim: KRC cycles %llu sent %llu replies %llu lost %llu (cycles without their reply) closed %llu "
                "stale %llu malformed %llu overruns %llu applied %llu\n",
                (unsigned long long)k.cycles, (unsigned long long)k.sent, (unsigned long long)k.replies,
                (unsigned long long)k.missed, (unsigned long long)k.closed_cycles, (unsigned long long)k.stale_replies,
                (unsigned long long)k.malformed_replies, (unsigned long long)k.overruns, (unsigned long long)k.applied);
    if (answered)
      std::printf("lab_sim: KRC first reply at t %.3f s, last at t %.3f s; between them sent %llu lost %llu\n",
                  double(first_reply_cycle) * T_krc, double(last_reply_cycle) * T_krc,
                  (unsigned long long)(last_reply_cycle + 1 - first_reply_cycle - (closed_at_last - closed_at_first)),
                  (unsigned long long)(missed_at_last - missed_at_first));
    else
      std::printf("lab_sim: KRC no reply from the remote\n");
    std::printf("lab_sim: KRC max_step %.6f m %.6f rad (between consecutive applied commands), max_entry_offset "
                "%.6f m %.6f rad (first command after entering CMD vs the set point the KRC held)\n",
                k.max_cmd_step_m, k.max_cmd_step_rad, k.max_entry_offset_m, k.max_entry_offset_rad);
    std::printf("lab_sim: KRC protocol mon_echo_errors %llu flag_errors %llu nonfinite %llu remote_seq_errors %llu; "
                "latency mean %.1f us max %.1f us\n",
                (unsigned long long)k.mon_echo_errors, (unsigned long long)k.flag_errors,
                (unsigned long long)k.nonfinite_commands, (unsigned long long)k.remote_seq_errors,
                k.replies ? 1e6 * k.sum_latency_s / double(k.replies) : 0.0, 1e6 * k.max_latency_s);
    std::printf("lab_sim: KRC link answers missed %llu late %llu (of the cycle: > %.0f %%), quality drops out of CMD %llu; "
                "measurements at UNACCEPTABLE %llu BAD %llu OK %llu PERFECT %llu; fault %s\n",
                (unsigned long long)k.answers_missed, (unsigned long long)k.answers_late,
                100.0 * kp.quality_rule.late_fraction, (unsigned long long)k.quality_drops,
                (unsigned long long)k.quality_cycles[0], (unsigned long long)k.quality_cycles[1],
                (unsigned long long)k.quality_cycles[2], (unsigned long long)k.quality_cycles[3],
                fri::toString(krc.fault()));
    std::printf("lab_sim: world steps %llu not_converged %llu invalid_commands %llu fatal %llu%s%s; WTS acquisitions "
                "%llu frames %llu, device frames sent %llu held %llu unplugged %llu commands %llu bad_commands %llu\n",
                (unsigned long long)w.physics_steps, (unsigned long long)w.not_converged,
                (unsigned long long)w.invalid_commands, (unsigned long long)w.fatal_steps,
                w.fatal_steps ? " first " : "", w.fatal_steps ? sim::toString(w.first_fatal) : "",
                (unsigned long long)w.acquisitions, (unsigned long long)w.frames, (unsigned long long)ws.frames,
                (unsigned long long)ws.held_frames, (unsigned long long)unplugs, (unsigned long long)ws.commands,
                (unsigned long long)ws.bad_commands);
    printForce("(all)", force_all, T_krc);
    printForce("(in CMD)", force_cmd, T_krc);
    const bool clean = k.mon_echo_errors == 0 && k.flag_errors == 0 && k.nonfinite_commands == 0;
    return clean ? 0 : 3;
  }
};

}  // namespace

int main(int argc, char** argv) {
  LabArgs args;
  if (int code = parseArgs(argc, argv, args); code >= 0) return code;
  const std::vector<std::string>& overrides = args.overrides;
  const double krc_cycle_ms = args.krc_cycle_ms, truth_period_ms = args.truth_period_ms;
  const bool krc_given = args.krc_given;

  sim::RunFiles files{args.scene_file, args.program_file, ""};
  ConfigResult bound = files.program.empty()
                           ? config::programForScene(args.registry, files.scene, files.program)
                           : ConfigResult::success();
  sim::Scene scene;
  if (ConfigResult r = bound ? sim::loadRun(files, scene, overrides) : bound; !r) {
    std::fprintf(stderr, "lab_sim: %s\n", r.message().c_str());
    return 2;
  }
  const double T_world = 1.0 / scene.rates.sim;
  const double T_krc = krc_cycle_ms > 0.0 ? krc_cycle_ms * 1e-3 : T_world;
  const long steps_per_cycle = wholeMultiple(T_krc, T_world);
  char msg[200];
  if (steps_per_cycle == 0) {
    std::snprintf(msg, sizeof msg, "--krc-cycle-ms = %g must be a whole number of world steps (%g ms, --period-ms)",
                  T_krc * 1e3, T_world * 1e3);
    return usage(msg);
  }
  const long truth_every = wholeMultiple(truth_period_ms * 1e-3, T_krc);
  if (truth_every == 0) {
    std::snprintf(msg, sizeof msg, "--truth-period-ms = %g must be a whole number of KRC cycles (%g ms)",
                  truth_period_ms, T_krc * 1e3);
    return usage(msg);
  }
  if (scene.world.fri_delay_s > 0.0 || scene.world.krc_cycle_s > 0.0)
    std::fprintf(stderr,
                 "lab_sim: warning: %s sets effects.fri_delay_s = %g s / krc_cycle_s = %g s: the world delays and holds "
                 "the set point on top of this KRC's own cycle\n",
                 scene.file.c_str(), scene.world.fri_delay_s, scene.world.krc_cycle_s);

  fri::KrcScript script;
  const std::string spec = krc_given ? args.krc_spec : scene.krc;
  if (ConfigResult r = script.parse(spec, krc_given ? std::string("--krc") : scene.file + ": krc"); !r) {
    std::fprintf(stderr, "lab_sim: %s\n", r.message().c_str());
    return 2;
  }

  lab::WorldPlant plant;
  if (ConfigResult r = plant.configure(scene); !r) {
    std::fprintf(stderr, "lab_sim: %s\n", r.message().c_str());
    return 2;
  }

  fri::SimKrcParams kp = krcParams(args, T_krc, plant);
  std::vector<lab::ScheduledWord> words;
  lab::scheduleFromScript(script, T_krc, kp.initial, kp.schedule, words);

  // The WTS0614 on a PTY, its frames from the world (the latest acquisition).
  wts::SimulatedWts wts;
  wts::SimulatedWts::Params wp;
  wp.cells.rows = scene.features.rows;
  wp.cells.cols = scene.features.cols;
  wp.link = args.wts_link;
  wts.setSource([&plant](uint32_t, RawTactileFrame& f) { plant.latestFrame(f); });
  std::string why;
  if (!wts.start(wp, &why)) {
    std::fprintf(stderr, "lab_sim: WTS device: %s\n", why.c_str());
    return 1;
  }

  fri::SimKrc krc;
  if (ConfigResult r = krc.configure(kp, plant); !r) {
    std::fprintf(stderr, "lab_sim: KRC: %s\n", r.message().c_str());
    return 1;
  }

  FILE* truth = nullptr;
  if (!args.truth_out.empty() && (truth = openTruth(args.truth_out)) == nullptr) return 1;

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  printBanner(args, scene, kp, T_world, T_krc, plant, wts);

  const uint64_t max_cycles =
      args.duration_s > 0.0 ? static_cast<uint64_t>(std::llround(args.duration_s / T_krc)) : 0;
  LabRun run{krc, plant, wts, words, T_krc, truth, truth_every};
  while (!g_stop.load() && (max_cycles == 0 || krc.stats().cycles < max_cycles)) run.cycle();
  return run.summary(kp);
}
