// WTS driver: SerialPort + Parser + FrameDecoder, with reconnection.
//
//   WtsDriver d;
//   d.configure(params);                 // may allocate (path), validates ranges
//   d.open();                            // opens the port, checks matrix info, starts acquisition
//   loop: d.poll(now_s, timeout_ms, raw) // allocation-free; bounded by timeout_ms
//           -> NewFrame / NoData / LinkErrors / Disconnected / Reconnected / DeviceError
//   calibration.step(raw, frame_in_newtons)   (tactile::Calibration, App. A)
//
// Acquisition modes: periodic_ms > 0 sends "start periodic" (0x21) with that
// delay and decodes the 0x00 frames the device streams; periodic_ms == 0 polls
// with "read single frame" (0x20), one request outstanding at a time.
// On Disconnected the driver closes the port and, once reconnect_period_s has
// passed (time is the caller's now_s), re-opens the same path, flushes and
// restarts acquisition; that poll() returns Reconnected. poll() never waits
// for a reply: the restart commands are sent without waiting (their replies are
// counted as other_packets) and its writes never wait for room in the output
// buffer (a request that does not fit is sent again by a later poll()), so
// poll(now_s, 0, out) returns without waiting. Malformed bytes are
// counted and skipped; only CRC-checked, size-checked frames are returned.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"
#include "tactile_wts/device_clock.hpp"
#include "tactile_wts/protocol.hpp"
#include "tactile_wts/serial_port.hpp"

namespace tactile {
namespace wts {

struct WtsParams {
  std::string device = "/dev/ttyACM0";
  CellMapParams cells;            ///< {s} size and device cell order (protocol.hpp)
  int periodic_ms = 10;           ///< [0, 1000]; 0 = read-single-frame polling
  bool rle = false;               ///< ask the device for RLE-compressed frames
  int command_timeout_ms = 300;   ///< [1, 10000] reply timeout of a command
  double reconnect_period_s = 0.5;///< [0.01, 60] between re-open attempts
  bool check_matrix_info = true;  ///< on open: 0x30 reply must match cells (res_x, res_y)
  /// Periodic mode: with no valid frame for this long, "start periodic" is sent
  /// again (device reset or a lost start command). [0.05, 60] s.
  double restart_after_s = 1.0;
};

enum class ReadStatus : uint8_t {
  NewFrame = 0,      ///< `out` holds the newest valid frame received in this call; its time_s is when the device took it (device_clock.hpp)
  NoData = 1,        ///< nothing complete arrived within the timeout
  LinkErrors = 2,    ///< bytes arrived but only malformed ones (CRC, size, RLE); no frame
  DeviceError = 3,   ///< the device answered a frame request with status != E_SUCCESS
  Reconnected = 4,   ///< port re-opened and acquisition restarted; no frame yet
  Disconnected = 5,  ///< port closed (unplugged); retrying every reconnect_period_s
  NotConfigured = 6,
};
const char* toString(ReadStatus s);

enum class CmdStatus : uint8_t { Ok = 0, DeviceError = 1, Timeout = 2, Disconnected = 3, NotOpen = 4, BadReply = 5 };
const char* toString(CmdStatus s);

struct DriverStats {
  uint64_t frames = 0;
  uint64_t bad_frames = 0;     ///< CRC-valid frame packets rejected by the decoder
  uint64_t disconnects = 0;
  uint64_t reconnects = 0;
  uint64_t restarts = 0;       ///< "start periodic" re-sent by the watchdog
  uint64_t bytes = 0;
  uint64_t other_packets = 0;  ///< replies not awaited (e.g. late acks)
};

class WtsDriver {
 public:
  ConfigResult configure(const WtsParams& p);
  const WtsParams& params() const { return p_; }

  /// Opens the port, reads matrix info (if check_matrix_info), starts acquisition.
  /// `why` (optional) receives a message on failure. Not real-time.
  CmdStatus open(std::string* why = nullptr);
  void close();
  bool isOpen() const { return port_.isOpen(); }
  /// The serial port's file descriptor, -1 while closed (unplugged): an event
  /// loop waits on it and calls poll(now_s, 0, ...) when it is readable. It
  /// changes when poll() closes the port or re-opens it.
  int fd() const { return port_.fd(); }

  /// Per-cycle call: reads what the device sent (waiting up to timeout_ms for
  /// the first byte), decodes, reconnects when due. Allocation-free.
  ReadStatus poll(double now_s, int timeout_ms, RawTactileFrame& out);

  // Commands (bounded by command_timeout_ms; frames arriving meanwhile are kept
  // and returned by the next poll()).
  CmdStatus tare(bool on = true);              ///< 0x23: device-side tare
  CmdStatus startPeriodic();                   ///< 0x21 with params' rle / periodic_ms
  CmdStatus stopPeriodic();                    ///< 0x22
  CmdStatus matrixInfo(MatrixInfo& info);      ///< 0x30
  CmdStatus temperature(double& deg_c);        ///< 0x46 (i16, 0.1 degC)
  CmdStatus loop(const uint8_t* data, uint16_t n, bool& echoed_ok);  ///< 0x06 echo
  StatusCode lastDeviceStatus() const { return last_status_; }

  const DriverStats& stats() const { return stats_; }
  /// The frames' delay from the device's clock (device_clock.hpp): a frame's
  /// time_s is when it was taken, in now_s's base.
  const DeviceClockStats& clockStats() const { return clock_.stats(); }
  const ParserStats& parserStats() const { return parser_.stats(); }
  IoStatus lastIo() const { return last_io_; }
  int lastErrno() const { return port_.lastErrno(); }

 private:
  /// Sends one command and waits for the reply with the same id.
  CmdStatus transact(Command c, const uint8_t* payload, uint16_t n);
  /// Writes tx_[0, len); waits at most timeout_ms for room (0 on the per-cycle path).
  CmdStatus sendPacket(std::size_t len, int timeout_ms);
  /// Reads once and processes every complete packet. Returns the I/O status.
  IoStatus pump(int timeout_ms, bool& got_frame, bool& link_error);
  void handlePacket(const PacketView& pkt, bool& got_frame, bool& link_error);
  CmdStatus startAcquisition();

  WtsParams p_;
  bool configured_ = false;
  SerialPort port_;
  Parser parser_{Direction::FromDevice};
  FrameDecoder decoder_;
  DeviceClock clock_;
  RawTactileFrame latest_{};
  bool have_latest_ = false;
  bool device_error_ = false;
  bool request_outstanding_ = false;
  double request_time_s_ = 0.0;
  double last_attempt_s_ = -1e300;
  bool want_open_ = false;
  uint32_t seq_ = 0;
  double last_frame_s_ = 0.0;
  bool frame_clock_started_ = false;
  /// Sends "start periodic" without waiting for the reply (per-cycle path).
  bool kickPeriodic();
  // awaited reply
  uint8_t await_id_ = 0xFF;
  bool await_done_ = false;
  std::array<uint8_t, 64> reply_{};
  uint16_t reply_size_ = 0;
  StatusCode last_status_ = StatusCode::Success;
  IoStatus last_io_ = IoStatus::NotOpen;
  std::array<uint8_t, 512> rx_{};
  std::array<uint8_t, 64> tx_{};
  DriverStats stats_;
};

}  // namespace wts
}  // namespace tactile
