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
// Exit status: 0 after N cycles, 2 on idle timeout, 1 on usage/configuration errors.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <arpa/inet.h>

#include "tactile_fri/bridge.hpp"
#include "tactile_fri/params_io.hpp"
#include "tactile_fri/udp.hpp"

using namespace tactile;
using namespace tactile::fri;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int usage(const char* msg) {
  std::fprintf(stderr,
               "fri_check: %s\nusage: fri_check --port P [--cycles N] [--motion hold|circle] [--bind ADDR] "
               "[--radius M] [--circle-period S] [--max-lin-speed V] [--max-rot-speed W] [--idle-timeout S]\n",
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

}  // namespace

int main(int argc, char** argv) {
  long port = -1;
  long cycles = 1000;
  std::string motion = "hold";
  UdpParams up;
  BridgeParams bp;
  double radius = 0.01, circle_period = 10.0, idle_timeout = 10.0;
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
    } else if (a == "--motion" && has) {
      motion = argv[++i];
      if (motion != "hold" && motion != "circle") return usage("--motion must be hold or circle");
    } else if (a == "--params" && has) {
      ++i;  // loaded above
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
    } else if (a == "--idle-timeout" && has) {
      if (!parseDouble(argv[++i], idle_timeout) || idle_timeout <= 0.0) return usage("--idle-timeout must be > 0 s");
    } else {
      return usage(("unknown or incomplete argument '" + a + "'").c_str());
    }
  }
  bool have_params = false;
  for (int i = 1; i < argc; ++i) have_params = have_params || std::string(argv[i]) == "--params";
  if (port < 0 && !have_params) return usage("--port (or --params FILE with fri.udp.port) is required");
  if (port >= 0) up.port = static_cast<uint16_t>(port);

  FriBridge bridge;
  if (ConfigResult r = bridge.configure(bp); !r) {
    std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
    return 1;
  }
  UdpSocket sock;
  if (ConfigResult r = sock.open(up); !r) {
    std::fprintf(stderr, "fri_check: %s\n", r.message().c_str());
    return 1;
  }
  std::printf("fri_check: listening on %s:%u, motion %s, %ld cycles\n", up.bind_address.c_str(),
              unsigned(sock.localPort()), motion.c_str(), cycles);
  std::fflush(stdout);

  static uint8_t buf[2048];
  static uint8_t tx[kCmdPacketSize];
  BridgeOutput out;
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  KDL::Frame anchor = KDL::Frame::Identity();
  bool have_anchor = false;  // the desired pose starts where the robot is (the bridge's start gate)
  bool in_cmd = false;
  uint64_t cmd_cycles = 0;
  RunningStat processing_us, period_ms;
  double last_arrival = 0.0, last_packet_time = now();
  uint64_t timeouts = 0, send_errors = 0, truncated = 0, status_changes = 0;
  BridgeStatus last_status = BridgeStatus::NotConfigured;
  float krc_latency = 0.0f, krc_answer_rate = 0.0f;
  uint32_t krc_miss = 0;
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

    // The desired pose: hold the CMD entry pose, or a circle around it.
    // Motion time base: CMD cycles times the KRC's command period (from the
    // previous packet), so the motion is smooth whatever the host's timing.
    const double krc_T = double(bridge.lastMeasurement().intf.desired_cmd_sample_time);
    const double T = (krc_T > 0.0 && krc_T <= 0.1) ? krc_T : bp.nominal_period_s;
    const double tc = static_cast<double>(cmd_cycles) * T;
    KDL::Frame target = anchor;
    if (motion == "circle") {
      const double ramp = tc < 2.0 ? 0.5 * (1.0 - std::cos(kPi * tc / 2.0)) : 1.0;  // smooth 2 s radius ramp
      const double w = 2.0 * kPi / circle_period;
      target.p = anchor.p + KDL::Vector(ramp * radius * (std::cos(w * tc) - 1.0), ramp * radius * std::sin(w * tc), 0.0);
    }
    toPose(target, desired.pose);
    desired.time_s = t_rx;

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

    processing_us.add((t_tx - t_rx) * 1e6);
    if (last_arrival > 0.0) period_ms.add((t_rx - last_arrival) * 1e3);
    last_arrival = t_rx;
    const MsrPacket& msr = bridge.lastMeasurement();
    krc_latency = msr.intf.stat.latency;
    krc_answer_rate = msr.intf.stat.answer_rate;
    krc_miss = msr.intf.stat.miss_counter;

    const bool cmd_now = out.state == State::Cmd && powerOn(msr);
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
  std::printf("latency: processing mean %.1f us max %.1f us; inter-arrival mean %.3f ms sd %.3f ms max %.3f ms; "
              "KRC-reported latency %.6f s answer_rate %.3f miss_counter %u\n",
              processing_us.mean(), processing_us.max, period_ms.mean(), period_ms.stddev(), period_ms.max,
              double(krc_latency), double(krc_answer_rate), krc_miss);
  return exit_code;
}
