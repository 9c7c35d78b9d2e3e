// A simulated KUKA KRC speaking FRI over UDP on the loopback interface, with
// fault injection, backed by a small plant interface. It is a test peer (it
// reads the clock when pacing in real time), not a real-time core. The KRC
// itself (packet contents, command handling, the checks) is
// tactile::fri::KrcModel, the same model the headless runner uses; this class
// adds the UDP transport, the pacing and the injected faults.
//
// Each cycle:
//   1. apply the scheduled state/quality events of this cycle;
//   2. advance the plant by one period towards the KRC's current set point
//      (the last applied command in CMD; the plant's holdPose() otherwise,
//      by default the measured pose: the robot holds still outside CMD);
//      with the interface closed (StateEvent::open false) steps 3 and 4 are
//      skipped: nothing is sent, the cycle is paced all the same;
//   3. send one measurement packet (916 bytes) to 127.0.0.1:remote_port, subject
//      to the injected faults (loss, duplicate, reorder, late, wrong size or id);
//   4. wait for the reply whose reflSeqCount is this cycle's sendSeqCount (until
//      the period's deadline in real time, or reply_timeout_s in fast mode) and
//      check it: size/id, the remote's sendSeqCount increments by one, flags,
//      (the next measurement's reflSeqCount is the sendSeqCount of the last
//      command taken, i.e. of the last reply that matched its measurement)
//      MON echo of the measured pose, and the step between consecutive applied
//      commands (the "no pose jump" check). Commands are applied only in CMD at
//      quality >= OK, as on the real KRC.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <random>
#include <vector>

#include <kdl/frames.hpp>

#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/protocol.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace fri {

/// The robot behind the simulated KRC (Cartesian impedance strategy): given the
/// commanded flange pose and dt, produce the measured state. Keep it small so
/// the LWR simulator (core/sim/lwr) can be adapted to it.
class Plant {
 public:
  virtual ~Plant() = default;
  virtual void reset(const KDL::Frame& initial_pose) = 0;
  virtual void step(const KDL::Frame& commanded, double dt, PlantState& out) = 0;
  /// The set point the robot's own controller holds while the KRC applies no
  /// remote command (MON, drives off, CMD before the first command taken):
  /// the KRL program's set point. The KRC reports it as cmdCartPos and steps
  /// the plant toward it. Default: the measured pose (a plant whose set point
  /// is where it stands, e.g. FirstOrderPlant). A plant in contact (the
  /// simulated world: the arm pressed by its impedance against an object)
  /// returns its last set point, which differs from the measured pose by the
  /// contact force over the stiffness, so that the arm stays pressed.
  virtual KDL::Frame holdPose(const PlantState& measured) const { return measured.pose; }
};

/// Built-in plant: first-order tracking of the commanded pose with time constant
/// tau (translation and rotation), no kinematics (joint positions constant at a
/// fixed configuration), a constant external wrench (zero by default: nothing
/// touches the arm; a bench peer pressing the pad sets the wrench that press
/// would put on the arm, so that the two sensors agree).
class FirstOrderPlant : public Plant {
 public:
  explicit FirstOrderPlant(double tau_s = 0.02) : tau_(tau_s) {}
  void reset(const KDL::Frame& initial_pose) override;
  void step(const KDL::Frame& commanded, double dt, PlantState& out) override;
  /// The estimated external wrench reported from now on ([Fx Fy Fz Tx Ty Tz],
  /// N, N m): in {g} axes, or with `tool_axes` in the flange's {e} axes (turned
  /// into {g} by the measured pose each step: a press on the pad that turns
  /// with the arm).
  void setWrench(const std::array<double, 6>& w, bool tool_axes = false) {
    wrench_ = w;
    tool_axes_ = tool_axes;
  }
  /// The pad's true load against the load the KRC's model compensates
  /// ($LOAD): mass m (kg) and centre of mass c (m, flange axes) of each. The
  /// KRC reports the difference's weight as an external wrench at the flange,
  /// added to the one above: force (m_t - m_k) g_vec, moment
  /// R (m_t c_t - m_k c_k) x g_vec, with g_vec = (0, 0, -9.80665) N/kg in {g}
  /// and R the measured {g}R{e}: it turns in the flange's axes as the arm
  /// reorients.
  void setPadLoad(double true_mass, const KDL::Vector& true_com, double model_mass, const KDL::Vector& model_com) {
    load_dm_ = true_mass - model_mass;
    load_s_ = true_com * true_mass - model_com * model_mass;
  }

 private:
  void fillWrench();
  double tau_;
  std::array<double, 6> wrench_{};
  bool tool_axes_ = false;
  double load_dm_ = 0.0;     // true - modelled pad mass (kg)
  KDL::Vector load_s_ = KDL::Vector::Zero();  // true - modelled first moment of mass (kg m, {e})
  PlantState state_{};
};

/// From cycle `cycle` on, the KRC reports this state and quality.
struct StateEvent {
  uint64_t cycle = 0;
  State state = State::Mon;
  Quality quality = Quality::Perfect;
  uint16_t power = 0x7F;
  /// false: the interface is closed (before friOpen, after friClose): the KRC
  /// sends nothing, the robot holds (holdPose()).
  bool open = true;
};

/// Per-measurement fault probabilities, drawn from a seeded generator.
struct FaultParams {
  double loss = 0.0;        ///< measurement not sent
  double duplicate = 0.0;   ///< measurement sent twice
  double reorder = 0.0;     ///< measurement held back and sent after the next one
  double late = 0.0;        ///< measurement sent after the reply deadline of its cycle
  double wrong_size = 0.0;  ///< a truncated/padded datagram is sent instead
  double wrong_id = 0.0;    ///< the datagram id is corrupted
  double cmd_loss = 0.0;    ///< a received command is discarded (loss on the way back)
  uint32_t seed = 1;
  /// A burst: the measurements of cycles [burst_start, burst_start + burst_length)
  /// are not sent (counted in inj_lost); burst_length 0 = none.
  uint64_t burst_start = 0;
  uint64_t burst_length = 0;
};

struct SimKrcParams {
  uint16_t remote_port = kDefaultPort;  ///< the bridge's port on 127.0.0.1
  /// The KRC's own UDP source port on 127.0.0.1 (its FRI init file's local
  /// port, what the bridge's krc_port checks); 0 = ephemeral.
  uint16_t local_port = 0;
  double period_s = 0.001;               ///< measurement period (s), (0, 0.1]
  bool real_time = true;                 ///< sleep to keep the period; false: run as fast as replies come
  double reply_timeout_s = 0.01;         ///< fast mode: how long to wait for a reply (s)
  KDL::Frame initial_pose = KDL::Frame(KDL::Rotation::RPY(3.14159265358979, 0.0, 0.0), KDL::Vector(0.5, 0.0, 0.4));
  ControlStrategy control = ControlStrategy::CartImpedance;
  /// The form of cmdCartPos / cmdCartPosFriOffset (KrcModelParams::cart_offset).
  CartOffset cart_offset = CartOffset::None;
  /// The axes of estExtTcpFT (KrcModelParams::wrench_frame: the KRC's $STIFFNESS.FRAMETYPE).
  WrenchFrame wrench_frame = WrenchFrame::Base;
  /// The sample times the KRC advertises in every measurement
  /// (desiredMsrSampleTime, desiredCmdSampleTime), s; 0 = period_s. A value
  /// other than period_s rehearses a KRC whose advertised cycle disagrees with
  /// its real one (the bridge's rate limiter steps by desiredCmdSampleTime).
  double msr_sample_time_s = 0.0;
  double cmd_sample_time_s = 0.0;
  /// The quality from the answers' timing (KrcModel): off by default here (a
  /// test peer's schedule alone decides); lab_sim and fri_sim_krc turn it on.
  /// In real time an answer's latency counts against late_fraction of the
  /// period; in fast mode only missed answers count.
  KrcQualityRule quality_rule{};
  /// $STIFFNESS.MAXFORCE / CPMAXDELTA (KrcModel): off by default (zeros).
  KrcStiffnessLimits limits{};
  StateEvent initial{};                  ///< state at cycle 0 (its `cycle` is ignored)
  std::vector<StateEvent> schedule;      ///< sorted by cycle
  FaultParams faults{};
};

/// The peer's statistics: the KRC model's (replies, applied commands, step
/// and entry checks) plus what only the UDP peer knows (injected faults,
/// misses, overruns, latency).
struct SimKrcStats : KrcModelStats {
  uint64_t cycles = 0;
  uint64_t sent = 0;              ///< measurement datagrams sent (incl. duplicates, corrupted)
  uint64_t inj_lost = 0, inj_duplicate = 0, inj_reorder = 0, inj_late = 0, inj_wrong_size = 0, inj_wrong_id = 0,
           inj_cmd_lost = 0;
  uint64_t missed = 0;            ///< cycles without a matching reply
  uint64_t overruns = 0;          ///< real time: host late by > 2 periods, period grid re-anchored
  uint64_t closed_cycles = 0;     ///< cycles with the interface closed (StateEvent::open false): nothing sent
  double max_latency_s = 0.0;     ///< send -> matching reply
  double sum_latency_s = 0.0;
};

class SimKrc {
 public:
  /// Opens a socket on 127.0.0.1 (ephemeral port) and resets the plant.
  ConfigResult configure(const SimKrcParams& params, Plant& plant);
  uint16_t localPort() const { return socket_.localPort(); }

  /// One cycle (see the file comment).
  void runCycle();
  /// `cycles` cycles, or until *stop becomes true.
  void run(uint64_t cycles, const std::atomic<bool>* stop = nullptr);

  /// One cycle's reply latency (benchmarks).
  struct LatencySample {
    double latency_s;  ///< measurement sent -> its reply received; NaN: no reply ever came
    bool on_time;      ///< the reply came before the next tick (it was taken)
  };
  /// Optional per-cycle record (benchmarks): one sample per cycle. A reply
  /// that misses its tick is ignored by the KRC (stale), but when it arrives
  /// within the next kLateWindow cycles its true latency is still entered in
  /// its cycle's sample (on_time false), so that the percentiles are the
  /// latencies, not a censored count. Not owned; reserve it beforehand
  /// (push_back per cycle).
  void setLatencyLog(std::vector<LatencySample>* log) { latency_log_ = log; }
  static constexpr std::size_t kLateWindow = 64;

  const SimKrcStats& stats() const { return stats_; }
  const PlantState& plantState() const { return plant_state_; }
  State state() const { return model_.state(); }
  Quality quality() const { return model_.quality(); }
  uint16_t power() const { return model_.power(); }
  bool open() const { return open_; }
  KrcFault fault() const { return model_.fault(); }
  const KDL::Frame& setPoint() const { return model_.setPoint(); }

 private:
  void buildMeasurement();
  void sendMeasurement(const uint8_t* buf, std::size_t n);
  void handleReply(const uint8_t* buf, std::size_t n, double t_sent, double now);
  // runCycle's steps: this cycle's measurement (n bytes in out_) sent with the
  // configured faults (returns whether a reply is expected; `late`: send it
  // after the wait); the wait for the reply (returns whether one matched).
  bool sendWithFaults(std::size_t n, bool& late);
  bool awaitReply(double t_sent, bool expect_reply);

  void syncStats();

  SimKrcParams params_{};
  KrcModel model_;  // the KRC's packets and command handling (shared with the headless runner)
  Plant* plant_ = nullptr;
  UdpSocket socket_;
  sockaddr_in remote_{};
  std::mt19937 rng_{1};
  std::uniform_real_distribution<double> uni_{0.0, 1.0};
  SimKrcStats stats_{};
  PlantState plant_state_{};
  std::size_t next_event_ = 0;
  bool open_ = true;  // the interface is open (the KRC sends)
  MsrPacket msr_{};
  std::array<uint8_t, 2048> out_{};
  std::array<uint8_t, 2048> in_{};
  std::array<uint8_t, 2048> held_{};  // reordered packet waiting for the next cycle
  std::size_t held_size_ = 0;
  double t0_ = 0.0;
  double answer_rate_ = 1.0;
  std::vector<LatencySample>* latency_log_ = nullptr;
  double cycle_latency_s_ = 0.0;  // this cycle's first matched reply (NaN: none yet)
  struct SentRecord {
    uint16_t seq = 0;
    double t_sent = 0.0;
    std::size_t log_index = 0;
    bool valid = false;
  };
  std::array<SentRecord, kLateWindow> sent_ring_{};  // the last cycles' measurements (late replies)
};

}  // namespace fri
}  // namespace tactile
