#include "tactile_wts/device_clock.hpp"

#include <algorithm>

namespace tactile {
namespace wts {

double DeviceClock::capture(uint32_t device_ms, double arrival_s) {
  const uint32_t step_ms = device_ms - last_ms_;  // modulo 2^32: the wrap unwrapped
  const bool advances = started_ && step_ms != 0 && step_ms < 0x80000000u;
  if (started_ && !advances) ++stats_.restarts;
  last_ms_ = device_ms;
  if (!advances) {
    started_ = true;
    device_s_ = 0.0;
    offset_s_ = arrival_s;
    last_arrival_s_ = arrival_s;
    last_capture_s_ = arrival_s;
    stats_.delay_last_s = 0.0;
    return arrival_s;
  }
  device_s_ += 1e-3 * step_ms;
  const double rise = max_skew_ * std::max(0.0, arrival_s - last_arrival_s_);
  last_arrival_s_ = arrival_s;
  offset_s_ = std::min(arrival_s - device_s_, offset_s_ + rise);
  // Never before the previous frame's (the floor can drop by more than a frame period early on),
  // never after the arrival (rounding).
  const double capture_s = std::min(arrival_s, std::max(device_s_ + offset_s_, last_capture_s_));
  last_capture_s_ = capture_s;
  stats_.delay_last_s = arrival_s - capture_s;
  stats_.delay_max_s = std::max(stats_.delay_max_s, stats_.delay_last_s);
  return capture_s;
}

}  // namespace wts
}  // namespace tactile
