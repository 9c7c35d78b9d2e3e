// Simulated WTS device on a pseudo-terminal (posix_openpt / grantpt /
// unlockpt). A thread owns the PTY master and answers the WTS protocol; the
// driver under test opens the slave path exactly as it would /dev/ttyACM0.
//
// Frames come from a FrameSource callback (e.g. the elastic pad simulator)
// or a recording (looped). They are sent in the device's cell order
// (CellMap::toDevice), plain or RLE as the host asked.
//
// Fault injection (per outgoing packet, deterministic seed): bit flips, dropped
// bytes, truncated packets, wrong CRC, garbage between packets, stalls; plus
// unplug()/replug() which closes the master (the driver sees a hangup) and
// creates a new PTY behind the same symlink path; hold(), a stalled stream
// (no frame sent, commands still answered); and taxel faults of the pad
// itself (TaxelFault: dead, stuck, noisy), applied to every frame's content.
//
// Not real-time and not allocation-free (test equipment).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tactile_types/types.hpp"
#include "tactile_wts/protocol.hpp"

namespace tactile {
namespace wts {

struct SimFaults {
  double bit_flip = 0.0;   ///< probability per packet: flip one random bit
  double drop_byte = 0.0;  ///< probability per packet: drop one random byte
  double truncate = 0.0;   ///< probability per packet: send only a random prefix
  double bad_crc = 0.0;    ///< probability per packet: corrupt the CRC
  double garbage = 0.0;    ///< probability per packet: 1..32 random bytes before it
  double stall = 0.0;      ///< probability per packet: sleep stall_ms before it
  int stall_ms = 50;
  uint32_t seed = 1;
};

/// A faulty taxel of the simulated pad, at {s} (row, col). Applied to every
/// frame after the source and the device tare, i.e. to what the host receives:
///   Dead:  always 0 (a broken trace: the taxel never responds);
///   Stuck: always `value` counts (a shorted cell or a frozen converter);
///   Noisy: the source's value plus Gaussian noise of `value` counts (1 sigma),
///          clamped to [0, full scale].
enum class TaxelFaultKind : uint8_t { Dead = 0, Stuck = 1, Noisy = 2 };
struct TaxelFault {
  int row = 0;
  int col = 0;
  TaxelFaultKind kind = TaxelFaultKind::Dead;
  double value = 0.0;  ///< Stuck: the constant count [0, full scale]; Noisy: 1-sigma counts (>= 0)
};

struct SimStats {
  uint64_t commands = 0;
  uint64_t frames = 0;
  uint64_t faults = 0;     ///< packets altered by fault injection
  uint64_t bad_commands = 0;
  uint64_t held_frames = 0;  ///< frames not sent while the stream was held (hold())
};

/// Fills `frame.counts` ({s} layout, row-major) for device time t_ms.
using FrameSource = std::function<void(uint32_t t_ms, RawTactileFrame& frame)>;

class SimulatedWts {
 public:
  struct Params {
    CellMapParams cells;          ///< what the device reports and how it orders cells
    uint16_t cell_size_10um = 340;///< 3.4 mm pitch
    uint16_t full_scale = kFullScale;
    std::string link;             ///< optional symlink to the slave (stable across replug)
    SimFaults faults;
    std::vector<TaxelFault> taxel_faults;  ///< checked by start() (row/col inside the pad, value range)
  };

  SimulatedWts() = default;
  ~SimulatedWts();
  SimulatedWts(const SimulatedWts&) = delete;
  SimulatedWts& operator=(const SimulatedWts&) = delete;

  /// Creates the PTY and starts the thread. False (and `why`) on failure.
  bool start(const Params& p, std::string* why = nullptr);
  void stop();
  /// Path for the driver: the symlink if configured, else the slave name.
  std::string path() const;

  void setSource(FrameSource src);
  void setRecording(std::vector<RawTactileFrame> frames);
  void setFaults(const SimFaults& f);
  /// Replaces the taxel faults; false (and `why`) when one lies outside the pad
  /// or its value outside its range (the previous faults are kept).
  bool setTaxelFaults(const std::vector<TaxelFault>& faults, std::string* why = nullptr);
  /// Simulate pulling the USB cable / plugging it back in.
  void unplug();
  bool replug();
  /// The frame stream stalls while `on`: no frame is sent (periodic or
  /// requested; counted as held_frames), commands are still answered.
  void hold(bool on) { held_.store(on); }
  bool held() const { return held_.load(); }
  bool plugged() const { return plugged_.load(); }
  /// Device reset behind the driver's back: periodic acquisition stops silently.
  void resetDevice() { streaming_ = false; }
  /// Device status returned to every command except loop (to test error paths).
  void forceStatus(StatusCode s) { forced_status_.store(static_cast<uint16_t>(s)); }

  SimStats stats() const;
  bool streaming() const { return streaming_.load(); }
  bool rleRequested() const { return rle_.load(); }

 private:
  bool openPty(std::string* why);
  void closePty();
  void run();
  void handle(const PacketView& pkt);
  void reply(uint8_t id, StatusCode st, const uint8_t* data, std::size_t n);
  void sendFrame(uint8_t id, bool with_status);
  void sendPacket(std::vector<uint8_t>& pkt);
  uint32_t nowMs() const;
  double uniform();
  double gaussian();  ///< standard normal from uniform() (Box-Muller); call with mu_ held
  bool checkTaxelFaults(const std::vector<TaxelFault>& faults, std::string* why) const;

  Params p_;
  CellMap map_;
  mutable std::mutex mu_;  ///< guards source_, recording_, faults_, stats_, fds
  FrameSource source_;
  std::vector<RawTactileFrame> recording_;
  std::size_t rec_index_ = 0;
  SimFaults faults_;
  std::vector<TaxelFault> taxel_faults_;
  SimStats stats_;
  uint64_t rng_ = 1;
  int master_ = -1;
  int slave_keep_ = -1;  ///< slave fd kept open by the sim (raw mode set, no EIO on master)
  std::string slave_name_;
  std::atomic<bool> running_{false};
  std::atomic<bool> plugged_{false};
  std::atomic<bool> streaming_{false};
  std::atomic<bool> rle_{false};
  std::atomic<bool> held_{false};
  std::atomic<uint16_t> forced_status_{0};
  uint16_t delay_ms_ = 10;
  std::array<uint16_t, kMaxTaxels> tare_{};
  std::thread thread_;
  long long t0_ms_ = 0;
};

}  // namespace wts
}  // namespace tactile
