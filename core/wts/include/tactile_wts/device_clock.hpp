// The WTS0614's own millisecond clock mapped onto the host's: when a frame was
// taken, not when its bytes reached the host.
//
// A frame's bytes can wait in the USB-serial link or in the kernel's tty
// worker (docs/realtime.md, "The sensor's tty under CPU load"); stamped at
// arrival, a frame held up there looks fresh to the servo's stale check and
// is fused with a newer wrench. Each frame carries the device's timestamp
// (protocol.hpp, device_time_ms). The offset host - device is estimated as
// the smallest (arrival - device time) seen, the one-way delay's floor, which
// may rise by at most max_skew seconds per second so a device clock slower
// than the host's is followed (a skew-bounded minimum filter, as in the
// one-way translators of ethz-asl's cuckoo_time_translator):
//
//   offset_k  = min(arrival_k - device_k, offset_{k-1} + max_skew (arrival_k - arrival_{k-1}))
//   capture_k = max(device_k + offset_k, capture_{k-1}),   delay_k = arrival_k - capture_k >= 0
//
// A device time that does not advance (a device that does not stamp its
// frames) or runs backwards (the device restarted) restarts the estimate:
// that frame is stamped at its arrival (delay 0), as without this clock.
// The 32-bit millisecond counter's wrap (49.7 days) is unwrapped.
//
// Real-time: capture() neither allocates nor blocks; time is passed in.
#pragma once

#include <cstdint>

namespace tactile {
namespace wts {

struct DeviceClockStats {
  double delay_last_s = 0.0;  ///< arrival - capture of the last frame
  double delay_max_s = 0.0;   ///< largest delay since the last restart() of the stats
  uint64_t restarts = 0;      ///< estimates restarted (device time not advancing or backwards)
};

class DeviceClock {
 public:
  /// max_skew: how fast (s/s) the offset may rise: the device's clock at
  /// most this much slower than the host's. 1e-3 covers a crystal's 100 ppm
  /// tenfold; a delay that persists is absorbed at this rate.
  explicit DeviceClock(double max_skew = 1e-3) : max_skew_(max_skew) {}

  /// Forgets the offset (a new connection, a re-opened port).
  void reset() { started_ = false; }

  /// The host time (arrival's base) at which the frame stamped `device_ms`
  /// was taken; `arrival_s` is when it was read.
  double capture(uint32_t device_ms, double arrival_s);

  const DeviceClockStats& stats() const { return stats_; }

 private:
  double max_skew_;
  bool started_ = false;
  uint32_t last_ms_ = 0;
  double device_s_ = 0.0;  ///< unwrapped device time since the estimate started
  double last_arrival_s_ = 0.0;
  double offset_s_ = 0.0;
  double last_capture_s_ = 0.0;
  DeviceClockStats stats_;
};

}  // namespace wts
}  // namespace tactile
